;;;; unreachable-goals.lisp -- why a goal cannot be reached from a state: goal
;;;; literals no op adds, or the preconditions that block in the reachable
;;;; states nearest the goal.

(in-package #:player.inspect)

;;;# Why a goal cannot be reached

(defun op-sets-literal-p (op literal)
  "Do OP's effects set LITERAL's variable to a value LITERAL allows?"
  (let ((effect (assoc (car literal) (op-effects op))))
    (and effect (logbitp (cdr effect) (cdr literal)))))

(defun plan-op-defs (machine)
  "The OP-DEFs MACHINE's plans may use."
  (mapcar #'planner-op-op (machine-operators machine)))

(defun unadded-literals (cubes state machine)
  "When every cube of goal CUBES lacks, in STATE, a literal that no op plans may
use adds: those literals, each as (EXPRESSION MUST-ASK-OP-NAMES), the must-ask
ops being those that would set it; else NIL."
  (let* ((spec (machine-spec machine))
         (ops (plan-op-defs machine))
         (per-cube (mapcar (lambda (cube)
                             (remove-if (lambda (literal)
                                          (some (lambda (op) (op-sets-literal-p op literal)) ops))
                                        (missing-literals cube state spec)))
                           cubes)))
    (when (every #'identity per-cube)
      (loop for literal in (remove-duplicates (reduce #'append per-cube) :test #'equal :from-end t)
            collect (list (literal-expression literal spec)
                          (loop for op in (spec-ops spec)
                                when (and (op-must-ask op) (op-sets-literal-p op literal))
                                  collect (op-name op)))))))

(defun states-reachable-from (state machine)
  "Every state MACHINE's plannable ops reach from STATE with their preconditions
respected, STATE first, in breadth-first order."
  (let* ((layout (machine-layout machine))
         (seen (make-array (layout-state-count layout) :element-type 'bit :initial-element 0))
         (queue (make-queue))
         (found '()))
    (setf (sbit seen (state-to-dense state layout)) 1)
    (enqueue state queue)
    (loop until (queue-empty-p queue)
          do (let ((current (dequeue queue)))
               (push current found)
               (dolist (op (machine-operators machine))
                 (when (first-cube-containing (planner-op-precondition op) current)
                   (let* ((next (apply-effects current op))
                          (dense (state-to-dense next layout)))
                     (when (zerop (sbit seen dense))
                       (setf (sbit seen dense) 1)
                       (enqueue next queue)))))))
    (nreverse found)))

(defun goal-literal-distance (cubes state spec)
  "(VALUES COUNT CUBE): the fewest literals of a cube of CUBES that STATE lacks, and that cube."
  (let ((best nil) (best-cube nil))
    (dolist (cube cubes (values best best-cube))
      (let ((count (length (missing-literals cube state spec))))
        (when (or (null best) (< count best))
          (setf best count best-cube cube))))))

(defun closest-precondition-failures (op state spec)
  "The literals of OP's precondition that fail in STATE, for the precondition
cube that fails on fewest; NIL when the precondition holds."
  (if (null (op-precond op))
      '()
      (let ((failures (mapcar (lambda (cube) (missing-literals cube state spec))
                              (expression-cubes (op-precond op) spec))))
        (reduce (lambda (a b) (if (< (length b) (length a)) b a)) failures))))

(defun literal-blockers (missing cube state machine)
  "For each plannable op that would set a literal of MISSING (CUBE's literals
STATE lacks): (OP-NAME FAILING UNDONE), FAILING its precondition's literals
that fail in STATE, or, when it applies, UNDONE the literals of CUBE its effects
would make false."
  (let ((spec (machine-spec machine)))
    (loop for op in (plan-op-defs machine)
          when (some (lambda (literal) (op-sets-literal-p op literal)) missing)
            collect (let ((failing (closest-precondition-failures op state spec))
                          (next (state-after-op op state)))
                      (list (op-name op)
                            (mapcar (lambda (l) (literal-expression l spec)) failing)
                            (and (null failing)
                                 (loop for literal in (cube-literals cube spec)
                                       when (and (literal-holds-p literal state)
                                                 (not (literal-holds-p literal next)))
                                         collect (literal-expression literal spec))))))))

(defparameter *nearest-states-shown* 3
  "How many of the reachable states nearest an unreachable goal an explanation shows.")

(defun blocked-states (cubes states machine)
  "(VALUES BLOCKED-STATES MORE DISTANCE): for the STATES (reachable ones) fewest
goal literals away from goal CUBES, the first *NEAREST-STATES-SHOWN* as
BLOCKED-STATEs, how many more are as near, and that number of literals."
  (let* ((spec (machine-spec machine))
         (distance (reduce #'min states :key (lambda (s) (goal-literal-distance cubes s spec))))
         (nearest (remove-if-not (lambda (s) (= distance (goal-literal-distance cubes s spec))) states)))
    (values (loop for state in nearest
                  repeat *nearest-states-shown*
                  collect (let* ((cube (nth-value 1 (goal-literal-distance cubes state spec)))
                                 (missing (missing-literals cube state spec)))
                            (make-blocked-state (explained-state-text state spec)
                                                (mapcar (lambda (l) (literal-expression l spec)) missing)
                                                (literal-blockers missing cube state machine))))
            (max 0 (- (length nearest) *nearest-states-shown*))
            distance)))

(defun explain-unreachable (goal expression state machine &optional event)
  "The EXPLAINED-UNREACHABLE for GOAL (written EXPRESSION), which no plan of
MACHINE reaches from STATE; EVENT, if any, stops there."
  (let ((cubes (goal-cubes goal))
        (spec (machine-spec machine)))
    (cond ((null cubes)
           (make-explained-unreachable expression :contradictory t :event event))
          ((unadded-literals cubes state machine)
           (make-explained-unreachable expression :unadded (unadded-literals cubes state machine)
                                                  :event event))
          (t (multiple-value-bind (nearest more distance)
                 (blocked-states cubes (states-reachable-from state machine) machine)
               (if (zerop distance)
                   (make-explained-unreachable expression :max-depth (spec-max-depth spec) :event event)
                   (make-explained-unreachable expression :nearest nearest :more-states more
                                                          :event event)))))))
