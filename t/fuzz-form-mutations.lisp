;;;; fuzz-form-mutations.lisp -- the fuzzer's hostile material and its
;;;; mutations of forms: sites in a tree of forms, deep nesting, top-level
;;;; payloads, deletions, swaps, wrong types and renames (see fuzz.lisp).

(in-package #:player-tests)

;;; ---------------------------------------------------------------------------
;;; Hostile material

(defparameter *fz-marker-placeholder* "@MARKER@"
  "Stands for the run's marker file in generated text; FZ-CASE-FILE-TEXT fills it in.")

(defun fz-marker-writer ()
  "Lisp text that creates the marker file when evaluated."
  (format nil "(with-open-file (s \"~A\" :direction :output :if-does-not-exist :create :if-exists :append))"
          *fz-marker-placeholder*))

(defun fz-read-eval-payloads ()
  "#. payloads: each would create the marker file or set a payload symbol if read with *READ-EVAL* on."
  (list (format nil "#.(progn ~A 'fz-read-eval)" (fz-marker-writer))
        (format nil "#.~A" (fz-marker-writer))
        "#.(progn (setf player-user::*fuzz-payload-var* t) 'fz-read-eval)"
        (format nil "#.(progn (sb-ext:run-program \"/usr/bin/touch\" (list \"~A\")) 1)" *fz-marker-placeholder*)
        (format nil "#+#.(cl:progn ~A :sbcl) fz-feature" (fz-marker-writer))
        (format nil "#.(cl:progn (cl:defun player-user::fuzz-payload-fn () 1) ~A 2)" (fz-marker-writer))
        "#.(error \"a #. payload ran\")"))

(defparameter *fz-reader-macros*
  '("#+sbcl fz-on-sbcl" "#-sbcl fz-not-sbcl" "#+(or) (never read)" "#+(and) fz-and"
    "#+(not sbcl) x" "#+(or" "#+" "#-" "#p\"/tmp/fuzz.lisp\"" "#P\"\"" "#p\"@MARKER@\"" "#p42"
    "#S(no-such-structure :a 1)" "#S(player-tests::fz-prng :state 7)" "#S(pathname)" "#S()" "#S"
    "#'car" "#'(lambda () 1)" "#'" "|weird sym|" "|a\\|b|" "|unterminated" "`(a ,b ,@c)" "`x" ",x" ",@x"
    "#1=(a . #1#)" "#1=(not #1#)" "#1#" "#1=#1#" "#1=(#1# . #1#)" "#9999999999999999999999=x"
    "#(1 2 3)" "#()" "#*1011" "#*2" "#2A((1 2) (3 4))" "#0Anil" "#c(1 2)" "#c(1)" "#x-FF" "#b102"
    "#36rZZZZ" "#o777" "#1000000000r1" "#:uninterned" "#\\Nul" "#\\Newline" "#\\no-such-char"
    "#<unreadable>" "#)" "#|unterminated" "#|nested #| |# |#" "#" "#A" "#=" "#?" "#{" "#[" "#$"
    "cl-user::fz" "no-such-package::fz" "player.spec::*specs*" "sb-impl::fz" ":" "::x" "a:b:c"
    "player-user:::x" "keyword::" "\\(" "\"unterminated" "\\" "'" "''" "#.")
  "Reader syntax to splice into a file: legal, illegal and odd.")

(defparameter *fz-number-tokens*
  '("1d308" "-1d308" "1.7976931348623157d308" "1d309" "-1d309" "1d-400" "4.9d-324" "-0.0" "0.0"
    "1f39" "1e39" "1/0" "0/0" "-7/2" "1/3" "1.5e" "1e" "#x" "+." "-" "+" "1s0" "1l0" "-1" "-1000000"
    "999999999999999999999" "-999999999999999999999" "123456789012345678901234567890.5" "#c(1d308 1d308)"
    "1000000000000000000000000000000000000000000000000000000000000000000000000000000000000d0")
  "Number-shaped tokens, besides the 401-digit integers FZ-HUGE-INTEGER-TEXT makes.")

(defparameter *fz-unicode-names*
  (list "é" "naïve-op" "中文" "emoji-😀" (coerce (list #\e (code-char #x301)) 'string) "ǅ" "ß" "ı" "İ" "ﬁ"
        "ς" (coerce (list #\a (code-char #x200B) #\b) 'string) (coerce (list #\a (code-char #x202E) #\b) 'string)
        (coerce (list #\a (code-char #x2028) #\b) 'string) (coerce (list #\a (code-char #xA0) #\b) 'string)
        "Ω" "ℵ" "𝔘𝔫𝔦" "٣" "¹²³" "½" "ÅNGSTRÖM" "ǆ" "Σ" "ﬀ")
  "Names in other scripts: combining marks, case-changing letters, invisible
and direction-changing characters, digits that are not ASCII.")

(defparameter *fz-c++-hostile-names*
  (list (format nil "a~%b") (coerce (list #\a #\Return #\b) 'string) "back\\slash" "tri??=graph" "??/"
        "??(x??)" "quote\"d" "apos'trophe" "end*/comment" "/*open" "//line" "#define" "a b"
        "class" "int" "new" "delete" "namespace" "_Reserved" "__double" "9lives" "" "with	tab"
        (coerce (list #\n (code-char 0) #\l) 'string) "dollar$" "std::string" "main" "State" "Controller"
        "Presenter" "v_x" "op_x" "ev_x" "achieve_goal0" "T_" "a.b.c" "x." ".x" "%s%n" "{}" "\\u0041"
        "R\"(raw)\"" "0x10" "true" "nullptr" "auto")
  "Names the C++ generator must mangle: newlines, CR, backslashes, trigraphs,
quotes, comment delimiters, C++ keywords and the generator's own prefixes.")

(defparameter *fz-spec-keywords*
  '(:precond :add :sub :seq :script :director :duration :must-ask :state :op :label :time :if
    :max-depth :scripts :body :colour :initial :values :and :or)
  "Option and directive keywords of specs (not :code: code is allowed to run).")

(defparameter *fz-library-keywords*
  '(:at :motor :for :animate :set :play :attach :to :keep-world :duration :loop :critical
    :documentation :kind :parent :position :rotation :properties :start :stop :as :keys
    :interpolation :noise :amplitude :frequency :seed :sum :product :vec3 :quat :degrees :euler
    :axis-angle :object :self :point :joint :offset :target :arm :right :left :times :name :blend
    :priority :hold :keyframe :gaze :reach :lips :visemes :idle :beat :blink :pose :direct :head
    :facing :eyebrows :step :linear :ease :catmull-rom :prop :camera :light :group :colour :number
    :vector :boolean :end :critical)
  "Keywords of script libraries.")

(defun fz-huge-integer-text (prng)
  "A 401-digit integer's text, sometimes negative."
  (with-output-to-string (out)
    (when (fz-chance prng 0.4) (write-char #\- out))
    (write-char (code-char (+ 49 (fz-below prng 9))) out)
    (loop repeat 400 do (write-char (code-char (+ 48 (fz-below prng 10))) out))))

(defun fz-long-name (prng)
  "A 10,000-character name."
  (let ((unit (fz-pick prng (list "x" "ab-" "é" "中" "name-" (format nil "a~%")))))
    (let ((name (with-output-to-string (out)
                  (loop while (< (file-position out) 10000) do (write-string unit out)))))
      (subseq name 0 (min (length name) 10000)))))

(defun fz-hostile-name (prng kind)
  "A name of KIND: :unicode, :long or :c++."
  (ecase kind
    (:unicode (fz-pick prng *fz-unicode-names*))
    (:long (fz-long-name prng))
    (:c++ (fz-pick prng *fz-c++-hostile-names*))))

(defun fz-nan () (sb-kernel:make-double-float #x7FF80000 0))
(defun fz-single-nan () (sb-kernel:make-single-float #x7FC00000))

(defun fz-special-floats ()
  "NaN and the infinities, double and single."
  (list (fz-nan) (fz-single-nan)
        sb-ext:double-float-positive-infinity sb-ext:double-float-negative-infinity
        sb-ext:single-float-positive-infinity sb-ext:single-float-negative-infinity))

(defun fz-numbers (prng)
  "Numbers for numeric slots: huge, tiny, negative, odd types."
  (list (parse-integer (fz-huge-integer-text prng)) (- (expt 10 400)) 1d308 -1d308
        most-positive-double-float least-positive-double-float 4.9d-324 -0.0d0 0 -1 -1000000
        (expt 2 63) (- (expt 2 63)) (1- (expt 2 64)) (expt 2 26) 1/3 -7/2 #c(1 2) 1.5f0
        most-positive-fixnum (1+ most-positive-fixnum) 1d15 1d16 123456789.123d0))

(defun fz-hostile-value (prng memory-p)
  "A value of a wrong or extreme type for any slot. MEMORY-P allows what text
cannot hold: NaN, infinities, unprintable objects, circular lists."
  (let ((choice (fz-below prng (if memory-p 32 26))))
    (case choice
      (0 "a string") (1 "") (2 (make-string 10000 :initial-element #\s)) (3 (vector 1 2 3))
      (4 (vector)) (5 #\a) (6 (fz-pick prng (list #\Newline (code-char 0) #\Space (code-char #x1F600))))
      (7 (fz-pick prng '(:keyword :precond :state :op :at :duration nil t)))
      (8 nil) (9 '(a . b)) (10 (list* 1 2 3)) (11 (fz-pick prng (fz-numbers prng)))
      (12 (fz-pick prng (fz-numbers prng))) (13 (fz-pick prng (fz-numbers prng)))
      (14 (pathname "/tmp/fuzz.lisp")) (15 (make-symbol "UNINTERNED"))
      (16 (fz-pick prng '(car cl:list sb-ext:*posix-argv* player.spec::*specs*)))
      (17 (make-array 3 :element-type 'bit :initial-contents '(1 0 1)))
      (18 (make-array '(2 2) :initial-contents '((1 2) (3 4))))
      (19 (list 'quote (intern "X" '#:player-user))) (20 (list 'function 'car))
      (21 (intern (fz-hostile-name prng :unicode) '#:player-user))
      (22 (intern (fz-hostile-name prng :c++) '#:player-user))
      (23 (intern (fz-long-name prng) '#:player-user))
      (24 (make-fz-prng 1)) (25 (list (list (list))))
      ;; Memory only:
      ((26 27 28) (fz-pick prng (fz-special-floats)))
      (29 (fz-pick prng (list (make-hash-table) #'car (find-package '#:cl) (make-string-output-stream))))
      (30 (let ((list (list 1 2 3))) (setf (cdr (last list)) list) list))
      (t (let ((cell (list 'not nil))) (setf (second cell) cell) cell)))))

;;; ---------------------------------------------------------------------------
;;; Sites: the places in a tree of forms a mutation can change

(defvar *fz-root* (make-symbol "ROOT")
  "The car of the cons holding the top-level forms (FZ-SITES' HOLDER).")

(defvar *fz-sublist* (make-symbol "SUBLIST")
  "The car of the pseudo-holders FZ-SITES makes for sub-lists.")

(defun fz-holder (forms)
  "A holder for FORMS: a cons whose cdr is the top-level list."
  (cons *fz-root* forms))

(defstruct (fz-site (:constructor make-fz-site (prev cell depth parent)))
  "An element of a list in the forms: CELL is the cons whose car it is, PREV
the cons whose cdr is CELL, PARENT the list holding it."
  prev cell depth parent)

(defun fz-sites (holder &key (max-depth 40))
  "Every list element in the tree under HOLDER (a cons whose cdr is the
top-level list), walked without recursion and without looping on shared or
circular conses."
  (let ((sites (make-array 64 :adjustable t :fill-pointer 0))
        (seen (make-hash-table :test 'eq))
        (stack (list (list holder 0 holder))))
    (loop while stack
          do (destructuring-bind (prev depth parent) (pop stack)
               (loop for cell = (cdr prev)
                     while (and (consp cell) (not (gethash cell seen)))
                     do (setf (gethash cell seen) t)
                        (vector-push-extend (make-fz-site prev cell depth parent) sites)
                        (when (and (consp (car cell)) (< depth max-depth)
                                   (not (gethash (car cell) seen)))
                          ;; A pseudo-holder whose cdr is the sub-list.
                          (push (list (cons *fz-sublist* (car cell)) (1+ depth) (car cell)) stack))
                        (setf prev cell))))
    sites))

(defun fz-site-set (site value)
  "Replace SITE's element by VALUE. A pseudo-holder's first cell is the
sub-list's own first cons, so replacing through it changes the tree."
  (setf (car (fz-site-cell site)) value))

(defun fz-random-site (prng holder &key (test (constantly t)) (min-depth 0))
  "A random site under HOLDER whose element passes TEST, or NIL."
  (let ((candidates (remove-if-not (lambda (site) (and (>= (fz-site-depth site) min-depth)
                                                       (funcall test (car (fz-site-cell site)))))
                                   (fz-sites holder))))
    (and (plusp (length candidates)) (fz-pick prng candidates))))

(defun fz-delete-site (site)
  "Remove SITE's element from its list. Through a pseudo-holder (the first
element of a sub-list) the first cons is overwritten by the second."
  (let ((prev (fz-site-prev site)) (cell (fz-site-cell site)))
    (if (eq (car prev) *fz-sublist*)
        (if (consp (cdr cell))
            (setf (car cell) (cadr cell) (cdr cell) (cddr cell))
            (setf (car cell) nil))
        (setf (cdr prev) (cdr cell)))))

(defun fz-insert-after (site value)
  "Insert VALUE after SITE's element."
  (let ((cell (fz-site-cell site)))
    (setf (cdr cell) (cons value (cdr cell)))))

(defun fz-note-site (site)
  "SITE's element and the list around it, for a note."
  (let ((parent (fz-site-parent site)))
    (format nil "~A in ~A" (fz-bounded-text (car (fz-site-cell site)) :limit 60)
            (if (and (consp parent) (eq (car parent) *fz-root*))
                "the top level"
                (fz-bounded-text parent :length 6 :level 2 :limit 100)))))

(defun fz-after-keyword-p (site &optional keywords)
  "Is SITE's element the value after a keyword (one of KEYWORDS, if given)?
Only the cons before it is looked at, so circular lists cost nothing."
  (let ((before (car (fz-site-prev site))))
    (and (keywordp before)
         (or (null keywords) (member before keywords)))))

(defun fz-option-value-site-p (site)
  "Is SITE's element the value after a keyword?"
  (fz-after-keyword-p site))

(defun fz-defined-names (holder)
  "The symbols forms under HOLDER define: the second element of op, event,
state-variable, defscript... forms."
  (let ((names '()))
    (loop for site across (fz-sites holder)
          for element = (car (fz-site-cell site))
          do (when (and (consp element) (symbolp (car element)) (consp (cdr element))
                        (symbolp (cadr element)) (cadr element) (not (keywordp (cadr element)))
                        (member (symbol-name (car element))
                                '("OP" "MACRO-OP" "EVENT" "STATE-VARIABLE" "TIME-VARIABLE" "STATE-CLASS"
                                  "DEFSCRIPT" "DEFDIRECTOR" "DEFOBJECT" "DEFSPEC" "AUTOSCRIPT")
                                :test #'string=))
               (pushnew (cadr element) names)))
    (nreverse names)))

(defun fz-copy (tree)
  "A copy of the conses of TREE, circular structure and all (a wrong-type value
may be a circular list)."
  (let ((copies (make-hash-table :test 'eq)))
    (labels ((copy (x)
               (cond ((not (consp x)) x)
                     ((gethash x copies))
                     (t (let ((new (cons nil nil)))
                          (setf (gethash x copies) new
                                (car new) (copy (car x))
                                (cdr new) (copy (cdr x)))
                          new)))))
      (copy tree))))

(defun fz-substitute-symbol (holder old new)
  "Replace every occurrence of the symbol OLD under HOLDER by NEW; the count."
  (let ((count 0))
    (loop for site across (fz-sites holder)
          when (eq (car (fz-site-cell site)) old)
            do (fz-site-set site new) (incf count))
    count))

;;; ---------------------------------------------------------------------------
;;; Deep nesting

(defparameter *fz-depths* '(1000 5000 15000 15000 15000 40000)
  "How deep the deep-nesting mutations nest.")

(defun fz-deep-form (kind depth leaf)
  "LEAF wrapped DEPTH times: (not (not ...)), ((...)), (and x (and ...)), #(#(...)) or '''."
  (let ((form leaf)
        (not-symbol (intern "NOT" '#:player-user))
        (and-symbol (intern "AND" '#:player-user)))
    (loop repeat depth
          do (setf form (ecase kind
                          (:not (list not-symbol form))
                          (:list (list form))
                          (:and (list and-symbol leaf form))
                          (:vector (vector form))
                          (:quote (list 'quote form)))))
    form))

(defun fz-deep-text (kind depth leaf)
  "The text of FZ-DEEP-FORM, made without the printer."
  (with-output-to-string (out)
    (ecase kind
      (:not (loop repeat depth do (write-string "(not " out)) (write-string leaf out)
       (loop repeat depth do (write-char #\) out)))
      (:list (loop repeat depth do (write-char #\( out)) (write-string leaf out)
       (loop repeat depth do (write-char #\) out)))
      (:and (loop repeat depth do (format out "(and ~A " leaf)) (write-string leaf out)
       (loop repeat depth do (write-char #\) out)))
      (:vector (loop repeat depth do (write-string "#(" out)) (write-string leaf out)
       (loop repeat depth do (write-char #\) out)))
      (:quote (loop repeat depth do (write-char #\' out)) (write-string leaf out))
      (:backquote (loop repeat depth do (write-char #\` out)) (write-string leaf out)))))

;;; ---------------------------------------------------------------------------
;;; Top-level payloads

(defun fz-toplevel-payloads (target)
  "Top-level forms that are not defspec (or, in a library, not one of its four
forms): code that must never run, odd IN-PACKAGEs, malformed definitions."
  (let ((marker (fz-marker-writer)))
    (append
     (list marker
           (format nil "(defun player-user::fuzz-payload-fn () ~A)" marker)
           "(setf player-user::*fuzz-payload-var* t)"
           (format nil "(defparameter player-user::*fuzz-payload-var* ~A)" marker)
           "(defmacro player-user::fuzz-payload-macro () nil)"
           (format nil "(progn ~A (defspec fuzz-progn (state-variable x boolean false)))" marker)
           (format nil "(eval-when (:compile-toplevel :load-toplevel :execute) ~A)" marker)
           (format nil "(sb-ext:run-program \"/usr/bin/touch\" '(\"~A\"))" *fz-marker-placeholder*)
           "(let () (setf player-user::*fuzz-payload-var* t))"
           "(defpackage :player-fuzz-payload-package)"
           "(in-package :player-fuzz-no-such-package)" "(in-package :cl-user)" "(in-package :player)"
           "(in-package :keyword)" "(in-package)" "(in-package 42)" "(in-package :player-user :extra)"
           "(in-package . :player-user)" "(cl:in-package \"PLAYER-USER\")" "(in-package #:player-user)"
           "42" "\"string\"" ":keyword" "#(1 2)" "nil" "t" "(quote x)" "()" "(error \"top-level\")")
     (if (eq target :spec)
         (list "(defspec)" "(defspec 42 (state-variable x boolean false))" "(defspec nil)" "(defspec :kw)"
               "(defspec \"str\")" "(defspec . fuzz-dotted)" "(defspec fuzz-dotted . 1)"
               "(defspec fuzz-extra (state-variable x boolean false) (op o :add x) (event e :state x))"
               "(player:defspec fuzz-qualified (state-variable x boolean false))" "(defspec fuzz-peedy)"
               "(defspec fuzz-mini (:max-depth 1d308))" "(defspec fuzz-extra \"doc\" \"doc\")")
         (list "(defscript)" "(defscript fz-x)" "(defscript fz-x () (:at 1d308 :play fz-x))"
               "(poses)" "(poses \"/etc/passwd\")" "(poses \"\")" "(poses \"/\")" "(poses \"/dev/null\")"
               "(poses \"peedy-poses.lisp\" extra)" "(poses \"fuzz-library.lisp\")" "(poses 42)"
               "(defobject)" "(defobject camera)" "(defobject fz-o :kind :camera :position (1d308 0 0))"
               "(defdirector fz-d)" "(defdirector fz-d (:start fz-d))" "(defdirector fz-d (:start 42 :at -1))")))))

;;; ---------------------------------------------------------------------------
;;; Form mutations

(defparameter *fz-form-kinds*
  '((10 . :delete) (8 . :duplicate) (7 . :swap) (6 . :transplant) (14 . :wrong-type) (10 . :number)
    (7 . :rename-unicode) (5 . :rename-long) (9 . :rename-c++) (3 . :collide) (6 . :keyword-swap)
    (4 . :dotted) (3 . :deep) (3 . :circular) (5 . :reader-macro) (4 . :read-eval) (5 . :toplevel))
  "Form mutation kinds and their weights. In memory mode :reader-macro,
:read-eval and :toplevel become :special-float and :wrong-type.")

(defparameter *fz-late-kinds* '(:deep :circular :reader-macro :read-eval :toplevel :special-float)
  "Kinds applied after the others: the earlier kinds copy and walk the tree,
which deep or circular structure and splice placeholders must not meet.")

(defun fz-mutate-forms (prng holder kind memory-p target splices)
  "Apply mutation KIND to the forms under HOLDER. Returns (VALUES NOTE SPLICES)."
  (flet ((site (&rest args) (apply #'fz-random-site prng holder args))
         (placeholder (text)
           (let ((symbol (make-symbol (format nil "FZSPLICE~D" (length splices)))))
             (push (cons symbol text) splices)
             symbol)))
    (let ((note
            (ecase kind
              (:delete (let ((s (site))) (when s (prog1 (format nil "deleted ~A" (fz-note-site s)) (fz-delete-site s)))))
              (:duplicate (let ((s (site)))
                            (when s (prog1 (format nil "duplicated ~A" (fz-note-site s))
                                      (fz-insert-after s (fz-copy (car (fz-site-cell s))))))))
              (:swap (let* ((s (site))
                            (siblings (and s (remove-if-not (lambda (o) (and (eq (fz-site-parent o) (fz-site-parent s))
                                                                            (not (eq o s))))
                                                            (fz-sites holder)))))
                       (when (plusp (length siblings))
                         (let ((o (fz-pick prng siblings)))
                           (prog1 (format nil "swapped ~A with ~A" (fz-note-site s)
                                          (fz-bounded-text (car (fz-site-cell o)) :limit 60))
                             (rotatef (car (fz-site-cell s)) (car (fz-site-cell o))))))))
              (:transplant (let ((s (site)) (o (site)))
                             (when (and s o)
                               (prog1 (format nil "replaced ~A by a copy of ~A" (fz-note-site s)
                                              (fz-bounded-text (car (fz-site-cell o)) :limit 60))
                                 (fz-site-set s (fz-copy (car (fz-site-cell o))))))))
              (:wrong-type (let ((s (site))
                                 (v (fz-hostile-value prng memory-p)))
                             (when (and s (fz-chance prng 0.5))
                               (let ((option (remove-if-not #'fz-option-value-site-p (fz-sites holder))))
                                 (when (plusp (length option)) (setf s (fz-pick prng option)))))
                             (when s (prog1 (format nil "replaced ~A by ~A" (fz-note-site s) (fz-bounded-text v :limit 60))
                                       (fz-site-set s v)))))
              (:number (let ((s (or (and (fz-chance prng 0.7) (site :test #'numberp))
                                    (let ((option (remove-if-not #'fz-option-value-site-p (fz-sites holder))))
                                      (and (plusp (length option)) (fz-pick prng option)))
                                    (site)))
                             (v (fz-pick prng (fz-numbers prng))))
                         (when s (prog1 (format nil "replaced ~A by ~A" (fz-note-site s) (fz-bounded-text v :limit 60))
                                   (fz-site-set s v)))))
              (:special-float (let ((s (or (and (fz-chance prng 0.7) (site :test #'numberp)) (site)))
                                    (v (fz-pick prng (fz-special-floats))))
                                (when s (prog1 (format nil "replaced ~A by ~A" (fz-note-site s) (fz-bounded-text v))
                                          (fz-site-set s v)))))
              ((:rename-unicode :rename-long :rename-c++)
               (let ((names (fz-defined-names holder)))
                 (when names
                   (let* ((old (fz-pick prng names))
                          (new (intern (fz-hostile-name prng (ecase kind (:rename-unicode :unicode) (:rename-long :long)
                                                                (:rename-c++ :c++)))
                                       '#:player-user))
                          (count (fz-substitute-symbol holder old new)))
                     (format nil "renamed ~A to ~A (~D places)" (fz-bounded-text old) (fz-bounded-text new :limit 60) count)))))
              (:collide (let ((names (fz-defined-names holder)))
                          (when (>= (length names) 2)
                            (let* ((pair (fz-pick prng '(("a-b" "a_b") ("x" "X") ("ab" "a.b") ("class" "class_")
                                                         ("v-x" "v_x") ("é" "É") ("ss" "ß") ("n" "n_"))))
                                   (a (fz-pick prng names))
                                   (b (fz-pick prng (remove a names))))
                              (fz-substitute-symbol holder a (intern (first pair) '#:player-user))
                              (fz-substitute-symbol holder b (intern (second pair) '#:player-user))
                              (format nil "renamed ~A and ~A to the colliding ~S and ~S"
                                      (fz-bounded-text a) (fz-bounded-text b) (first pair) (second pair))))))
              (:keyword-swap (let ((s (site :test #'keywordp))
                                   (k (fz-pick prng (if (eq target :spec) *fz-spec-keywords* *fz-library-keywords*))))
                               (when s (prog1 (format nil "replaced ~A by ~S" (fz-note-site s) k) (fz-site-set s k)))))
              (:dotted (let ((s (site :test (lambda (x) (and (consp x) (alexandria:proper-list-p x) (cdr x))))))
                         (when s
                           (let* ((list (car (fz-site-cell s)))
                                  (tail (last list 2)))
                             (prog1 (format nil "made ~A a dotted list" (fz-note-site s))
                               (setf (cdr tail) (cadr tail)))))))
              (:deep (let* ((s (or (and (fz-chance prng 0.6)
                                        (let ((slots (remove-if-not #'fz-expression-slot-p (fz-sites holder))))
                                          (and (plusp (length slots)) (fz-pick prng slots))))
                                   (site)))
                            (kind (fz-pick prng (if memory-p '(:not :not :list :and :vector :quote)
                                                    '(:not :not :list :and :vector :quote :backquote))))
                            (depth (fz-pick prng *fz-depths*)))
                       (when s
                         (prog1 (format nil "replaced ~A by ~(~A~) nesting ~D deep" (fz-note-site s) kind depth)
                           (fz-site-set s (if memory-p
                                              (fz-deep-form (if (eq kind :backquote) :quote kind) depth
                                                            (car (fz-site-cell s)))
                                              (placeholder (fz-deep-text kind depth "x"))))))))
              (:circular (let ((s (site :test (lambda (x) (and (consp x) (alexandria:proper-list-p x))))))
                           (cond ((and memory-p (eq target :spec) (fz-chance prng 0.2))
                                  (setf (cdr (last holder)) (cdr holder))
                                  "made the top-level list circular")
                                 ((null s) nil)
                                 ((fz-chance prng 0.5)
                                  (let ((list (car (fz-site-cell s))))
                                    (prog1 (format nil "made the tail of ~A circular" (fz-note-site s))
                                      (setf (cdr (last list)) list))))
                                 (t (let ((list (car (fz-site-cell s))))
                                      (prog1 (format nil "put ~A inside itself" (fz-note-site s))
                                        (setf (car (last list)) list)))))))
              (:reader-macro (let ((s (site)) (text (fz-pick prng *fz-reader-macros*)))
                               (when s (prog1 (format nil "replaced ~A by the text ~A" (fz-note-site s) text)
                                         (fz-site-set s (placeholder text))))))
              (:read-eval (let ((s (site)) (text (fz-pick prng (fz-read-eval-payloads))))
                            (when s (prog1 (format nil "replaced ~A by the text ~A" (fz-note-site s) (fz-visible text))
                                      (fz-site-set s (placeholder text))))))
              (:toplevel (let* ((top (remove-if-not (lambda (s) (zerop (fz-site-depth s))) (fz-sites holder)))
                                (text (fz-pick prng (fz-toplevel-payloads target)))
                                (symbol (placeholder text)))
                           (if (and (plusp (length top)) (fz-chance prng 0.8))
                               (let ((s (fz-pick prng top)))
                                 (fz-insert-after s symbol))
                               (push symbol (cdr holder)))
                           (format nil "added the top-level form ~A" (fz-visible text)))))))
      (values note splices))))

(defun fz-expression-slot-p (site)
  "Is SITE the value of a :precond, :state or :if (where expressions go)?"
  (fz-after-keyword-p site '(:precond :state :if)))
