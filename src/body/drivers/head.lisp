;;;; head.lisp -- the head driver (Pantomime's HeadDriver): nods, shakes, and
;;;; turns toward or away from a target; and the head-follow driver, the slave
;;;; a gaze driver makes so the head (and for a big shift the trunk) joins in.
;;;; The joints turn by aim links (aim.lisp).

(in-package #:player.body)

;;;# The head driver

(defclass head-driver (driver)
  ((links :accessor head-links :documentation "The aim links of the head (and neck).")
   (away :initform -1d0 :accessor head-away
         :documentation "For :turn-away, 1 to turn left, -1 right (about +y)."))
  (:documentation "Performs :head: a nod or shake that ends by itself, or a turn
toward or away from a target held until stopped."))

(defmethod driver-setup ((driver head-driver))
  (unless (integerp (driver-arg driver :count))
    (motor-fail (motor-call-frame (driver-call driver)) "head :count must be a whole number, not ~A"
                (lisp-text (driver-arg driver :count))))
  (when (and (member (driver-arg driver :action) '(:turn-to :turn-away))
             (null (driver-arg driver :target)))
    (motor-fail (motor-call-frame (driver-call driver)) "head ~A needs a :target"
                (lisp-text (driver-arg driver :action))))
  (setf (head-links driver) (head-chain driver))
  (aim-link-channels (head-links driver)))

(defmethod driver-begin ((driver head-driver) pose time)
  (declare (ignore time))
  (let ((links (head-links driver)))
    (capture-aim-starts links pose)
    (when (eq (driver-arg driver :action) :turn-away)
      ;; The side the target is on, seen from the first link's parent frame.
      (let ((yaw (aim-angles (driver-skeleton driver) (first links) pose
                             (object-world-transform (driver-body driver))
                             (%resolve-target (driver-arg driver :target) (driver-body driver) pose))))
        (setf (head-away driver)
              (if (and yaw (minusp (* yaw (dof-sign (aim-link-yaw-dof (first links)))))) 1d0 -1d0))))))

(defmethod driver-end-time ((driver head-driver))
  (and (member (driver-arg driver :action) '(:nod :shake))
       (+ (driver-start driver) (gesture-seconds driver :duration))))

(defmethod driver-additive-p ((driver head-driver))
  ;; A nod or shake adds onto whatever holds the head (a held turn, say).
  (and (driver-arg driver :additive) (member (driver-arg driver :action) '(:nod :shake)) t))

(defmethod driver-channel-sets ((driver head-driver))
  ;; The neck and head turn as one.
  (unless (driver-additive-p driver)
    (list (driver-channels driver))))

(defun gesture-offset (action u count amplitude)
  "The nod or shake angle (degrees) at U (0 to 1) of the gesture: a nod dips
COUNT times (sin^2), a shake swings COUNT times either way inside a smooth
envelope, so both start and end at rest with zero velocity."
  (ecase action
    (:nod (* amplitude (expt (sin (* pi count u)) 2)))
    (:shake (* amplitude (sin (* 2 pi count u))
               (smoothstep (min 1d0 (* 5d0 u) (* 5d0 (- 1d0 u))))))))

(defun set-link-angles (pose links key angles)
  "Write ANGLES, one per link of LINKS, into POSE at each link's pitch (KEY
:PITCH) or yaw (KEY :YAW) DOF, clamped to its limits."
  (loop for link in links
        for angle in angles
        do (if (eq key :pitch)
               (setf (aref pose (aim-link-pitch-index link))
                     (clamp-to-dof (aim-link-pitch-dof link) angle))
               (setf (aref pose (aim-link-yaw-index link))
                     (clamp-to-dof (aim-link-yaw-dof link) angle)))))

(defun add-link-angles (pose links key angles weight)
  "Add WEIGHT times ANGLES, one per link of LINKS, to POSE at each link's pitch
\(KEY :PITCH) or yaw (KEY :YAW) DOF."
  (loop for link in links
        for angle in angles
        do (incf (aref pose (if (eq key :pitch) (aim-link-pitch-index link) (aim-link-yaw-index link)))
                 (* weight angle))))

(defmethod driver-drive ((driver head-driver) time pose)
  (let* ((links (head-links driver))
         (action (driver-arg driver :action))
         (u (max 0d0 (min 1d0 (/ (- time (driver-start driver)) (gesture-seconds driver :duration)))))
         (amplitude (gesture-amplitude driver :amplitude)))
    (when (driver-additive-p driver)
      (let ((key (if (eq action :nod) :pitch :yaw)))
        (add-link-angles pose links key
                         (split-turn links (gesture-offset action u (driver-real driver :count) amplitude)
                                     (if (eq key :pitch) #'aim-link-pitch-dof #'aim-link-yaw-dof))
                         (driver-weight driver))
        (return-from driver-drive pose)))
    (ecase action
      (:nod
       (set-link-angles pose links :pitch
                        (mapcar #'+ (mapcar #'aim-link-start-pitch links)
                                (split-turn links (gesture-offset :nod u (driver-real driver :count) amplitude)
                                            #'aim-link-pitch-dof))))
      (:shake
       (set-link-angles pose links :yaw
                        (mapcar #'+ (mapcar #'aim-link-start-yaw links)
                                (split-turn links (gesture-offset :shake u (driver-real driver :count) amplitude)
                                            #'aim-link-yaw-dof))))
      (:turn-to
       (drive-aim-links (driver-skeleton driver) links pose
                        (object-world-transform (driver-body driver))
                        (%resolve-target (driver-arg driver :target) (driver-body driver) pose)
                        (minimum-jerk u)))
      (:turn-away
       ;; Yaw to the far side; the pitch holds where it was.
       (let ((progress (minimum-jerk u)))
         (set-link-angles pose links :yaw
                          (loop for link in links
                                for goal in (split-turn links (* (head-away driver) amplitude)
                                                        #'aim-link-yaw-dof)
                                for from = (aim-link-start-yaw link)
                                collect (+ from (* progress (- goal from)))))
         (set-link-angles pose links :pitch (mapcar #'aim-link-start-pitch links)))))))

(define-motor-function :head head-driver
  "Move the head: nod or shake it (ending by itself), or turn it toward or away
from a target and hold until stopped (Pantomime's headnod, headtowards, headaway)."
  (:action (:member :nod :shake :turn-to :turn-away) :nod
   "the gesture: :nod (pitch dips), :shake (yaw swings), :turn-to or :turn-away (needs :target)")
  (:count :positive 2 "how many nods or shakes (a whole number)")
  (:amplitude :non-negative 15 "degrees of each nod or shake; for :turn-away, how far past straight ahead")
  (:duration :positive 0.6 "seconds for the whole nod or shake, or to complete a turn")
  (:target (:or :target (:member nil)) nil "what to turn toward or away from")
  (:additive :boolean t "a nod or shake adds onto whatever holds the head; NIL makes it take the head")
  (:priority :real 20 "arbitration priority; higher wins"))

;;;# The head-follow driver: gaze's slave

(defclass head-follow-driver (driver)
  ((links :initarg :links :reader head-follow-links)
   (duration :initarg :duration :reader head-follow-duration
             :documentation "Seconds the head takes to arrive.")
   (point :initarg :point :reader head-follow-point
          :documentation "A function of TIME and POSE giving the world point to face."))
  (:documentation "The slave a gaze driver makes for a large shift: turns the
head (and trunk) toward the gaze target over DURATION, slower than the eyes,
then follows the target.  It shares its master's call, so its priority."))

(defun make-head-follow (master links duration point pose)
  "A head-follow slave of the gaze driver MASTER turning LINKS (from POSE, the
body's pose at MASTER's start) toward (FUNCALL POINT TIME POSE) over DURATION."
  (capture-aim-starts links pose)
  (let ((slave (make-instance 'head-follow-driver
                              :call (driver-call master) :body (driver-body master)
                              :start (driver-start master) :links links
                              :duration duration :point point)))
    (setf (driver-channels slave) (aim-link-channels links))
    slave))

(defmethod driver-setup ((driver head-follow-driver))
  (aim-link-channels (head-follow-links driver)))

(defmethod driver-drive ((driver head-follow-driver) time pose)
  (drive-aim-links (driver-skeleton driver) (head-follow-links driver) pose
                   (object-world-transform (driver-body driver))
                   (funcall (head-follow-point driver) time pose)
                   (minimum-jerk (/ (- time (driver-start driver)) (head-follow-duration driver)))))

(defmethod driver-default-blend ((driver head-driver))
  ;; It eases from the angles it captured at its start: a crossfade would only slow it.
  0d0)

(defmethod driver-default-blend ((driver head-follow-driver))
  ;; It eases from the angles it captured at its start: a crossfade would only slow it.
  0d0)
