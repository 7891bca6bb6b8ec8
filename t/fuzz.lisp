;;;; fuzz.lisp -- a seeded mutation fuzzer over spec files and script libraries,
;;;; and the harness that checks what Player does with each mutant.
;;;;
;;;; The generator starts from real inputs -- specs/peedy.lisp, the spec
;;;; fixtures, random specs from random-specs.lisp, specs/peedy-scripts.lisp and
;;;; t/fixtures/anim-scripts.lisp -- and mutates them in three modes:
;;;;   :text       the file's text: delete, duplicate or swap spans and lines,
;;;;               unbalance parentheses, stray dots, reader macros (#. payloads,
;;;;               #+, #p, #S, #', |...|, backquote, #1=...#1#), huge and odd
;;;;               number tokens, unicode, 10,000-character and C++-hostile
;;;;               names, control characters, bytes that are not UTF-8, deep
;;;;               nesting, truncation, top-level forms that are not defspec;
;;;;   :form-file  the forms read from the file, mutated as data (delete,
;;;;               duplicate, swap and transplant forms and sub-forms, wrong
;;;;               types in any slot, huge and negative numbers, consistent
;;;;               renames to hostile names, circular structure) and printed
;;;;               back, with text spliced into slots for what printing cannot
;;;;               make (reader macros, #. payloads, 15,000-deep nesting);
;;;;   :memory     the same form mutations, plus NaN, infinities, unprintable
;;;;               objects and real circular or deep conses, given straight to
;;;;               DEFINE-SPEC (or PARSE-SCRIPT-LIBRARY-FORMS): no text at all.
;;;; A case is named by a seed and a case number; FZ-GENERATE makes the same
;;;; case from them on every run (the PRNG is our own xorshift64*).
;;;;
;;;; The harness (FZ-EXECUTE) writes a case's text to a file in a per-run
;;;; directory and loads it with LOAD-SPEC or LOAD-SCRIPT-LIBRARY; an accepted
;;;; spec is compiled, given a controller with a null presenter and its events
;;;; (in order, then two at random), checked with CHECK-SPEC and, for a
;;;; deterministic subset, emitted as C++ into the run's emit directory; an
;;;; accepted library is checked against its spec and, for a subset, played on
;;;; a body.  A case must end in a PLAYER-ERROR or in acceptance.  Anything
;;;; else -- another error, a storage condition (stack or heap exhausted), a
;;;; non-error condition given to ERROR, a hang past the time limit, a report
;;;; that cannot be printed -- is an escape.  After every case: the marker
;;;; file the payloads would create must not exist, no payload symbol may be
;;;; set or defined, no file may have appeared in the run directory outside the
;;;; emit directory (nor payload-looking files in the working directory), and
;;;; the spec registry may only have grown by specs the case's file defined
;;;; (they are removed again).
;;;;
;;;; Some escapes kill SBCL outright (a stack exhausted while the runtime is
;;;; allocating is fatal), so FUZZ-RUN runs the cases in forked child
;;;; processes that send each FZ-RESULT back through a pipe; when a child dies
;;;; or stops answering, its case is reported CRASHED or HUNG, with the
;;;; runtime's last words, and a new child carries on with the next case.
;;;;
;;;; FUZZ-RUN runs cases and returns a FZ-SUMMARY; FZ-REPORT prints it, with the
;;;; escapes grouped by condition type, one reproducer each (and the first case
;;;; of every other cause of the same type).  (FUZZ-CASE SEED N) replays one
;;;; case and returns its FZ-RESULT; (FUZZ-CASE-TEXT SEED N) is its text;
;;;; (FUZZ-MINIMIZE SEED N) shrinks that text while it still fails the same way.
;;;; test-fuzz.lisp runs it in `make test`; fuzz-main.lisp is `make fuzz`.

(in-package #:player-tests)

(eval-when (:compile-toplevel :load-toplevel :execute)
  (require :sb-posix))

;;; ---------------------------------------------------------------------------
;;; A seeded PRNG: splitmix64 mixes the seed, xorshift64* draws.

(defun fz-splitmix (x)
  "The splitmix64 finaliser of X (an integer, taken modulo 2^64)."
  (let* ((z (ldb (byte 64 0) (+ (ldb (byte 64 0) x) #x9E3779B97F4A7C15)))
         (z (ldb (byte 64 0) (* (logxor z (ash z -30)) #xBF58476D1CE4E5B9)))
         (z (ldb (byte 64 0) (* (logxor z (ash z -27)) #x94D049BB133111EB))))
    (logxor z (ash z -31))))

(defstruct (fz-prng (:constructor %make-fz-prng (state)))
  "A xorshift64* generator."
  (state 1 :type (unsigned-byte 64)))

(defun make-fz-prng (&rest keys)
  "A generator whose whole output is determined by the integers KEYS."
  (let ((state 0))
    (dolist (key keys)
      (setf state (fz-splitmix (logxor state (fz-splitmix key)))))
    (%make-fz-prng (if (zerop state) 1 state))))

(defun fz-next (prng)
  "The next 64-bit output of PRNG."
  (let ((x (fz-prng-state prng)))
    (setf x (logxor x (ash x -12)))
    (setf x (logxor x (ldb (byte 64 0) (ash x 25))))
    (setf x (logxor x (ash x -27)))
    (setf (fz-prng-state prng) x)
    (ldb (byte 64 0) (* x #x2545F4914F6CDD1D))))

(defun fz-below (prng n)
  "A pseudo-random integer in [0, N)."
  (if (<= n 1) 0 (mod (ash (fz-next prng) -8) n)))

(defun fz-between (prng low high)
  "A pseudo-random integer in [LOW, HIGH]."
  (+ low (fz-below prng (1+ (- high low)))))

(defun fz-chance (prng probability)
  "True with PROBABILITY."
  (< (fz-below prng 1000000) (round (* probability 1000000))))

(defun fz-pick (prng sequence)
  "A pseudo-random element of the non-empty SEQUENCE."
  (elt sequence (fz-below prng (length sequence))))

(defun fz-weighted (prng choices)
  "The item of a pseudo-random entry of CHOICES, ((WEIGHT . ITEM) ...)."
  (let ((r (fz-below prng (reduce #'+ choices :key #'car))))
    (loop for (weight . item) in choices
          when (< r weight) return item
          do (decf r weight))))

;;; ---------------------------------------------------------------------------
;;; Cases and results

(defstruct (fz-case (:conc-name fzc-))
  "One generated input. TEXT (file modes) holds @MARKER@ where payloads name the
marker file; FORMS (memory mode) is what DEFINE-SPEC or
PARSE-SCRIPT-LIBRARY-FORMS gets: (NAME . BODY) of a spec, or a library's forms."
  seed index
  (target :spec)                        ; :spec or :library
  (mode :text)                          ; :text, :form-file or :memory
  base                                  ; the base's name, e.g. "peedy"
  (kinds '())                           ; the mutation kinds applied, in order
  (notes '())                           ; what each mutation did, as short strings
  text
  forms
  base-text                             ; the text the mutations started from
  companion                             ; for a library: its spec's base name
  (events '()))                         ; the base's event names (strings), for the command line

(defstruct (fz-result (:conc-name fzr-))
  "What one case did. OUTCOME is :ACCEPTED, :PLAYER-ERROR, :ESCAPED, :TIMEOUT,
or (the process running it died or stopped answering) :CRASHED or :HUNG;
CONDITION-TYPE the condition's class name (for a crash, the runtime's reason);
PHASE where it happened (:load, :compile, :send-event, :check-spec, :emit-c++,
:report, ...); VIOLATIONS the side effects seen after it (strings); EXCERPT
the input around the mutation."
  seed index target mode base kinds notes
  outcome condition-type message phase
  (violations '())
  excerpt
  (size 0)
  (seconds 0.0)
  (warnings 0)
  (condition nil))                      ; the condition itself, when the case ran in this process

(defparameter *fz-failing-outcomes* '(:escaped :timeout :crashed :hung)
  "The outcomes that fail a case by themselves.")

(defmethod print-object ((result fz-result) stream)
  (print-unreadable-object (result stream :type t)
    (format stream "seed ~A case ~A ~(~A ~A ~A~): ~(~A~)~@[ ~A~]~@[ in ~(~A~)~]~@[ violations: ~{~A~^; ~}~]"
            (fzr-seed result) (fzr-index result) (fzr-target result) (fzr-mode result)
            (fzr-base result) (fzr-outcome result) (fzr-condition-type result)
            (and (member (fzr-outcome result) *fz-failing-outcomes*) (fzr-phase result))
            (fzr-violations result))))

(defun fzr-failed-p (result)
  "Did RESULT escape, hang, crash or leave a side effect?"
  (or (member (fzr-outcome result) *fz-failing-outcomes*)
      (fzr-violations result)))

;;; ---------------------------------------------------------------------------
;;; Printing hostile data safely (for reports and notes)

(defun fz-bounded-text (object &key (length 8) (level 4) (limit 200))
  "OBJECT printed for a human, never looping or exhausting the stack: circular
structure as #n=, long and deep structure elided, cut to LIMIT characters."
  (let ((text (handler-case
                  (let ((*print-circle* t) (*print-length* length) (*print-level* level)
                        (*print-readably* nil) (*print-escape* t) (*print-pretty* nil)
                        (*print-lines* nil) (*print-case* :downcase)
                        (*package* (find-package '#:player-user)))
                    (prin1-to-string object))
                (serious-condition (c) (format nil "#<unprintable ~A>" (type-of c))))))
    (fz-visible (if (> (length text) limit)
                    (concatenate 'string (subseq text 0 (- limit 3)) "...")
                    text))))

(defun fz-visible (string)
  "STRING with line breaks, control characters and the raw-byte stand-ins
written as escapes, so a report stays one line per item."
  (with-output-to-string (out)
    (loop for char across string
          for code = (char-code char)
          do (cond ((char= char #\Newline) (write-string "\\n" out))
                   ((char= char #\Return) (write-string "\\r" out))
                   ((char= char #\Tab) (write-string "\\t" out))
                   ((<= #xE000 code #xE0FF) (format out "\\x~2,'0X" (- code #xE000)))
                   ((or (< code 32) (= code 127) (<= #x80 code #x9F) (member code '(#x2028 #x2029 #x202E #xFEFF #x200B)))
                    (format out "\\u{~X}" code))
                   (t (write-char char out))))))

(defun fz-clip (string limit)
  "STRING (or \"\" for NIL) made visible by FZ-VISIBLE and cut to about LIMIT characters."
  (let ((visible (fz-visible (or string ""))))
    (if (> (length visible) limit)
        (concatenate 'string (subseq visible 0 (- limit 3)) "...")
        visible)))

(defun fz-excerpt (text base &key (before 80) (after 320))
  "The part of TEXT around the first place it differs from BASE."
  (let* ((start (or (mismatch text (or base "")) 0))
         (from (max 0 (- start before)))
         (to (min (length text) (+ start after))))
    (fz-visible (format nil "~:[~;...~]~A~:[~;...~]"
                        (plusp from) (subseq text from to) (< to (length text))))))

;;; ---------------------------------------------------------------------------
;;; The base inputs

(defparameter *fz-spec-files*
  '(("peedy" "specs/peedy.lisp") ("mini" "t/fixtures/mini.lisp") ("anim" "t/fixtures/anim.lisp")
    ("anim-missing" "t/fixtures/anim-missing.lisp") ("bad-initial" "t/fixtures/bad-initial.lisp")
    ("no-spec" "t/fixtures/no-spec.lisp") ("unreadable" "t/fixtures/unreadable.lisp"))
  "The spec files the fuzzer starts from: (NAME CHECKOUT-PATH).")

(defparameter *fz-library-files*
  '(("peedy-scripts" "specs/peedy-scripts.lisp" "peedy")
    ("anim-scripts" "t/fixtures/anim-scripts.lisp" "anim"))
  "The script libraries the fuzzer starts from: (NAME CHECKOUT-PATH SPEC-BASE).")

(defparameter *fz-companion-files*
  '("specs/peedy-poses.lisp" "specs/peedy-scripts.lisp" "t/fixtures/anim-scripts.lisp")
  "Files copied into every run directory, so the bases' relative references resolve.")

(defstruct (fz-base (:conc-name fzb-))
  "A starting input: its TEXT (specs renamed FUZZ-...), its FORMS as read, or
NIL when it cannot be read, and the names of its events."
  name target text forms events companion
  printed)                              ; FORMS printed by FZ-PRINT-FORMS, made when first needed

(defvar *fz-bases* nil "The bases, read once: a list of FZ-BASEs.")

(defun fz-read-forms (text)
  "The top-level forms of TEXT read as data in PLAYER-USER, or NIL if it cannot be read."
  (handler-case
      (with-standard-io-syntax
        (let ((*read-eval* nil) (*package* (find-package '#:player-user))
              (*read-default-float-format* 'double-float))
          (with-input-from-string (in text)
            (loop for form = (read in nil in) until (eq form in) collect form))))
    (error () nil)))

(defun fz-rename-specs (text)
  "TEXT with every (defspec NAME renamed (defspec FUZZ-NAME, so a case never
replaces a spec another test defined."
  (with-output-to-string (out)
    (loop with start = 0
          for hit = (search "(defspec " text :start2 start)
          do (write-string text out :start start :end (if hit (+ hit 9) (length text)))
             (unless hit (return))
             (write-string "fuzz-" out)
             (setf start (+ hit 9)))))

(defun fz-event-names (forms)
  "The names of the events FORMS define, as lower-case strings."
  (let ((names '()))
    (labels ((walk (form depth)
               (when (and (consp form) (< depth 3) (alexandria:proper-list-p form))
                 (if (and (symbolp (first form)) (string-equal (first form) "event")
                          (symbolp (second form)))
                     (push (string-downcase (second form)) names)
                     (dolist (sub form) (walk sub (1+ depth)))))))
      (dolist (form forms) (walk form 0)))
    (nreverse names)))

(defun fz-bases ()
  "The base inputs (read once per image)."
  (or *fz-bases*
      (setf *fz-bases*
            (append
             (loop for (name path) in *fz-spec-files*
                   for text = (fz-rename-specs (alexandria:read-file-into-string
                                                (checkout-file path) :external-format :utf-8))
                   for forms = (fz-read-forms text)
                   collect (make-fz-base :name name :target :spec :text text :forms forms
                                         :events (fz-event-names forms)))
             (loop for (name path companion) in *fz-library-files*
                   for text = (alexandria:read-file-into-string (checkout-file path) :external-format :utf-8)
                   collect (make-fz-base :name name :target :library :text text
                                         :forms (fz-read-forms text) :companion companion))))))

(defun fz-base (name)
  "The base called NAME."
  (find name (fz-bases) :key #'fzb-name :test #'string=))

(defun fz-random-base (prng)
  "A random spec from random-specs.lisp (sometimes with random-events.lisp's
numbers, labels, times and autoscripts) as a base."
  (let* ((k (fz-below prng 1000000))
         (name (rs-symbol "fuzz-random-~D" k))
         (body (if (fz-chance prng 0.5)
                   (random-spec k :name name)
                   (c++-random-spec k)))
         (forms (list (list (intern "IN-PACKAGE" '#:player-user) :player-user)
                      (list* (intern "DEFSPEC" '#:player-user) name body))))
    (let ((text (fz-print-forms forms '())))
      (make-fz-base :name (format nil "random-~D" k) :target :spec
                    :text text :printed text :forms forms :events (fz-event-names forms)))))

;;; ---------------------------------------------------------------------------
;;; Printing forms back as text, with text spliced into placeholders

(defun fz-print-forms (forms splices)
  "FORMS written as a spec file's text, one top-level form per line (circular
structure as #n=); each placeholder symbol of SPLICES, ((SYMBOL . TEXT) ...),
replaced by its TEXT."
  (let ((text (let ((*package* (find-package '#:player-user)) (*print-circle* t)
                    (*print-readably* nil) (*print-escape* t) (*print-pretty* nil)
                    (*print-length* nil) (*print-level* nil) (*print-lines* nil)
                    (*print-case* :downcase) (*print-base* 10) (*print-radix* nil)
                    (*print-array* t) (*print-gensym* t)
                    (*read-default-float-format* 'double-float))
                (with-output-to-string (out)
                  (dolist (form forms)
                    (prin1 form out)
                    (terpri out))))))
    (loop for (symbol . splice) in splices
          for placeholder = (let ((*print-case* :downcase) (*print-gensym* t))
                              (prin1-to-string symbol))
          do (setf text (fz-replace-all text placeholder splice)))
    text))

(defun fz-replace-all (text old new)
  "TEXT with every occurrence of OLD replaced by NEW."
  (with-output-to-string (out)
    (loop with start = 0
          for hit = (search old text :start2 start)
          do (write-string text out :start start :end (or hit (length text)))
             (unless hit (return))
             (write-string new out)
             (setf start (+ hit (length old))))))

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
    "cl-user::fz" "no-such-package::fz" "player::*specs*" "sb-impl::fz" ":" "::x" "a:b:c"
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
      (16 (fz-pick prng '(car cl:list sb-ext:*posix-argv* player::*specs*)))
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

;;; ---------------------------------------------------------------------------
;;; The run: a temporary directory, the marker file, the emit directory

(defstruct (fz-run (:conc-name fzrun-))
  "Where one fuzzing run writes: DIRECTORY holds the case files and the
companion files; EMIT the directory given to EMIT-C++; MARKER the file the
payloads would create."
  directory emit marker
  (expected '())                        ; namestrings of the files that belong in DIRECTORY
  (symbols nil)                         ; PLAYER-USER's symbols when the run began
  (cwd-files '())                       ; the working directory's files when the run began
  (timeout 10)
  (patience nil)                        ; seconds of silence before a child counts as hung (default from TIMEOUT)
  (emit-every 5)                        ; emit C++ for every Nth case (and every hostile rename)
  (play-every 10)                       ; play every Nth accepted library on a body
  (emit-hook nil))                      ; called with the case and the emitted files, before they go

(defvar *fz-run-counter* 0)

(defun fz-open-run (&key (timeout 10) (emit-every 5) (play-every 10))
  "A fresh run directory under /tmp with the companion files copied in."
  (let* ((directory (pathname (format nil "/tmp/player-fuzz-~D-~D-~D/" (sb-unix:unix-getpid)
                                      (get-universal-time) (incf *fz-run-counter*))))
         (run (make-fz-run :directory directory :emit (merge-pathnames "emit/" directory)
                           :marker (merge-pathnames "marker" directory) :timeout timeout
                           :emit-every emit-every :play-every play-every)))
    (ensure-directories-exist (fzrun-emit run))
    (dolist (path *fz-companion-files*)
      (let ((to (merge-pathnames (file-namestring path) directory)))
        (alexandria:copy-file (checkout-file path) to)
        (push (namestring to) (fzrun-expected run))))
    (setf (fzrun-symbols run) (fz-package-symbols)
          (fzrun-cwd-files run) (mapcar #'namestring (directory (merge-pathnames "*.*" *default-pathname-defaults*)
                                                                :resolve-symlinks nil)))
    run))

(defun fz-close-run (run)
  "Delete RUN's directory."
  (uiop:delete-directory-tree (fzrun-directory run) :validate (lambda (p) (search "/tmp/player-fuzz-" (namestring p)))
                                                     :if-does-not-exist :ignore))

(defun fz-package-symbols ()
  "The symbols present in PLAYER-USER, as an EQ set."
  (let ((set (make-hash-table :test 'eq)) (package (find-package '#:player-user)))
    (do-symbols (symbol package)
      (when (eq (symbol-package symbol) package) (setf (gethash symbol set) t)))
    set))

(defun fz-forget-new-symbols (run)
  "Unintern the symbols cases interned in PLAYER-USER since RUN began, so a
long run does not grow without bound."
  (let ((package (find-package '#:player-user)) (new '()) (old (fzrun-symbols run)))
    (do-symbols (symbol package)
      (when (and (eq (symbol-package symbol) package) (not (gethash symbol old)))
        (push symbol new)))
    (dolist (symbol new) (unintern symbol package))))

(defun fz-case-file (case run)
  "Where CASE's file goes in RUN."
  (merge-pathnames (if (eq (fzc-target case) :spec) "fuzz-case.lisp" "fuzz-library.lisp")
                   (fzrun-directory run)))

(defun fz-case-file-text (case run)
  "CASE's text with the marker file's name filled in."
  (fz-replace-all (fzc-text case) *fz-marker-placeholder* (namestring (fzrun-marker run))))

(defun fz-write-case-file (text path)
  "Write TEXT to PATH as UTF-8, each raw-byte stand-in as its byte."
  (with-open-file (out path :direction :output :if-exists :supersede :element-type '(unsigned-byte 8))
    (let ((start 0))
      (flet ((flush (end)
               (when (< start end)
                 (write-sequence (sb-ext:string-to-octets text :external-format :utf-8 :start start :end end) out))))
        (loop for i from 0 below (length text)
              for code = (char-code (char text i))
              when (<= #xE000 code #xE0FF)
                do (flush i) (write-byte (- code #xE000) out) (setf start (1+ i)))
        (flush (length text)))))
  path)

;;; ---------------------------------------------------------------------------
;;; Running one case, protected

(defvar *fz-phase* nil "What the case is doing: :load, :compile, :send-event...")
(defvar *fz-warnings* 0 "Warnings signalled during the case.")
(defvar *fz-violations* nil "Side effects found during the case.")

(defun fz-protected (thunk timeout)
  "Call THUNK with the debugger and the terminal out of reach and a time limit.
Returns (VALUES OUTCOME CONDITION): :OK and THUNK's value, :PLAYER-ERROR,
:ESCAPED (any other serious condition, or any condition given to ERROR that
nobody handled) or :TIMEOUT."
  (let ((tag (list :fz-escape))
        (null-output (make-broadcast-stream)))
    (catch tag
      (flet ((escape (condition hook)
               (declare (ignore hook))
               (throw tag (values :escaped condition))))
        (handler-case
            (let ((*debugger-hook* #'escape)
                  (sb-ext:*invoke-debugger-hook* #'escape)
                  (*standard-output* null-output) (*error-output* null-output) (*trace-output* null-output)
                  (*standard-input* (make-string-input-stream ""))
                  (*terminal-io* (make-two-way-stream (make-string-input-stream "") null-output))
                  (*query-io* (make-two-way-stream (make-string-input-stream "") null-output))
                  (*debug-io* (make-two-way-stream (make-string-input-stream "") null-output))
                  (*print-readably* nil) (*print-circle* nil) (*print-length* nil) (*print-level* nil))
              (handler-bind ((warning (lambda (w)
                                        (incf *fz-warnings*)
                                        (let ((restart (find-restart 'muffle-warning w)))
                                          (when restart (invoke-restart restart))))))
                (sb-ext:with-timeout timeout
                  (values :ok (funcall thunk)))))
          (sb-ext:timeout (c) (values :timeout c))
          (player-error (c) (values :player-error c))
          (serious-condition (c) (values :escaped c)))))))

(defun fz-condition-message (condition timeout)
  "CONDITION's report as one string; (VALUES NIL ESCAPE) when printing the
report itself escapes or hangs."
  (multiple-value-bind (outcome value) (fz-protected (lambda () (princ-to-string condition)) timeout)
    (if (eq outcome :ok)
        value
        (values nil value outcome))))

(defun fz-events-to-send (machine prng)
  "MACHINE's events in order (the first 16), then two more chosen by PRNG:
deleting one event from a spec leaves the others sent as before."
  (let ((names (event-names machine)))
    (when names
      (append (subseq names 0 (min 16 (length names)))
              (loop repeat 2 collect (fz-pick prng names))))))

(defun fz-emit-p (case run)
  "Does CASE get emitted as C++? Every EMIT-EVERYth case, and every case with a hostile rename."
  (and (fzrun-emit-every run)
       (or (zerop (mod (fzc-index case) (fzrun-emit-every run)))
           (intersection (fzc-kinds case) '(:rename-c++ :collide :c++-token :rename-unicode :unicode-token)))))

(defun fz-run-spec (case run file prng)
  "The body of a spec case: load, then compile, control, check and emit every spec it defines."
  (setf *fz-phase* :load)
  (let ((specs (ecase (fzc-mode case)
                 ((:text :form-file) (load-spec file))
                 (:memory (let ((forms (fzc-forms case)))
                            (list (define-spec (if (consp forms) (car forms) forms)
                                               (if (consp forms) (cdr forms) nil)
                                               :package (find-package '#:player-user))))))))
    (setf *fz-phase* :returned-specs)
    (unless (listp specs) (error "load-spec returned ~S, not a list" (type-of specs)))
    (loop for spec in specs
          repeat 3
          do (setf *fz-phase* :compile)
             (let ((machine (compile-spec spec)))
               (setf *fz-phase* :make-controller)
               (let ((controller (make-controller machine :presenter (make-null-presenter))))
                 (setf *fz-phase* :send-event)
                 (dolist (event (fz-events-to-send machine prng))
                   (send-event controller event)))
               (setf *fz-phase* :check-spec)
               (check-spec machine)
               (when (fz-emit-p case run)
                 (setf *fz-phase* :emit-c++)
                 (fz-emit case run machine))))
    :accepted))

(defun fz-emit (case run machine)
  "Emit MACHINE as C++ into RUN's emit directory; record a violation for a file
written anywhere else, then empty the directory."
  (let* ((emit (fzrun-emit run))
         (paths (emit-c++ machine emit))
         (inside (namestring (truename emit))))
    (dolist (path paths)
      (let ((true (probe-file path)))
        (unless (and true (eql 0 (search inside (namestring true))))
          (push (format nil "emit-c++ wrote outside its directory: ~A" (fz-visible (namestring path)))
                *fz-violations*))))
    (when (fzrun-emit-hook run)
      (funcall (fzrun-emit-hook run) case (directory (merge-pathnames "*.*" emit))))
    (dolist (path (directory (merge-pathnames "*.*" emit)))
      (delete-file path))))

(defvar *fz-companion-specs* (make-hash-table :test 'equal)
  "The spec objects of the library bases' specs, parsed once (not registered).")

(defun fz-companion-spec (name)
  "The spec object of spec base NAME (e.g. \"peedy\"), parsed once and not left in the registry."
  (or (gethash name *fz-companion-specs*)
      (setf (gethash name *fz-companion-specs*)
            (let* ((base (fz-base name))
                   (form (find-if #'fz-defspec-form-p (fzb-forms base))))
              (prog1 (define-spec (second form) (cddr form) :package (find-package '#:player-user)
                                                             :source-file (checkout-file (second (assoc name *fz-spec-files* :test #'string=))))
                (remove-spec (second form)))))))

(defun fz-run-library (case run file prng)
  "The body of a library case: load it, check its spec's scripts against it, and sometimes play it."
  (setf *fz-phase* :load)
  (let ((library (ecase (fzc-mode case)
                   ((:text :form-file) (load-script-library file))
                   (:memory (player::parse-script-library-forms (fzc-forms case) :source (fz-case-file case run))))))
    (when (fzc-companion case)
      (let ((spec (fz-companion-spec (fzc-companion case))))
        (setf *fz-phase* :check-scripts)
        (player::check-spec-scripts spec library)
        (when (and (fzrun-play-every run) (zerop (mod (fzc-index case) (fzrun-play-every run))))
          (setf *fz-phase* :play)
          (let* ((presenter (make-body-presenter spec :scripts library))
                 (machine (compile-spec spec))
                 (controller (make-controller machine :presenter presenter)))
            (dolist (event (fz-events-to-send machine prng))
              (send-event controller event))
            (dolist (time '(0 0.5 2.5))
              (performance-frame (presenter-performance presenter) time))))))
    :accepted))

;;; The registry

(defun fz-registry ()
  "The registered specs, as a list of spec objects."
  (loop for name in (list-specs) for spec = (find-spec name nil) when spec collect spec))

(defun fz-restore-registry (before case file)
  "Check the registry against BEFORE (a list of spec objects): new specs must
come from CASE's FILE (or, in memory mode, be its spec). Remove them and put
back any spec they replaced; return the violations."
  (let* ((after (fz-registry))
         (file-name (and file (probe-file file) (namestring (truename file))))
         (memory-name (and (eq (fzc-mode case) :memory) (consp (fzc-forms case)) (car (fzc-forms case))))
         (violations '()))
    (dolist (spec after)
      (unless (member spec before)
        (let ((source (ignore-errors (spec-source-file spec))))
          (unless (or (and file-name source (ignore-errors (equal (namestring (truename source)) file-name)))
                      (and memory-name (symbolp memory-name)
                           (string-equal (symbol-name memory-name) (symbol-name (spec-name spec)))))
            (push (format nil "registry gained a spec the case did not define: ~A"
                          (fz-bounded-text (spec-name spec) :limit 80))
                  violations)))
        (remove-spec (spec-name spec))))
    (let ((table (symbol-value (find-symbol "*SPECS*" '#:player)))
          (key (fdefinition (find-symbol "NAME-KEY" '#:player))))
      (dolist (spec before)
        (unless (eq (find-spec (spec-name spec) nil) spec)
          (unless (find (spec-name spec) after :key #'spec-name :test #'string-equal)
            (push (format nil "spec disappeared from the registry: ~A" (fz-bounded-text (spec-name spec) :limit 80))
                  violations))
          (setf (gethash (funcall key (spec-name spec)) table) spec))))
    violations))

;;; Side effects

(defparameter *fz-payload-symbols* '("*FUZZ-PAYLOAD-VAR*" "FUZZ-PAYLOAD-FN" "FUZZ-PAYLOAD-MACRO")
  "The PLAYER-USER symbols the payloads set or define.")

(defun fz-side-effects (run case)
  "The side effects the case left: the marker file, payload symbols, a payload
package, files in the run directory that do not belong there. Each is undone."
  (let ((violations '()))
    (when (probe-file (fzrun-marker run))
      (push "marker file created: a payload ran" violations)
      (delete-file (fzrun-marker run)))
    (dolist (name *fz-payload-symbols*)
      (let ((symbol (find-symbol name '#:player-user)))
        (when symbol
          (when (boundp symbol)
            (push (format nil "payload symbol set: player-user::~A" name) violations)
            (makunbound symbol))
          (when (fboundp symbol)
            (push (format nil "payload function defined: player-user::~A" name) violations)
            (fmakunbound symbol)))))
    (let ((package (find-package "PLAYER-FUZZ-PAYLOAD-PACKAGE")))
      (when package
        (push "payload package defined: player-fuzz-payload-package" violations)
        (delete-package package)))
    (let ((allowed (list* (namestring (fz-case-file case run)) (fzrun-expected run))))
      (dolist (path (directory (merge-pathnames "**/*.*" (fzrun-directory run)) :resolve-symlinks nil))
        (when (and (pathname-name path) (not (member (namestring path) allowed :test #'string=)))
          (push (format nil "file outside the emit directory: ~A" (fz-visible (namestring path))) violations)
          (ignore-errors (delete-file path)))))
    ;; Relative names land in the working directory: look there for what a
    ;; payload or a code generator would leave (not for other people's files).
    (dolist (path (directory (merge-pathnames "*.*" *default-pathname-defaults*) :resolve-symlinks nil))
      (when (and (pathname-name path)
                 (not (member (namestring path) (fzrun-cwd-files run) :test #'string=))
                 (or (member (pathname-type path) '("hpp" "cpp" "h") :test #'equal)
                     (search "fuzz" (namestring path)) (search "marker" (file-namestring path))))
        (push (namestring path) (fzrun-cwd-files run))          ; reported once
        (push (format nil "file in the working directory: ~A" (fz-visible (namestring path))) violations)))
    violations))

(defun fz-new-result (case run)
  "A FZ-RESULT describing CASE, its outcome not yet known."
  (let ((text (and (fzc-text case) (fz-case-file-text case run))))
    (make-fz-result :seed (fzc-seed case) :index (fzc-index case) :target (fzc-target case)
                    :mode (fzc-mode case) :base (fzc-base case) :kinds (fzc-kinds case)
                    :notes (fzc-notes case) :size (if text (length text) 0)
                    :excerpt (if text
                                 (fz-excerpt text (fzc-base-text case))
                                 (fz-bounded-text (fzc-forms case) :length 12 :level 5 :limit 400)))))

(defun fz-execute (case run)
  "Run CASE in RUN and return its FZ-RESULT."
  (let* ((file (and (member (fzc-mode case) '(:text :form-file)) (fz-case-file case run)))
         (text (and file (fz-case-file-text case run)))
         (prng (make-fz-prng (fzc-seed case) (fzc-index case) #x72756E))
         (before (fz-registry))
         (start (get-internal-real-time))
         (*fz-phase* :write)
         (*fz-warnings* 0)
         (*fz-violations* '())
         (result (fz-new-result case run)))
    (when file (fz-write-case-file text file))
    (multiple-value-bind (outcome condition)
        (fz-protected (lambda ()
                        (if (eq (fzc-target case) :spec)
                            (fz-run-spec case run file prng)
                            (fz-run-library case run file prng)))
                      (fzrun-timeout run))
      (setf (fzr-phase result) *fz-phase*)
      (ecase outcome
        (:ok (setf (fzr-outcome result) :accepted))
        ((:player-error :escaped :timeout)
         (setf (fzr-outcome result) outcome
               (fzr-condition result) condition
               (fzr-condition-type result) (type-of condition))
         (multiple-value-bind (message escape escape-outcome) (fz-condition-message condition (fzrun-timeout run))
           (if message
               (setf (fzr-message result) (fz-clip message 300))
               ;; Reporting the condition failed: that is the escape.
               (setf (fzr-outcome result) (if (eq escape-outcome :timeout) :timeout :escaped)
                     (fzr-phase result) :report
                     (fzr-condition-type result) (type-of escape)
                     (fzr-message result) (format nil "printing the ~A report: ~A" (type-of condition)
                                                  (fz-clip (ignore-errors (princ-to-string escape)) 200))))))))
    (setf (fzr-violations result)
          (append (reverse *fz-violations*)
                  (fz-side-effects run case)
                  (fz-restore-registry before case file)))
    (setf (fzr-warnings result) *fz-warnings*
          (fzr-seconds result) (/ (- (get-internal-real-time) start) internal-time-units-per-second))
    (fz-forget-new-symbols run)
    (when file (ignore-errors (delete-file file)))
    result))

;;; ---------------------------------------------------------------------------
;;; Runs and summaries

(defstruct (fz-summary (:conc-name fzs-))
  "The results of a run: FAILURES holds every failed FZ-RESULT; the rest are counted."
  seed (cases 0) (seconds 0)
  (outcomes (make-hash-table :test 'equal))     ; outcome label -> count
  (kinds (make-hash-table :test 'eq))           ; kind -> #(cases accepted player-error failed)
  (failures '())
  (slowest '()))                                ; the five slowest results

(defun fz-outcome-label (result)
  "RESULT's outcome as a table row label."
  (ecase (fzr-outcome result)
    (:accepted "accepted")
    (:player-error (format nil "player-error ~A" (fz-type-name (fzr-condition-type result))))
    (:escaped (format nil "ESCAPED ~A" (fz-type-name (fzr-condition-type result))))
    (:timeout "TIMEOUT")
    (:crashed (format nil "CRASHED ~A" (fzr-condition-type result)))
    (:hung "HUNG (the process stopped answering)")))

(defun fz-type-name (type)
  "TYPE (a symbol) with its package unless it is PLAYER's or CL's."
  (if (and (symbolp type) (member (symbol-package type) (list (find-package '#:player) (find-package '#:cl))))
      (symbol-name type)
      (let ((*package* (find-package '#:keyword))) (prin1-to-string type))))

(defun fz-summarize (summary result)
  "Count RESULT into SUMMARY."
  (incf (fzs-cases summary))
  (incf (gethash (fz-outcome-label result) (fzs-outcomes summary) 0))
  (when (fzr-violations result)
    (incf (gethash "SIDE EFFECT" (fzs-outcomes summary) 0)))
  (dolist (kind (remove-duplicates (fzr-kinds result)))
    (let ((row (or (gethash kind (fzs-kinds summary))
                   (setf (gethash kind (fzs-kinds summary)) (make-array 4 :initial-element 0)))))
      (incf (aref row 0))
      (incf (aref row (cond ((fzr-failed-p result) 3) ((eq (fzr-outcome result) :accepted) 1) (t 2))))))
  (when (fzr-failed-p result)
    (push result (fzs-failures summary)))
  (let* ((all (cons result (fzs-slowest summary)))
         (count (min 5 (length all))))
    (setf (fzs-slowest summary) (subseq (sort all #'> :key #'fzr-seconds) 0 count))))

(defun fz-prepare ()
  "Read the bases and parse the library bases' specs, once, outside any case."
  (fz-bases)
  (dolist (entry *fz-library-files*) (fz-companion-spec (third entry))))

(defun fuzz-run (&key (seed 1) (cases 2000) (start 0) (timeout 10) (emit-every 5) (play-every 10)
                      emit-hook progress (isolate t))
  "Generate and run CASES cases of SEED (numbered from START) and return a FZ-SUMMARY.
With ISOLATE (the default) the cases run in forked child processes, so a case
that kills SBCL is reported and the run goes on. PROGRESS, a stream, gets a dot
every 1,000 cases."
  (fz-prepare)
  (let ((run (fz-open-run :timeout timeout :emit-every emit-every :play-every play-every))
        (summary (make-fz-summary :seed seed))
        (begin (get-internal-real-time)))
    (setf (fzrun-emit-hook run) emit-hook)
    (flet ((record (result)
             (fz-summarize summary result)
             (when (and progress (zerop (mod (1+ (fzr-index result)) 1000)))
               (format progress ".~:[~;~%~]" (zerop (mod (1+ (fzr-index result)) 50000)))
               (force-output progress))))
      (unwind-protect
           (if isolate
               (fz-run-forked run (lambda (index) (fz-generate seed index)) start (+ start cases) #'record)
               (loop for index from start below (+ start cases)
                     do (record (fz-execute (fz-generate seed index) run))))
        (fz-close-run run)))
    (setf (fzs-seconds summary) (/ (- (get-internal-real-time) begin) internal-time-units-per-second))
    summary))

(defun fuzz-case (seed index &key (timeout 10) keep-file (emit t) (play t) in-process)
  "Replay case INDEX of SEED in a fresh run directory and return its FZ-RESULT
(outcome, condition type, phase, message, violations). The case runs in a
forked child, as in FUZZ-RUN, unless IN-PROCESS: then it runs in this image and
FZR-CONDITION holds the condition itself (but a case that kills SBCL kills this
image too). With KEEP-FILE the case's file is also written to
/tmp/player-fuzz-SEED-INDEX.lisp, whose name is the second value."
  (fz-prepare)
  (let ((run (fz-open-run :timeout timeout :emit-every (and emit 1) :play-every (and play 1)))
        (case (fz-generate seed index))
        (result nil))
    (unwind-protect
         (progn
           (if in-process
               (setf result (fz-execute case run))
               (fz-run-forked run (lambda (i) (fz-generate seed i)) index (1+ index) (lambda (r) (setf result r))))
           (values result
                   (when (and keep-file (fzc-text case))
                     (fz-write-case-file (fz-case-file-text case run)
                                         (format nil "/tmp/player-fuzz-~D-~D.lisp" seed index)))))
      (fz-close-run run))))

;;; ---------------------------------------------------------------------------
;;; Running cases in child processes

(defparameter *fz-result-slots*
  '(fzr-seed fzr-index fzr-target fzr-mode fzr-base fzr-kinds fzr-notes fzr-outcome fzr-condition-type
    fzr-message fzr-phase fzr-violations fzr-excerpt fzr-size fzr-seconds fzr-warnings)
  "The readers of the FZ-RESULT slots a child sends its parent.")

(defun fz-send-result (result stream)
  "Write RESULT to STREAM as one readable form."
  (with-standard-io-syntax
    (let ((*print-readably* nil) (*print-pretty* nil))
      (prin1 (cons :result (mapcar (lambda (reader) (funcall reader result)) *fz-result-slots*)) stream)
      (terpri stream)
      (finish-output stream))))

(defun fz-receive-result (form)
  "The FZ-RESULT a child sent as FORM."
  (let ((result (make-fz-result)))
    (loop for reader in *fz-result-slots*
          for value in (rest form)
          do (funcall (fdefinition (list 'setf reader)) value result))
    result))

(defun fz-child (run make-case from to in out log)
  "In a forked child: run the cases MAKE-CASE makes of FROM below TO, sending each result
through the pipe OUT, with standard input from /dev/null and both outputs to
the file LOG (emptied before each case, so it holds what the last case printed).
Never returns."
  (sb-posix:close in)
  (let ((null (sb-posix:open "/dev/null" sb-posix:o-rdonly))
        (log-fd (sb-posix:open (namestring log) (logior sb-posix:o-wronly sb-posix:o-creat sb-posix:o-append)
                               #o644)))
    (sb-posix:dup2 null 0)
    (sb-posix:dup2 log-fd 1)
    (sb-posix:dup2 log-fd 2))
  (let ((stream (sb-sys:make-fd-stream out :output t :external-format :utf-8 :buffering :full)))
    (loop for index from from below to
          do (sb-posix:ftruncate 2 0)
             (let ((case nil))
               (handler-case (progn (setf case (funcall make-case index))
                                    (fz-send-result (fz-execute case run) stream))
                 (serious-condition (condition)
                   ;; The harness itself failed around the case (the registry
                   ;; could not be listed, say): an escape of that case.
                   (let ((result (make-fz-result :seed (and case (fzc-seed case)) :index index
                                                 :outcome :escaped :phase :harness
                                                 :condition-type (type-of condition)
                                                 :message (fz-clip (ignore-errors (princ-to-string condition))
                                                                           300))))
                     (ignore-errors (fz-send-result result stream)))))))
    (ignore-errors (prin1 '(:done) stream) (finish-output stream))
    (sb-ext:exit :code 0 :abort t)))

(defun fz-read-from-child (stream fd seconds)
  "The next form from a child: :EOF when it has gone, :TIMEOUT after SECONDS of silence."
  (if (or (listen stream) (sb-sys:wait-until-fd-usable fd :input seconds))
      (handler-case (with-standard-io-syntax
                      (let ((*read-eval* nil)) (read stream nil :eof)))
        (error () :eof))
      :timeout))

(defun fz-crash-reason (log-text)
  "What the runtime said when a child died: the line after 'fatal error', else
a line about exhaustion; NIL if neither."
  (let* ((lines (remove "" (mapcar (lambda (line) (string-trim '(#\Space #\Tab #\Return) line))
                                   (fz-split-lines log-text))
                        :test #'string=))
         (fatal (position-if (lambda (line) (search "fatal error" line)) lines))
         (line (cond (fatal (or (nth (1+ fatal) lines) (nth fatal lines)))
                     (t (find-if (lambda (line) (search "exhausted" line)) lines)))))
    (and line (subseq line 0 (or (position #\, line) (min (length line) 80))))))

(defun fz-dead-child-result (run make-case index wait-status hung log)
  "The FZ-RESULT of case INDEX (made by MAKE-CASE), during which the child died
(WAIT-STATUS) or was killed for not answering (HUNG)."
  (let* ((result (handler-case (sb-ext:with-timeout 20 (fz-new-result (funcall make-case index) run))
                   (serious-condition (c)
                     (make-fz-result :index index
                                     :notes (list (format nil "the case cannot be made again here: ~A"
                                                          (type-of c)))))))
         (log-text (or (ignore-errors (let ((text (alexandria:read-file-into-string log :external-format :latin-1)))
                                        (subseq text 0 (min (length text) 4000))))
                       ""))
         (status (cond (hung "was killed after it stopped answering")
                       ((null wait-status) "vanished")
                       ((sb-posix:wifsignaled wait-status)
                        (format nil "was killed by signal ~D" (sb-posix:wtermsig wait-status)))
                       ((sb-posix:wifexited wait-status)
                        (format nil "exited with status ~D" (sb-posix:wexitstatus wait-status)))
                       (t (format nil "ended with status ~D" wait-status)))))
    (setf (fzr-outcome result) (if hung :hung :crashed)
          (fzr-phase result) :process
          (fzr-condition-type result) (or (fz-crash-reason log-text) status)
          (fzr-message result) (format nil "the process ~A; it printed: ~A" status
                                       (fz-visible (subseq log-text 0 (min (length log-text) 300)))))
    result))

(defun fz-run-forked (run make-case from to record)
  "Run the cases MAKE-CASE makes of FROM below TO in forked children, calling
RECORD with each FZ-RESULT in order. A child that dies or stops answering costs the case
it was running (recorded :CRASHED or :HUNG); a new child starts after it.
Where fork is refused (other threads running), the cases run in this process."
  (let ((next from)
        (log (merge-pathnames "child.log" (fzrun-directory run)))
        (patience (or (fzrun-patience run) (+ 20 (* 3 (fzrun-timeout run))))))
    (pushnew (namestring log) (fzrun-expected run) :test #'string=)
    (loop while (< next to)
          do (multiple-value-bind (in out) (sb-posix:pipe)
               (finish-output *standard-output*)
               (finish-output *error-output*)
               (let ((pid (handler-case (sb-posix:fork)
                            (error ()
                              (sb-posix:close in)
                              (sb-posix:close out)
                              (format *error-output* "~&; fuzz: fork refused (threads: ~{~A~^, ~}); ~
                                                      the cases run in this process, unprotected from crashes~%"
                                      (mapcar #'sb-thread:thread-name (sb-thread:list-all-threads)))
                              (loop for index from next below to
                                    do (funcall record (fz-execute (funcall make-case index) run)))
                              (return-from fz-run-forked)))))
                 (when (zerop pid)
                   (fz-child run make-case next to in out log))
                 (sb-posix:close out)
                 (let ((stream (sb-sys:make-fd-stream in :input t :external-format :utf-8 :buffering :full))
                       (last (1- next))
                       (hung nil))
                   (unwind-protect
                        (loop (let ((form (fz-read-from-child stream in patience)))
                                (cond ((eq form :timeout)
                                       (setf hung t)
                                       (ignore-errors (sb-posix:kill pid sb-posix:sigkill))
                                       (return))
                                      ((and (consp form) (eq (first form) :result))
                                       (let ((result (fz-receive-result form)))
                                         (setf last (fzr-index result))
                                         (funcall record result)))
                                      (t (return)))))
                     (close stream))
                   (let ((status (nth-value 1 (ignore-errors (sb-posix:waitpid pid 0)))))
                     (if (>= (1+ last) to)
                         (setf next to)
                         (progn (funcall record (fz-dead-child-result run make-case (1+ last) status hung log))
                                (setf next (+ 2 last)))))))))))

(defun fuzz-case-text (seed index)
  "The text case INDEX of SEED writes (the marker file named by placeholder
@MARKER@), or, for a memory case, its forms."
  (let ((case (progn (fz-bases) (fz-generate seed index))))
    (or (fzc-text case) (fzc-forms case))))

(defun fz-failure-groups (failures)
  "FAILURES grouped by what went wrong: ((LABEL COUNT PHASES EXAMPLE
MEMORY-EXAMPLE OTHERS) ...), largest groups first. EXAMPLE is the file case with
the shortest input (else the first memory case); MEMORY-EXAMPLE, when EXAMPLE
is a file case, the first memory case of the group; OTHERS the first case of
each other cause ((SIGNATURE . RESULT) ...), told apart by FZ-SIGNATURE."
  (let ((groups (make-hash-table :test 'equal)))
    (dolist (result failures)
      (let ((labels (append (when (member (fzr-outcome result) *fz-failing-outcomes*)
                              (list (fz-outcome-label result)))
                            (mapcar (lambda (v) (format nil "SIDE EFFECT ~A" (subseq v 0 (or (search ": " v) (length v)))))
                                    (fzr-violations result)))))
        (dolist (label (remove-duplicates labels :test #'string=))
          (let ((entry (or (gethash label groups) (setf (gethash label groups) (list 0 '() nil nil '())))))
            (incf (first entry))
            (pushnew (fzr-phase result) (second entry))
            (let ((signature (fz-signature result)))
              (unless (assoc signature (fifth entry) :test #'string=)
                (setf (fifth entry) (append (fifth entry) (list (cons signature result))))))
            (if (eq (fzr-mode result) :memory)
                (unless (fourth entry) (setf (fourth entry) result))
                (when (or (null (third entry))
                          (< (fzr-size result) (fzr-size (third entry)))
                          (and (= (fzr-size result) (fzr-size (third entry)))
                               (< (fzr-index result) (fzr-index (third entry)))))
                  (setf (third entry) result)))))))
    (sort (loop for label being the hash-keys of groups using (hash-value (count phases file memory kinds))
                for example = (or file memory)
                collect (list label count (reverse phases) example (and file memory)
                              (remove (fz-signature example) kinds :key #'car :test #'string=)))
          #'> :key #'second)))

(defun fz-signature (result)
  "What distinguishes one cause from another within a failure group: the phase
and the message, digits and long tails left out."
  (let ((text (format nil "~(~A~): ~A" (fzr-phase result) (or (fzr-message result) ""))))
    (with-output-to-string (out)
      (loop with previous-digit = nil
            for char across (subseq text 0 (min 120 (length text)))
            do (if (digit-char-p char)
                   (unless previous-digit (write-char #\N out))
                   (write-char char out))
               (setf previous-digit (digit-char-p char))))))

(defun fz-describe-example (result stream)
  "Write RESULT as a reproducer."
  (format stream "    seed ~D case ~D: ~(~A ~A, base ~A~); replay: (player-tests::fuzz-case ~D ~D)~%"
          (fzr-seed result) (fzr-index result) (fzr-mode result) (fzr-target result) (fzr-base result)
          (fzr-seed result) (fzr-index result))
  (format stream "    phase ~(~A~); mutations: ~{~A~^; ~}~%" (fzr-phase result) (fzr-notes result))
  (when (fzr-message result)
    (format stream "    message: ~A~%" (fzr-message result)))
  (when (fzr-violations result)
    (format stream "    side effects: ~{~A~^; ~}~%" (fzr-violations result)))
  (format stream "    input: ~A~%" (fzr-excerpt result)))

(defun fz-write-group (group stream)
  "Write one group of FZ-FAILURE-GROUPS: what, how often, where, a reproducer."
  (destructuring-bind (label count phases example memory-example others) group
    (format stream "~A: ~D case~:P (phase~P ~(~{~A~^, ~}~))~%" label count (length phases) phases)
    (fz-describe-example example stream)
    (when memory-example
      (format stream "    also in memory, without a file: (player-tests::fuzz-case ~D ~D): ~{~A~^; ~}~%"
              (fzr-seed memory-example) (fzr-index memory-example) (fzr-notes memory-example)))
    (when others
      (format stream "    other causes:~%")
      (loop for (signature . result) in others
            repeat 6
            do (format stream "      ~A ~~ (player-tests::fuzz-case ~D ~D), ~(~A~)~%"
                       signature (fzr-seed result) (fzr-index result) (fzr-mode result)))
      (when (> (length others) 6)
        (format stream "      ... and ~D more~%" (- (length others) 6))))))

(defun fz-failure-report (failures &optional (stream nil))
  "The failures, grouped, one reproducer each, as a string (or written to STREAM)."
  (flet ((write-report (out)
           (dolist (group (fz-failure-groups failures))
             (fz-write-group group out))))
    (if stream (write-report stream) (with-output-to-string (out) (write-report out)))))

(defun fz-report (summary &optional (stream *standard-output*))
  "Print SUMMARY: outcomes, mutation kinds, the slowest cases and the failures."
  (format stream "~&Fuzzing: seed ~D, ~:D cases in ~,1F s (~,1F ms a case)~%"
          (fzs-seed summary) (fzs-cases summary) (fzs-seconds summary)
          (if (plusp (fzs-cases summary)) (/ (* 1000 (fzs-seconds summary)) (fzs-cases summary)) 0))
  (format stream "~%  ~40A ~8@A~%" "outcome" "cases")
  (let ((rows (sort (alexandria:hash-table-alist (fzs-outcomes summary)) #'string< :key #'car)))
    (loop for (label . count) in rows do (format stream "  ~40A ~8:D~%" label count)))
  (format stream "~%  ~18A ~8@A ~9@A ~13@A ~7@A~%" "mutation kind" "cases" "accepted" "player-error" "failed")
  (let ((rows (sort (alexandria:hash-table-alist (fzs-kinds summary)) #'string< :key (lambda (r) (symbol-name (car r))))))
    (loop for (kind . row) in rows
          do (format stream "  ~18A ~8:D ~9:D ~13:D ~7:D~%" (string-downcase kind) (aref row 0) (aref row 1) (aref row 2) (aref row 3))))
  (format stream "~%  slowest cases:~{ ~A~^,~}~%"
          (mapcar (lambda (r) (format nil "~D (~,2F s)" (fzr-index r) (fzr-seconds r))) (fzs-slowest summary)))
  (if (fzs-failures summary)
      (progn (format stream "~%~D failing case~:P, by kind (one reproducer each):~%" (length (fzs-failures summary)))
             (fz-failure-report (reverse (fzs-failures summary)) stream))
      (format stream "~%No escapes, hangs or side effects.~%"))
  summary)

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
