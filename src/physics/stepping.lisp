;;;; stepping.lisp -- advancing a scene's physics to a time: read what others
;;;; did to the props (held, placed by a script, tossed), step the world on its
;;;; fixed grid, write the free props' places back into the scene.

(in-package #:player.physics)

(defun advance-scene-physics (scene time)
  "Step SCENE's physics (if it has any) to the last step at or before TIME
\(seconds) and place its free dynamic props there.  Returns the SCENE-PHYSICS or NIL."
  (check-seconds 'advance-scene-physics 'time time)
  (let ((physics (scene-physics scene)))
    (when physics
      (ensure-ode-thread)
      (with-ode-traps-masked
        (place-statics physics)
        ;; The bodies were just posed: stop hands at contact before anything steps.
        (when (and *stop-at-contact* (scene-physics-colliders physics))
          (correct-collisions physics (float time 1d0)))
        (let ((target (floor (+ (/ time *physics-step*) 1d-6))))
          (when (and (> target (scene-physics-steps physics)) (scene-physics-props physics))
            (let ((time (float time 1d0)))
              (read-scene-changes physics time)
              (ode-world-step (scene-physics-world physics) (- target (scene-physics-steps physics)))
              (setf (scene-physics-time physics) time)
              (write-free-props physics)))
          (setf (scene-physics-steps physics) (max target (scene-physics-steps physics))))))
    physics))

;;;# Reading the scene

(defun held-p (object)
  "Does OBJECT hang from something that places it: a joint, a body or a prop (not
a group, which is a frame or a pendulum's pivot)?"
  (let ((parent (object-parent object)))
    (or (consp parent)
        (and parent (not (eq (object-kind parent) :group))))))

(defun placed-by-script-p (prop)
  "Has someone but the physics set PROP's position, rotation or velocity since it wrote them?"
  (let ((object (physics-prop-object prop))
        (carrier (physics-prop-carrier prop)))
    (or (not (equalp (property-value object 'position) (physics-prop-written-position prop)))
        (not (equalp (property-value object 'rotation) (physics-prop-written-rotation prop)))
        (and carrier
             (not (equalp (property-value carrier 'rotation) (physics-prop-written-carrier-rotation prop)))))))

(defun tossed-p (prop)
  "Has a script set PROP's VELOCITY since the physics wrote it?"
  (let ((velocity (declared-property (physics-prop-object prop) 'velocity)))
    (and velocity (not (equalp velocity (physics-prop-written-velocity prop))))))

(defun read-scene-changes (physics time)
  "Bring PHYSICS's bodies and static geoms to what the scene says at TIME."
  (let ((elapsed (- time (scene-physics-time physics))))
    (dolist (prop (scene-physics-props physics))
      (read-prop-change prop elapsed))))

(defun place-statics (physics)
  "Put PHYSICS's static geoms where their props are now (a script may move
them).  Only geoms move here, so each world transform is computed once."
  (with-world-transforms-memoised ()
   (dolist (static (scene-physics-statics physics))
    (let* ((object (physics-static-object static))
           (parent (object-parent object))
           (position (property-value object 'position))
           (rotation (property-value object 'rotation))
           (placed (physics-static-placed static)))
      ;; Properties are copied when set, so unchanged EQ values under no parent mean no move.
      (unless (and (null parent) placed
                   (eq (second placed) position) (eq (third placed) rotation))
        (multiple-value-bind (world-position world-rotation) (world-placement object)
          (set-ode-geom-placement (physics-static-geom static) world-position world-rotation)
          (setf (physics-static-placed static) (list parent position rotation)
                (physics-static-centre static) (apply #'make-vec3 world-position))
          (when (physics-static-box static)
            (apply #'set-box-rotation (physics-static-box static) world-rotation))))))))

(defun read-prop-change (prop elapsed)
  "Set PROP's mode and body from its object after ELAPSED seconds: held or
placed by a script, it is moved there kinematically, with the velocity of
that move when it was held or placed the advance before too; let go or left
alone, it is dynamic, flying on with the velocity it had."
  (let* ((object (physics-prop-object prop))
         (body (physics-prop-body prop))
         (before (physics-prop-mode prop))
         (mode (cond ((or (held-p object) (not (prop-dynamic-p object))) :held)
                     ;; Let go: the new parent's frame changed its numbers, not its place.
                     ((eq before :held) :released)
                     ((placed-by-script-p prop) :moved)
                     (t :free))))
    (setf (physics-prop-mode prop) (if (eq mode :released) :free mode))
    (if (eq mode :free)
        (when (ode-body-kinematic-p body)
          ;; Let go: it flies on with the velocity it was last moved at.
          (setf (ode-body-kinematic-p body) nil
                (ode-body-velocity body) (physics-prop-release-velocity prop)))
        (multiple-value-bind (position rotation) (world-placement object)
          (setf (physics-prop-release-velocity prop)
                (if (and (member before '(:held :moved)) (plusp elapsed))
                    (mapcar (lambda (new old) (/ (- new old) elapsed)) position (physics-prop-world-position prop))
                    (list 0 0 0)))
          (setf (ode-body-kinematic-p body) (not (eq mode :released)))
          (set-ode-body-placement body position rotation)
          ;; Held still while the world steps (a kinematic body would drift on
          ;; at its velocity, off a pendulum's circle); released, it flies.
          (setf (ode-body-velocity body) (if (eq mode :released) (physics-prop-release-velocity prop) (list 0 0 0))
                (ode-body-angular-velocity body) (list 0 0 0)
                (physics-prop-world-position prop) position)
          (remember-written prop)))
    (when (tossed-p prop)
      (let ((velocity (declared-property object 'velocity)))
        (setf (ode-body-velocity body) (vec3-list velocity)
              (physics-prop-written-velocity prop) velocity)))))

;;;# Writing the scene

(defun parent-frame-inverse (object)
  "The transform from the world into OBJECT's parent's frame (OBJECT hangs
from nothing or from a group)."
  (let ((parent (object-parent object)))
    (if parent
        (transform-invert (object-world-transform parent))
        (identity-transform))))

(defun body-blew-up-p (body)
  "Is BODY's position no longer finite (an explosion the solver could not recover from)?"
  (notevery #'finite-real-p (multiple-value-list (ode-body-position body))))

(defun write-free-props (physics)
  "Put each free dynamic prop of PHYSICS where its body is, in its parent's frame
\(one whose numbers stopped being finite goes back to where it last was, at rest)."
  (dolist (prop (scene-physics-props physics))
    (when (and (eq (physics-prop-mode prop) :free) (body-blew-up-p (physics-prop-body prop)))
      (set-ode-body-placement (physics-prop-body prop) (physics-prop-world-position prop))
      (setf (ode-body-velocity (physics-prop-body prop)) (list 0 0 0)
            (ode-body-angular-velocity (physics-prop-body prop)) (list 0 0 0)))
    (when (and (eq (physics-prop-mode prop) :free) (not (asleep-as-written-p prop)))
      (let* ((object (physics-prop-object prop))
             (body (physics-prop-body prop))
             (world (multiple-value-bind (x y z) (ode-body-position body)
                      (multiple-value-bind (qw qx qy qz) (ode-body-rotation body)
                        (make-transform :translation (make-vec3 x y z) :rotation (make-quat qw qx qy qz)))))
             (local (transform-compose (parent-frame-inverse object) world)))
        (if (physics-prop-carrier prop)
            ;; A pendulum: its pivot turns, carrying it (and its string).
            (write-pivot prop (transform-translation world))
            (setf (property-value object 'position) (transform-translation local)
                  (property-value object 'rotation) (transform-rotation local)))
        (when (declared-property object 'velocity)
          (setf (property-value object 'velocity)
                (multiple-value-bind (x y z) (ode-body-velocity body) (make-vec3 x y z))))
        (setf (physics-prop-world-position prop) (vec3-list (transform-translation world))
              (physics-prop-written-asleep prop) (not (ode-body-enabled-p body)))
        (remember-written prop)))))

(defun asleep-as-written-p (prop)
  "Is PROP's body asleep, and was it asleep when its place was last written?
Then the scene already shows where it lies (a prop hanging from nothing: a
group's move would change its numbers)."
  (and (physics-prop-written-asleep prop)
       (null (object-parent (physics-prop-object prop)))
       (null (physics-prop-carrier prop))
       (not (ode-body-enabled-p (physics-prop-body prop)))))

(defun physics-prop-resting-p (scene name)
  "Is the dynamic prop NAME of SCENE asleep: at rest, until something moves it?"
  (let* ((physics (scene-physics scene))
         (prop (and physics (find name (scene-physics-props physics)
                                  :key (lambda (p) (object-name (physics-prop-object p))) :test #'string-equal))))
    (and prop (not (ode-body-enabled-p (physics-prop-body prop))))))
