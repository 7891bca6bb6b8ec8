;;;; uniform-cost.lisp -- duration-optimal plans, for a spec that says
;;;; (:optimize :duration): the paper's regression (Kurlander & Ling, CHI '95,
;;;; Figure 4) made uniform-cost. WorkingQ is ordered by cost instead of first
;;;; in, first out: a plan's cost is its ops' total duration, then its number
;;;; of ops (a macro-op costs the sum of its :seq ops, see OP-PLANNING-DURATION).
;;;;
;;;; Main seeds WorkingQ with the empty plans. SubPlan takes off the cheapest
;;;; plan and only then looks at SolvedStates: if its start state holds states
;;;; not yet solved, nothing cheaper reaches the goal from them, so the plan
;;;; goes onto ResultQ; then each operator is prepended to it, as breadth first.
;;;; So ResultQ is in order of cost, and the first plan whose condition holds
;;;; in a state is a cheapest plan from it.
;;;;
;;;; :max-depth bounds the number of ops, and then a cheap long plan may be of
;;;; no use where a dearer short one still is (it has no ops to spare). So when
;;;; a plan reaches :max-depth, the goal is planned again with SolvedStates
;;;; kept per plan length: SolvedStates[L] holds the states some plan of at
;;;; most L ops solves, and a plan of L ops is extended while its start state
;;;; holds a state outside SolvedStates[L]. (When no plan reaches it, the bound
;;;; never cut the search, and one SolvedStates was enough.) With equal
;;;; durations this is the breadth-first planner, plan for plan.

(in-package #:player.planner)

(defstruct (costed-plan (:constructor make-costed-plan (plan cost length serial)))
  "A plan on WorkingQ with what orders it: its ops' total duration in seconds,
then their number, then the order plans were made in."
  (plan nil :type plan)
  (cost 0 :type rational)
  (length 0 :type (integer 0))
  (serial 0 :type (integer 0)))

(defun cheaper-p (a b)
  "True when costed plan A comes off WorkingQ before costed plan B."
  (let ((a-cost (costed-plan-cost a))
        (b-cost (costed-plan-cost b)))
    (cond ((/= a-cost b-cost) (< a-cost b-cost))
          ((/= (costed-plan-length a) (costed-plan-length b))
           (< (costed-plan-length a) (costed-plan-length b)))
          (t (< (costed-plan-serial a) (costed-plan-serial b))))))

;;; WorkingQ: a binary heap, cheapest first.

(defstruct (cost-queue (:constructor make-cost-queue ()))
  "Costed plans, the cheapest at the top of a binary heap; SERIALS counts the plans added."
  (heap (make-array 64 :adjustable t :fill-pointer 0))
  (serials 0 :type (integer 0)))

(defun cost-queue-empty-p (queue)
  "True when QUEUE holds no plan."
  (zerop (fill-pointer (cost-queue-heap queue))))

(defun enqueue-by-cost (plan cost length queue)
  "Add PLAN, of COST seconds and LENGTH ops, to QUEUE."
  (let ((heap (cost-queue-heap queue)))
    (vector-push-extend (make-costed-plan plan cost length (incf (cost-queue-serials queue))) heap)
    (loop with child = (1- (fill-pointer heap))
          for parent = (floor (1- child) 2)
          while (and (plusp child) (cheaper-p (aref heap child) (aref heap parent)))
          do (rotatef (aref heap child) (aref heap parent))
             (setf child parent))))

(defun dequeue-cheapest (queue)
  "Remove and return QUEUE's cheapest costed plan."
  (let* ((heap (cost-queue-heap queue))
         (cheapest (aref heap 0))
         (last (vector-pop heap))
         (count (fill-pointer heap)))
    (when (plusp count)
      (setf (aref heap 0) last)
      (loop with parent = 0
            for left = (1+ (* 2 parent))
            for best = (loop for child from left below (min (+ left 2) count)
                             with best = parent
                             when (cheaper-p (aref heap child) (aref heap best))
                               do (setf best child)
                             finally (return best))
            until (= best parent)
            do (rotatef (aref heap parent) (aref heap best))
               (setf parent best)))
    cheapest))

;;; SolvedStates by plan length.

(defstruct (solved-levels (:constructor %make-solved-levels (all levels)))
  "SolvedStates[L] for every plan length L: ALL holds every state solved so
far, which is SolvedStates[L] for every L from LONGEST (the longest plan
marked) on; LEVELS holds SolvedStates[L] for each L below LONGEST. Without
LEVELS (NIL), ALL stands for every SolvedStates[L]."
  (all nil :type solved-states)
  (levels nil :type (or null simple-vector))
  (longest 0 :type (integer 0)))

(defun make-solved-levels (layout max-depth per-length)
  "Empty SolvedStates of every plan length up to MAX-DEPTH for LAYOUT: one per
length when PER-LENGTH, else one for all."
  (%make-solved-levels (make-solved-states layout)
                       (when per-length (make-array max-depth :initial-element nil))))

(defun solved-within (solved length)
  "SolvedStates[LENGTH]: the states plans of at most LENGTH ops solve."
  (if (and (solved-levels-levels solved) (< length (solved-levels-longest solved)))
      (svref (solved-levels-levels solved) length)
      (solved-levels-all solved)))

(defun mark-solved-within (solved cube length layout)
  "Add CUBE's states, solved by a plan of LENGTH ops, to SolvedStates[L] for
every L >= LENGTH (up from LENGTH: once CUBE adds nothing, the longer ones,
which hold that one, already hold it)."
  (let ((levels (solved-levels-levels solved)))
    (when levels
      (loop for shorter from (solved-levels-longest solved) below length
            do (setf (svref levels shorter) (copy-solved-states-deeply (solved-levels-all solved))))
      (setf (solved-levels-longest solved) (max length (solved-levels-longest solved))))
    (when (loop for longer from length below (if levels (solved-levels-longest solved) 0)
                always (plusp (mark-cube (svref levels longer) cube layout)))
      (mark-cube (solved-levels-all solved) cube layout))))

;;; The planner

(defun plan-goal-by-duration (goal-cubes operators layout max-depth)
  "PLAN-GOAL for duration-optimal plans: the plans reaching the disjunction
GOAL-CUBES from every state that can in at most MAX-DEPTH OPERATORS, cheapest
first. Returns (VALUES PLANS SOLVED-STATES TRUNCATEDP) as PLAN-GOAL does."
  (multiple-value-bind (plans solved-states truncatedp reachedp)
      (uniform-cost-plan-goal goal-cubes operators layout max-depth nil)
    (if reachedp
        (uniform-cost-plan-goal goal-cubes operators layout max-depth t)
        (values plans solved-states truncatedp))))

(defun uniform-cost-plan-goal (goal-cubes operators layout max-depth per-length)
  "Main, uniform-cost: PLAN-GOAL-BY-DURATION's values, keeping SolvedStates
PER-LENGTH or not, and a fourth: whether a plan reached MAX-DEPTH (without
PER-LENGTH, the other values are then of no use)."
  (let ((result-q (make-queue))
        (working-q (make-cost-queue))
        (solved-states (make-solved-levels layout max-depth per-length)))
    (dolist (cube goal-cubes)
      (enqueue-by-cost (make-plan cube '()) 0 0 working-q))
    (multiple-value-bind (truncatedp reachedp)
        (sub-plan-by-duration result-q working-q solved-states operators layout max-depth)
      (values (queue-items result-q) (solved-states-bits (solved-levels-all solved-states))
              truncatedp reachedp))))

(defun sub-plan-by-duration (result-q working-q solved-states operators layout max-depth)
  "Take WORKING-Q's plans off cheapest first until it is empty, adding to
RESULT-Q every plan for a not yet solved start state, and extending every plan
that is the shortest so far for one of its states. Returns (VALUES TRUNCATEDP
REACHEDP): whether MAX-DEPTH truncated the search, and whether a plan for a
not yet solved start state reached it; without SolvedStates per length, the
search stops there."
  (let ((deepest '()))
    (loop until (cost-queue-empty-p working-q)
          do (let* ((root (dequeue-cheapest working-q))
                    (root-state (plan-condition (costed-plan-plan root)))
                    (length (progn (spend-planning-work 1) (costed-plan-length root)))
                    (newp (cube-has-unmarked-p (solved-levels-all solved-states) root-state layout))
                    (shortestp (and (< length max-depth)
                                    (or newp (cube-has-unmarked-p (solved-within solved-states length)
                                                                  root-state layout)))))
               (when (and newp (not shortestp) (null (solved-levels-levels solved-states)))
                 (return-from sub-plan-by-duration (values nil t)))
               (when (or newp shortestp)
                 (mark-solved-within solved-states root-state length layout)
                 (when newp
                   (enqueue (costed-plan-plan root) result-q))
                 (if shortestp
                     (extend-by-cost root working-q solved-states operators layout)
                     (push root-state deepest)))))
    (values (loop for root-state in deepest
                    thereis (could-extend-p root-state (solved-levels-all solved-states) operators layout))
            (and deepest t))))

(defun extend-by-cost (root working-q solved-states operators layout)
  "Put on WORKING-Q each operator prepended to costed plan ROOT, where its
start state holds states no plan as short already solves."
  (let* ((root-plan (costed-plan-plan root))
         (root-state (plan-condition root-plan))
         (length (1+ (costed-plan-length root))))
    (dolist (operator operators)
      (spend-planning-work 1)
      (dolist (new-state (regress root-state operator layout))
        (spend-planning-work 1)
        (unless (subsumed-by-solved-states-p new-state root-state
                                             (solved-within solved-states length) layout)
          (enqueue-by-cost (make-plan new-state (cons (planner-op-op operator) (plan-ops root-plan)))
                           (+ (costed-plan-cost root) (planner-op-duration operator))
                           length working-q))))))
