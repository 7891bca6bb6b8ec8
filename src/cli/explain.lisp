;;;; explain.lisp -- `player explain`: the plan from a state to a goal, or
;;;; through an event, each op with the literal it achieves (EXPLAIN-PLAN).

(in-package #:player.cli)

(defun read-goal-text (text)
  "The state expression TEXT (--goal's value) holds, read as data
\(READ-CLI-FORM), never evaluated; a USAGE-ERROR when TEXT is not one form."
  (multiple-value-bind (form one) (read-cli-form text "--goal")
    (if one
        form
        (usage-fail "--goal takes one state expression, e.g. posture.sit or \"(and alert.awake (not wing-at-ear))\", not ~S"
                    text))))

(define-command "explain" (file &key spec no-code initial goal event)
    (:summary "explain the plan from a state to a goal, or through an event"
     :description "From the initial state (overridden by --initial), one line per op the
controller would run, saying which literal of the next step's precondition, or
of the goal, it makes true.  With --event, each :state and :op directive in
turn, from the state the previous one leaves.  A goal that already holds says
so; for a goal no plan reaches, the literals no op adds, or else the
preconditions that block in the reachable states nearest the goal.  Give
exactly one of --goal and --event."
     :arguments ("SPEC-FILE")
     :options ("--spec" "--no-code" "--initial"
               ("--goal" :string "EXPR" "the state expression to reach, as in :state (quote it for the shell)")
               ("--event" :string "EV" "the event whose directives to explain"))
     :output "the explanation on standard output")
  (when (eq (null goal) (null event))
    (usage-fail "explain needs exactly one of --goal EXPR and --event EV"))
  (let ((goal (and goal (read-goal-text goal)))
        (spec (choose-spec file spec :allow-code (not no-code))))
    (print-explanation (if event
                           (explain-plan spec :initial initial :event event)
                           (explain-plan spec :initial initial :goal goal)))))
