;;;; macro-proof-budget.lisp -- how much work the exact-macro proof may do.
;;;;
;;;; The proof of macro-exactness.lisp splits a macro's start states by the
;;;; plans that achieve each sub-op's precondition, so a :seq of a few sub-ops
;;;; can ask for as many cases as the spec has states (2^26), each multiplied
;;;; again by the plans tried at the next sub-op.  Every step of it -- a plan
;;;; tried on a set of states, a branch made, a sub-op's effect applied -- is
;;;; paid for out of one budget shared by every macro-op of the spec, the
;;;; moment it is taken; the step that passes the budget stops the proof with
;;;; an error naming the chain: the enclosing macro-ops, the macro, and the
;;;; sub-ops whose preconditions split its start states (issue 31).

(in-package #:player.planner)

(defparameter *macro-proof-budget* 1000000
  "Most steps the exactness proof takes for all the macro-ops of one spec
(PROOF-STEP-COST weighs a step by the width of the state).  A step takes
1-2 microseconds, so the proof stops within about 2 s and a few hundred MB
whatever the spec (measured by t/test-macro-exactness.lisp's generator).")

(defvar *proof-steps-left* nil
  "Steps the proof under way may still take, or NIL when none is under way.")

(defvar *proof-step-cost* 1
  "What one step of the proof under way costs: more for a wider state.")

(defvar *proof-macro* nil "The macro-op being proved (PROVING-MACRO binds it).")

(defvar *proof-sub-op* nil "The sub-op of *PROOF-MACRO*'s :seq being followed.")

(defvar *proof-splits* '()
  "The sub-ops whose preconditions split *PROOF-MACRO*'s start states so far,
latest first, each as (SUB-OP . CASES-AFTER-IT).")

(defun proof-step-cost (spec)
  "What a step of the proof costs on SPEC: testing a set of states walks
every plannable variable, each time on integers as wide as the state, so a
step costs about a 64th of variables x words (at least 1)."
  (let ((variables (length (plannable-variables spec)))
        (words (ceiling (1+ (spec-bit-count spec)) 64)))
    (max 1 (ceiling (* variables words) 64))))

(defmacro with-macro-proof-budget ((spec) &body body)
  "Run BODY, a proof of some of SPEC's macro-ops, under a fresh budget of
*MACRO-PROOF-BUDGET* steps, unless a proof is already under way: BODY then
spends from its budget (not from a copy)."
  (let ((run (gensym "RUN")))
    `(flet ((,run () ,@body))
       (if *proof-steps-left*
           (,run)
           (let ((*proof-steps-left* *macro-proof-budget*)
                 (*proof-step-cost* (proof-step-cost ,spec)))
             (,run))))))

(defmacro proving-macro ((macro) &body body)
  "Run BODY, the proof of MACRO, naming it (and no sub-op yet) to budget errors."
  `(let ((*proof-macro* ,macro) (*proof-sub-op* nil) (*proof-splits* '()))
     ,@body))

(defun spend-proof-steps (count machine)
  "Pay for COUNT steps of the proof under way on MACHINE; past the budget,
signal the INEXACT-MACRO-ERROR that names the chain."
  (when (minusp (decf *proof-steps-left* (* count *proof-step-cost*)))
    (proof-budget-passed machine)))

(defun note-proof-split (sub-op before after)
  "Remember that achieving SUB-OP's precondition took BEFORE cases to AFTER."
  (when (> after before)
    (push (cons sub-op after) *proof-splits*)))

(defun enclosing-macros (macro spec)
  "The macro-ops that run MACRO, outermost first: one chain of SPEC's
macro-ops each running the next, up to one that nothing runs (macro cycles
were refused when the spec was validated)."
  (let ((chain '()))
    (loop for inner = macro then outer
          for outer = (find-if (lambda (op)
                                 (and (eq (op-kind op) :macro)
                                      (not (member op chain))
                                      (member inner (op-seq op) :key #'second)))
                               (spec-ops spec))
          while outer
          do (push outer chain))
    chain))

(defun proof-chain-text (spec)
  "The chain the proof under way was following, as text: the enclosing
macro-ops, the macro, and the sub-ops that split its start states."
  (let ((enclosing (enclosing-macros *proof-macro* spec))
        (splits (reverse *proof-splits*)))
    (format nil "~@[run by ~{~A~^ -> ~}, ~]~:[its :seq~;~:*its :seq splits its start states at ~{~A~^, ~}~]~@[, and was at sub-op ~A~]"
            (mapcar (lambda (op) (lisp-text (op-name op))) enclosing)
            (and splits
                 (mapcar (lambda (split)
                           (format nil "~A (~:D cases)" (lisp-text (op-name (car split))) (cdr split)))
                         (if (> (length splits) 6) (append (subseq splits 0 3) (last splits 3)) splits)))
            (and *proof-sub-op* (lisp-text (op-name *proof-sub-op*))))))

(defun proof-budget-passed (machine)
  "Signal the INEXACT-MACRO-ERROR of a proof that passed its budget."
  (let* ((spec (machine-spec machine))
         (form (op-form *proof-macro*)))
    (error 'inexact-macro-error
           :form form :spec (spec-name spec) :label (form-label form)
           :position (gethash form (spec-form-places spec))
           :message (format nil "cannot be proved exact within ~:D steps (for all the spec's macro-ops): ~A; split it into smaller macro-ops"
                            *macro-proof-budget* (proof-chain-text spec)))))
