;;;; test-rest31.lisp -- issue 31, what was left: a stop signal ends every
;;;; command with 143 (SIGTERM) or 130 (SIGINT) at any moment, start-up
;;;; included, and prints nothing; every error is one line on stderr.
;;;; Helpers are test-hostile-files.lisp's and test-bounds.lisp's.

(in-package #:player-tests)

(def-suite* rest31 :in player-tests)

;;;# Stop signals at any moment

(defun start-player-core (arguments)
  "Start the core bin/player runs (without its shell script, so a signal lands
in Player itself) on ARGUMENTS.  Returns the process and its two output files."
  (ensure-player-core)
  (let ((tag (format nil "/tmp/player-rest31-~D-~36R" (sb-posix:getpid) (random (expt 36 6)))))
    (values (sb-ext:run-program (namestring (checkout-file "build/player"))
                                (list* "--dynamic-space-size" "512MB" "--disable-ldb"
                                       "--end-runtime-options" arguments)
                                :output (format nil "~A.out" tag) :error (format nil "~A.err" tag)
                                :if-output-exists :supersede :if-error-exists :supersede
                                :input nil :wait nil :search nil :directory (namestring *root*))
            (format nil "~A.out" tag) (format nil "~A.err" tag))))

(defun stopped-by-p (process signal)
  "Did PROCESS end as a command stopped by SIGNAL does: exit 128 + SIGNAL, or
killed by it before any handler was in place?"
  (case (sb-ext:process-status process)
    (:exited (eql (+ 128 signal) (sb-ext:process-exit-code process)))
    (:signaled (eql signal (sb-ext:process-exit-code process)))))

(defun nested-macro-spec (depth)
  "A spec whose macro-ops M1..MDEPTH each run the one before, the deepest nesting allowed."
  (with-output-to-string (s)
    (format s "(defspec deep (state-variable x boolean false) (state-variable y boolean false)~%")
    (dotimes (j 12) (format s "  (state-variable v~D boolean false) (op on~D :add v~:*~D :duration 1)~%" j j))
    (format s "  (op base :add y :duration 1)~%")
    (loop for i from 1 to depth
          do (format s "  (macro-op m~D :precond (and (not x) v~D) :add x :seq (:op ~A))~%"
                     i (mod i 12) (if (= i 1) "base" (format nil "m~D" (1- i)))))
    (format s "  (event ev :op m~D))~%" depth)))

(defun check-stopped-at (arguments signal delay complete)
  "Start ARGUMENTS, send SIGNAL after DELAY seconds: the command must end within
5 s, stopped by SIGNAL with nothing on stderr -- or, when it had finished
first, with status 0 and COMPLETE on stdout."
  (multiple-value-bind (process out err) (start-player-core arguments)
    (sleep delay)
    (let ((alive (sb-ext:process-alive-p process)))
      (when alive (sb-ext:process-kill process signal))
      (let ((in-time (wait-for-process process 5))
            (stdout (take-file out))
            (stderr (take-file err)))
        (is-true in-time "signal ~D after ~,3F s: ~S did not end within 5 s" signal delay arguments)
        (when in-time
          (is (or (stopped-by-p process signal)
                  (and (eql 0 (sb-ext:process-exit-code process)) (string= stdout complete)))
              "signal ~D after ~,3F s: ~S ended ~A ~A" signal delay arguments
              (sb-ext:process-status process) (sb-ext:process-exit-code process))
          (is (string= "" stderr) "signal ~D after ~,3F s: stderr ~S" signal delay stderr))))))

(test stop-signals-end-a-command-at-any-moment-with-128-plus-the-signal
  ;; SBCL's own SIGTERM handler, in place while the core starts, exited 0.
  (let* ((arguments (list "check" (namestring (checkout-file "specs/peedy.lisp"))))
         (complete (multiple-value-bind (process out err) (start-player-core arguments)
                     (wait-for-process process 60)
                     (take-file err)
                     (take-file out))))
    (loop for try below (sweep-count 16 6)
          for delay = (* 0.3 (expt (/ try (sweep-count 16 6)) 2)) ; denser in the start-up
          do (check-stopped-at arguments (if (evenp try) sb-unix:sigterm sb-unix:sigint) delay complete))))

(test sigterm-during-plans-of-nested-macro-ops-never-deadlocks
  (let* ((file (scratch-spec (nested-macro-spec 99)))
         (arguments (list "plans" (namestring file)))
         (complete (multiple-value-bind (process out err) (start-player-core arguments)
                     (wait-for-process process 60)
                     (take-file err)
                     (take-file out))))
    (is (search "goal" complete))
    (loop for try below (sweep-count 9 3)
          do (check-stopped-at arguments sb-unix:sigterm (* try 0.01) complete))))

;;;# One error line, nothing else

(defun write-text-file (path text)
  "Write TEXT to PATH, replacing it; PATH."
  (with-open-file (out path :direction :output :if-exists :supersede :external-format :utf-8)
    (write-string text out))
  path)

(test library-chatter-never-reaches-stderr
  ;; espeak-ng without its data printed "Error processing file '.../phontab': No
  ;; such file or directory." on stderr before Player's own error line.
  (with-scratch-folder (folder "chatter")
    (let ((spec (write-text-file (merge-pathnames "talk.lisp" folder)
                                 "(defspec talk (:scripts \"talk-scripts.lisp\") (:body parrot)
  (state-variable x boolean false) (op say :add x :duration 1) (event ev :op say))"))
          (empty (merge-pathnames "no-voices/" folder)))
      (write-text-file (merge-pathnames "talk-scripts.lisp" folder)
                       "(defscript say (:duration 1) (:at 0 :say \"hi there\" :voice \"en\")
  (:at (:word \"there\") :motor (:blink)))")
      (ensure-directories-exist empty)
      (multiple-value-bind (out err code in-time)
          (bounded-player 30 (list "check" (namestring spec))
                          :environment (list (format nil "ESPEAK_DATA_PATH=~A" (namestring empty))))
        (is-true in-time)
        (is (eql 1 code) "exit ~A: ~A" code err)
        (is (search "espeak-ng could not start" out) "stdout ~S" out)
        (is (equal (list "player: error: check found 1 error in spec talk (see standard output)")
                   (lines err))
            "stderr ~S" err)))))

(test code-compiler-notes-never-reach-stderr
  ;; SBCL's compiler printed its notes on :code (an unused variable, an
  ;; undefined function) on stderr before the error line.
  (let ((spec (scratch-spec "(defspec coder (state-variable x boolean false)
  (op poke :code (let ((unused 1)) (no-such-function-here)) :add x) (event ev :op poke))" "code")))
    (multiple-value-bind (out err code in-time) (bounded-player 30 (list "run" spec "--events" "ev"))
      (is-true in-time)
      (is (eql 1 code) "exit ~A: ~A" code err)
      (is (search "(:event ev :time 0)" out))
      (is (= 1 (length (lines err))) "stderr ~S" err)
      (is (search "no-such-function-here" (string-downcase err)) "stderr ~S" err))))

;;;# Control characters in trace lines, in both backends

(test both-backends-escape-control-characters-alike
  ;; Loading refuses such text; a string changed afterwards (through the Lisp
  ;; API) still prints escaped, by the generated C++ as by Lisp.
  (with-spec (spec escapes
               (state-variable mood string "calm" ("calm" "odd"))
               (state-variable flag boolean false)
               (op stir :add (mood.odd flag) :duration 1)
               (event ev :op stir))
    (let* ((var (find "MOOD" (player.spec:spec-variables spec) :key (lambda (v) (symbol-name (player.spec:var-name v)))
                                                                :test #'string=))
           (odd (format nil "o~Cd~Cd~C" (code-char 27) (code-char 7) (code-char #x85))))
      (setf (aref (player.spec:var-domain var) 1) odd)
      (let* ((machine (compile-spec spec))
             (lisp (lisp-trace machine '() '(ev))))
        (is (find-if (lambda (line) (search "\"o\\x1Bd\\x07d\\x85\"" line)) lisp) "Lisp trace ~S" lisp)
        (is (notany (lambda (line) (find-if #'player.base:control-character-p line)) lisp))
        (let ((problem (compare-backends machine '() '(ev))))
          (is (null problem) "~A" problem))
        (let ((problem (compare-timed-backends machine '() '((ev . 0) ev))))
          (is (null problem) "timed: ~A" problem))))))

;;;# Compose builders capped at load

(defun nodes-text (prefix count)
  "(PREFIX0 PREFIX1 ...), COUNT node names, as text."
  (format nil "(~{~A~^ ~})" (loop for i below count collect (format nil "~A~D" prefix i))))

(test compose-builders-are-capped-by-states-and-work
  ;; A 15 KB file asked for a product of 10^9 states with no edge at all, which
  ;; the edge limit let through: the heap ran out.
  (let ((nodes (nodes-text "n" 1000)))
    (check-quick-load-error 2 graph-expression-error "the product would have 1000000000 states, more than 500000"
      (format nil "(defspec p (:graph (product (graph ~A ()) (graph ~:*~A ()) (graph ~:*~A ()))))" nodes)))
  ;; A large graph used many times: each use counts its size, refused before the sum.
  (check-quick-load-error 5 graph-expression-error "the expression has handled"
    (format nil "(defspec s (:graph (let* ((a (product (graph ~A ()) (graph ~A ())))) (sum~{ ~A~}))))"
            (nodes-text "n" 500) (nodes-text "m" 900) (make-list 200 :initial-element "a")))
  ;; Within the limits it builds.
  (is (null (load-error (format nil "(defspec q (:graph (let* ((a (complete ~A))) (sum a a a))))"
                                (nodes-text "n" 30))))))
