;;;; facing.lisp -- the facing driver (Pantomime's FacingDriver): turns the
;;;; whole body about the vertical, by its root joint's y DOF, so that its
;;;; front (+z) faces a target horizontally.

(in-package #:player.body)

(defclass facing-driver (driver)
  ((dof :accessor facing-dof :documentation "The root's DOF about the vertical.")
   (from :initform 0d0 :accessor facing-from :documentation "Its angle at the start.")
   (to :initform 0d0 :accessor facing-to :documentation "Its angle facing the target."))
  (:documentation "Performs :facing: turns the body to face the target over
:duration, eased, then ends (the root holds the angle)."))

(defmethod driver-setup ((driver facing-driver))
  (let* ((root (skeleton-root (driver-skeleton driver)))
         (dof (find :y (body-joint-dofs root) :key #'dof-axis-line)))
    (unless dof
      (motor-fail (motor-call-frame (driver-call driver))
                  "the root joint ~A of skeleton ~A cannot turn about the vertical (no y DOF)"
                  (lisp-text (body-joint-name root))
                  (lisp-text (skeleton-name (driver-skeleton driver)))))
    (setf (facing-dof driver) dof)
    (list (+ (body-joint-dof-start root) (position dof (body-joint-dofs root))))))

(defparameter *facing-offsets* '((:full . 0d0) (:half . 45d0) (:away . 90d0))
  "Degrees each facing mode turns the body off the target: full faces it, half
stands at 45 degrees to it, away shows it a shoulder (Pantomime's full, half, away).")

(defun facing-heading (driver pose)
  "The angle (degrees, in the root y DOF's convention) that turns the root's
front toward DRIVER's target, horizontally, from the body's placement frame;
NIL when the target is straight above or below the root.  It assumes the root
otherwise stands upright (its x and z DOFs near zero)."
  (let* ((body (driver-body driver))
         (placement (object-world-transform body))
         (root (skeleton-root (driver-skeleton driver)))
         (position (transform-point placement (joint-offset root)))
         (target (driver-arg driver :target))
         ;; No target: the front the body was placed with (the audience).
         (direction (if target
                        (transform-vector (transform-invert placement)
                                          (v- (%resolve-target target body pose) position))
                        (vec3 0d0 0d0 1d0))))
    (unless (< (+ (expt (vec3-x direction) 2) (expt (vec3-z direction) 2)) 1d-18)
      (* (dof-sign (facing-dof driver)) (/ 180d0 pi)
         (atan (vec3-x direction) (vec3-z direction))))))

(defun nearest-turn (from heading dof)
  "The angle equal to HEADING modulo 360 nearest FROM, within DOF's limits if one is."
  (let* ((turn (- heading from))
         (near (+ from (- turn (* 360d0 (fround turn 360d0))))))
    (loop for candidate in (list near (- near 360d0) (+ near 360d0))
          when (<= (body-dof-min dof) candidate (body-dof-max dof))
            return candidate
          finally (return (clamp-to-dof dof near)))))

(defmethod driver-begin ((driver facing-driver) pose time)
  (declare (ignore time))
  (let* ((from (aref pose (first (driver-channels driver))))
         (heading (facing-heading driver pose))
         (offset (cdr (assoc (driver-arg driver :mode) *facing-offsets*)))
         (amount (min 1d0 (driver-real driver :amount))))
    (setf (facing-from driver) from
          (facing-to driver)
          (if heading
              (let* ((toward (nearest-turn from heading (facing-dof driver)))
                     ;; Half and away turn off the target on the side the body already is.
                     (goal (nearest-turn from (+ toward (* (if (< from toward) -1d0 1d0) offset))
                                         (facing-dof driver))))
                (+ from (* amount (- goal from))))
              from))))

(defmethod driver-end-time ((driver facing-driver))
  (+ (driver-start driver) (gesture-seconds driver :duration)))

(defmethod driver-drive ((driver facing-driver) time pose)
  (let ((from (facing-from driver)))
    (setf (aref pose (first (driver-channels driver)))
          (+ from (* (ramp time (driver-start driver) (gesture-seconds driver :duration))
                     (- (facing-to driver) from))))))

(define-motor-function :facing facing-driver
  "Turn the whole body about the vertical to face a target, eased over :duration
(Pantomime's facing); the body stays turned when it ends."
  (:target (:or :target (:member nil)) nil "what to face; NIL: the front the body was placed with")
  (:mode (:member :full :half :away) :full "face it fully, stand at 45 degrees to it, or at 90 (a shoulder to it)")
  (:amount :non-negative 1 "how much of the turn to make, 0 to 1")
  (:duration :positive 1.0 "seconds to complete the turn")
  (:priority :real 15 "arbitration priority; higher wins"))

(defmethod driver-default-blend ((driver facing-driver))
  ;; It eases from the angles it captured at its start: a crossfade would only slow it.
  0d0)
