;;;; macro-exactness.lisp -- is a macro-op's declared effect what its :seq does?
;;;;
;;;; The planner treats a macro-op as one operator: from any state where its
;;;; precondition holds, it leads to that state with the declared :add/:sub
;;;; applied. Its :seq, meanwhile, runs real sub-ops that change the state. The
;;;; paper's semantics (the default, (:macros :declared)) resets the state to the
;;;; declared one when the macro ends, so whatever the sub-ops changed beyond it
;;;; silently flips back -- autoscripts started along the way stop again.
;;;; Under (:macros :exact) the state after a macro is the one its sub-ops
;;;; produced with the declared effects on top, and this file proves, when the
;;;; spec is planned, that this is the state the planner assumed, from every
;;;; start state where the precondition holds; else it names the macro and a
;;;; witness state.
;;;;
;;;; The proof runs the :seq on sets of states, not state by state, so it costs
;;;; the same for 2^26 states as for ten. A branch is a cube of start states
;;;; together with the fields the :seq has set so far and their values (every
;;;; effect is a constant assignment, so that is all a sub-op can do to a
;;;; state). Achieving a sub-op's precondition splits a branch by the plans the
;;;; controller would run, in the order it tries them; start states no plan
;;;; serves are where the macro fails, which is not an inexactness.

(in-package #:player.planner)

(defstruct (macro-branch (:constructor make-macro-branch (cube &optional (mask 0) (bits 0))))
  "Start states CUBE of a macro, and what its :seq has done to them so far:
the fields MASK set to the one-hot BITS."
  (cube 0 :type integer)
  (mask 0 :type integer)
  (bits 0 :type integer))

(defun spec-macro-semantics (spec)
  "What SPEC's (:macros SEMANTICS) option says: :DECLARED (the default) or :EXACT."
  (getf (spec-options spec) :macros :declared))

(defun branch-after-effects (branch mask bits)
  "BRANCH after an effect that sets the fields MASK to BITS."
  (make-macro-branch (macro-branch-cube branch)
                     (logior (macro-branch-mask branch) mask)
                     (logior (logandc2 (macro-branch-bits branch) mask) bits)))

(defun branch-after-op (branch op)
  "BRANCH after OP's effects (a macro's declared ones: under :declared they
are what it leaves, under :exact its own proof makes them so)."
  (branch-after-effects branch (op-effect-mask op) (op-effect-bits op)))

(defun pulled-back-condition (condition branch)
  "The start states of BRANCH's kind whose current state lies in the cube
CONDITION, as a cube (to be met with BRANCH's cube), or NIL when the values the
:seq has set already rule CONDITION out."
  (let ((bits (macro-branch-bits branch)))
    (when (zerop (logandc2 bits condition))
      (logior condition (macro-branch-mask branch)))))

(defun cube-difference (cube taken spec)
  "The states of CUBE outside the cube TAKEN, as disjoint cubes."
  (let ((pieces '())
        (rest cube))
    (dolist (var (plannable-variables spec) (nreverse pieces))
      (let* ((mask (var-field-mask var))
             (field (logand rest mask))
             (outside (logandc2 field taken)))
        (unless (zerop outside)
          (push (logior (logandc2 rest mask) outside) pieces))
        (setf rest (logior (logandc2 rest mask) (logand field taken)))
        (when (zerop (logand rest mask))
          (return (nreverse pieces)))))))

(defun branch-after-goal (branch goal machine)
  "The branches BRANCH becomes when the controller achieves GOAL: each part of
its start states runs the first of GOAL's plans whose condition its current
state meets. Start states no plan serves are dropped. Each plan tried on each
part, and each branch made, is a step of the proof's budget, paid before it
is taken."
  (let ((spec (machine-spec machine))
        (remaining (list (macro-branch-cube branch)))
        (result '()))
    (loop for plan across (goal-plans goal)
          while remaining
          do (spend-proof-steps (length remaining) machine)
             (let ((pulled (pulled-back-condition (plan-condition plan) branch)))
               (when pulled
                 (let ((left '()))
                   (dolist (cube remaining)
                     (let ((part (logand cube pulled)))
                       (if (cube-empty-p part spec)
                           (push cube left)
                           (let ((served (make-macro-branch part (macro-branch-mask branch)
                                                            (macro-branch-bits branch))))
                             (spend-proof-steps (+ 2 (length (plan-ops plan))) machine)
                             (push (reduce #'branch-after-op (plan-ops plan) :initial-value served) result)
                             (setf left (revappend (cube-difference cube pulled spec) left))))))
                   (setf remaining left)))))
    result))

(defun macro-seq-branches (macro machine)
  "The branches MACRO's :seq ends in, from the start states its precondition
allows; an INEXACT-MACRO-ERROR naming the chain when that passes the proof's
budget.  Called inside PROVING-MACRO, which names MACRO to that error."
  (let* ((spec (machine-spec machine))
         (branches (mapcar #'make-macro-branch (expression-cubes (op-precond macro) spec)))
         (count (length branches)))
    (spend-proof-steps count machine)
    (dolist (directive (op-seq macro) branches)
      (when (eq (first directive) :op)
        (let ((sub (second directive)))
          (setf *proof-sub-op* sub)
          (when (op-precond sub)
            (let ((goal (machine-goal-for machine (op-precond sub)))
                  (before count))
              (setf branches (loop for branch in branches
                                   nconc (branch-after-goal branch goal machine))
                    count (length branches))
              (note-proof-split sub before count)))
          (spend-proof-steps count machine)
          (setf branches (mapcar (lambda (branch) (branch-after-op branch sub)) branches)))))))

(defun cube-witness (cube spec)
  "One state of the non-empty CUBE: each variable at the first value it allows."
  (loop for var in (plannable-variables spec)
        for field = (logand cube (var-field-mask var))
        sum (logand field (- field))))

(defun macro-inexactness (macro machine)
  "NIL when MACRO's :seq, from every start state its precondition allows, leaves
every variable it does not declare an effect on as it found it; else a witness:
(VALUES START-STATE VARIABLE VALUE-BIT), a one-hot start state from which the
:seq leaves VARIABLE at VALUE-BIT, a value it did not have."
  (with-macro-proof-budget ((machine-spec machine))
    (proving-macro (macro)
      (macro-inexactness-of-branches macro (macro-seq-branches macro machine) machine))))

(defun macro-inexactness-of-branches (macro branches machine)
  "MACRO-INEXACTNESS, from the BRANCHES its :seq ends in."
  (let* ((spec (machine-spec machine))
         (declared (op-effect-mask macro)))
    (spend-proof-steps (length branches) machine)
    (dolist (branch branches)
      (dolist (var (plannable-variables spec))
        (let ((mask (var-field-mask var)))
          (when (and (logtest mask (macro-branch-mask branch)) (not (logtest mask declared)))
            (let* ((value (logand (macro-branch-bits branch) mask))
                   (changed (logandc2 (macro-branch-cube branch) value)))
              (unless (zerop (logand changed mask))
                (return-from macro-inexactness-of-branches
                  (values (cube-witness changed spec) var value))))))))))

(defun value-bit-expression (var bit spec)
  "The literal VAR = the value of one-hot BIT, as a readable expression."
  (field-expression var (ash bit (- (var-bit-offset var))) spec))

(defun inexact-macro-message (start var value spec)
  "Why a macro is not exact, from the witness START, VAR and VALUE."
  (format nil "from the state ~A its :seq leaves ~A, an effect the macro does not declare; the planner assumes ~A (declare it with :add/:sub, or undo it in the :seq)"
          (bounded-lisp-text (cube-expression start spec) 300)
          (lisp-text (value-bit-expression var value spec))
          (lisp-text (value-bit-expression var (logand start (var-field-mask var)) spec))))

(defun inexact-macros (machine)
  "Every macro-op of MACHINE's spec that is not exact, as (MACRO . WHY); the
proofs share one budget (macro-proof-budget.lisp)."
  (let ((spec (machine-spec machine)))
    (with-macro-proof-budget (spec)
     (loop for op in (spec-ops spec)
          when (eq (op-kind op) :macro)
            nconc (multiple-value-bind (start var value) (macro-inexactness op machine)
                    (when start
                      (list (cons op (inexact-macro-message start var value spec)))))))))

(defun check-exact-macros (machine)
  "Under (:macros :exact), signal an INEXACT-MACRO-ERROR naming the first
macro-op whose :seq leaves a state other than the one the planner assumed."
  (let ((spec (machine-spec machine)))
    (when (eq (spec-macro-semantics spec) :exact)
      (when-let ((inexact (first (inexact-macros machine))))
        (let ((form (op-form (car inexact))))
          (error 'inexact-macro-error :form form :spec (spec-name spec) :label (form-label form)
                                      :position (gethash form (spec-form-places spec))
                                      :message (format nil "not exact: ~A" (cdr inexact))))))
    machine))
