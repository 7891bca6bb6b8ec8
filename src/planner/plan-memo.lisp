;;;; plan-memo.lisp -- incremental planning: a spec planned again (redefined
;;;; at the REPL, reloaded by `view --watch`) rebuilds only the goal rows
;;;; whose planning inputs changed.
;;;;
;;;; A goal's plan table depends on its canonical cubes and on what the search
;;;; reads: the layout's field sizes, the planner operators (name,
;;;; precondition cubes, effect bits, and the duration when plans minimise it),
;;;; :max-depth and :optimize.  Everything but the cubes is one SIGNATURE
;;;; shared by every row of a spec; the memo of a spec name keeps the rows of
;;;; its last planning under that signature.  So changing an op's script or an
;;;; event's other fields rebuilds no row, changing one event's goal rebuilds
;;;; that goal's row, and changing an op's precondition rebuilds every row
;;;; (any op may shorten any plan).  Plans name ops by position, so rows are
;;;; shared across specs whose op objects differ.

(in-package #:player.planner)

(defvar *reuse-plans* t
  "When true, PLAN-SPEC reuses the plan rows of the spec name's last planning
whose inputs are unchanged.  The benchmarks bind it to NIL to time real planning.")

(defvar *plan-rows-built* 0
  "How many goal rows (a goal's plan table) the planner has built in this
image: PLAN-SPEC adds one per goal it actually plans, none for a reused row.")

(defparameter *plan-memo-limit* 32
  "How many spec names keep their last plan rows; past that, all are forgotten.")

(defvar *plan-memos* (make-hash-table :test 'equal)
  "Spec name key -> PLAN-MEMO of its last planning.")

(defvar *plan-memo-lock* (bt:make-lock "player plan memos")
  "Held while *PLAN-MEMOS* is read or changed: specs may be planned on several threads.")

(defstruct (plan-memo (:constructor make-plan-memo (signature rows)))
  "The rows of one planning: SIGNATURE (PLANNING-SIGNATURE) and ROWS, an EQUAL
hash table from a goal's cubes to its PLAN-ROW."
  (signature nil)
  (rows nil :type hash-table))

(defstruct (plan-row (:constructor make-plan-row (plans solved truncatedp)))
  "A goal's plan table, independent of op objects: PLANS as (CONDITION . OP
POSITIONS) with positions into the planner operators, the SOLVED bitmap, and
whether :max-depth truncated the search."
  (plans '() :type list)
  (solved nil)
  (truncatedp nil))

(defun planning-signature (spec layout operators)
  "What planning any goal of SPEC reads besides the goal: :optimize,
:max-depth, LAYOUT's field sizes and the planner OPERATORS (and, in the
reachable regime, what decides the reachable states)."
  (let ((optimize (spec-optimize spec)))
    (list* optimize (spec-max-depth spec) (coerce (layout-sizes layout) 'list)
           (mapcar (lambda (operator)
                     (list (name-key (op-name (planner-op-op operator)))
                           (planner-op-precondition operator)
                           (planner-op-effect-mask operator)
                           (planner-op-effect-bits operator)
                           (and (eq optimize :duration) (planner-op-duration operator))))
                   operators)
           ;; The reachable regime's rows are over its states, which the
           ;; initial state, :start-states and every transition decide.
           (when-let ((index (layout-reachable layout)))
             (list (reachable-index-signature index))))))

(defun previous-plan-rows (spec signature)
  "The rows of SPEC's name's last planning when it had SIGNATURE, else NIL."
  (when *reuse-plans*
    (bt:with-lock-held (*plan-memo-lock*)
      (let ((memo (gethash (name-key (spec-name spec)) *plan-memos*)))
        (and memo (equal signature (plan-memo-signature memo)) (plan-memo-rows memo))))))

(defun remember-plan-rows (spec signature goals operators)
  "Keep GOALS' plan tables as SPEC's name's last planning under SIGNATURE."
  (when *reuse-plans*
    (let ((rows (make-hash-table :test 'equal))
          (position (make-hash-table :test 'eq)))
      (loop for operator in operators
            for k from 0
            do (setf (gethash (planner-op-op operator) position) k))
      (loop for goal across goals
            do (setf (gethash (goal-cubes goal) rows)
                     (make-plan-row (map 'list (lambda (plan)
                                                 (cons (plan-condition plan)
                                                       (mapcar (lambda (op) (gethash op position))
                                                               (plan-ops plan))))
                                         (goal-plans goal))
                                    (goal-solved goal) (goal-truncatedp goal))))
      (bt:with-lock-held (*plan-memo-lock*)
        (when (>= (hash-table-count *plan-memos*) *plan-memo-limit*)
          (clrhash *plan-memos*))
        (setf (gethash (name-key (spec-name spec)) *plan-memos*)
              (make-plan-memo signature rows))))))

(defun reuse-plan-row (goal rows operators)
  "Fill GOAL's plans from its row in ROWS (a hash table or NIL), its ops
taken from OPERATORS by position; true when there was a row."
  (let ((row (and rows (gethash (goal-cubes goal) rows))))
    (when row
      (let ((ops (map 'simple-vector #'planner-op-op operators)))
        (setf (goal-plans goal)
              (map 'simple-vector (lambda (entry)
                                    (make-plan (car entry) (mapcar (lambda (k) (svref ops k)) (cdr entry))))
                   (plan-row-plans row))
              (goal-solved goal) (copy-seq (plan-row-solved row))
              (goal-solved-count goal) (count-marked (plan-row-solved row))
              (goal-truncatedp goal) (plan-row-truncatedp row)))
      t)))

(defun plan-goals (goals operators layout spec)
  "Plan every goal of GOALS (a vector) for SPEC, reusing the rows of the spec
name's last planning that have the same inputs.  Returns how many rows were built."
  (let* ((signature (planning-signature spec layout operators))
         (rows (previous-plan-rows spec signature))
         (built 0))
    (note-planning-regime layout)
    (noting-goals-planned (0 (length goals) (layout-state-count layout))
      (loop for goal across goals
            unless (reuse-plan-row goal rows operators)
              do (solve-goal goal operators layout spec)
                 (incf built)
            do (note-goal-planned)))
    (incf *plan-rows-built* built)
    (remember-plan-rows spec signature goals operators)
    built))
