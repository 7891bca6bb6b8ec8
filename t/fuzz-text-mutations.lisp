;;;; fuzz-text-mutations.lisp -- the fuzzer's mutations of a file's text, and
;;;; how a case is generated from a seed and a case number (see fuzz.lisp).

(in-package #:player-tests)

;;; ---------------------------------------------------------------------------
;;; Text mutations

(defparameter *fz-text-kinds*
  '((7 . :text-delete) (5 . :text-duplicate) (4 . :text-swap-lines) (6 . :unbalance) (4 . :stray-dot)
    (8 . :reader-macro) (6 . :read-eval) (7 . :number-token) (5 . :unicode-token) (4 . :long-token)
    (6 . :c++-token) (4 . :control-char) (4 . :invalid-utf8) (3 . :truncate) (4 . :deep-text)
    (7 . :toplevel) (2 . :bom))
  "Text mutation kinds and their weights.")

(defun fz-token-char-p (char)
  "Can CHAR be part of a plain symbol token?"
  (or (alphanumericp char) (find char "-.*+<>=/?!%&$_~^")))

(defun fz-boundary (prng text)
  "A position in TEXT at the end of a token (before whitespace or a closing
parenthesis), where a new token can go."
  (let* ((n (length text))
         (p (fz-below prng (1+ n))))
    (or (position-if (lambda (c) (member c '(#\Space #\Newline #\)))) text :start (min p n)) n)))

(defun fz-insert (text position insertion)
  "TEXT with INSERTION at POSITION."
  (concatenate 'string (subseq text 0 position) insertion (subseq text position)))

(defun fz-symbol-tokens (text)
  "The distinct plain symbol tokens of TEXT (outside comments, roughly)."
  (let ((tokens (make-hash-table :test 'equal)) (i 0) (n (length text)))
    (loop while (< i n)
          do (let ((c (char text i)))
               (cond ((char= c #\;) (setf i (or (position #\Newline text :start i) n)))
                     ((char= c #\") (setf i (1+ (or (position #\" text :start (1+ i)) n))))
                     ((char= c #\|) (setf i (1+ (or (position #\| text :start (1+ i)) n))))
                     ((and (alpha-char-p c)
                           (or (zerop i) (find (char text (1- i)) '(#\Space #\( #\Newline #\Tab))))
                      (let ((end (or (position-if-not #'fz-token-char-p text :start i) n)))
                        (setf (gethash (subseq text i end) tokens) t)
                        (setf i end)))
                     (t (incf i)))))
    (sort (alexandria:hash-table-keys tokens) #'string<)))

(defparameter *fz-max-growth* 300000
  "How many characters one rename may add to a text (a 10,000-character name
put in a thousand places would otherwise make a 10-million-character file).")

(defun fz-replace-token (text old new)
  "TEXT with the whole-token occurrences of OLD replaced by NEW: all of them,
unless that would grow TEXT by more than *FZ-MAX-GROWTH* characters."
  (with-output-to-string (out)
    (loop with start = 0 and n = (length text)
          with budget = (max 1 (floor *fz-max-growth* (max 1 (- (length new) (length old)))))
          for hit = (and (plusp budget) (search old text :start2 start :test #'char-equal))
          do (cond ((null hit) (write-string text out :start start) (return))
                   ((and (or (zerop hit) (not (fz-token-char-p (char text (1- hit)))))
                         (or (= (+ hit (length old)) n) (not (fz-token-char-p (char text (+ hit (length old)))))))
                    (write-string text out :start start :end hit) (write-string new out)
                    (decf budget)
                    (setf start (+ hit (length old))))
                   (t (write-string text out :start start :end (1+ hit)) (setf start (1+ hit)))))))

(defun fz-split-lines (text)
  "TEXT's lines."
  (loop for start = 0 then (1+ end)
        for end = (or (position #\Newline text :start start) (length text))
        collect (subseq text start end)
        while (< end (length text))))

(defun fz-symbol-text (name)
  "NAME as the text of a symbol, |escaped| as the printer does."
  (let ((*package* (find-package '#:player-user)) (*print-case* :downcase))
    (prin1-to-string (intern name '#:player-user))))

(defun fz-raw-bytes (octets)
  "Stand-in characters for OCTETS: FZ-WRITE-CASE-FILE writes each as that raw byte."
  (map 'string (lambda (octet) (code-char (+ #xE000 octet))) octets))

(defun fz-mutate-text (prng text kind target)
  "Apply text mutation KIND to TEXT. Returns (VALUES NEW-TEXT NOTE)."
  (let ((n (length text)))
    (flet ((at-boundary (insertion what)
             (let ((p (fz-boundary prng text)))
               (values (fz-insert text p (format nil " ~A " insertion))
                       (format nil "inserted ~A ~A at ~D" what (fz-bounded-text insertion :limit 80) p)))))
      (ecase kind
        (:text-delete (if (and (plusp n) (fz-chance prng 0.3))
                          (let* ((start (or (position #\Newline text :end (fz-below prng n) :from-end t) 0))
                                 (end (or (position #\Newline text :start (1+ start)) n)))
                            (values (concatenate 'string (subseq text 0 start) (subseq text end))
                                    (format nil "deleted the line at ~D" start)))
                          (let* ((start (fz-below prng (max 1 n)))
                                 (end (min n (+ start (fz-pick prng '(1 1 2 3 10 40 200))))))
                            (values (concatenate 'string (subseq text 0 start) (subseq text end))
                                    (format nil "deleted ~S at ~D" (fz-visible (subseq text start end)) start)))))
        (:text-duplicate (let* ((start (fz-below prng (max 1 n)))
                                (end (min n (+ start (fz-pick prng '(1 2 5 20 80 300))))))
                           (values (fz-insert text end (subseq text start end))
                                   (format nil "duplicated ~S at ~D" (fz-bounded-text (subseq text start end) :limit 60) start))))
        (:text-swap-lines (let* ((lines (coerce (fz-split-lines text) 'vector))
                                 (a (fz-below prng (length lines))) (b (fz-below prng (length lines))))
                            (when (plusp (length lines)) (rotatef (aref lines a) (aref lines b)))
                            (values (format nil "~{~A~^~%~}" (coerce lines 'list)) (format nil "swapped lines ~D and ~D" (1+ a) (1+ b)))))
        (:unbalance (let ((choice (fz-below prng 5)) (p (fz-below prng (1+ n))))
                      (case choice
                        (0 (values (fz-insert text p "(") (format nil "inserted ( at ~D" p)))
                        (1 (values (fz-insert text p ")") (format nil "inserted ) at ~D" p)))
                        (2 (let ((q (position-if (lambda (c) (find c "()")) text :start (min p n))))
                             (if q
                                 (values (concatenate 'string (subseq text 0 q) (subseq text (1+ q)))
                                         (format nil "deleted the ~C at ~D" (char text q) q))
                                 (values (concatenate 'string text "(((") "appended ((("))))
                        (3 (values (concatenate 'string text (fz-pick prng '("(((" "(" "(defspec" "#(" "\"" "|" "#|")))
                                   "appended an unclosed form"))
                        (t (values (concatenate 'string ")" text) "prepended )")))))
        (:stray-dot (at-boundary (fz-pick prng '("." ". ." "..." "(. x)" "(x .)" "(x . y z)" "( . )" ".5." "'." "(x . . y)" ". ;"))
                                 "a stray dot"))
        (:reader-macro (at-boundary (fz-pick prng *fz-reader-macros*) "reader syntax"))
        (:read-eval (at-boundary (fz-pick prng (fz-read-eval-payloads)) "the #. payload"))
        (:number-token (at-boundary (if (fz-chance prng 0.35) (fz-huge-integer-text prng) (fz-pick prng *fz-number-tokens*))
                                    "the number"))
        (:unicode-token (let ((tokens (fz-symbol-tokens text)))
                          (if (and tokens (fz-chance prng 0.6))
                              (let ((old (fz-pick prng tokens)) (new (fz-pick prng *fz-unicode-names*)))
                                (values (fz-replace-token text old new) (format nil "renamed ~A to ~A" old (fz-visible new))))
                              (at-boundary (fz-pick prng *fz-unicode-names*) "the unicode token"))))
        (:long-token (let ((tokens (fz-symbol-tokens text)))
                       (if (and tokens (fz-chance prng 0.6))
                           (let ((old (fz-pick prng tokens)) (new (fz-symbol-text (fz-long-name prng))))
                             (values (fz-replace-token text old new) (format nil "renamed ~A to a 10,000-character name" old)))
                           (at-boundary (fz-pick prng (list (fz-symbol-text (fz-long-name prng))
                                                            (format nil "~S" (make-string 10000 :initial-element #\s))))
                                        "the 10,000-character token"))))
        (:c++-token (let ((tokens (fz-symbol-tokens text)))
                      (if (and tokens (fz-chance prng 0.8))
                          (let ((old (fz-pick prng tokens)) (new (fz-symbol-text (fz-pick prng *fz-c++-hostile-names*))))
                            (values (fz-replace-token text old new) (format nil "renamed ~A to ~A" old (fz-visible new))))
                          (at-boundary (fz-symbol-text (fz-pick prng *fz-c++-hostile-names*)) "the C++-hostile name"))))
        (:control-char (let ((p (fz-below prng (1+ n)))
                             (c (fz-pick prng (list (code-char 0) (code-char 127) (code-char 26) #\Return #\Page
                                                    (code-char 11) (code-char #x2028) (code-char #xA0)
                                                    (code-char #xFEFF) (code-char #x200B) (code-char #x85)))))
                         (values (fz-insert text p (string c)) (format nil "inserted ~A at ~D" (fz-visible (string c)) p))))
        (:invalid-utf8 (let ((p (fz-below prng (1+ n)))
                             (bytes (fz-pick prng '((#xFF) (#xC3) (#xE2 #x82) (#xED #xA0 #x80) (#xC0 #xAF)
                                                   (#xF5 #x80 #x80 #x80) (#x80) (#xFE #xFF)))))
                         (values (fz-insert text p (fz-raw-bytes bytes))
                                 (format nil "inserted the bytes ~{~2,'0X~^ ~} at ~D" bytes p))))
        (:truncate (let ((p (fz-below prng (max 1 n))))
                     (values (subseq text 0 p) (format nil "cut the text at ~D of ~D" p n))))
        (:deep-text (let ((kind (fz-pick prng '(:not :not :list :and :vector :quote :backquote)))
                          (depth (fz-pick prng *fz-depths*)))
                      (let ((p (let ((q (search ":precond " text :start2 (fz-below prng (1+ n)))))
                                 (if (and q (fz-chance prng 0.6)) (+ q 9) (fz-boundary prng text)))))
                        (values (fz-insert text p (concatenate 'string (fz-deep-text kind depth "x") " "))
                                (format nil "inserted ~(~A~) nesting ~D deep at ~D" kind depth p)))))
        (:toplevel (let* ((payload (fz-pick prng (fz-toplevel-payloads target)))
                          (starts (loop for i from 1 below n
                                        when (and (char= (char text i) #\() (char= (char text (1- i)) #\Newline))
                                          collect i))
                          (p (if (and starts (fz-chance prng 0.7)) (fz-pick prng starts) n)))
                     (values (fz-insert text p (format nil "~%~A~%" payload))
                             (format nil "added the top-level form ~A at ~D" (fz-visible payload) p))))
        (:bom (values (concatenate 'string (string (code-char #xFEFF)) text) "prepended a byte-order mark"))))))

;;; ---------------------------------------------------------------------------
;;; Generating a case

(defparameter *fz-spec-base-weights*
  '((14 . "peedy") (10 . "mini") (5 . "anim") (2 . "anim-missing") (2 . "bad-initial")
    (2 . "no-spec") (2 . "unreadable") (18 . :random))
  "How often each spec base is chosen.")

(defun fz-generate (seed index &key modes (library-probability 0.25))
  "Case INDEX of SEED, an FZ-CASE: the same case every time. MODES restricts
the modes (the CLI cases use only file modes)."
  (let* ((prng (make-fz-prng seed index #x66757A7A))
         (target (if (fz-chance prng library-probability) :library :spec))
         (base (if (eq target :library)
                   (fz-base (fz-pick prng (mapcar #'first *fz-library-files*)))
                   (let ((choice (fz-weighted prng *fz-spec-base-weights*)))
                     (if (eq choice :random) (fz-random-base prng) (fz-base choice)))))
         (mode (let ((mode (fz-weighted prng '((40 . :text) (38 . :form-file) (22 . :memory)))))
                 (cond ((null (fzb-forms base)) :text)     ; unreadable and no-spec: text only
                       ((and modes (not (member mode modes))) (first modes))
                       ((and (eq mode :memory) (eq target :spec)
                             (not (find-if #'fz-defspec-form-p (fzb-forms base))))
                        :text)
                       (t mode))))
         (count (fz-weighted prng '((50 . 1) (30 . 2) (14 . 3) (6 . 4))))
         (case (make-fz-case :seed seed :index index :target target :mode mode :base (fzb-name base)
                             :companion (fzb-companion base) :events (fzb-events base))))
    (if (eq mode :text)
        (let ((text (fzb-text base)) (kinds '()) (notes '()))
          (setf (fzc-base-text case) text)
          (loop repeat count
                do (let ((kind (fz-weighted prng *fz-text-kinds*)))
                     (multiple-value-bind (new note) (fz-mutate-text prng text kind target)
                       (setf text new) (push kind kinds) (push note notes))))
          (setf (fzc-text case) text (fzc-kinds case) (nreverse kinds) (fzc-notes case) (nreverse notes)))
        (let* ((memory-p (eq mode :memory))
               (forms (copy-tree (fzb-forms base)))
               (holder (fz-holder (if (and memory-p (eq target :spec))
                                       ;; (NAME . BODY) of the first defspec.
                                       (rest (find-if #'fz-defspec-form-p forms))
                                       forms)))
               (kinds (loop repeat count
                            collect (let ((kind (fz-weighted prng *fz-form-kinds*)))
                                      (if (and memory-p (member kind '(:reader-macro :read-eval :toplevel)))
                                          (if (eq kind :reader-macro) :special-float :wrong-type)
                                          kind))))
               ;; Late kinds last, each at most once, so deep or circular structure is made last.
               (kinds (append (remove-if (lambda (k) (member k *fz-late-kinds*)) kinds)
                              (remove-duplicates (remove-if-not (lambda (k) (member k *fz-late-kinds*)) kinds)
                                                 :from-end t)))
               (kinds (if (and (member :circular kinds) (member :deep kinds)) (remove :deep kinds) kinds))
               (splices '()) (notes '()))
          (dolist (kind kinds)
            (multiple-value-bind (note new-splices) (fz-mutate-forms prng holder kind memory-p target splices)
              (setf splices new-splices)
              (push (or note (format nil "~(~A~): no site" kind)) notes)))
          (setf (fzc-kinds case) kinds (fzc-notes case) (nreverse notes))
          (if memory-p
              (setf (fzc-forms case) (cdr holder))
              (setf (fzc-base-text case) (or (fzb-printed base)
                                             (setf (fzb-printed base) (fz-print-forms (fzb-forms base) '())))
                    (fzc-text case) (fz-print-forms (cdr holder) splices)))))
    case))

(defun fz-defspec-form-p (form)
  "Is FORM (defspec NAME ...)?"
  (and (consp form) (symbolp (car form)) (string= (symbol-name (car form)) "DEFSPEC")
       (consp (cdr form))))
