;;;; door.lisp -- the door of doc/lisp-api.md's REPL session, as a spec file:
;;;; with no script library, the placeholders of doc/animation.md play it.

(in-package :player-user)

(defspec door
  (state-variable open boolean false)
  (state-variable locked boolean true)
  (op unlock :precond locked :sub locked)
  (op open-door :precond (not locked) :add open)
  (event ev-enter :state open))
