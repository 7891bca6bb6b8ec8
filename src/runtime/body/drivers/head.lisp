;;;; head.lisp -- the head driver (Pantomime's HeadDriver): nods, shakes, and
;;;; turns toward or away from a target; and the head-follow driver, the slave
;;;; a gaze driver makes so the head (and for a big shift the trunk) joins in.
;;;; Joints aim with AIM-ANGLES, which gaze.lisp shares for the eyes.

(in-package #:player)

;;;# Aiming a joint

;;; A joint aims when its +z axis, its front at rest, points at a world point.
;;; It aims with its first two DOFs, one about x (pitch) and one about y (yaw);
;;; a later DOF (a roll about z) turns +z into itself, so it changes nothing.
;;; With pitch outermost R = Rx(p) Ry(y) takes +z to
;;; (sin y, -cos y sin p, cos y cos p): a positive pitch looks down (rotating
;;; +z about +x by p gives (0, -sin p, cos p)), a positive yaw to the figure's
;;; left.  With yaw outermost, Ry(y) Rx(p) takes +z to (cos p sin y, -sin p, cos p cos y).

(defstruct (aim-link (:constructor %make-aim-link))
  "A joint that aims: the pose indices and DOFs of its pitch and yaw, whether
pitch is the outer rotation, the share of its own aim it takes (a fraction, or
:RANGE for a share of the turn in proportion to its range, see DRIVE-AIM-LINKS),
and its angles when its driver began."
  joint pitch-index yaw-index pitch-dof yaw-dof pitch-outer-p
  (pitch-share 1d0) (yaw-share 1d0)
  (start-pitch 0d0 :type double-float)
  (start-yaw 0d0 :type double-float))

(defun make-aim-link (driver joint &key (pitch-share 1d0) (yaw-share 1d0))
  "An AIM-LINK for JOINT of DRIVER's skeleton; a MOTOR-ERROR naming DRIVER's
frame unless JOINT's first two DOFs turn about x and y."
  (let* ((dofs (body-joint-dofs joint))
         (lines (mapcar #'dof-axis-line (subseq dofs 0 (min 2 (length dofs))))))
    (unless (or (equal lines '(:x :y)) (equal lines '(:y :x)))
      (motor-fail (motor-call-frame (driver-call driver))
                  "joint ~A cannot aim: its first two DOFs must turn about x and y"
                  (lisp-text (body-joint-name joint))))
    (let ((pitch (if (eq (first lines) :x) 0 1)))
      (%make-aim-link :joint joint :pitch-outer-p (zerop pitch)
                      :pitch-index (+ (body-joint-dof-start joint) pitch)
                      :yaw-index (+ (body-joint-dof-start joint) (- 1 pitch))
                      :pitch-dof (nth pitch dofs) :yaw-dof (nth (- 1 pitch) dofs)
                      :pitch-share pitch-share :yaw-share yaw-share))))

(defun aim-link-channels (links)
  "The pose indices LINKS drive."
  (loop for link in links collect (aim-link-pitch-index link) collect (aim-link-yaw-index link)))

(defun capture-aim-starts (links pose)
  "Remember each of LINKS' angles in POSE as where it starts."
  (dolist (link links)
    (setf (aim-link-start-pitch link) (aref pose (aim-link-pitch-index link))
          (aim-link-start-yaw link) (aref pose (aim-link-yaw-index link)))))

(defun dof-sign (dof)
  "1 for a DOF turning about a positive axis, -1 about a negative one."
  (if (member (body-dof-axis dof) '(:-x :-y :-z)) -1d0 1d0))

(defun clamp-to-dof (dof angle)
  "ANGLE (degrees) clamped into DOF's limits."
  (max (float (body-dof-min dof) 1d0) (min (float (body-dof-max dof) 1d0) angle)))

(defun joint-parent-frame (skeleton pose joint placement)
  "The world transform JOINT's local transform is relative to, in POSE."
  (let ((parent (body-joint-parent joint)))
    (if parent (joint-world-transform skeleton pose parent placement) placement)))

(defun aim-angles (skeleton link pose placement point)
  "The pitch and yaw (degrees, in LINK's DOF conventions, unclamped) that turn
LINK's joint's +z toward the world POINT, its parents placed by POSE and
PLACEMENT; NIL and NIL when POINT is at the joint."
  (let* ((frame (joint-parent-frame skeleton pose (aim-link-joint link) placement))
         (position (transform-point frame (joint-offset (aim-link-joint link))))
         (direction (transform-vector (transform-invert frame) (v- point position)))
         (length (vnorm direction)))
    (if (< length 1d-9)
        (values nil nil)
        (let ((x (/ (vec3-x direction) length))
              (y (/ (vec3-y direction) length))
              (z (/ (vec3-z direction) length))
              (degrees (/ 180d0 pi)))
          (flet ((arcsin (s) (asin (max -1d0 (min 1d0 s)))))
            (multiple-value-bind (pitch yaw)
                (if (aim-link-pitch-outer-p link)
                    (values (atan (- y) z) (arcsin x))
                    (values (arcsin (- y)) (atan x z)))
              (values (* degrees pitch (dof-sign (aim-link-pitch-dof link)))
                      (* degrees yaw (dof-sign (aim-link-yaw-dof link))))))))))

(defun driver-real (driver key)
  "DRIVER's numeric parameter KEY as a double-float at its written value (a
:duration of 0.6 is 0.6d0, not the single-float's 0.6000000238418579d0)."
  (to-double (driver-arg driver key)))

(defun minimum-jerk (u)
  "The minimum-jerk profile 10u^3 - 15u^4 + 6u^5 of U clamped to [0, 1]: a
bell-shaped velocity, zero with zero acceleration at both ends."
  (let ((u (max 0d0 (min 1d0 (float u 1d0)))))
    (* u u u (+ 10d0 (* u (+ -15d0 (* 6d0 u)))))))

(defun dof-side-range (dof angle)
  "How far DOF can turn from zero toward the side of ANGLE (degrees, >= 0)."
  (max 0d0 (if (>= angle 0) (float (body-dof-max dof) 1d0) (- (float (body-dof-min dof) 1d0)))))

(defun range-share (dof partner angle)
  "The share of a turn ANGLE that DOF takes beside PARTNER's DOF, in proportion
to how far each can turn that way."
  (let ((mine (dof-side-range dof angle))
        (theirs (dof-side-range partner angle)))
    (if (plusp (+ mine theirs)) (/ mine (+ mine theirs)) 0d0)))

(defun drive-aim-links (skeleton links pose placement point progress)
  "Write into POSE, parent first, each of LINKS' angles PROGRESS (0 to 1) of the
way from its start to its goal: its share of its own aim at POINT, given the
links before it as already written; the last link takes what remains (share 1).
A :RANGE share splits the turn with the last link by their ranges."
  (let ((last (car (last links))))
    (dolist (link links)
      (multiple-value-bind (pitch yaw) (aim-angles skeleton link pose placement point)
        (flet ((goal (angle share dof partner start)
                 (cond ((null angle) start)
                       ((eq link last) (clamp-to-dof dof angle))
                       (t (clamp-to-dof dof (* angle (if (eq share :range)
                                                         (range-share dof partner angle)
                                                         share)))))))
          (let ((p (goal pitch (aim-link-pitch-share link) (aim-link-pitch-dof link)
                         (aim-link-pitch-dof last) (aim-link-start-pitch link)))
                (y (goal yaw (aim-link-yaw-share link) (aim-link-yaw-dof link)
                         (aim-link-yaw-dof last) (aim-link-start-yaw link))))
            (setf (aref pose (aim-link-pitch-index link))
                  (+ (aim-link-start-pitch link) (* progress (- p (aim-link-start-pitch link))))
                  (aref pose (aim-link-yaw-index link))
                  (+ (aim-link-start-yaw link) (* progress (- y (aim-link-start-yaw link)))))))))))

(defun split-turn (links angle dof-key)
  "ANGLE (degrees about the positive axis) split among LINKS in proportion to
their ranges that way, as each link's DOF value (DOF-KEY reads the DOF)."
  (let* ((values (mapcar (lambda (link) (* angle (dof-sign (funcall dof-key link)))) links))
         (ranges (mapcar (lambda (link value) (dof-side-range (funcall dof-key link) value))
                         links values))
         (total (reduce #'+ ranges)))
    (mapcar (lambda (value range) (if (plusp total) (* value (/ range total)) 0d0))
            values ranges)))

;;;# Which joints turn the head

(defparameter *neck-length* 0.15d0
  "A :spine joint at most this far (metres) below the head is a neck that turns
with it (the parrot's); a longer one carries the trunk (the humanoid's vl5).")

(defun head-chain (driver &key trunk-yaw-share)
  "The aim links that turn DRIVER's head, parent first: the :spine joints near
the head (necks, sharing the turn by range), then the head role joint; with
TRUNK-YAW-SHARE, first the other :spine joints, taking that share of the yaw
and none of the pitch."
  (let* ((head (role-joint driver :head))
         (spine (remove head (ensure-list (role-joint driver :spine nil))))
         (centre (body-joint-center head)))
    (flet ((neck-p (joint)
             (<= (sqrt (loop for i below 3 sum (expt (- (svref centre i)
                                                        (svref (body-joint-center joint) i))
                                                     2)))
                 *neck-length*)))
      (append (and trunk-yaw-share
                   (loop for joint in (remove-if #'neck-p spine)
                         collect (make-aim-link driver joint :pitch-share 0d0
                                                             :yaw-share trunk-yaw-share)))
              (loop for joint in (remove-if-not #'neck-p spine)
                    collect (make-aim-link driver joint :pitch-share :range :yaw-share :range))
              (list (make-aim-link driver head))))))

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
                             (resolve-target (driver-arg driver :target) (driver-body driver) pose))))
        (setf (head-away driver)
              (if (and yaw (minusp (* yaw (dof-sign (aim-link-yaw-dof (first links)))))) 1d0 -1d0))))))

(defmethod driver-end-time ((driver head-driver))
  (and (member (driver-arg driver :action) '(:nod :shake))
       (+ (driver-start driver) (driver-real driver :duration))))

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

(defmethod driver-drive ((driver head-driver) time pose)
  (let* ((links (head-links driver))
         (action (driver-arg driver :action))
         (u (max 0d0 (min 1d0 (/ (- time (driver-start driver)) (driver-real driver :duration)))))
         (amplitude (driver-real driver :amplitude)))
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
                        (resolve-target (driver-arg driver :target) (driver-body driver) pose)
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
