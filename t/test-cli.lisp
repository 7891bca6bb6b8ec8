;;;; test-cli.lisp -- bin/player as a user runs it: output, errors, exit codes.

(in-package #:player-tests)

(def-suite* cli :in player-tests)

(defun player-command (&rest arguments)
  "Run bin/player with ARGUMENTS; return (VALUES STDOUT STDERR EXIT-CODE)."
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
  (check-cli-error 1 "bad-initial.lisp:4: in spec bad-initial: initial value 3 of boolean x" "check" (fixture "bad-initial.lisp"))
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
