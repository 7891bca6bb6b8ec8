;;;; joints.lisp -- joints that hold bodies together: a ball joint hangs a
;;;; pendulum (a cradle's sphere) from a point of the world or of another body.

(in-package #:player.ode)

(defstruct (ode-joint (:constructor %make-ode-joint))
  "A joint of WORLD at POINTER."
  (pointer (cffi:null-pointer) :type sb-sys:system-area-pointer)
  (world nil :type ode-world))

(defun make-ode-ball-joint (world body anchor &optional other)
  "A ball joint holding BODY at ANCHOR (x y z, world coordinates) to OTHER (a
body) or, without it, to the world itself."
  (live-world 'make-ode-ball-joint world)
  (live-body 'make-ode-ball-joint body)
  (check-argument 'make-ode-ball-joint 'anchor anchor #'finite-triple-p "a list of three finite numbers (metres)")
  (when other (live-body 'make-ode-ball-joint other))
  (let ((pointer (with-ode-traps-masked (%d-joint-create-ball (ode-world-pointer world) (cffi:null-pointer)))))
    (with-ode-traps-masked
      (%d-joint-attach pointer (ode-body-pointer body) (if other (ode-body-pointer other) (cffi:null-pointer)))
      (apply #'%d-joint-set-ball-anchor pointer (mapcar (lambda (x) (float x 1d0)) anchor)))
    (%make-ode-joint :pointer pointer :world world)))
