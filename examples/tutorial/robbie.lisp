;;;; robbie.lisp -- Robbie the receptionist, the character of doc/tutorial.md.

(in-package :player-user)

(defspec robbie
  "Robbie the receptionist: dozes at the desk, wakes, waves, bows, points the way."
  (:body humanoid)
  (state-variable awake boolean false)
  (state-variable arms string down (down raised on-hips))
  (state-class ready (awake arms.down))
  (op wake-up :precond (not awake) :add awake :duration 1)
  (op doze-off :precond ready :sub awake :duration 1.5)
  (op raise-arms :precond ready :add arms.raised :duration 0.8 :interrupt :anytime)
  (op lower-arms :precond arms.raised :add arms.down :duration 0.8)
  (op wave :precond arms.raised :duration 2 :interrupt (:at 0.5 1 1.5))
  (op hands-on-hips :precond ready :add arms.on-hips :duration 1)
  (op relax :precond arms.on-hips :add arms.down :duration 0.6)
  (op bow :precond ready :duration 1.5)
  (op point :precond ready :duration 1.2)
  (event ev-hello :op wave :state ready)
  (event ev-thanks :op bow)
  (event ev-where :op point)
  (event ev-wait :state arms.on-hips)
  (event ev-sleep (:when-busy :preempt) :state (not awake)))
