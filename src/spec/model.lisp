;;;; model.lisp -- the parsed, validated form of a spec: plain structures.
;;;; PARSE turns a DEFSPEC's forms into these; the planner and code generators
;;;; read only these, never the raw forms (except to quote them in messages).

(in-package #:player.spec)

(defstruct (spec (:constructor %make-spec))
  "A parsed controller spec."
  (name nil :type symbol)
  (documentation nil :type (or null string))
  (max-depth 16 :type (integer 0))
  ;; Plist of (:KEY VALUE) options besides :MAX-DEPTH.
  (options '() :type list)
  ;; VARIABLE-DEFs in declaration order.
  (variables '() :type list)
  ;; Name string -> CLASS-DEF.
  (classes (make-hash-table :test 'equal))
  ;; OP-DEFs (ops and macro-ops) in declaration order.
  (ops '() :type list)
  ;; AUTOSCRIPT-DEFs in declaration order.
  (autoscripts '() :type list)
  ;; EVENT-DEFs in declaration order.
  (events '() :type list)
  ;; TIMER-DEFs and TRIGGER-DEFs in declaration order (timed controllers only).
  (timers '() :type list)
  (triggers '() :type list)
  ;; Slots in the labels array.
  (label-count 0 :type (integer 0))
  ;; Bits of the one-hot plannable state.
  (bit-count 0 :type (integer 0))
  ;; The DEFSPEC body as written.
  (forms '() :type list)
  ;; Pathname the spec was loaded from, or NIL.
  (source-file nil)
  ;; Its top-level forms -> (FILE . POSITION), so errors found after parsing
  ;; (when it is planned) still name the line of the form at fault.
  (form-places (make-hash-table :test 'eq))
  ;; Each :code form -> ((FILE . POSITION) . LABEL): where it is written and
  ;; the label of the form holding it, for errors found when it is compiled.
  (code-places (make-hash-table :test 'eq))
  ;; Package the spec's forms were read in.
  (package *package*))

(defstruct (variable-def (:conc-name var-))
  "A state or time variable. KIND is :BOOLEAN or :ENUMERATED (plannable),
:NUMBER (runtime-only integer/float) or :TIME."
  (name nil :type symbol)
  (type :boolean :type (member :boolean :integer :float :string :time))
  (kind :boolean :type (member :boolean :enumerated :number :time))
  (initial nil)
  ;; Values of a plannable variable, by value index.
  (domain #() :type simple-vector)
  ;; For a time variable: the event names that set it.
  (events '() :type list)
  ;; First bit of a plannable variable's one-hot field.
  (bit-offset 0 :type (integer 0))
  ;; Index in the runtime values vector (numbers and times).
  (slot 0 :type (integer 0))
  (form nil))

(defun plannable-p (var)
  "True when VAR is part of the planned (one-hot encoded) state."
  (member (var-kind var) '(:boolean :enumerated)))

(defun var-domain-size (var)
  "Number of values of plannable VAR."
  (length (var-domain var)))

(defun var-field-mask (var)
  "The bits of plannable VAR's one-hot field."
  (ash (1- (ash 1 (var-domain-size var))) (var-bit-offset var)))

(defun var-value-bit (var index)
  "The single bit meaning 'VAR has its INDEXth value'."
  (ash 1 (+ (var-bit-offset var) index)))

(defstruct (class-def (:conc-name state-class-))
  "A state class: a named conjunction where later elements override earlier ones."
  (name nil :type symbol)
  ;; Parsed expressions, in order.
  (elements '() :type list)
  (form nil)
  ;; Cached canonical DNF (list of cubes), computed on first use.
  (dnf nil))

(defstruct (op-def (:conc-name op-))
  "An operator or macro-operator. KIND is :SCRIPT, :DIRECTOR, :CODE or :MACRO."
  (name nil :type symbol)
  (kind :script :type (member :script :director :code :macro))
  (script nil :type symbol)
  (director nil :type symbol)
  ;; Lisp form run for a :CODE op.
  (code nil)
  (c++ nil :type (or null string))
  ;; The :PRECOND expression as written, or NIL.
  (precond-form nil)
  ;; Parsed :PRECOND expression, or NIL for none.
  (precond nil)
  ;; ((VARIABLE-DEF . VALUE-INDEX) ...), adds and subs merged.
  (effects '() :type list)
  (must-ask nil :type boolean)
  (duration 1d0 :type double-float)
  ;; For a macro: parsed directives of :SEQ.
  (seq '() :type list)
  ;; How a timed controller may cut the op short: :NEVER, :ANYTIME, or a
  ;; list of points, each seconds into the op or the name of a critical time
  ;; of its script.
  (interrupt :never)
  ;; Effects applied instead of OP's own when it is cut, as EFFECTS.
  (cut-effects '() :type list)
  ;; The body channels it declares (:channels), as lower-case strings; NIL
  ;; when undeclared (a script library may infer them).
  (channels '() :type list)
  (form nil))

(defun op-effect-mask (op)
  "The one-hot fields of the plannable variables OP sets."
  (loop for (var) in (op-effects op) sum (var-field-mask var)))

(defun op-effect-bits (op)
  "The value bits OP's effects set those fields to."
  (loop for (var . index) in (op-effects op) sum (var-value-bit var index)))

(defstruct (autoscript-def (:conc-name autoscript-))
  "Procedures that run while a variable holds a value."
  (variable nil :type (or null variable-def))
  ;; Value index (plannable) or number (runtime variable).
  (value-index 0)
  (procs '() :type list)
  (form nil))

(defun autoscript-value (auto)
  "The value AUTO watches for, as written in the trace."
  (let ((var (autoscript-variable auto)))
    (if (plannable-p var)
        (aref (var-domain var) (autoscript-value-index auto))
        (autoscript-value-index auto))))

(defstruct (event-def (:conc-name event-))
  "An event: a named sequence of directives."
  (name nil :type symbol)
  ;; Parsed directives (see PARSE-DIRECTIVES).
  (directives '() :type list)
  ;; Time variables this event sets.
  (time-variables '() :type list)
  ;; What a timed controller does when this event arrives while it is busy
  ;; (a member of *WHEN-BUSY-POLICIES*), or NIL for the spec's default.
  (when-busy nil :type symbol)
  (form nil))

(defstruct (timer-def (:conc-name timer-))
  "(timer NAME :after SECONDS :event EV [:repeat t] [:restart-on (EV...)]):
EV is sent AFTER seconds after the timer is armed (when the controller starts,
and again whenever one of RESTART-ON is sent)."
  (name nil :type symbol)
  (after 0d0 :type double-float)
  (event nil :type (or null event-def))
  (repeat nil :type boolean)
  ;; EVENT-DEFs that re-arm the timer, or :ANY for every event sent from outside.
  (restart-on '() :type (or list (eql :any)))
  (form nil))

(defstruct (trigger-def (:conc-name trigger-))
  "(trigger NAME :when EXPRESSION :event EV): EV is sent each time EXPRESSION
becomes true."
  (name nil :type symbol)
  ;; The parsed expression (runtime comparisons allowed).
  (condition nil)
  (event nil :type (or null event-def))
  (form nil))

;;;# At the REPL: one line each (DESCRIBE shows the slots)

(defmethod print-object ((spec spec) stream)
  (print-unreadable-object (spec stream :type t)
    (format stream "~A ~D var~:P, ~D op~:P, ~D event~:P" (lisp-text (spec-name spec))
            (length (spec-variables spec)) (length (spec-ops spec)) (length (spec-events spec)))))

(defmethod print-object ((var variable-def) stream)
  (print-unreadable-object (var stream :type t)
    (format stream "~A ~(~A~)~@[ ~A~]" (lisp-text (var-name var)) (var-type var)
            (and (eq (var-kind var) :enumerated) (bounded-lisp-text (coerce (var-domain var) 'list) 60)))))

(defmethod print-object ((op op-def) stream)
  (print-unreadable-object (op stream :type t)
    (format stream "~A ~(~A~) ~As" (lisp-text (op-name op)) (op-kind op) (format-number (op-duration op)))))

(defmethod print-object ((event event-def) stream)
  (print-unreadable-object (event stream :type t)
    (format stream "~A ~D directive~:P" (lisp-text (event-name event)) (length (event-directives event)))))

(defmethod print-object ((timer timer-def) stream)
  (print-unreadable-object (timer stream :type t)
    (format stream "~A ~As -> ~A" (lisp-text (timer-name timer)) (format-number (timer-after timer))
            (and (timer-event timer) (lisp-text (event-name (timer-event timer)))))))

(defmethod print-object ((trigger trigger-def) stream)
  (print-unreadable-object (trigger stream :type t)
    (format stream "~A -> ~A" (lisp-text (trigger-name trigger))
            (and (trigger-event trigger) (lisp-text (event-name (trigger-event trigger)))))))

(defmethod print-object ((class class-def) stream)
  (print-unreadable-object (class stream :type t)
    (write-string (lisp-text (state-class-name class)) stream)))

(defmethod print-object ((auto autoscript-def) stream)
  (print-unreadable-object (auto stream :type t)
    (if (autoscript-variable auto)
        (format stream "~A=~A ~A" (lisp-text (var-name (autoscript-variable auto)))
                (lisp-text (autoscript-value auto)) (bounded-lisp-text (autoscript-procs auto) 60))
        (write-string (bounded-lisp-text (autoscript-procs auto) 60) stream))))
