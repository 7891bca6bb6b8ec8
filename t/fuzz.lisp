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
