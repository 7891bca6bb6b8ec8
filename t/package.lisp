;;;; package.lisp -- the test package, the root suite and the runner `make test` uses.

(defpackage #:player-tests
  (:use #:cl #:player #:fiveam)
  (:export #:run-tests-and-report #:*last-run-failed*))

(in-package #:player-tests)

(def-suite player-tests :description "Every test of Player.")

(defvar *last-run-failed* nil
  "True when the last RUN-TESTS-AND-REPORT saw a failure; the Makefile exits 1 on it.")

(defparameter *root* (asdf:system-source-directory "player")
  "The checkout the tests run from.")

(defun checkout-file (relative)
  "RELATIVE (a string) as a pathname inside the checkout."
  (merge-pathnames relative *root*))

(defun run-tests-and-report ()
  "Run every test, explain the failures, and end with the line 'N passed, N failed'."
  (let* ((results (let ((*standard-output* *standard-output*))
                    (run 'player-tests)))
         (passed (count-if (lambda (r) (typep r 'fiveam::test-passed)) results))
         (failed (- (length results) passed)))
    (when (plusp failed)
      (explain! (remove-if (lambda (r) (typep r 'fiveam::test-passed)) results)))
    (setf *last-run-failed* (plusp failed))
    (format t "~&~D passed, ~D failed~%" passed failed)
    (zerop failed)))

(defmacro with-spec ((var name &rest body-forms) &body body)
  "Define a throwaway spec NAME from BODY-FORMS, bind VAR to it, run BODY, forget it."
  `(let ((,var (define-spec ',name ',body-forms :package (find-package '#:player-tests))))
     (unwind-protect (progn ,@body)
       (remove-spec ',name))))

(defun trace-of (controller)
  "The trace lines of CONTROLLER's trace presenter, as printed text."
  (mapcar #'trace-line-string (trace-lines (controller-presenter controller))))
