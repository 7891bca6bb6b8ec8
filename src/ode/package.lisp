;;;; package.lisp -- player.ode: the Open Dynamics Engine (Debian's libode8) through CFFI: raw %d bindings, then worlds, bodies, geoms, joints and contacts checked in Lisp.

(defpackage #:player.ode
  (:use #:cl #:player.base)
  (:documentation "The Open Dynamics Engine (Debian's libode8) through CFFI: raw
%d bindings, then worlds, bodies, geoms, joints and contacts checked in Lisp.")
  (:export
   #:ode-error #:ode-unavailable #:ensure-ode #:ensure-ode-thread #:ode-available-p #:with-ode-traps-masked
   ;; worlds
   #:make-ode-world #:ode-world-p #:destroy-ode-world #:ode-world-step #:ode-world-gravity
   #:ode-world-step-size #:ode-world-geoms #:ode-world-bodies #:ode-world-contact-filter
   ;; bodies
   #:make-ode-body #:ode-body-p #:ode-body-position #:ode-body-rotation #:ode-body-velocity
   #:ode-body-angular-velocity #:ode-body-kinematic-p #:ode-body-enabled-p #:ode-body-mass
   #:ode-body-data #:set-ode-body-placement
   ;; geoms
   #:make-ode-geom #:ode-geom-p #:ode-geom-shape #:ode-geom-body #:ode-geom-data
   #:set-ode-geom-placement #:set-ode-geom-position #:set-ode-geom-rotation #:set-ode-capsule-size #:ode-geom-friction
   #:ode-geom-bounce #:ode-geom-enabled-p #:ode-shape-p
   ;; joints and contacts
   #:make-ode-ball-joint #:ode-joint-p #:ode-geom-contacts #:ode-contact #:ode-contact-position
   #:ode-contact-normal #:ode-contact-depth #:ode-geom-depth #:ode-world-touching-pairs))
