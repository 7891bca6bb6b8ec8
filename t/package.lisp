;;;; package.lisp -- the test package, the root suite and the runner `make test` uses.
;;;;
;;;; Two tiers run the same suites:
;;;;   full  `make test`, the one the README and .ci/run use: every check at its
;;;;         full size. PLAYER_TEST_TIER unset (or "full").
;;;;   fast  `make test-fast` (PLAYER_TEST_TIER=fast), for a contributor between
;;;;         edits: every suite and every test still runs, but the heavy sweeps
;;;;         (random seeds, specs, streams, fuzz cases) play a sample, chosen by
;;;;         SWEEP-COUNT and SWEEP-SAMPLE below. A sweep sampled in the fast tier
;;;;         asks the same questions of fewer cases; it proves less, so run
;;;;         `make test` before a commit. One single check is left out of the
;;;;         fast tier, with a comment saying why (C++-TIMED-ERRORS' 5 s run).
;;;; The tier is read once, when the tests are loaded (*TEST-TIER*), so a sweep
;;;; whose cases are a DEFPARAMETER takes its size then. A sweep that builds C++
;;;; builds in the fast tier nothing the full tier does not (it samples the runs
;;;; played on a shared program, or the specs built one program each), so both
;;;; tiers share the compiled programs in the C++ cache. `make test-times` prints
;;;; what each suite costs (t/suite-times.lisp).

(defpackage #:player-tests
  (:use #:cl #:player #:fiveam)
  (:export #:run-tests-and-report #:*last-run-failed*))

(in-package #:player-tests)

(def-suite player-tests :description "Every test of Player.")

(defvar *last-run-failed* nil
  "True when the last RUN-TESTS-AND-REPORT saw a failure; the Makefile exits 1 on it.")

(defun tier-from-environment ()
  "The tier PLAYER_TEST_TIER names: :FAST for \"fast\", :FULL when unset or empty.
Any other value is an error, so a typo cannot quietly run the wrong tier."
  (let ((name (uiop:getenv "PLAYER_TEST_TIER")))
    (cond ((or (null name) (string= name "") (string-equal name "full")) :full)
          ((string-equal name "fast") :fast)
          (t (error "PLAYER_TEST_TIER is ~S; it must be fast or full." name)))))

(defvar *test-tier* (tier-from-environment)
  "The tier of this run, :FULL (`make test`) or :FAST (`make test-fast`); see the
top of this file. Read from PLAYER_TEST_TIER when the tests are loaded.")

(defun sweep-count (full fast)
  "FULL in the full tier, FAST in the fast one: the size of a heavy sweep (how
many seeds, cases, streams or rounds), or its stride. Both positive integers."
  (check-type full (integer 1))
  (check-type fast (integer 1))
  (if (eq *test-tier* :fast) fast full))

(defun sweep-sample (cases fast)
  "CASES (a list) in the full tier; in the fast one, FAST of them spread evenly
from the first to the last, so a sample still meets every family of a sweep
whose cases come in runs (seeds with one set of options, then another)."
  (check-type fast (integer 1))
  (let ((count (length cases)))
    (if (or (eq *test-tier* :full) (<= count fast))
        cases
        (loop for i below fast
              collect (nth (floor (* i (1- count)) (max 1 (1- fast))) cases)))))

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
  "Define a throwaway spec NAME from BODY-FORMS, bind VAR to it, run BODY, forget it.
VAR is ignorable: a test may want the spec defined without reading it."
  `(let ((,var (define-spec ',name ',body-forms :package (find-package '#:player-tests))))
     (declare (ignorable ,var))
     (unwind-protect (progn ,@body)
       (remove-spec ',name))))

(defun trace-of (controller)
  "The trace lines of CONTROLLER's trace presenter, as printed text."
  (mapcar #'trace-line-string (trace-lines (controller-presenter controller))))
