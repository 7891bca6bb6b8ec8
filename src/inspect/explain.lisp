;;;; explain.lisp -- why this plan: the ops a planned machine runs from one
;;;; state towards a goal (or through an event's directives), each with the
;;;; literal it makes true for a later step's precondition or for the goal;
;;;; and, for a goal it cannot reach, why: goal literals no op adds, or the
;;;; preconditions that block in the reachable states nearest the goal.
;;;;
;;;; EXPLAIN-PLAN returns a list of steps, one struct per kind of line, and
;;;; PRINT-EXPLANATION writes them (one WRITE-EXPLANATION-STEP method each).
;;;; The ops are the controller's: the first plan whose condition holds, as
;;;; COMPILE-ACHIEVER picks it, from the state the previous step leaves.
;;;; The steps and their printing are in explanation-steps.lisp, the analysis
;;;; of unreachable goals in unreachable-goals.lisp.

(in-package #:player.inspect)

;;;# Why each op of a plan

(defstruct (explainer (:constructor make-explainer (machine state)))
  "What EXPLAIN-PLAN carries from step to step: the MACHINE, the STATE the
steps so far leave, how many ops they ran (COUNT), and the STEPS, latest first."
  machine state (count 0 :type (integer 0)) (steps '()))

(defun add-explanation-step (explainer step)
  "Add STEP to EXPLAINER's steps."
  (push step (explainer-steps explainer)))

(defun op-precondition-cubes (op spec)
  "OP's precondition as cubes: every state when it has none."
  (if (op-precond op)
      (expression-cubes (op-precond op) spec)
      (list (top-cube spec))))

(defun plan-run-states (ops state)
  "The states a run of OPS passes through: STATE, then the state after each op."
  (cons state (loop for op in ops
                    do (setf state (state-after-op op state))
                    collect state)))

(defun need-cubes (ops states final-cubes spec)
  "For each op of OPS, the cube of what the step after it needs, holding in the
state it leaves (STATES from RUN-STATES): the next op's precondition, or
FINAL-CUBES after the last op."
  (loop for (nil . rest) on ops
        for after in (rest states)
        collect (or (first-cube-containing (if rest (op-precondition-cubes (first rest) spec) final-cubes)
                                     after)
                    (top-cube spec))))

(defun op-purpose (i ops states needs spec)
  "(VALUES J LITERALS): the first step J, from op I of OPS on, whose need (of
NEEDS) constrains a variable op I changed, still at the value op I gave it;
the literals it needs of those variables. NIL when no step does."
  (let* ((before (nth i states))
         (after (nth (1+ i) states))
         (changed (loop for (var) in (op-effects (nth i ops))
                        unless (= (literal-state-index before var) (literal-state-index after var))
                          collect var)))
    (loop for j from i below (length ops)
          for cube in (nthcdr i needs)
          for state in (nthcdr (1+ j) states)
          for literals = (loop for literal in (cube-literals cube spec)
                               when (and (member (car literal) changed)
                                         (= (literal-state-index state (car literal))
                                            (literal-state-index after (car literal))))
                                 collect literal)
          when literals
            return (values j literals))))

(defun explain-op-purpose (explainer i ops states needs final)
  "The EXPLAINED-OP for op I of OPS, run as the plan for FINAL: (:GOAL
EXPRESSION) or (:PRECONDITION OP-NAME STEP-NUMBER)."
  (let* ((spec (machine-spec (explainer-machine explainer)))
         (base (explainer-count explainer))
         (last (1- (length ops))))
    (multiple-value-bind (j literals) (op-purpose i ops states needs spec)
      (make-explained-op (+ base i 1) (op-name (nth i ops))
                         (explained-changes (nth i states) (nth (1+ i) states) spec)
                         (cond ((null j) nil) ((< j last) :precondition) (t (first final)))
                         (cond ((null j) nil) ((< j last) (op-name (nth (1+ j) ops))) (t (second final)))
                         (mapcar (lambda (l) (literal-expression l spec)) literals)
                         (cond ((or (null j) (= j i)) nil)
                               ((< j last) (+ base j 2))
                               (t (third final)))))))

(defun explain-plan-ops (explainer ops final-cubes final)
  "Add an EXPLAINED-OP for each of OPS, the plan run from EXPLAINER's state to
reach FINAL-CUBES (described by FINAL, see EXPLAIN-OP-PURPOSE); move the state
and the count past them."
  (let* ((spec (machine-spec (explainer-machine explainer)))
         (states (plan-run-states ops (explainer-state explainer)))
         (needs (need-cubes ops states final-cubes spec)))
    (loop for i below (length ops)
          do (add-explanation-step explainer (explain-op-purpose explainer i ops states needs final)))
    (incf (explainer-count explainer) (length ops))
    (setf (explainer-state explainer) (car (last states)))))

(defun plan-applying-in (goal state)
  "The plan of GOAL the controller runs from STATE (the first whose condition
holds), or NIL."
  (find-if (lambda (plan) (state-in-cube-p state (plan-condition plan))) (goal-plans goal)))

(defun explain-goal (explainer goal kind expression &key op event)
  "Add the steps achieving planned GOAL from EXPLAINER's state: a heading (KIND
and EXPRESSION as for MAKE-EXPLAINED-GOAL; OP the op whose precondition it is),
then each op of the plan. Returns true; when no plan applies, adds why (EVENT
stopping there) and returns NIL."
  (let* ((machine (explainer-machine explainer))
         (plan (plan-applying-in goal (explainer-state explainer))))
    (if (null plan)
        (progn (add-explanation-step explainer (explain-unreachable goal expression (explainer-state explainer)
                                                        machine (and event (event-name event))))
               nil)
        (let ((ops (plan-ops plan)))
          (add-explanation-step explainer (make-explained-goal kind expression (null ops) (and op (op-name op))))
          (explain-plan-ops explainer ops (goal-cubes goal)
                            (if op
                                (list :precondition (op-name op) (+ (explainer-count explainer) (length ops) 1))
                                (list :goal expression)))
          t))))

;;;# Goals and events

(defun explain-goal-form (explainer form)
  "Add the steps reaching the state expression FORM. Signals a SPEC-ERROR when
FORM is not a state expression of the spec."
  (let* ((machine (explainer-machine explainer))
         (spec (machine-spec machine))
         (cubes (with-spec-context (:spec spec :spec-name (spec-name spec))
                  (expression-cubes (parse-expression form) spec))))
    (explain-goal explainer (machine-goal-with-cubes machine cubes form) :goal form)))

(defgeneric explain-directive (kind directive explainer event)
  (:documentation "Add the steps of EVENT's parsed DIRECTIVE, whose first element
is KIND, to EXPLAINER. True to go on with the next directive, NIL when the
event fails here."))

(defmethod explain-directive (kind directive explainer event)
  ;; :label, :time, :code, :c++ and number increments leave the planned state alone.
  (declare (ignore kind directive explainer event))
  t)

(defmethod explain-directive ((kind (eql :achieve)) directive explainer event)
  (destructuring-bind (ast form) (rest directive)
    (explain-goal explainer (machine-goal-for (explainer-machine explainer) ast) :state form
                  :event event)))

(defun explain-requested-op (explainer op event)
  "Add the EXPLAINED-OP for OP, run because EVENT's :op asks for it."
  (let* ((spec (machine-spec (explainer-machine explainer)))
         (before (explainer-state explainer))
         (after (state-after-op op before)))
    (add-explanation-step explainer (make-explained-op (incf (explainer-count explainer)) (op-name op)
                                           (explained-changes before after spec)
                                           :requested (event-name event) '()))
    (setf (explainer-state explainer) after)))

(defmethod explain-directive ((kind (eql :op)) directive explainer event)
  (let ((op (second directive)))
    (add-explanation-step explainer (make-explained-directive (format nil ":op ~A" (lisp-text (op-name op)))))
    (when (or (null (op-precond op))
              (explain-goal explainer (machine-goal-for (explainer-machine explainer) (op-precond op))
                            :precondition (op-precond-form op) :op op :event event))
      (explain-requested-op explainer op event)
      t)))

(defmethod explain-directive ((kind (eql :assign)) directive explainer event)
  (declare (ignore event))
  (destructuring-bind (var index) (rest directive)
    (let* ((spec (machine-spec (explainer-machine explainer)))
           (before (explainer-state explainer))
           (after (logior (logandc2 before (var-field-mask var)) (var-value-bit var index))))
      (add-explanation-step explainer (make-explained-assignment
                           (format nil "sets ~A" (lisp-text (field-expression var (ash 1 index) spec)))
                           (explained-changes before after spec)))
      (setf (explainer-state explainer) after)
      t)))

(defmethod explain-directive ((kind (eql :if)) directive explainer event)
  (destructuring-bind (condition body form) (rest directive)
    (let* ((spec (machine-spec (explainer-machine explainer)))
           (outcome (cond ((not (state-only-p condition)) :assumed)
                          ((first-cube-containing (expression-cubes condition spec) (explainer-state explainer))
                           :true)
                          (t :false))))
      (add-explanation-step explainer (make-explained-condition (first form) outcome))
      (or (eq outcome :false)
          (explain-directives body explainer event)))))

(defun explain-directives (directives explainer event)
  "Explain EVENT's parsed DIRECTIVES in turn, until one fails; true when none does."
  (loop for directive in directives
        always (explain-directive (first directive) directive explainer event)))

(defun find-explained-event (spec name)
  "SPEC's event NAME (a symbol or string); UNKNOWN-EVENT when there is none."
  (or (find (if (stringp name) (string-upcase name) (name-key name)) (spec-events spec)
            :key (lambda (event) (name-key (event-name event))) :test #'string=)
      (error 'unknown-event :name name :known (mapcar #'event-name (spec-events spec)))))

;;;# The entry point

(defun explanation-initial-state (spec initial)
  "The one-hot state of SPEC's initial values with INITIAL (an alist of variable
name -> value) applied; a SPEC-ERROR for an unknown variable or a bad value."
  (loop for (var . value) in (initial-assignments spec initial)
        when (plannable-p var) sum (var-value-bit var value)))

(defun initial-alist-p (x)
  "Is X a proper alist ((VARIABLE . VALUE) ...) of bounded, finite forms, symbols for variables?"
  (and (proper-form-list-p x) (finite-form-p x)
       (every (lambda (entry) (and (consp entry) (symbolp (car entry)))) x)))

(defun explain-plan (machine &key initial (goal nil goal-p) event)
  "Explain what MACHINE (a machine, a spec or a spec's name) does from the
state of its initial values overridden by INITIAL (an alist ((VARIABLE . VALUE)
...)), for exactly one of GOAL (a state expression, as in :state) or EVENT (an
event's name, a symbol or string). Returns a list of EXPLANATION-STEPs, for
PRINT-EXPLANATION: where it starts; then for GOAL, or for each directive of
EVENT in turn, the ops the controller would run, each EXPLAINED-OP saying which
literal of a later op's precondition or of the goal it makes true; a goal that
already holds says so; an unreachable goal ends it with an EXPLAINED-UNREACHABLE
saying why (goal literals no op adds, or the preconditions that block in the
reachable states nearest the goal). Signals UNKNOWN-EVENT for an event the spec
lacks, a SPEC-ERROR for a GOAL that is no state expression of the spec or an
unknown variable or bad value in INITIAL, STATE-OUTSIDE-PLANNED-SET for a
state a spec planned for its reachable states only has no plans from, and an
ARGUMENT-ERROR for an argument of the wrong kind or for giving both or neither
of GOAL and EVENT."
  (check-argument 'explain-plan 'machine machine #'machine-designator-p *machine-designator*)
  (check-argument 'explain-plan :initial initial #'initial-alist-p
                  "a proper alist ((variable . value) ...) with symbols for variables and finite numbers")
  (unless (if goal-p (null event) event)
    (argument-fail 'explain-plan :event event
                   (if goal-p "NIL when :goal is given (give one of :goal and :event)" "an event's name, or give :goal")))
  (when goal-p
    (check-argument 'explain-plan :goal goal (lambda (x) (and (bounded-form-p x) (finite-form-p x)))
                    "a state expression"))
  (when event
    (check-argument 'explain-plan :event event #'name-designator-p "an event's name (a symbol or string)"))
  (let* ((machine (ensure-machine machine 'explain-plan))
         (spec (machine-spec machine))
         (explainer (make-explainer machine (explanation-initial-state spec initial))))
    ;; outside the reachable regime's planned set no plan is known to be shortest
    (unless (planned-state-p machine (explainer-state explainer))
      (refuse-unplanned-state machine (explainer-state explainer)))
    (add-explanation-step explainer (make-explanation-start (spec-name spec)
                                                (explained-state-text (explainer-state explainer) spec)))
    (if goal-p
        (explain-goal-form explainer goal)
        (let ((event (find-explained-event spec event)))
          (add-explanation-step explainer (make-explained-directive (format nil "event ~A" (lisp-text (event-name event)))))
          (explain-directives (event-directives event) explainer event)))
    (reverse (explainer-steps explainer))))
