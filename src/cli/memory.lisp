;;;; memory.lisp -- the memory budget every command runs under.  SBCL's heap
;;;; (its dynamic space) is fixed when the process starts: bin/player starts
;;;; the core with a fraction of the machine's memory, and `--max-memory SIZE`,
;;;; which every command takes, starts it again with SIZE.  Running out is one
;;;; "ran out of memory (limit ...)" line: a STORAGE-CONDITION where SBCL can
;;;; still signal one, and before that a guard after every garbage collection
;;;; that stops the command while the heap is still 90% full, since SBCL dies
;;;; outright ("Heap exhausted, game over") when a collection itself runs out.

(in-package #:player.cli)

(defparameter *smallest-max-memory* (* 256 1024 1024)
  "The smallest --max-memory accepted: Player itself needs about 150 MB.")

(defparameter *memory-guard-fraction* 0.5
  "The share of the heap still in use after a garbage collection at which the
guard stops the command.")

(defun parse-memory-size (text)
  "TEXT (\"512M\", \"2G\", \"1536MB\"; a bare number is megabytes) as bytes; a
USAGE-ERROR when it is not a size of at least *SMALLEST-MAX-MEMORY*."
  (let* ((upper (string-upcase (string-trim " " text)))
         (upper (if (and (> (length upper) 1) (char= (char upper (1- (length upper))) #\B)
                         (not (digit-char-p (char upper (- (length upper) 2)))))
                    (subseq upper 0 (1- (length upper)))
                    upper))
         (unit (and (plusp (length upper)) (position (char upper (1- (length upper))) "KMGT")))
         (digits (if unit (subseq upper 0 (1- (length upper))) upper))
         (number (and (plusp (length digits)) (<= (length digits) 9) (every #'digit-char-p digits)
                      (parse-integer digits)))
         (bytes (and number (* number (expt 1024 (if unit (1+ unit) 2))))))
    (unless (and bytes (<= *smallest-max-memory* bytes (expt 1024 5)))
      (usage-fail "--max-memory takes a size of at least 256M, such as 512M or 2G, not ~A" text))
    bytes))

(defun memory-text (bytes)
  "BYTES as a size a reader takes in: \"1.5 GB\", \"512 MB\"."
  (if (>= bytes (expt 1024 3))
      (format nil "~A GB" (format-number (/ (round (* 10 bytes) (expt 1024 3)) 10)))
      (format nil "~D MB" (round bytes (expt 1024 2)))))

(defun take-memory-option (arguments)
  "ARGUMENTS without --max-memory SIZE (or --max-memory=SIZE), and the SIZE in
bytes (or NIL): the option every command takes, read before the command's own."
  (let ((rest '()) (size nil))
    (loop while arguments
          do (let ((argument (pop arguments)))
               (cond ((string= argument "--max-memory")
                      (unless arguments (usage-fail "option --max-memory needs a value (SIZE)"))
                      (when size (usage-fail "option --max-memory given twice"))
                      (setf size (parse-memory-size (pop arguments))))
                     ((and (> (length argument) 13) (string= "--max-memory=" argument :end2 13))
                      (when size (usage-fail "option --max-memory given twice"))
                      (setf size (parse-memory-size (subseq argument 13))))
                     (t (push argument rest)))))
    (values (nreverse rest) size)))

(defun heap-limit ()
  "The size of this process's heap, in bytes."
  (sb-ext:dynamic-space-size))

(defun memory-limit-message ()
  "The one line printed when the heap runs out."
  (format nil "ran out of memory (limit ~A; a larger --max-memory may help)" (memory-text (heap-limit))))

(defun memory-guard ()
  "After a garbage collection: stop the command with its one line when the heap
is still *MEMORY-GUARD-FRACTION* full, before SBCL itself runs out."
  (when (> (sb-kernel:dynamic-usage) (* *memory-guard-fraction* (heap-limit)))
    (exit-with-error 1 (memory-limit-message))))

(defun install-memory-guard ()
  "Run MEMORY-GUARD after every garbage collection of this process."
  (pushnew 'memory-guard sb-ext:*after-gc-hooks*))

(defun restart-with-memory (bytes arguments)
  "Unless the heap is BYTES already, run this executable again with a heap of
BYTES and the command line ARGUMENTS; does not return then."
  (let ((megabytes (ceiling bytes (* 1024 1024))))
    (unless (or (= megabytes (ceiling (heap-limit) (* 1024 1024)))
                ;; Once restarted, never again, whatever size the runtime rounded to.
                (sb-posix:getenv "PLAYER_HEAP_RESTARTED"))
      (sb-posix:setenv "PLAYER_HEAP_RESTARTED" "1" 1)
      (let ((argv (list* (sb-ext:native-namestring sb-ext:*runtime-pathname*)
                         "--dynamic-space-size" (format nil "~DMB" megabytes)
                         "--disable-ldb" "--end-runtime-options"
                         "--max-memory" (format nil "~DM" megabytes) arguments)))
        (finish-output *standard-output*)
        (finish-output *error-output*)
        (execute-program argv)))))

(defun execute-program (argv)
  "Replace this process by the program ARGV names (execv); a PLAYER-ERROR when that fails."
  (let* ((count (length argv))
         (vector (sb-alien:make-alien sb-alien:c-string (1+ count))))
    (loop for i from 0 for word in argv do (setf (sb-alien:deref vector i) word))
    (setf (sb-alien:deref vector count) nil)
    (sb-alien:alien-funcall
     (sb-alien:extern-alien "execv" (function sb-alien:int sb-alien:c-string (* sb-alien:c-string)))
     (first argv) vector)
    (error 'player-error-with-message
           :message (format nil "cannot restart with a larger heap: ~A" (sb-int:strerror)))))

(defun restart-with-memory-option (arguments)
  "When the command line ARGUMENTS gives --max-memory, run it again under that
heap (see RESTART-WITH-MEMORY), unless the heap has that size already."
  (multiple-value-bind (rest size) (take-memory-option arguments)
    (when size (restart-with-memory size rest))))
