;;;; goals.lisp -- the distinct goals a spec needs plans for.
;;;; Every :state argument and the precondition of every op an event or macro
;;;; requests is a goal. Goals that hold in the same states are one goal
;;;; (goal-identity.lisp), planned once, however each is written.  The GOAL
;;;; record is declared in records.lisp.

(in-package #:player.planner)

(defun map-directives (function directives)
  "Call FUNCTION on every directive of DIRECTIVES, inside :IF bodies too."
  (dolist (directive directives)
    (funcall function directive)
    (when (eq (first directive) :if)
      (map-directives function (third directive)))))

(defun op-goal-form (op)
  "What to call OP's precondition goal in messages: the :precond as written."
  (op-precond-form op))

(defun spec-goal-sources (spec)
  "Every (AST . FORM) a goal must be planned for, in spec order: the :state
arguments of events and the preconditions of the ops events and macros request."
  (let ((sources '()))
    (flet ((collect (directive)
             (case (first directive)
               (:achieve (push (cons (second directive) (third directive)) sources))
               (:op (let ((op (second directive)))
                      (when (op-precond op)
                        (push (cons (op-precond op) (op-goal-form op)) sources)))))))
      (dolist (event (spec-events spec))
        (map-directives #'collect (event-directives event)))
      (dolist (op (spec-ops spec))
        (map-directives #'collect (op-seq op))))
    (nreverse sources)))

(defun find-goal (cubes goals)
  "The goal among GOALS with canonical CUBES, or NIL."
  (find cubes goals :key #'goal-cubes :test #'equal))

(defun intern-goal (ast form goals spec)
  "The goal for AST in GOALS (a list, most recent first), adding a new one if needed.
Returns (VALUES GOAL GOALS)."
  (let* ((cubes (expression-cubes ast spec))
         (goal (find-equivalent-goal cubes goals spec)))
    (if goal
        (progn (pushnew form (goal-forms goal) :test #'equal)
               (values goal goals))
        (let ((goal (%make-goal :id (length goals) :cubes cubes
                                :expression (cubes-expression cubes spec)
                                :forms (list form))))
          (values goal (cons goal goals))))))

(defun spec-optimize (spec)
  "What SPEC's plans minimise: :STEPS, the number of operators (the default),
or :DURATION, their total duration; SPEC's (:optimize CRITERION) option."
  (getf (spec-options spec) :optimize :steps))

(defun solve-goal (goal operators layout spec)
  "Plan GOAL for SPEC, filling in its plans and coverage: fewest operators
breadth first (regression.lisp), or least total duration (uniform-cost.lisp)."
  ;; SolvedStates is made, then counted, a word at a time
  (spend-planning-units (* 2 (ceiling (layout-state-count layout) 64)))
  (multiple-value-bind (plans solved truncatedp)
      (funcall (ecase (spec-optimize spec)
                 (:steps #'plan-goal)
                 (:duration #'plan-goal-by-duration))
               (goal-cubes goal) operators layout (spec-max-depth spec))
    (setf (goal-plans goal) (coerce plans 'simple-vector)
          (goal-solved goal) solved
          (goal-solved-count goal) (count-marked solved)
          (goal-truncatedp goal) truncatedp)
    goal))

(defun goal-holds-p (goal state)
  "Does GOAL hold in the one-hot STATE?"
  (some (lambda (cube) (state-in-cube-p state cube)) (goal-cubes goal)))
