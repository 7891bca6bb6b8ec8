;;;; test-polish-code.lisp -- a :code form the compiler warns of (an undefined
;;;; function, a call with the wrong arguments) is one error naming its file,
;;;; line and form, from `check` before anything runs and from `run` when the
;;;; event comes (src/control/code-forms.lisp); clean code still runs.

(in-package #:player-tests)

(def-suite* polish-code :in player-tests)

(defun write-code-spec (directory name text)
  "Write a spec file NAME.lisp in DIRECTORY holding (in-package :player-user)
and TEXT; return its path as a string."
  (let ((path (merge-pathnames (format nil "~A.lisp" name) directory)))
    (with-open-file (out path :direction :output :if-exists :supersede)
      (format out "(in-package :player-user)~%~A~%" text))
    (namestring path)))

(defparameter *undefined-in-event* "(defspec undef \"Calls a function nobody defined.\"
  (state-variable done boolean false)
  (op finish :add done :duration 1)
  (event ev-go
    :code (no-such-function 1 2)
    :op finish))"
  "A spec whose event's :code, on line 6 of its file, calls an undefined function.")

(defparameter *undefined-in-op* "(defspec oper \"An op whose code calls a function nobody defined.\"
  (state-variable done boolean false)
  (op finish :code (other-missing-function) :add done :duration 1)
  (event ev-go :op finish))"
  "A spec whose op's :code, on line 4 of its file, calls an undefined function.")

(defparameter *wrong-arguments* "(defspec wrong \"Calls CAR with two arguments.\"
  (state-variable done boolean false)
  (op finish :add done :duration 1)
  (event ev-go
    :if ((not done)
         :code (car '(1) 2))
    :op finish))"
  "A spec whose event's :code, inside an :if on line 7, calls CAR with two arguments.")

(defun nonblank-lines (text)
  "TEXT's lines that are not empty."
  (remove "" (uiop:split-string text :separator '(#\Newline)) :test #'string=))

(defun check-code-error-line (text expected)
  "Check TEXT (stderr) is one `player: error:` line holding EXPECTED."
  (let ((lines (nonblank-lines text)))
    (is (= 1 (length lines)) "not one line: ~S" lines)
    (is (eql 0 (search "player: error: " (first lines))) "~A" text)
    (is (search expected text) "~S lacks ~S" text expected)))

(test check-reports-undefined-functions-in-code-at-their-line
  (with-temporary-directory (dir)
    (loop for (name text expected)
            in `(("undef" ,*undefined-in-event*
                  "error: undef.lisp:6: event ev-go: :code calls the undefined function no-such-function in (no-such-function 1 2)")
                 ("oper" ,*undefined-in-op*
                  "error: oper.lisp:4: op finish: :code calls the undefined function other-missing-function")
                 ("wrong" ,*wrong-arguments*
                  "error: wrong.lisp:7: event ev-go: :code does not compile: The function CAR is called with two arguments"))
          do (multiple-value-bind (out err code) (player-command "check" (write-code-spec dir name text))
               (is (= 1 code) "check ~A: exit ~D: ~A" name code err)
               (is (search expected out) "check ~A printed ~S, not ~S" name out expected)
               (check-code-error-line err "check found 1 error")))))

(test run-reports-undefined-functions-in-code-at-their-line
  (with-temporary-directory (dir)
    (loop for (name text expected)
            in `(("undef" ,*undefined-in-event*
                  "player: error: undef.lisp:6: event ev-go: :code calls the undefined function no-such-function in (no-such-function 1 2)")
                 ("oper" ,*undefined-in-op*
                  "player: error: oper.lisp:4: op finish: :code calls the undefined function other-missing-function"))
          do (multiple-value-bind (out err code) (player-command "run" (write-code-spec dir name text) "--events" "ev-go")
               (is (= 1 code) "run ~A: exit ~D: ~A" name code err)
               (is (search "(:event ev-go :time 0)" out) "~A" out)
               (check-code-error-line err expected)))))

(test clean-code-checks-and-runs
  "Code calling defined functions, and the Lisp API, draws no diagnostic and runs."
  (with-temporary-directory (dir)
    (let ((path (write-code-spec dir "clean" "(defspec clean \"Clean code.\"
  (state-variable done boolean false)
  (op finish :code (list 1 2) :add done :duration 1)
  (event ev-go :code (state-value *controller* 'done) :op finish))")))
      (multiple-value-bind (out err code) (player-command "check" path)
        (is (= 0 code) "exit ~D: ~A" code err)
        (is (search "clean: no problems found" out) "~A" out))
      (multiple-value-bind (out err code) (player-command "run" path "--events" "ev-go")
        (is (= 0 code) "exit ~D: ~A" code err)
        (is (search "(:op finish" out) "~A" out)))))

(test code-errors-from-lisp-name-the-form
  "From Lisp, a spec defined without a file: the CODE-ERROR still names the
spec, the form and the undefined function when the event runs."
  (let* ((spec (player:define-spec 'polish-undef '((state-variable done boolean false)
                                                   (op finish :add done :duration 1)
                                                   (event ev-go :code (polish-no-such-function) :op finish))))
         (controller (player:make-controller spec)))
    (unwind-protect
         (handler-case (progn (player:send-event controller 'ev-go)
                              (fail "no error for the undefined function"))
           (player:code-error (condition)
             (let ((text (princ-to-string condition)))
               (is (search "polish-no-such-function" text) "~A" text)
               (is (search "event ev-go" text) "~A" text))))
      (player:remove-spec 'polish-undef))))

(defparameter *signalling-code* "(defspec boom \"Code that signals an error when it runs.\"
  (state-variable done boolean false)
  (op finish :add done :duration 1)
  (event ev-go
    :code (error \"the jukebox is ~A\" 'jammed)
    :op finish))"
  "A spec whose event's :code, on line 6 of its file, signals an error when it runs.")

(test run-time-errors-in-code-name-their-line
  "An error the code signals as it runs is one line naming the code's file and
line, and what it signalled."
  (with-temporary-directory (dir)
    (multiple-value-bind (out err code) (player-command "run" (write-code-spec dir "boom" *signalling-code*)
                                                        "--events" "ev-go")
      (is (= 1 code) "exit ~D: ~A" code err)
      (is (search "(:event ev-go :time 0)" out) "~A" out)
      (check-code-error-line err "player: error: boom.lisp:6: event ev-go: :code signalled an error: the jukebox is JAMMED"))))

(test run-time-errors-in-code-reach-the-caller-unchanged
  "From Lisp the code's own condition arrives as it was signalled (a handler
for it still works); only its one-line report names the code's place."
  (let* ((spec (player:define-spec 'polish-boom '((state-variable done boolean false)
                                                  (op finish :add done :duration 1)
                                                  (event ev-go :code (error 'division-by-zero) :op finish))))
         (controller (player:make-controller spec)))
    (unwind-protect
         (handler-case (progn (player:send-event controller 'ev-go)
                              (fail "no error from the code"))
           (division-by-zero (condition)
             (let ((line (player.base:condition-line condition)))
               (is (search "event ev-go: :code signalled an error: " line) "~A" line)
               (is (search "division-by-zero" line) "~A" line))))
      (player:remove-spec 'polish-boom))))
