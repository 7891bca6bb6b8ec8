;;;; ir.lisp -- the steps every code generator compiles: one structure per kind
;;;; of directive, with the planner's goals resolved. The Lisp-closure backend
;;;; (COMPILE-STEP) and the C++ backend dispatch on these same classes.

(in-package #:player.ir)

(defstruct (failure (:constructor make-failure (goal-form)))
  "What a step returns when its goal cannot be achieved: the goal as written."
  goal-form)

(defstruct ir-step
  "One directive of an event or macro-op.")

(defstruct (achieve-step (:include ir-step))
  "Run the plan that makes GOAL true (:state)."
  (goal nil :type goal)
  (failure nil :type failure))

(defstruct (op-step (:include ir-step))
  "Achieve OP's precondition (GOAL, or NIL when it has none), then run OP (:op)."
  (op nil :type op-def)
  (goal nil :type (or null goal))
  (failure nil :type (or null failure)))

(defstruct (label-step (:include ir-step))
  "Record the scheduling clock in label SLOT (:label)."
  (slot 0 :type (integer 0))
  (name nil))

(defstruct (time-step (:include ir-step))
  "Set the scheduling clock (:time). TIME is (:relative SECONDS) or (:absolute NUMBER-AST)."
  (time nil))

(defstruct (if-step (:include ir-step))
  "Run BODY only when CONDITION (a runtime expression AST) holds (:if)."
  (condition nil)
  (body '() :type list))

(defstruct (assign-step (:include ir-step))
  "Set plannable VARIABLE to its INDEXth value (:add/:sub of a literal)."
  (variable nil :type variable-def)
  (index 0 :type (integer 0)))

(defstruct (increment-step (:include ir-step))
  "Add DELTA to number VARIABLE (:add/:sub (VAR N))."
  (variable nil :type variable-def)
  (delta 0 :type real))

(defstruct (code-step (:include ir-step))
  "Evaluate the Lisp FORM (:code)."
  (form nil))

(defstruct (c++-step (:include ir-step))
  "C++ TEXT, meaningful only to the C++ backend (:c++)."
  (text "" :type string))

(defun directive-steps (directives machine)
  "The IR steps of parsed DIRECTIVES, with goals looked up in MACHINE."
  (mapcar (lambda (directive) (directive-step directive machine)) directives))

(defun directive-step (directive machine)
  "The IR step of one parsed DIRECTIVE."
  (destructuring-bind (kind &rest args) directive
    (ecase kind
      (:achieve (make-achieve-step :goal (machine-goal-for machine (first args))
                                   :failure (make-failure (second args))))
      (:op (let ((op (first args)))
             (make-op-step :op op
                           :goal (and (op-precond op) (machine-goal-for machine (op-precond op)))
                           :failure (and (op-precond op) (make-failure (op-precond-form op))))))
      (:label (make-label-step :slot (first args) :name (second args)))
      (:time (make-time-step :time (first args)))
      (:if (make-if-step :condition (first args)
                         :body (directive-steps (second args) machine)))
      (:assign (make-assign-step :variable (first args) :index (second args)))
      (:increment (make-increment-step :variable (first args) :delta (second args)))
      (:code (make-code-step :form (first args)))
      (:c++ (make-c++-step :text (first args))))))
