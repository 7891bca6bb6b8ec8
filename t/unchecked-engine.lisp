;;;; unchecked-engine.lisp -- the timeline suites against the unchecked engine.
;;;; The timed engine compiles checked (safety 1) unless :PLAYER-UNCHECKED-ENGINE
;;;; is in *FEATURES* when it compiles (src/control/timeline/agenda.lisp); the
;;;; benchmarks may build it so.  This script, loaded by `make
;;;; test-unchecked-engine' in an SBCL of its own after bin/load-system.lisp,
;;;; builds Player with the feature and runs the suites of the timed engine on
;;;; it, so both builds stay tested.  ASDF's fasl cache does not key on
;;;; *FEATURES*, so this build's fasls go to build/unchecked-engine/ (below):
;;;; the checked fasls of the usual cache are neither used nor overwritten.

(in-package #:cl-user)

(defparameter *unchecked-engine-suites*
  '("TIMELINE" "TIMELINE-MODEL" "ITEM-POOL" "PLAN-TAPES" "C++-TIMELINE" "ENGINE-SAFETY")
  "The suites (of PLAYER-TESTS) that exercise the timed engine, run unchecked.")

(defun unchecked-engine-output-translations (root)
  "ASDF output translations sending the fasls of the checkout ROOT (a
directory pathname) to ROOT's build/unchecked-engine/, others where they go."
  `(:output-translations
    (,(merge-pathnames "**/*.*" root)
     ,(merge-pathnames "build/unchecked-engine/**/*.*" root))
    :inherit-configuration))

(defun run-unchecked-engine-suites ()
  "Build Player with :PLAYER-UNCHECKED-ENGINE, run *UNCHECKED-ENGINE-SUITES*,
print 'unchecked-engine: N passed, N failed, N skipped' and exit 0 when none failed, 1
otherwise (also when the build did not take the feature)."
  (pushnew :player-unchecked-engine *features*)
  (asdf:initialize-output-translations (unchecked-engine-output-translations (truename "./")))
  (unless (uiop:symbol-call '#:player-build '#:load-checked "player/tests")
    (uiop:quit 1))
  ;; The build must really be the unchecked one, or this run proves nothing.
  (unless (equal (symbol-value (find-symbol "*TIMELINE-OPTIMIZE*" "PLAYER.CONTROL"))
                 '(optimize (speed 1) (safety 0) (debug 0)))
    (format t "~&unchecked-engine: the build did not take :player-unchecked-engine~%")
    (uiop:quit 1))
  (let* ((results (loop for name in *unchecked-engine-suites*
                        append (funcall (find-symbol "RUN" "FIVEAM") (find-symbol name "PLAYER-TESTS"))))
         (passed (count-if (lambda (result) (typep result (find-symbol "TEST-PASSED" "FIVEAM"))) results))
         ;; Skipped: the checks only the checked engine makes (test-engine-safety.lisp).
         (skipped (count-if (lambda (result) (typep result (find-symbol "TEST-SKIPPED" "FIVEAM"))) results))
         (failures (remove-if (lambda (result)
                                (typep result `(or ,(find-symbol "TEST-PASSED" "FIVEAM")
                                                   ,(find-symbol "TEST-SKIPPED" "FIVEAM"))))
                              results)))
    (when failures
      (funcall (find-symbol "EXPLAIN!" "FIVEAM") failures))
    ;; Skipped: the checks only the checked engine makes.  `make test` runs this
    ;; before the full suite, whose line is the last one it prints.
    (format t "~&unchecked-engine: ~D passed, ~D failed, ~D skipped~%" passed (length failures) skipped)
    (finish-output)
    (uiop:quit (if failures 1 0))))
