;;;; test-side-effects.lisp -- `check` warns when an event's plan changes a
;;;; variable its goal does not mention and no later step needs (issue 27,
;;;; item 7): the robot that gave its cup away to free its hands for a
;;;; greeting.  Steps towards the goal (sitting down to sleep) are no side
;;;; effect; :must-ask on the op silences it.

(in-package #:player-tests)

(def-suite* side-effects :in player-tests)

(defun side-effect-messages (spec)
  "The messages of SPEC's :SIDE-EFFECT diagnostics."
  (mapcar #'player.planner::diagnostic-message
          (remove :side-effect (check-spec spec) :key #'player.planner::diagnostic-kind :test-not #'eq)))

(test check-warns-of-a-side-effect
  "The greeting's plan from holding the cup runs hand-over, which gives the
cup away: the warning names the event, the op, the variable and the state,
and suggests :must-ask."
  (with-spec (spec robot-greets
                   (state-variable holding boolean true)
                   (state-variable cup string hand (hand visitor))
                   (op hand-over :precond holding :sub holding :add cup.visitor)
                   (op greet :precond (not holding))
                   (event ev-greet :op greet))
    (let ((messages (side-effect-messages spec)))
      (is (= 1 (length messages)) "~S" messages)
      (is (equal "event ev-greet, from holding: its plan runs op hand-over, which changes cup, a variable op greet does not mention; if that is not meant, make hand-over :must-ask"
                 (first messages))))))

(test steps-towards-the-goal-are-no-side-effect
  "Sitting down to sleep changes posture, which the sleep's precondition
needs; putting the cup down to greet changes only what the greeting needs;
and a :must-ask hand-over is never a step."
  (with-spec (spec robot-sleeps
                   (state-variable posture string stand (stand sit))
                   (state-variable asleep boolean false)
                   (op sit :precond posture.stand :add posture.sit)
                   (op doze :precond posture.sit :add asleep)
                   (event ev-sleep :state asleep))
    (is (null (side-effect-messages spec))))
  (with-spec (spec robot-greets-politely
                   (state-variable holding boolean true)
                   (state-variable cup string hand (hand visitor table))
                   (op hand-over :precond holding :sub holding :add cup.visitor :must-ask true)
                   (op put-down :precond holding :sub holding :add cup.table)
                   (op greet :precond (not holding))
                   (event ev-greet :op greet)
                   (event ev-give :op hand-over))
    ;; put-down moves the cup too: the author is told, and can say it is meant.
    (is (every (lambda (message) (search "op put-down" message)) (side-effect-messages spec)))
    (is (notany (lambda (message) (search "op hand-over" message)) (side-effect-messages spec)))))

(test check-command-prints-the-side-effect-warning
  "`player check` prints the warning on a spec file."
  (let ((path (temp-path "robot.lisp")))
    (with-open-file (out path :direction :output :if-exists :supersede)
      (write-string "(defspec robot
  (state-variable holding boolean true)
  (state-variable cup string hand (hand visitor))
  (op hand-over :precond holding :sub holding :add cup.visitor)
  (op greet :precond (not holding))
  (event ev-greet :op greet))
" out))
    (multiple-value-bind (out err code) (player-command "check" path)
      (is (= 0 code) "~A" err)
      (is (search "warning: event ev-greet, from holding: its plan runs op hand-over, which changes cup" out)
          "~A" out))))
