;;;; state-space.lisp -- the spec options that say which states get plans.
;;;;
;;;;   (:state-space :auto | :full | :reachable)
;;;;       :full plans from every combination of the plannable values (the
;;;;       paper's way, up to *STATE-LIMIT* states); :reachable plans from the
;;;;       states reachable from the initial state (src/planner/reachable.lisp);
;;;;       :auto, the default, is :full when the product space fits the limit.
;;;;   (:start-states EXPR...)
;;;;       more states to plan from in the reachable regime: every state where
;;;;       some EXPR holds, and what is reachable from it.
;;;;   (:unplanned-states :refuse | :search)
;;;;       what a controller does in a state outside the planned set: signal
;;;;       STATE-OUTSIDE-PLANNED-SET (the default), or search a plan from it
;;;;       at run time (src/control/controller/unplanned-states.lisp).
;;;;
;;;; The options are read with the spec's header, before its variables exist;
;;;; the :start-states expressions are parsed once every form is defined.

(in-package #:player.spec)

(defparameter *state-space-regimes* '(:auto :full :reachable)
  "What (:state-space REGIME) may say.")

(defparameter *unplanned-state-policies* '(:refuse :search)
  "What (:unplanned-states POLICY) may say.")

(defun record-start-states-option (option)
  "Keep (:start-states EXPR...) OPTION's expressions in *SPEC* for
PARSE-START-STATES; a SPEC-SYNTAX-ERROR when it is not a proper list of at
least one expression."
  (unless (and (proper-list-p option) (rest option))
    (spec-fail 'spec-syntax-error option "expected (:start-states EXPR...), one state expression or more"))
  (setf (getf (spec-options *spec*) :start-states)
        (append (getf (spec-options *spec*) :start-states) (rest option))))

(defun parse-start-states (spec)
  "Parse SPEC's :start-states expressions (now that its variables and classes
exist) into ASTs, kept as the :START-STATE-ASTS option. A SPEC-ERROR naming
an expression that is not a state expression."
  (let ((forms (getf (spec-options spec) :start-states)))
    (when forms
      (setf (getf (spec-options spec) :start-state-asts)
            (mapcar (lambda (form)
                      (unless (or (symbolp form) (proper-list-p form))
                        (spec-fail 'spec-syntax-error form
                                   ":start-states takes state expressions; ~A is not one"
                                   (bounded-lisp-text form 60)))
                      (let ((ast (parse-expression form)))
                        (unless (state-only-p ast)
                          (spec-fail 'spec-syntax-error form
                                     ":start-states takes state expressions; ~A is not one"
                                     (bounded-lisp-text form 60)))
                        ast))
                    forms)))))

(defun spec-state-space (spec)
  "SPEC's (:state-space REGIME): :AUTO (the default), :FULL or :REACHABLE."
  (getf (spec-options spec) :state-space :auto))

(defun spec-start-state-asts (spec)
  "The parsed expressions of SPEC's (:start-states EXPR...), or NIL."
  (getf (spec-options spec) :start-state-asts))

(defun spec-unplanned-states (spec)
  "SPEC's (:unplanned-states POLICY): :REFUSE (the default) or :SEARCH."
  (getf (spec-options spec) :unplanned-states :refuse))
