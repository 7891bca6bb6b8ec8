;;;; machine.lisp -- a planned spec: every goal with its plan table.
;;;; PLAN-SPEC is the planner's whole job; a code generator then turns the
;;;; machine into something that runs (Lisp closures, or C++ source).  The
;;;; MACHINE record is declared in records.lisp.

(in-package #:player.planner)

(defun machine-designator-p (x)
  "Is X a machine, a spec or a spec's name?"
  (or (spec-designator-p x) (machine-p x)))

(defparameter *machine-designator* "a machine (from compile-spec or plan-spec), a spec or a spec's name"
  "How argument errors describe a machine designator.")

(defun machine-state-count (machine)
  "How many states MACHINE has plans from: every plannable state of its spec,
or in the reachable regime its reachable states."
  (check-argument 'machine-state-count 'machine machine #'machine-p "a machine")
  (layout-state-count (machine-layout machine)))

(defun designated-spec (designator function)
  "The spec DESIGNATOR (a spec or a spec's name) designates, for FUNCTION's
argument errors; an UNKNOWN-NAME-ERROR for an undefined name."
  (check-argument function 'spec designator #'spec-designator-p *spec-designator*)
  (if (spec-p designator) designator (find-spec designator)))

(defun initial-state (spec)
  "The one-hot state of SPEC's declared initial values."
  (loop for var in (plannable-variables spec)
        sum (var-value-bit var (var-initial var))))

(defun plan-spec (spec &key (constructor #'%make-machine))
  "Plan every goal of SPEC (a spec or a spec's name) and return the MACHINE,
made by CONSTRUCTOR (which takes MACHINE's slots as keywords: a code generator
may extend the struct).  Goal rows whose planning inputs are those of the
spec name's last planning are reused, not searched again (plan-memo.lisp).
Under (:macros :exact), every macro-op is proved exact (macro-exactness.lisp)."
  (let* ((spec (designated-spec spec 'plan-spec))
         (operators (planner-ops spec))
         (goal-of (make-hash-table :test 'eq))
         (goals '()))
    (loop for (ast . form) in (spec-goal-sources spec)
          do (multiple-value-bind (goal all) (intern-goal ast form goals spec)
               (setf goals all
                     (gethash ast goal-of) goal)))
    (let ((goals (coerce (reverse goals) 'simple-vector)))
      (multiple-value-bind (planned work)
          (with-planning-budget (spec)
            (let ((layout (make-layout spec)))
              (cons layout (plan-goals goals operators layout spec))))
        (destructuring-bind (layout . built) planned
          (check-exact-macros
           (funcall constructor :spec spec :rows-built built :planning-work work :layout layout
                                :goal-table goals :goal-of goal-of
                                :operators operators :initial-state (initial-state spec)
                                :watched-variables (watched-plannable-variables spec)
                                :autoscript-mask (reduce #'logior (watched-plannable-variables spec)
                                                         :key #'var-field-mask :initial-value 0))))))))

(defun ensure-machine (designator &optional (function 'ensure-machine))
  "DESIGNATOR as a MACHINE: itself, or the planned machine of a spec or a
spec's name.  An ARGUMENT-ERROR for FUNCTION when it is none of those."
  (check-argument function 'machine designator #'machine-designator-p *machine-designator*)
  (if (machine-p designator) designator (plan-spec designator)))

(defun watched-plannable-variables (spec)
  "SPEC's plannable variables that some autoscript watches, in declaration order."
  (let ((watched (mapcar #'autoscript-variable (spec-autoscripts spec))))
    (remove-if-not (lambda (var) (member var watched)) (plannable-variables spec))))

(defun machine-goal-for (machine ast)
  "The goal MACHINE planned for goal AST (a :state argument or precondition)."
  (or (gethash ast (machine-goal-of machine))
      (error "internal: no goal was planned for ~S" ast)))

(defun machine-goal-with-cubes (machine cubes form)
  "MACHINE's goal holding in the states of CUBES (however its cubes are
written), or a new goal, written FORM, planned on the spot."
  (let ((spec (machine-spec machine)))
    (or (find-equivalent-goal cubes (coerce (machine-goal-table machine) 'list) spec)
        (solve-goal (%make-goal :cubes cubes :forms (list form) :expression (cubes-expression cubes spec))
                    (machine-operators machine) (machine-layout machine) spec))))

(defun machine-goals (machine)
  "The distinct goals of MACHINE, as readable canonical expressions, in the order planned."
  (check-argument 'machine-goals 'machine machine #'machine-p "a machine")
  (map 'list #'goal-expression (machine-goal-table machine)))

