;;;; aim.lisp -- joints that aim their front at a point: aim links, the
;;;; angles that point a joint, chains that share a turn by range, and the
;;;; chain that turns a head.  The head driver and the gaze driver (for the
;;;; eyes, and for the head it drives as its slave) both aim this way.

(in-package #:player.body)

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
