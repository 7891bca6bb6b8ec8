;;;; fuzz-minimize.lisp -- shrinking a failing fuzz case to a small
;;;; reproducer (see fuzz.lisp).

(in-package #:player-tests)

;;; ---------------------------------------------------------------------------
;;; Minimizing a reproducer

(defun fz-failure-labels (result)
  "The labels FZ-FAILURE-GROUPS files RESULT under (none when it passed)."
  (mapcar #'first (fz-failure-groups (list result))))

(defun fz-balanced-spans (text &key (limit 3000) (max-depth most-positive-fixnum))
  "The (START . END) spans of TEXT's parenthesised forms no deeper than
MAX-DEPTH (0 is the top level), the longest first (at most LIMIT of them).
Strings, |symbols|, comments and #\\( are skipped; the scan keeps its own
stack, so any nesting is fine."
  (let ((spans '()) (open '()) (i 0) (n (length text)))
    (flet ((skip-to (close)
             (loop (incf i)
                   (when (>= i n) (return))
                   (let ((c (char text i)))
                     (cond ((char= c #\\) (incf i))
                           ((char= c close) (return)))))))
      (loop while (< i n)
            do (let ((c (char text i)))
                 (case c
                   (#\( (push i open))
                   (#\) (when open
                          (let ((start (pop open)))
                            (when (<= (length open) max-depth)
                              (push (cons start (1+ i)) spans)))))
                   (#\" (skip-to #\"))
                   (#\| (skip-to #\|))
                   (#\; (setf i (or (position #\Newline text :start i) n)))
                   (#\\ (incf i))
                   (#\# (when (and (< (1+ i) n) (char= (char text (1+ i)) #\\)) (incf i 2)))))
               (incf i)))
    (let ((sorted (sort spans #'> :key (lambda (span) (- (cdr span) (car span))))))
      (subseq sorted 0 (min limit (length sorted))))))

(defun fz-longest-run (text &key (minimum 16))
  "(START . END) of the longest run of one repeated character in TEXT, if at least MINIMUM long."
  (let ((best nil) (best-length (1- minimum)) (i 0) (n (length text)))
    (loop while (< i n)
          do (let ((end (or (position (char text i) text :start i :test-not #'char=) n)))
               (when (> (- end i) best-length)
                 (setf best (cons i end) best-length (- end i)))
               (setf i end)))
    best))

(defun fz-try-text (run case text)
  "The FZ-RESULT of CASE with TEXT in place of its own, run in a forked child."
  (let ((variant (copy-fz-case case)) (result nil))
    (setf (fzc-text variant) text)
    (fz-run-forked run (lambda (index) (declare (ignore index)) variant) 0 1
                   (lambda (r) (setf result r)))
    result))

(defun fz-minimize (case label &key (tries 400) (seconds 60) (timeout 10))
  "A smaller text on which CASE (a file-mode case) still fails with LABEL (as
FZ-FAILURE-LABELS names it): balanced forms, the longest first, then lines, are
deleted while the failure stays. At most TRIES runs and about SECONDS.
Returns the text and the number of runs."
  (let ((run (fz-open-run :timeout timeout :emit-every 1 :play-every 1))
        (text (fzc-text case))
        (count 0)
        (deadline (+ (get-internal-real-time) (* seconds internal-time-units-per-second))))
    (flet ((budget-left-p ()
             (and (< count tries) (< (get-internal-real-time) deadline)))
           (still-fails-p (candidate)
             (incf count)
             (member label (fz-failure-labels (fz-try-text run case candidate)) :test #'string=)))
      (unwind-protect
           (progn
             ;; Whole forms, the longest first; after each success the spans
             ;; are found again, and those longer than the one just deleted
             ;; (all tried already) are skipped.
             (dotimes (pass 2)                 ; the second pass without skipping
               (loop with progress = t and longest = most-positive-fixnum
                     while (and progress (budget-left-p))
                     do (setf progress nil)
                        (loop for (start . end) in (fz-balanced-spans text :max-depth 8)
                              while (budget-left-p)
                              when (or (= pass 1) (<= (- end start) longest))
                                do (let ((candidate (concatenate 'string (subseq text 0 start) (subseq text end))))
                                     (when (still-fails-p candidate)
                                       (setf text candidate progress t longest (- end start))
                                       (return))))))
             ;; The longest run of one character (15,000 backquotes): bisect
             ;; its length down to about the shortest that still fails.
             (let ((run (fz-longest-run text)))
               (when run
                 (destructuring-bind (start . end) run
                   (let ((short 0) (long (- end start)))
                     (flet ((with-length (k)
                              (concatenate 'string (subseq text 0 (+ start k)) (subseq text end))))
                       (loop while (and (> (- long short) (max 1 (floor long 50))) (budget-left-p))
                             do (let ((middle (floor (+ short long) 2)))
                                  (if (still-fails-p (with-length middle))
                                      (setf long middle)
                                      (setf short middle))))
                       (setf text (with-length long)))))))
             ;; Then single lines, from the end.
             (let ((lines (fz-split-lines text)))
               (loop for i from (1- (length lines)) downto 0
                     while (budget-left-p)
                     do (let ((candidate (format nil "~{~A~^~%~}" (append (subseq lines 0 i) (subseq lines (1+ i))))))
                          (when (still-fails-p candidate)
                            (setf lines (append (subseq lines 0 i) (subseq lines (1+ i)))
                                  text candidate))))))
        (fz-close-run run)))
    (values text count)))

(defun fuzz-minimize (seed index &key label (tries 400) (seconds 60))
  "Minimize case INDEX of SEED: the smallest text found that fails as it does
(with LABEL, by default its first failure label). Returns the text (with
@MARKER@ standing for the marker file), the label and the number of runs."
  (fz-prepare)
  (let* ((case (fz-generate seed index))
         (label (or label (first (fz-failure-labels (fuzz-case seed index))))))
    (cond ((null (fzc-text case)) (values nil label 0))
          ((null label) (values (fzc-text case) nil 0))
          (t (multiple-value-bind (text count) (fz-minimize case label :tries tries :seconds seconds)
               (values text label count))))))
