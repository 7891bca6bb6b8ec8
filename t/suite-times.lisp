;;;; suite-times.lisp -- `make test-times`: what each top-level suite costs.
;;;;
;;;; Runs the suites of PLAYER-TESTS one at a time, in the order `make test`
;;;; runs them, each under GET-INTERNAL-REAL-TIME, and prints a table of
;;;; seconds and shares of the whole, dearest first, then the usual line
;;;; "N passed, N failed". PLAYER_TIMES_SUITE=NAME (e.g. reachable), or
;;;; several names separated by commas, or "all" (every top-level suite),
;;;; prints the same table for the tests of each of those suites instead.
;;;; PLAYER_TEST_TIER=fast times the fast tier. The times are wall clock: on a
;;;; shared machine, read the shares, not the seconds.
;;;; Loaded after the player/tests system:
;;;;   sbcl ... --load t/suite-times.lisp --eval '(player-tests::suite-times)'

(in-package #:player-tests)

(defun suite-children (suite-name)
  "The names of the tests and suites directly in SUITE-NAME, in the order FiveAM runs them."
  (loop for name being the hash-keys of (fiveam::tests (fiveam::get-test suite-name))
        collect name))

(defun timed-run (test-name)
  "Run TEST-NAME (a test or suite) quietly; return (VALUES SECONDS PASSED FAILED)."
  (let* ((start (get-internal-real-time))
         (results (let ((*test-dribble* (make-broadcast-stream)))
                    (run test-name)))
         (seconds (/ (- (get-internal-real-time) start) internal-time-units-per-second))
         (passed (count-if (lambda (r) (typep r 'fiveam::test-passed)) results)))
    (values seconds passed (- (length results) passed))))

(defun print-times-table (rows total)
  "Print ROWS, lists (NAME SECONDS PASSED FAILED), dearest first, with each one's share of TOTAL seconds."
  (let ((width (reduce #'max rows :key (lambda (row) (length (symbol-name (first row))))
                                  :initial-value 10)))
    (format t "~&~vA ~9@A ~7@A ~8@A~%" width "suite" "seconds" "share" "checks")
    (dolist (row (sort (copy-list rows) #'> :key #'second))
      (destructuring-bind (name seconds passed failed) row
        (format t "~vA ~9,2F ~6,1F% ~8D~:[~; (~D failed)~]~%"
                width (string-downcase name) seconds (* 100 (/ seconds (max total 1/1000)))
                (+ passed failed) (plusp failed) failed)))
    (format t "~vA ~9,2F~%" width "total" total)))

(defun suites-to-time ()
  "The suites PLAYER_TIMES_SUITE names (comma-separated, e.g. \"reachable,fuzz\"),
every top-level suite for \"all\", or (PLAYER-TESTS) when it is unset."
  (let ((names (uiop:getenv "PLAYER_TIMES_SUITE")))
    (cond
      ((null names) (list 'player-tests))
      ((string-equal names "all") (suite-children 'player-tests))
      ((plusp (length names))
        (mapcar (lambda (name) (intern (string-upcase (string-trim " " name)) '#:player-tests))
                (uiop:split-string names :separator ",")))
      (t (list 'player-tests)))))

(defun time-children (suite)
  "Run and time each child of SUITE, print their table; return (VALUES PASSED FAILED)."
  (let ((rows (loop for name in (suite-children suite)
                    collect (multiple-value-bind (seconds passed failed) (timed-run name)
                              (list name (float seconds) passed failed)))))
    (format t "~&~%~(~A~):~%" suite)
    (print-times-table rows (reduce #'+ rows :key #'second))
    (values (reduce #'+ rows :key #'third) (reduce #'+ rows :key #'fourth))))

(defun suite-times (&optional (suites (suites-to-time)))
  "Time each child of each of SUITES (default: PLAYER-TESTS, or the suites
PLAYER_TIMES_SUITE names), print a table per suite and 'N passed, N failed',
and exit 1 when a check failed."
  (format t "~&tier ~(~A~), load average ~A~%" *test-tier* (uiop:read-file-line "/proc/loadavg"))
  (let ((passed 0) (failed 0))
    (dolist (suite suites)
      (multiple-value-bind (p f) (time-children suite)
        (incf passed p)
        (incf failed f)))
    (format t "~&garbage collection: ~,2F s of the run~%"
            (/ sb-ext:*gc-run-time* internal-time-units-per-second))
    (format t "~&~D passed, ~D failed~%" passed failed)
    (uiop:quit (if (zerop failed) 0 1))))
