;;;; graph-specs.lisp -- what `check` adds for a spec made by (:graph ...): a
;;;; behaviour should not get stuck, and every goal should be reachable.
;;;;
;;;; Such a spec is a transition system of the algebra, so its dead ends are
;;;; the behaviour's, not a spec's ordinary "nothing left to do": the check
;;;; model-checks deadlock-freedom, (AG (EX t)), and (EF GOAL) for each
;;;; event's goal, on its reachable states.

(in-package #:player.logic)

(defun graph-spec-p (spec)
  "Was SPEC (a spec) written with a (:graph ...) option?"
  (some (lambda (form) (and (consp form) (eq (first form) :graph))) (spec-forms spec)))

(defun event-goal-forms (event)
  "The state expressions EVENT's :state directives ask for, as written."
  (loop for directive in (event-directives event)
        when (and (consp directive) (eq (first directive) :achieve)) collect (third directive)))

(defun graph-spec-diagnostics (spec)
  "For a SPEC made by (:graph ...), DIAGNOSTICs: an error when a reachable
state has no successor (deadlock-freedom fails; the path to it is named), an
error for each event goal no path from the initial state reaches. NIL for
any other spec."
  (when (graph-spec-p spec)
    (let ((behaviour (spec-behaviour spec))
          (diagnostics '()))
      (multiple-value-bind (holds path) (verify behaviour '(ag (ex t)))
        (unless holds
          (push (make-diagnostic :deadlock
                                 (format nil "the behaviour gets stuck: ~A has no successor (reached by ~{~A~^ -> ~}); (AG (EX t)) fails"
                                         (car (last (counterexample-names behaviour path)))
                                         (counterexample-names behaviour path))
                                 nil)
                diagnostics)))
      (dolist (event (spec-events spec))
        (dolist (goal (event-goal-forms event))
          (progn
            (unless (verify behaviour (list 'ef goal))
              (push (make-diagnostic :unreachable-goal
                                     (format nil "goal ~A of event ~A is reached by no path from the initial state; (EF ~:*~:*~A) fails"
                                             (lisp-text goal) (lisp-text (event-name event)))
                                     goal)
                    diagnostics)))))
      (nreverse diagnostics))))
