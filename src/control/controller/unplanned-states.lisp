;;;; unplanned-states.lisp -- a controller in a state its machine has no plans for.
;;;;
;;;; In the reachable regime (src/planner/reachable.lisp) plans are shortest
;;;; only for the reachable states. A controller gets outside them only when
;;;; told to (an :initial-state, --initial, a redefined spec), and then a
;;;; plan whose condition happens to hold might be longer than need be. So
;;;; the goal procedures of such a machine first ask whether the state is one
;;;; planned for (a hash lookup; full-space machines are never guarded, their
;;;; procedures are unchanged). Outside, the spec's (:unplanned-states POLICY)
;;;; decides: :refuse signals STATE-OUTSIDE-PLANNED-SET; :search looks for a
;;;; plan from that state at run time (breadth first, or cheapest first under
;;;; (:optimize :duration)), reports it in the trace as
;;;;   (:search GOAL :ops (OP...) :time T)   or   (:search GOAL :unreachable t :time T)
;;;; and runs it. MAKE-CONTROLLER refuses a start outside under :refuse.

(in-package #:player.control)

(defparameter *unplanned-search-limit* 1000000
  "Most states a run-time search from an unplanned state visits before it gives up.")

(defparameter *unplanned-search-memo-limit* 1024
  "From how many states a goal procedure remembers the plan it searched (it
forgets them all past that).")

;;; The presenter's report

(defgeneric present-search (presenter goal ops time)
  (:documentation "At TIME, a controller in a state outside its machine's
planned set searched a plan for GOAL (as written): OPS, the ops it will run,
or :NONE when no plan was found.")
  (:method ((presenter presenter) goal ops time)
    (declare (ignore goal ops time))
    nil))

(defmethod present-search ((presenter trace-presenter) goal ops time)
  (record-line presenter (if (eq ops :none)
                             (list :search goal :unreachable t :time time)
                             (list :search goal :ops (mapcar #'op-name ops) :time time))))

;;; Refusing

(defun check-planned-state (machine state)
  "Signal STATE-OUTSIDE-PLANNED-SET when a controller of MACHINE may not start
in one-hot STATE: outside the planned set, with (:unplanned-states :refuse)."
  (unless (or (planned-state-p machine state)
              (eq (spec-unplanned-states (machine-spec machine)) :search))
    (refuse-unplanned-state machine state)))

;;; Searching

(defun search-unplanned-plan (state goal machine)
  "The ops of a shortest plan (fewest ops, or least duration under
(:optimize :duration), then fewest ops) from one-hot STATE to GOAL with
MACHINE's planner operators, at most :max-depth of them; :NONE when there is
none (or the search passes *UNPLANNED-SEARCH-LIMIT* states). Uniform-cost
search forward, on the WorkingQ of uniform-cost.lisp: a queued plan's
condition is the state it has reached and its ops are in reverse."
  (let* ((spec (machine-spec machine))
         (by-duration (eq (spec-optimize spec) :duration))
         (max-depth (spec-max-depth spec))
         (queue (make-cost-queue))
         ;; state -> fewest ops it was expanded with: a later, dearer visit
         ;; is of use only when it has ops to spare (see uniform-cost.lisp)
         (expanded (make-hash-table)))
    (enqueue-by-cost (make-plan state '()) 0 0 queue)
    (loop until (cost-queue-empty-p queue)
          do (let* ((entry (dequeue-cheapest queue))
                    (here (plan-condition (costed-plan-plan entry)))
                    (length (costed-plan-length entry))
                    (seen (gethash here expanded)))
               (when (goal-holds-p goal here)
                 (return-from search-unplanned-plan (reverse (plan-ops (costed-plan-plan entry)))))
               (when (and (< length max-depth) (or (null seen) (< length seen)))
                 (setf (gethash here expanded) length)
                 (when (> (hash-table-count expanded) *unplanned-search-limit*)
                   (return-from search-unplanned-plan :none))
                 (dolist (operator (machine-operators machine))
                   (when (op-applies-p operator here)
                     (enqueue-by-cost (make-plan (apply-effects here operator)
                                                 (cons (planner-op-op operator)
                                                       (plan-ops (costed-plan-plan entry))))
                                      (+ (costed-plan-cost entry)
                                         (if by-duration (planner-op-duration operator) 0))
                                      (1+ length) queue))))))
    :none))

(defun remembered-search (memo state goal machine)
  "SEARCH-UNPLANNED-PLAN of STATE and GOAL, remembered in MEMO (a synchronized table)."
  (multiple-value-bind (ops found) (gethash state memo)
    (if found
        ops
        (let ((ops (search-unplanned-plan state goal machine)))
          (when (>= (hash-table-count memo) *unplanned-search-memo-limit*)
            (clrhash memo))
          (setf (gethash state memo) ops)))))

(defun run-searched-plan (controller ops procedures)
  "Run OPS on CONTROLLER through their procedures (PROCEDURES, the machine's
table of boxes), stopping at the first failure: what a plan runner does."
  (dolist (op ops t)
    (let ((result (call-box (gethash op procedures) controller)))
      (unless (eq result t) (return result)))))

;;; The guard

(defun guard-planned-states (achiever goal machine)
  "GOAL's procedure for MACHINE: ACHIEVER itself in the full space; in the
reachable regime, ACHIEVER from a planned state, and from any other the
spec's :unplanned-states policy (refuse, or search and run a plan).
Called while the machine compiles (*PROCEDURES* is its table of boxes)."
  (let ((index (layout-reachable (machine-layout machine))))
    (if (null index)
        achiever
        (let ((numbers (reachable-index-numbers index))
              (searchp (eq (spec-unplanned-states (machine-spec machine)) :search))
              (procedures *procedures*)
              (memo (make-hash-table :synchronized t))
              (form (first (last (goal-forms goal)))))
          (lambda (controller)
            (let ((state (controller-bits controller)))
              (cond ((nth-value 1 (gethash state numbers))
                     (funcall (the function achiever) controller))
                    ((not searchp)
                     (refuse-unplanned-state machine state goal))
                    (t (let ((ops (remembered-search memo state goal machine)))
                         (present-search (controller-presenter controller) form ops
                                         (micros->seconds (controller-schedule controller)))
                         (and (not (eq ops :none))
                              (run-searched-plan controller ops procedures)))))))))))
