;;;; test-cli.lisp -- bin/player as a user runs it: output, errors, exit codes.

(in-package #:player-tests)

(def-suite* cli :in player-tests)

(defvar *core-built* nil
  "True once this test run has made sure bin/player's saved core is up to date.")

(defun ensure-player-core ()
  "Build bin/player's core now, if it is stale, so no test sees the build's
progress line on its stderr."
  (unless *core-built*
    (sb-ext:run-program (namestring (checkout-file "bin/player")) '("help")
                        :output nil :error nil :search nil :directory (namestring *root*))
    (setf *core-built* t)))

(defun player-command (&rest arguments)
  "Run bin/player with ARGUMENTS; return (VALUES STDOUT STDERR EXIT-CODE)."
  (ensure-player-core)
  (let* ((out (make-string-output-stream))
         (err (make-string-output-stream))
         (process (sb-ext:run-program (namestring (checkout-file "bin/player")) arguments
                                      :output out :error err :search nil
                                      :directory (namestring *root*))))
    (values (get-output-stream-string out) (get-output-stream-string err)
            (sb-ext:process-exit-code process))))

(defun lines (text)
  "TEXT split into its lines."
  (with-input-from-string (in text)
    (loop for line = (read-line in nil) while line collect line)))

(defun fixture (name)
  "The path of test fixture NAME as a string."
  (namestring (checkout-file (format nil "t/fixtures/~A" name))))

(test run-prints-the-trace
  (multiple-value-bind (out err code)
      (player-command "run" (fixture "mini.lisp") "--initial" "alert=snore,posture=sit"
                      "--events" "ev-search,ev-search")
    (is (= 0 code))
    (is (string= "" err))
    (is (equal '("(:autoscript-start snore-loop :var alert :value snore :time 0)"
                 "(:event ev-search :time 0)"
                 "(:op hard-wake :script hard-wake :start 0 :end 3)"
                 "(:op snort :script snort :start 0 :end 1)"
                 "(:op exhale :script exhale :start 1 :end 2)"
                 "(:op focus :script focus :start 2 :end 3)"
                 "(:autoscript-stop snore-loop :var alert :value snore :time 3)"
                 "(:op standup :script standup :start 3 :end 4)"
                 "(:op search :script stream :start 4 :end 6.5)"
                 "(:state (holding-note . t) (posture . stand) (alert . awake) (wing-at-ear . nil) (wearing-phones . nil) (count . 0) (last-heard . nil))"
                 "(:event ev-search :time 6.5)"
                 "(:op drop-note :script drop-note :start 6.5 :end 7.5)"
                 "(:op search :script stream :start 7.5 :end 10)"
                 "(:state (holding-note . t) (posture . stand) (alert . awake) (wing-at-ear . nil) (wearing-phones . nil) (count . 0) (last-heard . nil))")
               (lines out)))))

(test run-reports-failures-in-the-trace
  (multiple-value-bind (out err code)
      (player-command "run" (fixture "mini.lisp") "--initial" "wearing-phones=true" "--events" "ev-search")
    (is (= 0 code))
    (is (string= "" err))
    (is (member "(:fail ev-search :goal stand-noteless :time 0)" (lines out) :test #'string=))))

(defmacro check-cli-error (expected-code fragment &rest arguments)
  "bin/player ARGUMENTS must fail with EXPECTED-CODE and one error line containing FRAGMENT."
  `(multiple-value-bind (out err code) (player-command ,@arguments)
     (declare (ignorable out))
     (is (= ,expected-code code) "exit code ~A for ~S" code (list ,@arguments))
     (is (eql 0 (search "player: error: " err)) "stderr ~S" err)
     (is (search ,fragment err) "stderr ~S lacks ~S" err ,fragment)
     (is (not (search "debugger" err)))
     (is (not (search "Backtrace" err)))))

(test errors-are-one-line-with-status-1
  (check-cli-error 1 "unknown event ev-nope (known events:" "run" (fixture "mini.lisp") "--events" "ev-search,ev-nope")
  (check-cli-error 1 "unreadable.lisp:3: cannot read form" "run" (fixture "unreadable.lisp"))
  (check-cli-error 1 "bad-initial.lisp:5: state-variable x: initial value 3 of boolean x" "check" (fixture "bad-initial.lisp"))
  (check-cli-error 1 "fly is not a value of alert" "run" (fixture "mini.lisp") "--initial" "alert=fly")
  (check-cli-error 1 "unknown variable mood in the initial state" "run" (fixture "mini.lisp") "--initial" "mood=happy")
  (check-cli-error 1 "cannot open spec file" "run" "/nonexistent/spec.lisp"))

(test usage-errors-have-status-2
  (check-cli-error 2 "unknown option --colour for run" "run" (fixture "mini.lisp") "--colour" "red")
  (check-cli-error 2 "unknown command fly" "fly")
  (check-cli-error 2 "run needs a SPEC-FILE" "run")
  (check-cli-error 2 "--initial takes var=value pairs" "run" (fixture "mini.lisp") "--initial" "alert")
  (check-cli-error 2 "defines no spec nope" "run" (fixture "mini.lisp") "--spec" "nope"))

(test run-no-trace-before-an-unknown-event
  (multiple-value-bind (out err code)
      (player-command "run" (fixture "mini.lisp") "--events" "ev-search,ev-nope")
    (declare (ignore err))
    (is (= 1 code))
    (is (not (search "(:event" out)))))

(test plans-and-check-commands
  (multiple-value-bind (out err code) (player-command "plans" (fixture "mini.lisp"))
    (is (= 0 code))
    (is (string= "" err))
    (is (search "goal 1: (and (not holding-note) posture.stand alert.awake (not wing-at-ear) (not wearing-phones))" out))
    (is (search "requested as: stand-noteless" out))
    (is (search "run (hard-wake standup)" out)))
  (multiple-value-bind (out err code) (player-command "check" (fixture "mini.lisp"))
    (is (= 0 code))
    (is (string= "" err))
    (is (search "warning: goal stand-noteless is unreachable from" out))))

(test help-prints-usage
  (multiple-value-bind (out err code) (player-command "help")
    (is (= 0 code))
    (is (string= "" err))
    (is (search "usage: player COMMAND" out))))

;;; The command table: per-command help, consistent exit codes, quiet pipes.

(test every-command-has-help
  (dolist (command player.cli::*commands*)
    (let ((name (player.cli::command-name command)))
      (multiple-value-bind (out err code) (player-command name "--help")
        (is (= 0 code) "~A --help exits ~A" name code)
        (is (string= "" err))
        (is (eql 0 (search (format nil "usage: player ~A" name) out)) "~A --help: ~S" name out)
        (is (search "output: " out) "~A's help says where its output goes" name)
        (dolist (option (player.cli::command-options command))
          (is (search (player.cli::option-name option) out) "~A's help lacks ~A" name
              (player.cli::option-name option))))
      (is (string= (player-command name "--help") (player-command "help" name))
          "help ~A and ~A --help differ" name name)
      (is (search (player.cli::command-summary command) (player-command "help"))
          "the global help lacks ~A" name)))
  (multiple-value-bind (out err code) (player-command "render" "-h")
    (declare (ignore err))
    (is (= 0 code))
    (is (search "--out DIR" out))
    ;; Help wraps its columns: compare with the blanks folded.
    (is (search "(default:render/)" (remove-if (lambda (c) (member c '(#\Space #\Newline))) out)))))

(test wrong-command-lines-exit-2
  (check-cli-error 2 "--fps takes a frame rate above 0 and at most 1000, not \"0\""
                   "render" (fixture "anim.lisp") "--fps" "0")
  (check-cli-error 2 "--size takes WIDTHxHEIGHT" "render" (fixture "anim.lisp") "--size" "0x3")
  (check-cli-error 2 "--size takes WIDTHxHEIGHT" "view" (fixture "anim.lisp") "--size" "big")
  (check-cli-error 2 "--frames takes a positive integer" "view" (fixture "anim.lisp") "--frames" "0")
  (check-cli-error 2 "--seed takes an integer" "simulate" (fixture "anim.lisp") "--seed" "1.5")
  (check-cli-error 2 "--backend takes one of lisp, c++" "run" (fixture "mini.lisp") "--backend" "java")
  (check-cli-error 2 "option --events given twice" "run" (fixture "mini.lisp") "--events" "a" "--events" "b")
  (check-cli-error 2 "option --events needs a value" "run" (fixture "mini.lisp") "--events")
  (check-cli-error 2 "--initial gives alert twice" "run" (fixture "mini.lisp") "--initial" "alert=snore,alert=sleep")
  (check-cli-error 2 "unexpected argument extra" "plans" (fixture "mini.lisp") "extra")
  (check-cli-error 2 "unknown command fly" "help" "fly")
  (check-cli-error 2 "emit-c++ needs --out DIR" "emit-c++" (fixture "mini.lisp"))
  (check-cli-error 2 "no command given" ))

(test failed-work-exits-1
  (check-cli-error 1 "no-spec.lisp defines no spec" "run" (fixture "no-spec.lisp"))
  (check-cli-error 1 "unknown event" "render" (fixture "anim.lisp") "--events" "ev-nope"))

(test option-values-may-follow-an-equals-sign
  (multiple-value-bind (out err code)
      (player-command "run" (fixture "mini.lisp") "--initial=alert=snore" "--events=ev-search")
    (is (= 0 code) "stderr ~S" err)
    (is (search "(:autoscript-start snore-loop" out))))

(test run-without-events-prints-the-initial-state
  (dolist (backend '("lisp" "c++"))
    (multiple-value-bind (out err code)
        (player-command "run" (fixture "mini.lisp") "--initial" "alert=snore" "--backend" backend)
      (is (= 0 code) "~A: ~S" backend err)
      (is (equal '("(:autoscript-start snore-loop :var alert :value snore :time 0)"
                   "(:state (holding-note . nil) (posture . stand) (alert . snore) (wing-at-ear . nil) (wearing-phones . nil) (count . 0) (last-heard . nil))")
                 (lines out))
          "~A backend: ~S" backend out))))

(test a-closed-pipe-ends-quietly
  ;; Thousands of events print far more than a pipe buffers, so player is
  ;; still writing when head has gone.
  (let* ((events (format nil "~{~A~^,~}" (loop repeat 4000 collect "ev-search")))
         (script (format nil "\"$0\" run \"$1\" --initial alert=snore --events \"$2\" 2>\"$3\" | head -n 2; echo \"status ${PIPESTATUS[0]}\""))
         (errors (format nil "/tmp/player-pipe-test-~D.err" (sb-posix:getpid)))
         (out (make-string-output-stream)))
    (sb-ext:run-program "/bin/bash" (list "-c" script (namestring (checkout-file "bin/player"))
                                          (fixture "mini.lisp") events errors)
                        :output out :directory (namestring *root*))
    (let ((printed (lines (get-output-stream-string out))))
      (is (= 3 (length printed)) "~S" printed)
      (is (equal "status 141" (third printed)) "~S" printed))
    (is (string= "" (alexandria:read-file-into-string errors)) "stderr after a closed pipe")
    (delete-file errors)))

(test the-core-is-rebuilt-when-the-checkout-moves
  ;; bin/player keeps the checkout's path beside the core; another path means
  ;; the core's compiled-in paths are wrong, so it must build a new one.
  (player-command "help")
  (let ((stamp (checkout-file "build/player.root")))
    (is (probe-file stamp))
    (with-open-file (out stamp :direction :output :if-exists :supersede)
      (write-line "/somewhere/else" out))
    (multiple-value-bind (out err code) (player-command "help")
      (is (= 0 code))
      (is (search "building Player once" err))
      (is (search "usage: player COMMAND" out)))
    (is (string= (string-right-trim "/" (namestring *root*))
                 (string-trim '(#\Newline) (alexandria:read-file-into-string stamp))))
    (multiple-value-bind (out err code) (player-command "help")
      (declare (ignore out))
      (is (= 0 code))
      (is (string= "" err) "a fresh core is not rebuilt"))))
