;;;; parse.lisp -- turn a DEFSPEC body into a SPEC structure.
;;;; Two passes: declarations first (so forms may refer to names defined later),
;;;; then the bodies of classes, ops, autoscripts and events.

(in-package #:player.spec)

(defparameter *default-max-depth* 16
  "Longest plan, in operators, the planner searches for when a spec gives no :MAX-DEPTH.")

(defun parse-spec (name body &key source-file (package *package*) form-positions)
  "Parse BODY, the forms after DEFSPEC NAME, into a validated SPEC.
Signals a SPEC-ERROR naming the offending form when BODY is malformed; with
FORM-POSITIONS (BODY's forms' character positions in SOURCE-FILE) the error
points at the line of the form it is about, and names that form."
  (let ((places (form-places body form-positions source-file)))
    (with-spec-context (:spec-name name
                        :spec (%make-spec :name name :forms body :source-file source-file
                                          :package package :max-depth *default-max-depth*
                                          :form-places places)
                        :form-places places)
      (let ((forms (parse-spec-header body)))
        (flet ((each-form (function)
                 (dolist (form forms)
                   (with-spec-context (:source-position (or (gethash form places) *source-position*)
                                       :form-label (form-label form))
                     (funcall function form)))))
          (each-form #'declare-form)
          (assign-layout *spec*)
          (each-form #'define-form)))
      (parse-start-states *spec*)
      (validate-spec *spec*)
      *spec*)))

(defun form-places (body positions file)
  "A table from each form of BODY to its (FILE . POSITION), from POSITIONS."
  (let ((table (make-hash-table :test 'eq)))
    (when file
      (loop for form in body
            for position in positions
            when (consp form) do (setf (gethash form table) (cons file position))))
    table))

(defun form-kind (form)
  "The keyword naming FORM's kind, or a syntax error."
  (unless (and (consp form) (proper-list-p form) (symbolp (first form)))
    (spec-fail 'spec-syntax-error form "expected a spec form such as (state-variable ...) or (op ...)"))
  (or (loop for kind in '(:state-variable :time-variable :state-class :op :macro-op
                          :autoscript :event :timer :trigger)
            when (word-p (first form) (symbol-name kind)) return kind)
      (spec-fail 'spec-syntax-error form
                 "unknown form ~A (expected state-variable, time-variable, state-class, op, macro-op, autoscript, event, timer or trigger)"
                 (lisp-text (first form)))))

;;; Pass 1: declarations

(defun declare-form (form)
  "Register the name FORM defines; variables are parsed whole."
  (ecase (form-kind form)
    (:state-variable (add-variable (parse-state-variable form)))
    (:time-variable (add-variable (parse-time-variable form)))
    (:state-class (declare-class form))
    ((:op :macro-op) (declare-op form))
    ((:autoscript :timer :trigger))
    (:event (declare-event form))))

(defun check-new-expression-name (name form)
  "Signal DUPLICATE-DEFINITION if NAME already names a variable or class."
  (when (or (find-variable-named name) (find-class-named name))
    (spec-fail 'duplicate-definition form "~A is already defined as a ~:[state class~;variable~]"
               (lisp-text name) (find-variable-named name))))

(defun add-variable (var)
  "Append VAR to the spec's variables."
  (check-new-expression-name (var-name var) (var-form var))
  (setf (spec-variables *spec*) (append (spec-variables *spec*) (list var))))

(defun declare-class (form)
  "Register (state-class NAME (STATE...)); its elements are parsed in pass 2."
  (unless (= (length form) 3)
    (spec-fail 'spec-syntax-error form "expected (state-class NAME (STATE...))"))
  (let ((name (require-name (second form) form "a class name")))
    (check-new-expression-name name form)
    (setf (gethash (name-key name) (spec-classes *spec*))
          (make-class-def :name name :form form))))

(defvar *op-indexes* (make-hash-table :test 'eq :weakness :key :synchronized t)
  "Per spec: (COUNT . TABLE), its first COUNT ops by name key (see DEFINITION-INDEX).")

(defvar *event-indexes* (make-hash-table :test 'eq :weakness :key :synchronized t)
  "Per spec: (COUNT . TABLE), its first COUNT events by name key (see DEFINITION-INDEX).")

(defun definition-index (indexes spec list name-of)
  "A table from name keys to the definitions of LIST (SPEC's ops or events,
which only grow at their end), the first of each name; kept in INDEXES and
extended by the definitions added since, so that looking up each of 20,000
names while they are declared costs no walk of them all."
  (let ((entry (gethash spec indexes)) (count (length list)))
    (when (or (null entry) (> (car entry) count))
      (setf entry (cons 0 (make-hash-table :test 'equal))
            (gethash spec indexes) entry))
    (when (< (car entry) count)
      (dolist (definition (nthcdr (car entry) list))
        (let ((key (name-key (funcall name-of definition))))
          (unless (gethash key (cdr entry))
            (setf (gethash key (cdr entry)) definition))))
      (setf (car entry) count))
    (cdr entry)))

(defun find-op-named (name)
  "The op or macro-op of *SPEC* named NAME, or NIL."
  (and (symbolp name)
       (values (gethash (name-key name) (definition-index *op-indexes* *spec* (spec-ops *spec*) #'op-name)))))

(defun find-event-named (name)
  "The event of *SPEC* named NAME, or NIL."
  (and (symbolp name)
       (values (gethash (name-key name)
                        (definition-index *event-indexes* *spec* (spec-events *spec*) #'event-name)))))

(defun declare-op (form)
  "Register an op or macro-op by name."
  (unless (cdr form)
    (spec-fail 'spec-syntax-error form "expected (~A NAME ...)" (lisp-text (first form))))
  (let ((name (require-name (second form) form "an op name")))
    (when (find-op-named name)
      (spec-fail 'duplicate-definition form "op ~A is defined twice" (lisp-text name)))
    (setf (spec-ops *spec*)
          (append (spec-ops *spec*)
                  (list (make-op-def :name name :script name :form form
                                     :kind (if (eq (form-kind form) :macro-op) :macro :script)))))))

(defun declare-event (form)
  "Register an event by name."
  (unless (cdr form)
    (spec-fail 'spec-syntax-error form "expected (event NAME DIRECTIVE...)"))
  (let ((name (require-name (second form) form "an event name")))
    (when (find-event-named name)
      (spec-fail 'duplicate-definition form "event ~A is defined twice" (lisp-text name)))
    (setf (spec-events *spec*)
          (append (spec-events *spec*) (list (make-event-def :name name :form form))))))

(defun assign-layout (spec)
  "Give each plannable variable its one-hot bit field and each runtime variable its slot."
  (let ((bit 0) (slot 0))
    (dolist (var (spec-variables spec))
      (if (plannable-p var)
          (setf (var-bit-offset var) bit
                bit (+ bit (var-domain-size var)))
          (setf (var-slot var) slot
                slot (1+ slot))))
    (setf (spec-bit-count spec) bit)))

;;; Pass 2: bodies

(defun define-form (form)
  "Parse the body of FORM into the structure pass 1 registered."
  (ecase (form-kind form)
    ((:state-variable :time-variable))
    (:state-class (define-class form))
    (:op (define-op form))
    (:macro-op (define-macro-op form))
    (:autoscript (define-autoscript form))
    (:event (define-event form))
    (:timer (define-timer form))
    (:trigger (define-trigger form))))

(defun expression-form-p (list)
  "True when LIST reads as one expression rather than a list of elements."
  (or (word-p (first list) "NOT" "AND" "OR")
      (and (cddr list) (word-p (second list) "AND" "OR"))))

(defun define-class (form)
  "Parse a state class's elements."
  (let ((class (find-class-named (unquote (second form))))
        (states (unquote (third form))))
    (setf (state-class-elements class)
          (mapcar #'parse-expression
                  (cond ((not (listp states)) (list states))
                        ((not (proper-list-p states))
                         (spec-fail 'spec-syntax-error form "STATES must be a list"))
                        ((expression-form-p states) (list states))
                        (t states))))))

(defun literal-list (lits &optional form)
  "LITS (one literal or a proper list of them) as a list; a SPEC-SYNTAX-ERROR
about FORM for a dotted list."
  (cond ((not (listp lits)) (list lits))
        ((not (proper-list-p lits))
         (spec-fail 'spec-syntax-error form "~A is not a literal or a list of literals"
                    (bounded-lisp-text lits 60)))
        ((expression-form-p lits) (list lits))
        (t lits)))

(defun parse-effect (lit addp form)
  "Parse one :ADD (ADDP true) or :SUB literal of an op: (VARIABLE-DEF . VALUE-INDEX)."
  (let ((lit (unquote lit)))
    (unless (and (symbolp lit) lit)
      (spec-fail 'spec-syntax-error form "~:[:sub~;:add~] takes a boolean variable or var.value, not ~A"
                 addp (lisp-text lit)))
    (unless (or (find-variable-named lit)
                (some (lambda (split) (find-variable-named (car split))) (split-dotted lit)))
      (spec-fail 'unknown-name-error form "unknown variable ~A (~:[:sub~;:add~] takes a boolean variable or var.value)"
                 (lisp-text lit) addp))
    (let ((ast (handler-case (parse-expression lit)
                 (goal-error ()
                   (spec-fail 'effect-error form "ops cannot change runtime-only variable ~A; use :add (~A N) in an event"
                              (lisp-text lit) (lisp-text lit))))))
      (unless (eq (first ast) :lit)
        (spec-fail 'effect-error form "~A is not a variable literal" (lisp-text lit)))
      (destructuring-bind (var index) (rest ast)
        (cond (addp (cons var index))
              ((eq (var-kind var) :enumerated)
               (spec-fail 'effect-error form ":sub cannot be used on enumerated variable ~A; :add ~A.VALUE instead"
                          (lisp-text (var-name var)) (lisp-text (var-name var))))
              ((word-p lit (symbol-name (var-name var))) (cons var 0))
              (t (spec-fail 'effect-error form ":sub takes a bare boolean variable, not ~A"
                            (lisp-text lit))))))))

(defun parse-effects (options form)
  "The merged :ADD and :SUB effects of an op; contradictions are errors."
  (let ((effects (append (mapcar (lambda (l) (parse-effect l t form))
                                 (literal-list (getf options :add) form))
                         (mapcar (lambda (l) (parse-effect l nil form))
                                 (literal-list (getf options :sub) form)))))
    (loop for ((var . index) . rest) on effects
          for clash = (find var rest :key #'car)
          when (and clash (/= index (cdr clash)))
            do (spec-fail 'effect-error form "contradictory effects: ~A is set to both ~A and ~A"
                          (lisp-text (var-name var))
                          (lisp-text (aref (var-domain var) index))
                          (lisp-text (aref (var-domain var) (cdr clash)))))
    (remove-duplicates effects :test #'equal)))

(defun parse-precondition (options form)
  "The parsed :PRECOND of OPTIONS, or NIL when absent."
  (declare (ignore form))
  (when (member :precond options)
    (parse-expression (getf options :precond))))

(defun define-op (form)
  "Parse (op NAME [:script S | :director D | :code FORM] ...)."
  (let* ((op (find-op-named (unquote (second form))))
         (options (parse-options form (cddr form)
                                 '(:script :director :code :precond :add :sub :must-ask
                                   :duration :c++ :interrupt :if-cut :channels))))
    (when (> (count-if (lambda (k) (member k options)) '(:script :director :code)) 1)
      (spec-fail 'spec-syntax-error form "give only one of :script, :director and :code"))
    (cond ((member :director options)
           (setf (op-kind op) :director
                 (op-director op) (require-name (getf options :director) form "a director name")))
          ((member :code options)
           (setf (op-kind op) :code (op-code op) (note-code-form (getf options :code))))
          ((member :script options)
           (setf (op-script op) (require-name (getf options :script) form "a script name"))))
    (setf (op-precond-form op) (getf options :precond)
          (op-precond op) (parse-precondition options form)
          (op-effects op) (parse-effects options form)
          (op-must-ask op) (parse-flag (getf options :must-ask) form)
          (op-duration op) (parse-duration options form)
          (op-c++ op) (parse-c++ (getf options :c++) form)
          (op-interrupt op) (parse-interrupt (getf options :interrupt :never) form))
    (check-interruption-points op form)
    (when (member :channels options)
      (setf (op-channels op) (parse-channels (getf options :channels) form)))
    (when (member :if-cut options)
      (setf (op-cut-effects op) (parse-cut-effects (getf options :if-cut) op form)))))

(defun parse-flag (value form)
  "A boolean option's value."
  (multiple-value-bind (truth ok) (boolean-word value)
    (unless ok
      (spec-fail 'type-error-in-spec form "~A is not true or false" (lisp-text value)))
    truth))

(defun parse-duration (options form)
  "The :DURATION of OPTIONS in seconds (default 1)."
  (spec-seconds (getf options :duration 1) form ":duration" :minimum 0))

(defun parse-c++ (text form)
  "A :C++ option's text, which must be a string."
  (unless (or (null text) (stringp text))
    (spec-fail 'type-error-in-spec form ":c++ takes a string of C++ code"))
  text)

(defun define-macro-op (form)
  "Parse (macro-op NAME :precond EXPR [:add LITS] [:sub LITS] :seq (DIRECTIVE...))."
  (let ((op (find-op-named (unquote (second form))))
        (options (parse-options form (cddr form) '(:precond :add :sub :seq :c++))))
    (dolist (key '(:precond :seq))
      (unless (member key options)
        (spec-fail 'spec-syntax-error form "a macro-op needs ~A" (lisp-text key))))
    (let ((seq (getf options :seq)))
      (unless (and (proper-list-p seq) seq)
        (spec-fail 'spec-syntax-error form ":seq must be a non-empty list of directives"))
      (setf (op-precond-form op) (getf options :precond)
            (op-precond op) (parse-precondition options form)
            (op-effects op) (parse-effects options form)
            (op-c++ op) (parse-c++ (getf options :c++) form)
            (op-seq op) (parse-directives seq form :allowed '(:op :label :time))))))

(defun define-autoscript (form)
  "Parse (autoscript VAR VALUE (PROC...))."
  (unless (= (length form) 4)
    (spec-fail 'spec-syntax-error form "expected (autoscript VARIABLE VALUE (PROC...))"))
  (destructuring-bind (var-name value procs) (mapcar #'unquote (rest form))
    (let ((var (and (symbolp var-name) (find-variable-named var-name))))
      (unless var
        (spec-fail 'unknown-name-error form "unknown variable ~A" (lisp-text var-name)))
      (when (eq (var-kind var) :time)
        (spec-fail 'type-error-in-spec form "autoscripts cannot watch time variable ~A"
                   (lisp-text var-name)))
      (unless (and (proper-list-p procs) procs)
        (spec-fail 'spec-syntax-error form "PROCs must be a non-empty list of names"))
      (setf (spec-autoscripts *spec*)
            (append (spec-autoscripts *spec*)
                    (list (make-autoscript-def
                           :variable var
                           :value-index (if (plannable-p var)
                                            (value-index var value form)
                                            (runtime-number var value form))
                           :procs (mapcar (lambda (p) (require-name p form "a procedure name")) procs)
                           :form form)))))))

(defun runtime-number (var value form)
  "VALUE as a value of number variable VAR: an integer of 64 bits, or a finite
double for floats."
  (cond ((and (eq (var-type var) :integer) (int64-p value)) value)
        ((and (eq (var-type var) :float) (finite-real-p value)) (to-double value))
        (t (spec-fail 'type-error-in-spec form "~A is not ~:[a finite number~;an integer from -2^63 to 2^63-1~] for ~A"
                      (bounded-lisp-text value 40) (eq (var-type var) :integer) (lisp-text (var-name var))))))

(defun define-event (form)
  "Parse (event NAME [(:when-busy POLICY)] DIRECTIVE...)."
  (let ((event (find-event-named (unquote (second form)))))
    (setf (event-directives event)
          (parse-directives (parse-event-options event form) form))))
