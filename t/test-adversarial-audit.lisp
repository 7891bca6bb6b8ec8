;;;; test-adversarial-audit.lisp -- issue 31, item 8 audited: causes of the
;;;; issue's "Why" that had no child-process test with their one error line
;;;; and a time and memory bound, starting with the exact-macro proof's
;;;; budget (item 3).  Runs bin/player through FZB-RUN (fuzz-bounds.lisp),
;;;; which reports the time and the peak resident memory.

(in-package #:player-tests)

(def-suite* adversarial-audit :in player-tests)

(defun bounded-case (files arguments &key input)
  "Run bin/player ARGUMENTS in a fresh folder holding FILES (an alist of a
name to its text): (VALUES EXIT STDERR SECONDS MEGABYTES)."
  (let ((directory (format nil "/tmp/player-audit-~D-~D/" (sb-posix:getpid) (incf *scratch-counter*))))
    (ensure-directories-exist directory)
    (unwind-protect
         (progn
           (loop for (name . text) in files
                 do (alexandria:write-string-into-file text (concatenate 'string directory name)
                                                       :if-exists :supersede :external-format :utf-8))
           (fzb-run arguments directory input))
      (uiop:delete-directory-tree (pathname directory) :validate t :if-does-not-exist :ignore))))

(defmacro check-bounded-case ((exit fragment &key (seconds 5) (megabytes 1024)) files &rest arguments)
  "bin/player ARGUMENTS, in a folder holding FILES, ends with EXIT within
SECONDS and MEGABYTES, its stderr one player: error: line holding FRAGMENT
(or empty when FRAGMENT is NIL)."
  `(multiple-value-bind (code stderr seconds megabytes) (bounded-case ,files (list ,@arguments))
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
