;;;; side-effects.lisp -- CHECK-SPEC's warning about side effects the author
;;;; did not ask for.  The planner may use any op that is not :must-ask as a
;;;; step: a robot told to greet chose `hand-over` (give the cup away) just to
;;;; free its hands.  An event's plan that, from some states, leaves a
;;;; variable changed that its goal does not mention and no later step's
;;;; precondition needs (sitting down to sleep is a step; giving the cup
;;;; away to greet is not) is reported, naming the event, the op, the
;;;; variable and the states, with the remedy: make the op :must-ask, so
;;;; only events and macro-ops that name it run it.

(in-package #:player.planner)

(defun goal-fields (goal spec)
  "The one-hot fields of the plannable variables GOAL constrains: those some
cube of it does not allow every value of."
  (loop for var in (plannable-variables spec)
        for field = (var-field-mask var)
        when (some (lambda (cube) (/= (logand cube field) field)) (goal-cubes goal))
          sum field))

(defun precondition-fields (op spec)
  "The fields of the plannable variables OP's precondition constrains."
  (if (op-precond op) (expression-fields (op-precond op) spec) 0))

(defun plan-side-effects (plan mentioned spec)
  "The variables PLAN leaves changed, from some state of its condition, that
neither the fields MENTIONED (the goal's) nor the precondition of an op
after the one that changed it need, each as (VAR . OP), OP the last op of
PLAN that sets it.  A variable is left changed unless the condition allows
it no value but the one the plan ends with."
  (let ((changes '()))
    (loop for (op . later) on (plan-ops plan)
          for needed = (reduce #'logior later :key (lambda (next) (precondition-fields next spec))
                                              :initial-value mentioned)
          do (loop for (var . index) in (op-effects op)
                   do (let ((entry (assoc var changes)))
                        (cond ((logtest needed (var-field-mask var))
                               ;; A step towards the goal: not a side effect.
                               (setf changes (remove var changes :key #'car)))
                              (entry (setf (cdr entry) (cons op index)))
                              (t (push (cons var (cons op index)) changes))))))
    (loop for (var op . index) in (nreverse changes)
          unless (= (logand (plan-condition plan) (var-field-mask var)) (var-value-bit var index))
            collect (cons var op))))

(defun event-goal-directives (event machine)
  "(GOAL . OP) for each goal EVENT's directives plan for: a :state
directive's goal (OP NIL), and for an :op directive the precondition of its OP."
  (let ((spec (machine-spec machine))
        (found '()))
    (flet ((note (expression form op)
             (push (cons (machine-goal-with-cubes machine (expression-cubes expression spec) form) op)
                   found)))
      (map-directives (lambda (directive)
                        (case (first directive)
                          (:achieve (note (second directive) (third directive) nil))
                          (:op (let ((op (second directive)))
                                 (when (op-precond op)
                                   (note (op-precond op) (op-precond-form op) op))))))
                      (event-directives event)))
    (nreverse found)))

(defun side-effect-diagnostic (event goal named-op plan var op spec)
  "The :SIDE-EFFECT diagnostic of EVENT's PLAN for GOAL (the precondition of
NAMED-OP, or a :state goal when it is NIL) running OP, which changes VAR."
  (make-diagnostic
   :side-effect
   (format nil "event ~A, from ~A: its plan runs op ~A, which changes ~A, a variable ~A does not mention; if that is not meant, make ~A :must-ask"
           (lisp-text (event-name event))
           (lisp-text (cube-expression (plan-condition plan) spec))
           (lisp-text (op-name op)) (lisp-text (var-name var))
           (if named-op
               (format nil "op ~A" (lisp-text (op-name named-op)))
               (format nil "its goal ~A" (goal-description goal)))
           (lisp-text (op-name op)))
   (list :event (event-name event) :op (op-name op) :variable (var-name var) :from (plan-condition plan))))

(defun side-effect-diagnostics (machine)
  "A :SIDE-EFFECT diagnostic for each event, op and variable where the
event's plan from some state runs the op as a step and it changes the
variable, which the event's goal (an :op directive's op, and its
precondition) does not mention, nor a later step's precondition needs."
  (let ((spec (machine-spec machine))
        (seen (make-hash-table :test 'equal))
        (diagnostics '()))
    (dolist (event (spec-events spec) (nreverse diagnostics))
      (loop for (goal . named-op) in (event-goal-directives event machine)
            for mentioned = (logior (goal-fields goal spec)
                                    (if named-op (op-variable-fields named-op spec) 0))
            do (loop for plan across (goal-plans goal)
                     do (loop for (var . op) in (plan-side-effects plan mentioned spec)
                              for key = (list (event-name event) (op-name op) (var-name var))
                              ;; Once per event, op and variable: the first states found.
                              unless (gethash key seen)
                                do (setf (gethash key seen) t)
                                   (push (side-effect-diagnostic event goal named-op plan var op spec)
                                         diagnostics)))))))
