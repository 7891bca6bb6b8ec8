;;;; pendulums.lisp -- a dynamic prop that hangs: declared with the property
;;;; (hangs :boolean t) and hung from a group (its pivot), it swings on a
;;;; ball joint at the pivot's origin, as far from it as it was declared.
;;;; The physics turns the pivot, not the prop, so whatever else hangs from
;;;; the pivot (a cradle's string) swings along; a script turning the pivot
;;;; (a hand lifting the sphere) moves it, and when it lets go the sphere
;;;; swings on by itself.  Newton's cradle is five of them in a row
;;;; (src/compose/cradle-ode-scripts.lisp).

(in-package #:player.physics)

(defun hanging-prop-p (object)
  "Does the dynamic prop OBJECT hang from its parent, a group (its HANGS property true)?"
  (let ((parent (object-parent object)))
    (and (dynamic-prop-p object)
         (declared-property object 'hangs)
         (typep parent 'scene-object)
         (eq (object-kind parent) :group))))

(defun hang-prop (world prop)
  "Hold PROP's body on a ball joint at its pivot's origin; note the pivot as its carrier."
  (let ((pivot (object-parent (physics-prop-object prop))))
    (setf (physics-prop-carrier prop) pivot)
    (make-ode-ball-joint world (physics-prop-body prop) (vec3-list (object-world-position pivot)))
    (remember-written prop)))

(defun shortest-arc (from to)
  "The rotation (a quat) turning the unit vector FROM onto the unit vector TO."
  (let ((w (+ 1 (vdot from to))))
    (if (< w 1d-9)
        ;; Opposite: half a turn about any axis square to FROM.
        (let ((axis (vnormalize (if (> (abs (vec3-x from)) 0.9d0)
                                    (vcross from (make-vec3 0d0 1d0 0d0))
                                    (vcross from (make-vec3 1d0 0d0 0d0))))))
          (make-quat 0d0 (vec3-x axis) (vec3-y axis) (vec3-z axis)))
        (let ((axis (vcross from to)))
          (qnormalize (make-quat w (vec3-x axis) (vec3-y axis) (vec3-z axis)))))))

(defun write-pivot (prop world-position)
  "Turn PROP's pivot so that PROP, at its declared offset, is at WORLD-POSITION (a vec3)."
  (let* ((object (physics-prop-object prop))
         (pivot (physics-prop-carrier prop))
         (into-parent (parent-frame-inverse pivot))
         (pivot-at (transform-translation (object-world-transform pivot)))
         (down (vnormalize (transform-vector into-parent (v- world-position pivot-at))))
         (rest (vnormalize (property-value object 'position))))
    (setf (property-value pivot 'rotation) (shortest-arc rest down))))

(defun pendulum-filter (physics)
  "A contact filter for PHYSICS's world: a pendulum touches only other dynamic
props (a cradle's balls meet each other, never the stand they hang in)."
  (let ((pendulums (loop for prop in (scene-physics-props physics)
                         when (physics-prop-carrier prop) collect (physics-prop-object prop))))
    (and pendulums
         (lambda (a b)
           (let ((object-a (ode-geom-data a)) (object-b (ode-geom-data b)))
             (flet ((pendulum-p (object) (member object pendulums))
                    (dynamic-p (object) (and (typep object 'scene-object) (dynamic-prop-p object))))
               (not (or (and (pendulum-p object-a) (not (dynamic-p object-b)))
                        (and (pendulum-p object-b) (not (dynamic-p object-a)))))))))))
