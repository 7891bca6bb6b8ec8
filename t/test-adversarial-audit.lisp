;;;; test-adversarial-audit.lisp -- issue 31, item 8 audited: causes of the
;;;; issue's "Why" that had no child-process test with their one error line
;;;; and a time and memory bound, starting with the exact-macro proof's
;;;; budget (item 3).  Runs bin/player through FZB-RUN (fuzz-bounds.lisp),
;;;; which reports the time and the peak resident memory.

(in-package #:player-tests)

(def-suite* adversarial-audit :in player-tests)

(defun write-case-files (directory files)
  "Write FILES (an alist of a name to its text or octets) into DIRECTORY."
  (loop for (name . content) in files
        for path = (concatenate 'string directory name)
        do (if (stringp content)
               (alexandria:write-string-into-file content path :if-exists :supersede :external-format :utf-8)
               (alexandria:write-byte-vector-into-file (coerce content '(vector (unsigned-byte 8))) path
                                                       :if-exists :supersede))))

(defun bounded-case (files arguments &key input after)
  "Run bin/player ARGUMENTS in a fresh folder holding FILES (an alist of a
name to its text or octets): (VALUES EXIT STDERR SECONDS MEGABYTES), after
calling AFTER, when given, with the folder before it is removed."
  (let ((directory (format nil "/tmp/player-audit-~D-~D/" (sb-posix:getpid) (incf *scratch-counter*))))
    (ensure-directories-exist directory)
    (unwind-protect
         (progn
           (write-case-files directory files)
           (multiple-value-prog1 (fzb-run arguments directory input)
             (when after (funcall after directory))))
      (uiop:delete-directory-tree (pathname directory) :validate t :if-does-not-exist :ignore))))

(defmacro check-bounded-case ((exit fragment &key (seconds 5) (megabytes 1024) input after) files &rest arguments)
  "bin/player ARGUMENTS, in a folder holding FILES (with standard INPUT, then
AFTER as for BOUNDED-CASE), ends with EXIT within SECONDS and MEGABYTES, its
stderr one player: error: line holding FRAGMENT (or empty when FRAGMENT is NIL)."
  `(multiple-value-bind (code stderr seconds megabytes)
       (bounded-case ,files (list ,@arguments) :input ,input :after ,after)
     (is (eql ,exit code) "exit ~A for ~S: ~A" code (list ,@arguments) stderr)
     (is (< seconds ,seconds) "~S took ~,1F s" (list ,@arguments) seconds)
     (is (< (or megabytes 0) ,megabytes) "~S used ~,0F MB" (list ,@arguments) megabytes)
     (if ,fragment
         (progn (is (= 1 (length (lines stderr))) "stderr is not one line: ~S" stderr)
                (is (eql 0 (search "player: error: " stderr)) "stderr ~S" stderr)
                (is (search ,fragment stderr) "stderr ~S lacks ~S" stderr ,fragment))
         (is (string= "" stderr) "stderr ~S" stderr))))

;;;# Item 3: the exact-macro proof is counted and capped

(test exact-macro-proof-past-its-budget-fails-fast
  ;; 20^4 = 160,000 cases passes the budget at the last sub-op; 20^3 cases
  ;; then 5,000 ticks would take 40 million steps: both stop at the budget.
  (check-bounded-case (1 "fz.lisp:96: macro-op m: cannot be proved exact within 1,000,000 steps")
      (list (cons "fz.lisp" (splitting-macro-spec 4 20 :name "fz")))
    "plans" "fz.lisp")
  (check-bounded-case (1 "use3 (8,000 cases), and was at sub-op tick")
      (list (cons "fz.lisp" (splitting-macro-spec 3 20 :name "fz" :tail 5000)))
    "check" "fz.lisp")
  ;; Under the default semantics check warns instead, and still stops.
  (multiple-value-bind (code stderr seconds) (bounded-case (list (cons "fz.lisp" (splitting-macro-spec 4 20 :name "fz" :semantics :declared)))
                                                           (list "check" "fz.lisp"))
    (is (eql 0 code) "~A" stderr)
    (is (< seconds 5))))

;;;# Causes whose test ran in process: now through bin/player, bounded

(defun fan-out-files (kind)
  "Files of a spec whose KIND (:macro, :play or :pose) doubles at 40-60 levels."
  (ecase kind
    (:macro (list (cons "fz.lisp" (doubling-macro-spec 40))))
    (:play (list (cons "fz.lisp" "(defspec fz (:scripts \"fz-scripts.lisp\") (:body parrot) (state-variable x boolean false)
  (op s40 :duration 1 :add x) (event ev :op s40))")
                 (cons "fz-scripts.lisp" (doubling-play-library 40))))
    (:pose (list (cons "fz.lisp" "(defspec fz (:scripts \"fz-scripts.lisp\") (:body parrot) (state-variable x boolean false)
  (op s :duration 1 :add x) (event ev :op s))")
                 (cons "fz-scripts.lisp" "(poses \"fz-poses.lisp\") (:pose-when x p60)
(defscript s (:duration 1) (:at 0 :motor (:blink)))")
                 (cons "fz-poses.lisp"
                       (with-output-to-string (s)
                         (format s "(defpose p0 (l_eye pitch 1))~%")
                         (loop for i from 1 to 60
                               do (format s "(defpose p~D (:include p~D) (:include p~:*~D) (:mirror p~:*~D))~%" i (1- i)))))))))

(test small-inputs-asking-for-unbounded-work-end-bounded
  ;; Issue 31, "Why" 3 and 5, each through bin/player within 5 s and 1 GB.
  (flet ((spec (value) (list (cons "fz.lisp" (spec-around value)))))
    (check-bounded-case (1 "at least 0.001 (a faster clock sends more events than can be played), not 1.0e-9")
        (list (cons "fz.lisp" "(defspec t1 (state-variable x boolean false) (event ev) (timer fast :after 1d-9 :event ev :repeat t))"))
      "check" "fz.lisp")
    (dolist (token (list (make-string 2000000 :initial-element #\7)
                         (format nil "~A/3" (make-string 2000000 :initial-element #\7))
                         (format nil "#36r~A" (make-string 2000000 :initial-element #\Z))))
      (check-bounded-case (1 "a token is longer than 4,096 characters") (spec token) "check" "fz.lisp"))
    (check-bounded-case (1 "runs 16,384 ops through m14 -> m13") (fan-out-files :macro) "plans" "fz.lisp")
    (check-bounded-case (1 "plays 1,534 items through s9 -> s8") (fan-out-files :play)
      "simulate" "fz.lisp" "--events" "ev" "--fps" "5" "--frames" "fz.frames")
    (check-bounded-case (1 "(newton-cradle 6) is built on demand")
        (list (cons "fz.lisp" "(defspec c (:graph (newton-cradle 6)))")) "plans" "fz.lisp"))
  ;; 2^60 pose inclusions, each pose resolved once.
  (check-bounded-case (0 nil) (fan-out-files :pose) "simulate" "fz.lisp" "--events" "ev" "--fps" "5" "--frames" "fz.frames"))

(test a-blink-too-fast-is-refused-saying-its-interval
  ;; The message once said "not 0": 1d-9 printed at the microsecond.
  (check-bounded-case (1 ":mean-interval must be a number of seconds of at least 0.05 (a reflex fires no faster), or one of nil, not 1.0e-9")
      (list (cons "fz.lisp" "(defspec fz (:scripts \"fz-scripts.lisp\") (:body parrot) (state-variable x boolean false)
  (op blinky :duration 2 :add x) (event ev :op blinky))")
            (cons "fz-scripts.lisp" "(defscript blinky (:duration 2) (:at 0 :motor (:blink :mean-interval 1d-9)))"))
    "simulate" "fz.lisp" "--events" "ev" "--fps" "5" "--frames" "fz.frames"))

(test a-hostile-memory-file-is-refused-and-kept
  ;; "Why" 4: 14 bytes asking for 4 billion elements, never written back.
  (let ((kept nil))
    (check-bounded-case (1 "memory.lisp:1: #4000000000...: a reader count larger than 1,000,000"
                         :input (format nil "hello~%quit~%")
                         :after (lambda (folder)
                                  (setf kept (alexandria:read-file-into-string
                                              (concatenate 'string folder "memory.lisp")))))
        (list (cons "memory.lisp" (format nil "#4000000000*1~%")))
      "chat" (namestring (checkout-file "specs/peedy-dialogue.lisp")) "--memory" "memory.lisp")
    (is (equal (format nil "#4000000000*1~%") kept))))

(test a-one-hertz-wav-is-refused-before-decoding
  (check-bounded-case (1 "it declares 1 channel at 1 Hz; 1 or 2 channels at 8,000 to 96,000 Hz")
      (list (cons "fz.wav" (wav-octets :rate 1 :data '(0 0 1 0))))
    "chat" (namestring (checkout-file "specs/peedy-dialogue.lisp")) "--wav" "fz.wav"))

(defun chained-objects-files (count)
  "A spec whose script library declares COUNT objects, each hanging from the one before."
  (list (cons "fz.lisp" "(defspec fz (:scripts \"fz-scripts.lisp\") (:body parrot) (state-variable x boolean false)
  (op s :duration 1 :add x) (event ev :op s))")
        (cons "fz-scripts.lisp"
              (with-output-to-string (s)
                (format s "(defscript s (:duration 1) (:at 0 :motor (:blink)))~%(defobject o0 :position (0 0 0))~%")
                (loop for i from 1 below count
                      do (format s "(defobject o~D :parent o~D :position (0 0 0))~%" i (1- i)))))))

(test a-long-chain-of-objects-is-placed-in-linear-time
  ;; "Why" 5: each object's world transform walked the chain above it, for
  ;; every static geom at every physics step and every frame: 1,000 chained
  ;; objects took 5.6 s to check, 2,000 took 20 s.
  (check-bounded-case (0 nil :seconds 10) (chained-objects-files 5000) "check" "fz.lisp")
  (check-bounded-case (0 nil :seconds 10) (chained-objects-files 5000)
    "simulate" "fz.lisp" "--events" "ev" "--fps" "5" "--frames" "fz.frames"))

(test verify-of-1200-frames-is-bounded
  ;; "Why" 5: verify was quadratic in frames (21 s for 1,200).
  (let ((trace (format nil "/tmp/player-audit-~D-long.trace" (sb-posix:getpid))))
    (unwind-protect
         (progn
           (check-bounded-case (0 nil :seconds 10) '()
             "record" (namestring (checkout-file "specs/peedy.lisp")) "--events" "ev-search" "--at" "40"
             "--fps" "30" "--frames" "--out" trace)
           (check-bounded-case (0 nil :seconds 10) '()
             "verify" (namestring (checkout-file "specs/peedy.lisp")) trace))
      (ignore-errors (delete-file trace)))))

(test templates-reach-the-terminal-escaped
  ;; "Why" 8: a template's ESC and BEL once retitled and cleared the terminal.
  (let* ((dialogue (scratch-peedy-dialogue ""))
         (text (alexandria:read-file-into-string dialogue)))
    (alexandria:write-string-into-file
     (let ((at (search "\"Hi! What would you like to hear?\"" text)))
       (concatenate 'string (subseq text 0 at)
                    (format nil "\"Hi!~C]0;PWNED~C~C[2J What?\"" (code-char 27) (code-char 7) (code-char 27))
                    (subseq text (+ at (length "\"Hi! What would you like to hear?\"")))))
     dialogue :if-exists :supersede)
    (let* ((input (make-string-input-stream (format nil "hello~%quit~%")))
           (out (make-string-output-stream)))
      (ensure-player-core)
      (sb-ext:run-program (namestring (checkout-file "bin/player")) (list "chat" dialogue)
                          :input input :output out :error nil :search nil)
      (let ((shown (get-output-stream-string out)))
        (is (search "Hi!\\x1B]0;PWNED\\x07\\x1B[2J What?" shown) "~A" shown)
        (is (notany (lambda (c) (member (char-code c) '(7 27))) shown))))))

(defun doubling-director-files (levels)
  "A spec and library whose directors D<i> (:on EV<i>) each send EV<i+1> twice."
  (list (cons "fz.lisp"
              (format nil "(defspec fz (:scripts \"fz-scripts.lisp\") (:body parrot) (state-variable x boolean false)
  (op s :duration 0.1 :add x)~{ (event ev~D)~} (event go :op s))" (loop for i to levels collect i)))
        (cons "fz-scripts.lisp"
              (with-output-to-string (s)
                (format s "(defscript s (:duration 0.1) (:at 0 :motor (:blink)))~%")
                (format s "(defdirector d-go (:on go) (:send ev0 :at 0) (:send ev0 :at 0))~%")
                (loop for i below levels
                      do (format s "(defdirector d~D (:on ev~D) (:send ev~D :at 0) (:send ev~:*~D :at 0))~%"
                                 i i (1+ i)))))))

(test directors-multiplying-each-other-are-capped
  ;; "What to build" 3, directors: 40 levels each sending the next event
  ;; twice start 2^41 times, in a chain only 41 deep; simulate hung.
  (check-bounded-case (1 "reactive directors started over 10,000 times in one performance" :seconds 10)
      (doubling-director-files 40)
    "simulate" "fz.lisp" "--events" "go" "--fps" "5" "--frames" "fz.frames")
  ;; Ten levels (2,047 starts) play.
  (check-bounded-case (0 nil :seconds 10) (doubling-director-files 10)
    "simulate" "fz.lisp" "--events" "go" "--fps" "5" "--frames" "fz.frames"))

(test argument-values-too-small-for-microseconds-are-shown-in-full
  (is (string= "1.0e-9" (player.base:argument-value-text 1d-9)))
  (is (string= "-1.0e-7" (player.base:argument-value-text -1d-7)))
  (is (string= "0.5" (player.base:argument-value-text 0.5d0)))
  (is (string= "0" (player.base:argument-value-text 0)))
  (is (string= "nan" (player.base:argument-value-text (fz-nan))))
  (is (string= "inf" (player.base:argument-value-text sb-ext:double-float-positive-infinity))))

;;;# Command-line values ask the reader no more than a data file may

(test command-line-values-are-read-within-the-reader-limits
  ;; #100000000A() as --at took 10 s and 2 GB before it was refused; a
  ;; 120,000-digit time took 4 s of bignum arithmetic.
  (let ((spec (list (cons "fz.lisp" "(defspec fz (state-variable x boolean false) (op o :add x) (event ev :op o))"))))
    (check-bounded-case (2 "a reader count larger than 1,000,000") spec "run" "fz.lisp" "--at" "#100000000A()")
    (check-bounded-case (2 "a reader count larger than 1,000,000") spec "run" "fz.lisp" "--at" "#4000000000*1")
    (check-bounded-case (2 "a token is longer than 4,096 characters" :seconds 2)
        spec "run" "fz.lisp" "--at" (format nil "25.~A" (make-string 120000 :initial-element #\7)))
    (check-bounded-case (2 "a token is longer than 4,096 characters" :seconds 2)
        spec "run" "fz.lisp" "--events" (format nil "ev@1.~A" (make-string 120000 :initial-element #\7)))
    (check-bounded-case (0 nil) spec "run" "fz.lisp" "--events" "ev@1/3" "--at" "1.000000000000000000001")
    ;; Every option read as a Lisp datum: --goal, --formula, dot's --goal.
    (check-bounded-case (2 "cannot read --goal \"#100000000A()\": #100000000...: a reader count larger than 1,000,000")
        spec "explain" "fz.lisp" "--goal" "#100000000A()")
    (check-bounded-case (2 "cannot read --formula \"#100000000A()\"") spec "verify-graph" "fz.lisp" "--formula" "#100000000A()")
    (check-bounded-case (2 "cannot read --goal \"#4000000000*1\"") spec "dot" "fz.lisp" "--goal" "#4000000000*1")))

(test command-line-forms-are-read-as-data-files-are
  "A command-line datum is read with a data file's syntax: #S, which would
call a structure's constructor, and #. are refused; blanks after one datum
are allowed, a second datum is not."
  (is (null (player.cli::read-cli-form "#S(sb-impl::hash-table)" "--formula")))
  (is (null (player.cli::read-cli-form "#.(list 1)" "--goal")))
  (is (null (player.cli::read-cli-form "a b" "--goal")))
  (multiple-value-bind (form one) (player.cli::read-cli-form " (and a.x b) " "--goal")
    (is-true one)
    (is (equal '("AND" "A.X" "B") (mapcar #'symbol-name form)))
    (is (eq (find-package '#:player-user) (symbol-package (second form)))))
  (is (eql 1.5d0 (player.cli::read-cli-value "1.5"))))
