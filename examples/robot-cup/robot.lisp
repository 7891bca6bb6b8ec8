;;;; robot.lisp -- the robot that gave its cup away to greet someone: the
;;;; side effect `check` warns about (doc/language.md, "When to use :must-ask").

(in-package :player-user)

(defspec robot
  "A robot holding a cup, told to greet a visitor, which needs both hands."
  (state-variable holding boolean true)
  (state-variable cup string hand (hand visitor))
  (op hand-over :precond holding :sub holding :add cup.visitor)
  (op greet :precond (not holding))
  (event ev-greet :op greet))
