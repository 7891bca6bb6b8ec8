;;;; regression.lisp -- the paper's planner: breadth-first goal regression that
;;;; finds, for one goal, plans from every start state that can reach it.
;;;;
;;;; Kurlander & Ling, CHI '95, Figure 4. Main seeds ResultQ and WorkingQ with
;;;; the empty plan; SubPlan takes plans off WorkingQ in breadth-first order
;;;; and prepends each operator whose effects could have produced the plan's
;;;; start state, regressing that state through the operator's inverse. A new
;;;; start state is kept only if it is not subsumed by SolvedStates (the states
;;;; already solved, here a bit per state read a word at a time, see
;;;; solved-states.lisp: asking it costs about the new state's size, where
;;;; scanning ResultQ for a plan covering it made planning quadratic in the
;;;; number of plans). So the first plan whose condition holds in a state is a
;;;; shortest plan from it.

(in-package #:player.planner)

(defstruct (plan (:constructor make-plan (condition ops)))
  "A (condition . op sequence) pair: from any state in cube CONDITION, running
OPS (OP-DEFs, first to run first) reaches the goal."
  (condition 0 :type integer)
  (ops '() :type list))

(defmethod print-object ((plan plan) stream)
  (print-unreadable-object (plan stream :type t)
    (format stream "run ~A" (bounded-lisp-text (mapcar #'op-name (plan-ops plan)) 80))))

(defun make-planner-op (op spec)
  "Normalise OP into a PLANNER-OP of SPEC."
  (%make-planner-op
   :op op
   :precondition (if (op-precond op)
                     (expression-cubes (op-precond op) spec)
                     (list (top-cube spec)))
   :effect-mask (op-effect-mask op)
   :effect-bits (op-effect-bits op)
   :duration (op-planning-duration op)))

(defun op-planning-duration (op)
  "OP's duration for planning, as an exact rational: its declared :duration; for
a macro-op, which declares none, the sum of its :seq ops' (:label and :time
are left out, as are the plans its sub-ops' preconditions may need)."
  (if (eq (op-kind op) :macro)
      (reduce #'+ (macro-sub-ops op) :key #'op-planning-duration)
      (rational (op-duration op))))

(defun planner-ops (spec)
  "The operators the planner may use: every op that is not must-ask, and every
macro-op, in declaration order; ops without effects cannot help and are left out."
  (loop for op in (spec-ops spec)
        unless (or (op-must-ask op) (null (op-effects op)))
          collect (make-planner-op op spec)))

(defun apply-effects (state planner-op)
  "The one-hot state after PLANNER-OP's effects act on STATE."
  (logior (logandc2 state (planner-op-effect-mask planner-op))
          (planner-op-effect-bits planner-op)))

(defun regress (cube planner-op layout)
  "The cubes of states from which PLANNER-OP is applicable and leads into CUBE:
its precondition, conjoined with CUBE freed of the variables the op sets.
NIL when the op's effects contradict CUBE."
  (when (cube-subset-p (planner-op-effect-bits planner-op) cube)
    (loop with freed = (logior cube (planner-op-effect-mask planner-op))
          for precondition in (planner-op-precondition planner-op)
          for new = (logand precondition freed)
          unless (layout-cube-empty-p new layout) collect new)))

(defun make-queue ()
  "An empty FIFO queue."
  (let ((cell (list nil))) (cons cell cell)))

(defun enqueue (item queue)
  "Add ITEM at the end of QUEUE."
  (setf (cdr queue) (setf (cddr queue) (list item))))

(defun dequeue (queue)
  "Remove and return QUEUE's first item."
  (let ((item (cadar queue)))
    (setf (car queue) (cdar queue))
    item))

(defun queue-empty-p (queue)
  "True when QUEUE has no items."
  (null (cdar queue)))

(defun queue-items (queue)
  "QUEUE's items, first first."
  (cdar queue))

(defun plan-goal (goal-cubes operators layout max-depth)
  "Plans reaching the disjunction GOAL-CUBES from every state that can, using at
most MAX-DEPTH OPERATORS. Returns (VALUES PLANS SOLVED-STATES TRUNCATEDP):
the plans in breadth-first order, the bitmap of states they cover, and whether
MAX-DEPTH cut off plans for states still unsolved."
  (let ((result-q (make-queue))
        (working-q (make-queue))
        (solved-states (make-solved-states layout)))
    (dolist (cube goal-cubes)
      (when (plusp (mark-cube solved-states cube layout))
        (let ((empty-plan (make-plan cube '())))
          (enqueue empty-plan result-q)
          (enqueue empty-plan working-q))))
    (let ((truncatedp (sub-plan result-q working-q solved-states operators layout max-depth)))
      (values (queue-items result-q) (solved-states-bits solved-states) truncatedp))))

(defun sub-plan (result-q working-q solved-states operators layout max-depth)
  "Expand WORKING-Q breadth first until it is empty, adding every plan for a
not yet solved start state to RESULT-Q. Returns true if MAX-DEPTH truncated the search."
  (let ((truncatedp nil)
        (operator-count (length operators)))
    (loop until (queue-empty-p working-q)
          do (let* ((root-plan (dequeue working-q))
                    (root-state (plan-condition root-plan))
                    (root-ops (plan-ops root-plan)))
               (spend-planning-work operator-count)
               (if (>= (length root-ops) max-depth)
                   (unless truncatedp
                     (setf truncatedp (could-extend-p root-state solved-states operators layout)))
                   (dolist (operator operators)
                     (dolist (new-state (regress root-state operator layout))
                       (spend-planning-work 1)
                       (unless (subsumed-by-solved-states-p new-state root-state solved-states layout)
                         (mark-cube solved-states new-state layout)
                         (let ((new-plan (make-plan new-state
                                                    (cons (planner-op-op operator) root-ops))))
                           (enqueue new-plan result-q)
                           (enqueue new-plan working-q))))))))
    truncatedp))

(defun subsumed-by-solved-states-p (new-state root-state solved-states layout)
  "True when SolvedStates already holds every state of cube NEW-STATE, so it
needs no plan. A cube inside ROOT-STATE (solved before it was expanded) is the
cheap first test; otherwise SolvedStates is read a word at a time, up to the
first unsolved state."
  (or (cube-subset-p new-state root-state)
      (not (cube-has-unmarked-p solved-states new-state layout))))

(defun could-extend-p (root-state solved-states operators layout)
  "True when one more operator before ROOT-STATE would solve new states."
  (loop for operator in operators
          thereis (loop for new-state in (regress root-state operator layout)
                          thereis (cube-has-unmarked-p solved-states new-state layout))))
