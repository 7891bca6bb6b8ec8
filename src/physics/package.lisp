;;;; package.lisp -- player.physics: a scene's props and bodies as ODE objects: dynamic props that fall, collide and rest; bones and props as collision shapes; contacts reported.

(defpackage #:player.physics
  (:use #:cl #:player.base #:player.spec #:player.body #:player.ode)
  (:documentation "A scene's props and bodies as ODE objects: dynamic props that
fall, collide and rest; bones and props as collision shapes; contacts reported.")
  (:export
   #:*physics-step* #:*prop-density* #:prop-shape #:dynamic-prop-p #:prop-dynamic-p
   #:scene-physics #:scene-physics-p #:advance-scene-physics #:scene-physics-steps
   #:forget-scene-physics #:physics-prop-resting-p #:*collisions* #:*stop-at-contact* #:*contact-tolerance*
   #:scene-collisions))
