;;;; diagnostics.lisp -- what an author wants to know about a planned spec:
;;;; plan tables, and CHECK-SPEC's warnings (unreachable goals, unused ops,
;;;; depth truncation, states the agent can never get into).

(in-package #:player.planner)

(defstruct (diagnostic (:constructor make-diagnostic (kind message &optional details)))
  "One finding of CHECK-SPEC. KIND is :UNREACHABLE-GOAL, :UNUSED-OP,
:TRUNCATED, :UNREACHABLE-STATES, :INEXACT-MACRO, :SHARED-CHANNEL or
:SIDE-EFFECT (side-effects.lisp), or :CODE (a :code form the compiler warns
of, src/control/code-forms.lisp)."
  (kind nil :type keyword)
  (message "" :type string)
  (details nil))

(defmethod print-object ((diagnostic diagnostic) stream)
  ;; One line at the REPL; the details (often long lists of states) stay in DESCRIBE.
  (print-unreadable-object (diagnostic stream :type t)
    (format stream "~(~A~) ~A" (diagnostic-kind diagnostic)
            (truncate-text (diagnostic-message diagnostic) 100))))

(defun goal-plan-table (goal spec)
  "GOAL's plans as a list of (CONDITION-EXPRESSION . OP-NAMES)."
  (map 'list (lambda (plan)
               (cons (cube-expression (plan-condition plan) spec)
                     (mapcar #'op-name (plan-ops plan))))
       (goal-plans goal)))

(defun plans (machine goal)
  "The plans MACHINE uses for GOAL (a state expression, as in :state), as a list
of (CONDITION . OPS) in the order they are tried. A goal no event asks for is
planned on the spot."
  (let* ((machine (ensure-machine machine 'plans))
         (spec (machine-spec machine))
         (cubes (with-spec-context (:spec spec :spec-name (spec-name spec))
                  (expression-cubes (parse-expression goal) spec)))
         (planned (machine-goal-with-cubes machine cubes goal)))
    (goal-plan-table planned spec)))

(defun used-ops (machine)
  "The ops some plan, event or macro :seq can run."
  (let ((used '())
        (spec (machine-spec machine)))
    (loop for goal across (machine-goal-table machine)
          do (loop for plan across (goal-plans goal)
                   do (dolist (op (plan-ops plan)) (pushnew op used))))
    (flet ((collect (directive)
             (when (eq (first directive) :op) (pushnew (second directive) used))))
      (dolist (event (spec-events spec)) (map-directives #'collect (event-directives event)))
      (dolist (op (spec-ops spec)) (map-directives #'collect (op-seq op))))
    used))

(defparameter *max-enumerated-states* (expt 2 20)
  "The most states CHECK-SPEC visits one by one to find those unreachable from
the initial state: a breadth-first search over 2^23 states takes minutes,
while a 2 KB spec can declare them.")

(defun reachable-states (machine)
  "Bitmap of the states reachable from the initial state by any op (must-ask
too) or event :add/:sub, with every precondition respected."
  (let* ((spec (machine-spec machine))
         (layout (machine-layout machine))
         (transitions (append (transition-ops spec) (event-assignment-ops spec)))
         (seen (make-array (layout-state-count layout) :element-type 'bit :initial-element 0))
         (queue (list (machine-initial-state machine))))
    (setf (sbit seen (state-to-dense (first queue) layout)) 1)
    (loop while queue
          do (let ((state (pop queue)))
               (dolist (op transitions)
                 (when (op-applies-p op state)
                   (let* ((next (apply-effects state op))
                          (dense (state-to-dense next layout)))
                     (when (zerop (sbit seen dense))
                       (setf (sbit seen dense) 1)
                       (push next queue)))))))
    seen))

(defun goal-description (goal)
  "GOAL as its author wrote it (first writing), for messages."
  (lisp-text (first (last (goal-forms goal)))))

(defun check-spec (spec)
  "Plan SPEC (a spec, its name, or a machine) and return a list of DIAGNOSTICs:
goals unreachable from some or all states, ops nothing uses, goals whose search
MAX-DEPTH truncated, states unreachable from the initial state, and plans
that change variables their event's goal does not mention."
  (let* ((machine (ensure-machine spec 'check-spec))
         (spec (machine-spec machine))
         (total (machine-state-count machine))
         (used (used-ops machine))
         (diagnostics '()))
    (loop for goal across (machine-goal-table machine)
          for missing = (- total (goal-solved-count goal))
          when (plusp missing)
            do (push (make-diagnostic
                      :unreachable-goal
                      (if (= missing total)
                          (format nil "goal ~A is unreachable from every state" (goal-description goal))
                          (format nil "goal ~A is unreachable from ~D of ~D states, e.g. ~A"
                                  (goal-description goal) missing total
                                  (lisp-text (cube-expression
                                              (dense-to-state (bitmap-first-clear (goal-solved goal) total)
                                                              (machine-layout machine))
                                              spec))))
                      (goal-expression goal))
                     diagnostics)
          when (goal-truncatedp goal)
            do (push (make-diagnostic
                      :truncated
                      (format nil "planning for goal ~A stopped at :max-depth ~D; longer plans may exist"
                              (goal-description goal) (spec-max-depth spec))
                      (goal-expression goal))
                     diagnostics))
    (dolist (op (spec-ops spec))
      (unless (member op used)
        (push (make-diagnostic :unused-op
                               (format nil "op ~A is used by no plan, event or macro-op~:[~; (it is must-ask)~]"
                                       (lisp-text (op-name op)) (op-must-ask op))
                               (op-name op))
              diagnostics)))
    (let* ((reachable (and (<= total *max-enumerated-states*) (reachable-states machine)))
           (unreachable (if reachable (count 0 reachable) 0)))
      (unless reachable
        (push (make-diagnostic :unreachable-states
                               (format nil "the states unreachable from the initial state were not counted: ~:D states are more than check visits one by one (~:D)"
                                       total *max-enumerated-states*)
                               0)
              diagnostics))
      (when (plusp unreachable)
        (push (make-diagnostic :unreachable-states
                               (format nil "~D of ~D states cannot be reached from the initial state, e.g. ~A"
                                       unreachable total
                                       (lisp-text (cube-expression
                                                   (dense-to-state (position 0 reachable)
                                                                   (machine-layout machine))
                                                   spec)))
                               unreachable)
              diagnostics)))
    (nreverse (revappend (append (inexact-macro-diagnostics machine) (channel-diagnostics spec)
                                 (side-effect-diagnostics machine))
                         diagnostics))))

(defun inexact-macro-diagnostics (machine)
  "An :INEXACT-MACRO diagnostic for each macro-op whose :seq changes a variable
its declared effects do not mention, under the default (:macros :declared):
that change is undone when the macro ends. (Under :exact, planning the spec
already refused it.) A macro the proof gives up on is reported as such."
  (handler-case
      (loop for (macro . why) in (inexact-macros machine)
            collect (make-diagnostic :inexact-macro
                                     (format nil "macro-op ~A is not exact: ~A; under the default (:macros :declared) the state flips back when it ends"
                                             (lisp-text (op-name macro)) why)
                                     (op-name macro)))
    (inexact-macro-error (condition)
      (list (make-diagnostic :inexact-macro (format nil "~@[~A ~]~A" (spec-error-label condition)
                                                    (spec-error-message condition))
                             (spec-error-form condition))))))

(defun channel-diagnostics (spec)
  "A :SHARED-CHANNEL diagnostic for each pair of SPEC's ops that declare a
common :channels name while no plannable variable appears in both (their
preconditions and effects): only the channel then stops two events that play
them from overlapping on a timed controller."
  (let ((ops (remove-if-not #'op-channels (spec-ops spec))))
    (loop for (op . rest) on ops
          nconc (loop for other in rest
                      for shared = (intersection (op-channels op) (op-channels other) :test #'string=)
                      when (and shared (not (logtest (op-variable-fields op spec)
                                                     (op-variable-fields other spec))))
                        collect (make-diagnostic
                                 :shared-channel
                                 (format nil "ops ~A and ~A both drive ~{~A~^, ~} and no state variable keeps them apart: events playing them wait for each other (or cut each other) on the channel"
                                         (lisp-text (op-name op)) (lisp-text (op-name other)) shared)
                                 (list (op-name op) (op-name other) shared))))))
