;;;; scene-physics.lisp -- a scene's dynamic props simulated by ODE.  A scene
;;;; with a prop declared (defobject NAME ... :dynamic t) gets a world: every
;;;; prop is a collision shape, the dynamic ones rigid bodies, and the set has
;;;; a floor (the FLOOR prop's plane, else the plane y = 0).
;;;;
;;;; The rule, in one sentence: a dynamic prop is the physics' while it lies
;;;; free (hangs from nothing, or from a group); whoever else places it -- a
;;;; hand holding it, a script's :set or :animate of its position -- moves it
;;;; as a kinematic body, and when they let go it flies on with the velocity
;;;; they gave it (a script may also :set its VELOCITY, a toss).
;;;;
;;;; Time: the world steps on a fixed grid of *PHYSICS-STEP* seconds from 0,
;;;; so the same calls give the same frames; a scene replayed from the start
;;;; is a fresh scene and gets a fresh world.

(in-package #:player.physics)

(defparameter *physics-step* (/ 1d0 240)
  "Seconds per step of a scene's world.")

(defstruct (physics-prop (:constructor make-physics-prop (object body geom)))
  "A dynamic prop OBJECT as an ODE BODY with its GEOM.  MODE is :FREE (the
physics moves it), :HELD (it hangs from something that moves it) or :MOVED (a
script placed it since the last advance).  WRITTEN-* are the property values
the physics last wrote, so a script's change shows; WORLD-POSITION is where
it was at the last advance."
  object body geom
  (mode :free)
  written-position written-rotation written-velocity
  world-position)

(defstruct (physics-static (:constructor make-physics-static (object geom)))
  "A prop that does not move by itself, as a static GEOM placed where OBJECT is."
  object geom (placed nil))

(defstruct (scene-physics (:constructor %make-scene-physics (scene world)))
  "The physics of SCENE: its ODE WORLD, its dynamic PROPS and STATICS, the
STEPS done and the TIME of the last advance."
  scene world (props '()) (statics '()) (steps 0 :type fixnum) (time 0d0 :type double-float))

(defvar *scene-physics* (make-hash-table :test #'eq :weakness :key :synchronized t)
  "Each scene's SCENE-PHYSICS (or :NONE when it has no dynamic prop).")

(defun scene-physics (scene)
  "SCENE's physics, made on first use; NIL when SCENE has no dynamic prop."
  (check-argument 'scene-physics 'scene scene (lambda (x) (typep x 'scene)) "a scene")
  (let ((physics (gethash scene *scene-physics*)))
    (cond ((eq physics :none) nil)
          (physics physics)
          ((notany #'dynamic-prop-p (scene-objects scene))
           (setf (gethash scene *scene-physics*) :none)
           nil)
          (t (setf (gethash scene *scene-physics*) (make-scene-physics scene))))))

(defun forget-scene-physics (scene)
  "Drop SCENE's physics (its world is freed); the next advance starts a fresh one."
  (let ((physics (gethash scene *scene-physics*)))
    (when (scene-physics-p physics)
      (destroy-ode-world (scene-physics-world physics)))
    (remhash scene *scene-physics*)
    nil))

;;;# Building

(defun vec3-list (v) (list (vec3-x v) (vec3-y v) (vec3-z v)))
(defun quat-list (q) (list (quat-w q) (quat-x q) (quat-y q) (quat-z q)))

(defun world-placement (object)
  "OBJECT's world position and rotation, as lists (x y z) and (w x y z)."
  (let ((transform (object-world-transform object)))
    (values (vec3-list (transform-translation transform)) (quat-list (transform-rotation transform)))))

(defun make-scene-physics (scene)
  "A SCENE-PHYSICS for SCENE: a world, a body for each dynamic prop, a static
geom for every other prop with a shape, and the floor."
  (let* ((world (make-ode-world :step-size *physics-step*))
         (physics (%make-scene-physics scene world))
         (floor-found nil))
    (dolist (object (scene-objects scene))
      (let ((shape (and (eq (object-kind object) :prop) (prop-shape object))))
        (cond ((null shape))
              ((eq (first shape) :plane)
               (setf floor-found t)
               (make-ode-geom world (list :plane 0 1 0 (vec3-y (object-world-position object))) :data object))
              ((dynamic-prop-p object)
               (multiple-value-bind (position rotation) (world-placement object)
                 (let* ((body (make-ode-body world shape :mass (prop-mass object shape)
                                                         :position position :rotation rotation :data object))
                        (geom (make-ode-geom world shape :body body :data object
                                                         :bounce (if (eq (first shape) :sphere) 0.4 0.05)))
                        (prop (make-physics-prop object body geom)))
                   (remember-written prop)
                   (setf (physics-prop-world-position prop) position)
                   (push prop (scene-physics-props physics)))))
              (t (push (make-physics-static object (make-ode-geom world shape :data object))
                       (scene-physics-statics physics))))))
    (unless floor-found
      (make-ode-geom world '(:plane 0 1 0 0)))
    (setf (scene-physics-props physics) (nreverse (scene-physics-props physics))
          (scene-physics-statics physics) (nreverse (scene-physics-statics physics)))
    physics))

(defun remember-written (prop)
  "Note PROP's object's placement properties as the physics' own."
  (let ((object (physics-prop-object prop)))
    (setf (physics-prop-written-position prop) (property-value object 'position)
          (physics-prop-written-rotation prop) (property-value object 'rotation)
          (physics-prop-written-velocity prop) (declared-property object 'velocity))))
