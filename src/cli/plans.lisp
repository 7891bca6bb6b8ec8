;;;; plans.lisp -- `player plans`: every goal's plan table.

(in-package #:player.cli)

(define-command "plans" (file &key spec no-code)
    (:summary "print every goal's plan table"
     :description "For each goal: the forms that request it, then its plans in the order
they are tried, each a condition on the state and the ops to run."
     :arguments ("SPEC-FILE")
     :options ("--spec" "--no-code")
     :output "standard output")
  (let* ((spec (choose-spec file spec :allow-code (not no-code)))
         (machine (plan-spec spec)))
    (format t "spec ~A: ~D goals, ~D ~:[~;reachable ~]states, max-depth ~D~:[~;, optimize :duration~]~%"
            (lisp-text (spec-name spec)) (length (machine-goal-table machine))
            (machine-state-count machine) (layout-reachable (machine-layout machine))
            (spec-max-depth spec) (eq (spec-optimize spec) :duration))
    (loop for goal across (machine-goal-table machine)
          do (format t "~%goal ~D: ~A~%" (1+ (goal-id goal)) (lisp-text (goal-expression goal)))
             (format t "  requested as: ~{~A~^, ~}~%" (mapcar #'lisp-text (reverse (goal-forms goal))))
             (loop for (condition . ops) in (goal-plan-table goal spec)
                   for i from 1
                   do (format t "  ~3D. if ~A~%       run ~A~%" i (lisp-text condition)
                              (if ops (lisp-text ops) "nothing (already true)")))
             (let ((missing (- (machine-state-count machine) (goal-solved-count goal))))
               (when (plusp missing)
                 (format t "  unreachable from ~D of ~D ~:[~;reachable ~]states~%" missing
                         (machine-state-count machine) (layout-reachable (machine-layout machine))))))))
