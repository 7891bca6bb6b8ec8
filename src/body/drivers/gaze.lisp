;;;; gaze.lisp -- the gaze driver (Pantomime's GazeDriver and TrackingDriver):
;;;; a saccade of both eyes to a target, each eye aiming from where it is (so
;;;; the eyes converge), the head joining large shifts through a head-follow
;;;; slave (head.lisp) while the eyes counter-rotate to stay on the target, and
;;;; smooth pursuit of a moving target.  A body with a head but no eye joints
;;;; (many imported models) gazes with its head alone.

(in-package #:player.body)

;;;# Timing

;;; Saccade durations follow the "main sequence": D = 21 ms + 2.2 ms per degree
;;; of amplitude (R. H. S. Carpenter, Movements of the Eyes, 2nd ed., Pion,
;;; 1988), about 65 ms for 20 degrees.  The velocity profile is the
;;; bell-shaped minimum-jerk curve (MINIMUM-JERK in head.lisp).

(defun saccade-duration (amplitude &optional (speed 1))
  "Seconds a saccade of AMPLITUDE degrees takes, by the main sequence, divided by SPEED."
  (/ (+ 0.021d0 (* 0.0022d0 amplitude)) speed))

;;; In a combined eye-head gaze shift the head starts with the eyes but moves
;;; for several hundred milliseconds, longer for larger shifts, so the eyes
;;; land first and then counter-rotate (Guitton & Volle, "Gaze control in
;;; humans", J. Neurophysiology 58, 1987).  The constants are estimates in that range.

(defun head-shift-duration (amplitude &optional (speed 1))
  "Seconds the head takes to join a gaze shift of AMPLITUDE degrees, divided by SPEED."
  (/ (+ 0.25d0 (* 0.005d0 amplitude)) speed))

(defparameter *gaze-trunk-yaw-share* 0.2d0
  "The share of a big gaze shift's yaw the trunk (:spine below the neck) takes.")

;;;# The driver

(defclass gaze-driver (driver)
  ((eyes :accessor gaze-eyes :documentation "The aim links of the left and right eye.")
   (point :initform nil :accessor gaze-fixed-point
          :documentation "Where the target was at the start (fixated when not tracking).")
   (amplitude :initform 0d0 :accessor gaze-amplitude
              :documentation "Degrees between the line of sight at the start and the target.")
   (saccade :initform 0d0 :accessor gaze-saccade
            :documentation "Seconds the saccade takes.")
   (slave :initform nil :accessor gaze-slave
          :documentation "The head-follow driver of a large shift, or NIL."))
  (:documentation "Performs :gaze: both eyes saccade to the target and hold it;
for a large shift the head (and trunk) follows; with :track the eyes pursue a
moving target.  Runs until stopped."))

(defun head-only-gaze-p (driver)
  "Does DRIVER gaze with the head alone: its skeleton has a :head but no eyes?"
  (let ((skeleton (driver-skeleton driver)))
    (and (skeleton-role skeleton :head)
         (not (and (skeleton-role skeleton :left-eye) (skeleton-role skeleton :right-eye))))))

(defmethod driver-setup ((driver gaze-driver))
  (setf (gaze-eyes driver)
        (unless (head-only-gaze-p driver)
          (list (make-aim-link driver (role-joint driver :left-eye))
                (make-aim-link driver (role-joint driver :right-eye)))))
  (aim-link-channels (gaze-eyes driver)))

(defun gaze-point (driver time pose)
  "The world point DRIVER fixates at TIME: the target now when tracking one that
can move, else where it was at the start."
  (declare (ignore time))
  (let ((target (driver-arg driver :target)))
    (if (and (driver-arg driver :track) (not (eq (first target) :point)))
        (%resolve-target target (driver-body driver) pose)
        (gaze-fixed-point driver))))

(defun eyes-line-of-sight (driver pose)
  "Where DRIVER's eyes are (their midpoint) and where they look (the mean of
their +z axes, unit), in the world, in POSE."
  (let ((skeleton (driver-skeleton driver))
        (placement (object-world-transform (driver-body driver)))
        (position (vec3)) (direction (vec3)))
    (when (null (gaze-eyes driver))
      ;; Head alone: it looks along its +z, the front at rest.
      (let ((frame (joint-world-transform skeleton pose (skeleton-role skeleton :head) placement)))
        (return-from eyes-line-of-sight
          (values (transform-translation frame) (transform-vector frame (vec3 0d0 0d0 1d0))))))
    (dolist (eye (gaze-eyes driver))
      (let ((frame (joint-world-transform skeleton pose (aim-link-joint eye) placement)))
        (nv+ position (v* (transform-translation frame) 0.5d0))
        (nv+ direction (transform-vector frame (vec3 0d0 0d0 1d0)))))
    (values position (vnormalize direction))))

(defun angle-between (a b)
  "The angle in degrees between the nonzero vectors A and B."
  (* (/ 180d0 pi)
     (acos (max -1d0 (min 1d0 (/ (vdot a b) (max 1d-12 (* (vnorm a) (vnorm b)))))))))

(defun eyes-reach-p (driver pose point)
  "Can both of DRIVER's eyes aim at POINT within their limits, the head as in POSE?"
  (let ((placement (object-world-transform (driver-body driver))))
    (every (lambda (eye)
             (multiple-value-bind (pitch yaw)
                 (aim-angles (driver-skeleton driver) eye pose placement point)
               (or (null pitch)
                   (and (= pitch (clamp-to-dof (aim-link-pitch-dof eye) pitch))
                        (= yaw (clamp-to-dof (aim-link-yaw-dof eye) yaw))))))
           (gaze-eyes driver))))

(defmethod driver-begin ((driver gaze-driver) pose time)
  (let* ((body (driver-body driver))
         (point (%resolve-target (driver-arg driver :target) body pose))
         (speed (driver-real driver :speed))
         (threshold (driver-real driver :head-threshold)))
    (capture-aim-starts (gaze-eyes driver) pose)
    (setf (gaze-fixed-point driver) point)
    (multiple-value-bind (position direction) (eyes-line-of-sight driver pose)
      (setf (gaze-amplitude driver) (angle-between direction (v- point position))))
    (let* ((amplitude (gaze-amplitude driver))
           (chain (and (skeleton-role (driver-skeleton driver) :head)
                       (or (null (gaze-eyes driver))
                           (> amplitude threshold) (not (eyes-reach-p driver pose point)))
                       ;; A head that cannot aim (no x and y DOFs) leaves the eyes alone.
                       (handler-case (head-chain driver :trunk-yaw-share
                                                 (and (> amplitude (* 2 threshold))
                                                      *gaze-trunk-yaw-share*))
                         (motor-error () nil)))))
      (setf (gaze-saccade driver) (saccade-duration amplitude speed))
      (when chain
        (setf (gaze-slave driver)
              (make-head-follow driver chain (head-shift-duration amplitude speed)
                                (lambda (time pose) (gaze-point driver time pose))
                                pose))))
    (values)))

(defmethod slave-drivers ((driver gaze-driver))
  (and (gaze-slave driver) (list (gaze-slave driver))))

(defmethod driver-drive ((driver gaze-driver) time pose)
  ;; The head slave has written the head already (a slave composes just before
  ;; its master), so each eye aims from where the head puts it: the eyes
  ;; counter-rotate while the head turns.
  (let ((point (gaze-point driver time pose))
        (placement (object-world-transform (driver-body driver)))
        (progress (minimum-jerk (/ (- time (driver-start driver))
                                   (max 1d-6 (gaze-saccade driver))))))
    (dolist (eye (gaze-eyes driver))
      (drive-aim-links (driver-skeleton driver) (list eye) pose placement point progress))))

(defmethod driver-report ((driver gaze-driver))
  ;; Called when DRIVER finishes, the body's pose composed for that moment.
  (let* ((pose (body-pose (driver-body driver)))
         (point (and (gaze-fixed-point driver)
                     ;; A tracked object may have left the scene by now.
                     (handler-case (gaze-point driver (body-time (driver-body driver)) pose)
                       (motor-error () nil)))))
    (when (and point (not (eyes-reach-p driver pose point)))
      "gaze: the target was beyond the reach of the eyes (and head)")))

(define-motor-function :gaze gaze-driver
  "Look at a target: a saccade of both eyes, the head joining large shifts, then
fixation (or pursuit, with :track) until stopped (Pantomime's saccade and eyetrack)."
  (:target :target :required "what to look at")
  (:speed :positive 1.0 "saccade speed factor: durations follow the main sequence divided by it")
  (:head-threshold :non-negative 15
   "degrees of shift beyond which the head joins (it joins too when the eyes cannot reach)")
  (:track :boolean t "follow a moving target (an :object or :joint) each frame")
  (:priority :real 30 "arbitration priority; higher wins"))

(defmethod driver-default-blend ((driver gaze-driver))
  ;; It eases from the angles it captured at its start: a crossfade would only slow it.
  0d0)

(defmethod driver-channel-sets ((driver gaze-driver))
  ;; Both eyes converge on one point: neither looks alone.
  (list (driver-channels driver)))
