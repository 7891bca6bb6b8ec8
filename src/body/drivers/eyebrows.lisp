;;;; eyebrows.lisp -- the eyebrows driver (Pantomime's EyebrowsDriver): raise
;;;; or lower the brows by a fraction of their range, hold, and let them fall
;;;; back.  A figure without brows but with a crest (the parrot) raises that.

(in-package #:player.body)

(defclass eyebrows-driver (driver)
  ((dofs :accessor eyebrows-dofs :documentation "The brow (or crest) DOFs it moves.")
   (from :initform '() :accessor eyebrows-from :documentation "Their angles at the start."))
  (:documentation "Performs :eyebrows: moves the brows (or crest) to :raise of
their range over :duration, holds them :hold seconds, and brings them back over
:duration; with :hold NIL they stay until stopped."))

(defun brow-joints (driver)
  "The joints DRIVER moves: the brows of its :side, or the :crest when the
skeleton has no brows; a MOTOR-ERROR naming DRIVER's frame when it has neither."
  (let* ((roles (ecase (driver-arg driver :side)
                  (:left '(:left-brow))
                  (:right '(:right-brow))
                  (:both '(:left-brow :right-brow))))
         (brows (remove nil (mapcar (lambda (role) (role-joint driver role nil)) roles))))
    (or brows
        (let ((crest (role-joint driver :crest nil)))
          (and crest (list crest)))
        (motor-fail (motor-call-frame (driver-call driver))
                    "skeleton ~A has neither ~{~A~^ nor ~} nor a crest to raise"
                    (lisp-text (skeleton-name (driver-skeleton driver)))
                    (mapcar #'lisp-text roles)))))

(defmethod driver-setup ((driver eyebrows-driver))
  (let ((raise (driver-arg driver :raise)))
    (unless (<= -1 raise 1)
      (motor-fail (motor-call-frame (driver-call driver))
                  "eyebrows :raise must lie between -1 and 1 (a fraction of the range), not ~A"
                  (lisp-text raise))))
  (let ((joints (brow-joints driver)))
    (setf (eyebrows-dofs driver)
          (mapcar (lambda (joint) (or (body-joint-dof joint 'raise) (first (body-joint-dofs joint))))
                  joints))
    (loop for joint in joints
          for dof in (eyebrows-dofs driver)
          unless dof
            do (motor-fail (motor-call-frame (driver-call driver)) "joint ~A has no DOF to raise"
                           (lisp-text (body-joint-name joint)))
          collect (+ (body-joint-dof-start joint) (position dof (body-joint-dofs joint))))))

(defmethod driver-begin ((driver eyebrows-driver) pose time)
  (declare (ignore time))
  (setf (eyebrows-from driver) (loop for i in (driver-channels driver) collect (aref pose i))))

(defun brow-goal (dof raise)
  "The angle RAISE (-1 to 1) of the way from DOF's neutral angle (zero, within
its limits) to its maximum, or for a negative RAISE to its minimum."
  (let ((neutral (clamp-to-dof dof 0d0)))
    (+ neutral (* (abs raise) (- (float (if (minusp raise) (body-dof-min dof) (body-dof-max dof)) 1d0)
                                 neutral)))))

(defmethod driver-end-time ((driver eyebrows-driver))
  (let ((hold (driver-arg driver :hold)))
    (and hold (+ (driver-start driver) (* 2 (driver-real driver :duration)) (to-double hold)))))

(defun eyebrows-level (driver time)
  "How far (0 to 1) DRIVER's brows are from where they started toward the goal at TIME."
  (let* ((start (driver-start driver))
         (duration (driver-real driver :duration))
         (hold (and (driver-arg driver :hold) (driver-real driver :hold))))
    (if (and hold (> time (+ start duration hold)))
        (- 1d0 (ramp time (+ start duration hold) duration))
        (ramp time start duration))))

(defmethod driver-drive ((driver eyebrows-driver) time pose)
  (let ((level (eyebrows-level driver time)))
    (loop for index in (driver-channels driver)
          for dof in (eyebrows-dofs driver)
          for from in (eyebrows-from driver)
          do (setf (aref pose index)
                   (+ from (* level (- (brow-goal dof (driver-real driver :raise)) from)))))))

(define-motor-function :eyebrows eyebrows-driver
  "Raise (or lower) the eyebrows, hold, and let them return (Pantomime's
eyebrows); a figure with a crest and no brows raises the crest."
  (:raise :real 1.0 "fraction of the brow's range, -1 to 1: positive raises toward its maximum, negative lowers")
  (:side (:member :left :right :both) :both "which brow")
  (:duration :positive 0.3 "seconds to move, and again to return")
  (:hold (:or :non-negative (:member nil)) 1.0 "seconds to hold before returning; NIL holds until stopped")
  (:priority :real 20 "arbitration priority; higher wins"))

(defmethod driver-default-blend ((driver eyebrows-driver))
  ;; It eases from the angles it captured at its start: a crossfade would only slow it.
  0d0)
