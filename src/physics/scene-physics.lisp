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
  world-position
  ;; A hanging prop's pivot (pendulums.lisp), which the physics turns; and its rotation as written.
  (carrier nil) written-carrier-rotation
  ;; The velocity (x y z) it was last moved at by others, which it keeps when let go.
  (release-velocity (list 0 0 0))
  ;; True when what was last written was the body asleep: nothing moves it until it wakes.
  (written-asleep nil))

(defstruct (physics-static (:constructor make-physics-static (object geom)))
  "A prop that does not move by itself, as a static GEOM placed where OBJECT
is; PLACED is what it was placed by, CENTRE and REACH a sphere holding it
\(REACH NIL: a plane).  BOX, for a box, holds its world rotation (9 numbers,
row by row) and half sizes (3), for an exact distance test (collisions.lisp)."
  object geom (placed nil) (centre (make-vec3 0d0 0d0 0d0)) (reach nil)
  (box nil :type (or null (simple-array double-float (12)))))

(defstruct (scene-physics (:constructor %make-scene-physics (scene world)))
  "The physics of SCENE: its ODE WORLD, its dynamic PROPS and STATICS, its
bodies' COLLIDERS, the STEPS done and the TIME of the last advance."
  scene world (props '()) (statics '()) (colliders '())
  (steps 0 :type fixnum) (time 0d0 :type double-float))

(defvar *collisions* t
  "When true, a scene with a visible body and props gets collision shapes, and
poses that would pass a hand through a prop or a body stop at contact
\(collisions.lisp).")

(defvar *stop-at-contact* t
  "When true, a composed pose that would pass a hand through something stops at
contact; when NIL the shapes are there (SCENE-COLLISIONS reports) but nothing
is corrected, as `check` plays scripts.")

(defvar *scene-physics* (make-hash-table :test #'eq :weakness :key :synchronized t)
  "Each scene's SCENE-PHYSICS (or :NONE when it needs none).")

(defun visible-bodies (scene)
  "SCENE's bodies that are drawn."
  (remove-if-not (lambda (object) (and (typep object 'body) (property-value object 'visible)))
                 (scene-objects scene)))

(defun needs-physics-p (scene)
  "Does SCENE need a world: a dynamic prop, or (with *COLLISIONS*, when ODE is
installed) a visible body and a prop?"
  (or (some #'dynamic-prop-p (scene-objects scene))
      (and *collisions*
           (visible-bodies scene)
           (some (lambda (object) (and (eq (object-kind object) :prop) (prop-shape object)))
                 (scene-objects scene))
           ;; Collisions are a refinement: without libode a body plays on unstopped.
           (ode-available-p))))

(defun scene-physics (scene)
  "SCENE's physics, made on first use; NIL when SCENE needs none (no dynamic
prop, and no body and prop to collide)."
  (check-argument 'scene-physics 'scene scene (lambda (x) (typep x 'scene)) "a scene")
  (let ((physics (gethash scene *scene-physics*)))
    (cond ((eq physics :none) nil)
          (physics physics)
          ((not (needs-physics-p scene))
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

(defun vec3-list (v)
  "The vec3 V as a list (x y z), as the ODE layer takes points."
  (list (vec3-x v) (vec3-y v) (vec3-z v)))

(defun quat-list (q)
  "The quat Q as a list (w x y z), as the ODE layer takes rotations."
  (list (quat-w q) (quat-x q) (quat-y q) (quat-z q)))

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
    ;; Nothing moves here: each world transform is computed once, so a long
    ;; chain of objects costs its length, not its length squared.
    (with-world-transforms-memoised ()
     (dolist (object (scene-objects scene))
      (let ((shape (and (eq (object-kind object) :prop) (prop-shape object))))
        (cond ((null shape))
              ((eq (first shape) :plane)
               ;; The floor: the plane through where the FLOOR prop stands.
               (setf floor-found t)
               (make-ode-geom world (list :plane 0 1 0 (vec3-y (object-world-position object))) :data object))
              ((dynamic-prop-p object)
               (multiple-value-bind (position rotation) (world-placement object)
                 (let* ((body (make-ode-body world shape :mass (prop-mass object shape)
                                                         :position position :rotation rotation :data object))
                        (geom (make-ode-geom world shape :body body :data object
                                                         :friction (surface object 'friction 0.6)
                                                         :bounce (surface object 'bounce
                                                                          (if (eq (first shape) :sphere) 0.4 0.05))))
                        (prop (make-physics-prop object body geom)))
                   (remember-written prop)
                   (setf (physics-prop-world-position prop) position)
                   (push prop (scene-physics-props physics)))))
              (t (let ((static (make-physics-static object (make-ode-geom world shape :data object))))
                   (setf (physics-static-reach static) (static-reach shape)
                         (physics-static-box static) (static-box shape))
                   (push static (scene-physics-statics physics))))))))
    (dolist (prop (scene-physics-props physics))
      (when (hanging-prop-p (physics-prop-object prop))
        (hang-prop world prop)))
    (setf (ode-world-contact-filter world) (pendulum-filter physics))
    (unless floor-found
      (make-ode-geom world '(:plane 0 1 0 0)))
    (when *collisions*
      (setf (scene-physics-colliders physics)
            (mapcar (lambda (body) (make-body-collider world body)) (visible-bodies scene))))
    (setf (scene-physics-props physics) (nreverse (scene-physics-props physics))
          (scene-physics-statics physics) (nreverse (scene-physics-statics physics)))
    physics))

(defun remember-written (prop)
  "Note PROP's object's placement properties (and its pivot's) as the physics' own."
  (let ((object (physics-prop-object prop)))
    (setf (physics-prop-written-position prop) (property-value object 'position)
          (physics-prop-written-rotation prop) (property-value object 'rotation)
          (physics-prop-written-velocity prop) (declared-property object 'velocity)
          (physics-prop-written-carrier-rotation prop)
          (and (physics-prop-carrier prop) (property-value (physics-prop-carrier prop) 'rotation)))))

(defun surface (object name default)
  "OBJECT's surface property NAME (FRICTION 0 to 10, BOUNCE 0 to 1) when it declares it, else DEFAULT."
  (let ((value (declared-property object name)))
    (if (realp value) (max 0 (min value (if (eq name 'bounce) 1 10))) default)))
