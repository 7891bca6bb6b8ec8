;;;; pose.lisp -- a body's pose: one angle per DOF, clamped to the joint limits,
;;;; and the world transforms of the joints that follow from it.

(in-package #:player.body)

;;; A pose is a vector of double-floats, one per DOF of a skeleton, in degrees,
;;; in SKELETON-CHANNELS order: joints parent first, each joint's DOFs in file
;;; order, so the DOFs of JOINT are the BODY-JOINT-DOF-START-th and following.
;;; After the DOFs come the weights of its morph targets (SKELETON-MORPHS, an
;;; imported model's blend shapes), each from 0 to 1: channels the drivers,
;;; arbitration and blending treat like any other, which no joint turns by.
;;; A joint's local rotation is the product of its DOF rotations in file order,
;;; the first outermost: R = R(dof1) R(dof2) ... (as BVH channels compose).
;;; Its local translation is its centre minus its parent's centre, so the zero
;;; pose is the rest pose of the skeleton file.

(deftype pose ()
  "One angle in degrees per DOF of a skeleton, in SKELETON-CHANNELS order."
  '(simple-array double-float (*)))

(defun pose-of-p (skeleton x)
  "Is X a POSE of SKELETON: a double-float vector of its DOF count, every angle finite?"
  (and (typep x 'pose) (= (length x) (skeleton-channel-count skeleton))
       (every #'finite-number-p x)))

(defun pose-phrase (skeleton)
  "How argument errors describe a pose of SKELETON."
  (format nil "a pose of skeleton ~A (a (simple-array double-float (~D)) of finite angles, from make-pose)"
          (lisp-text (skeleton-name skeleton)) (skeleton-channel-count skeleton)))

(defun make-pose (skeleton)
  "The rest pose of SKELETON: every DOF at zero (clamped into its limits when
zero lies outside them)."
  (check-argument 'make-pose 'skeleton skeleton #'skeleton-p "a skeleton (from load-skeleton)")
  (%clamp-pose skeleton (make-array (skeleton-channel-count skeleton)
                                   :element-type 'double-float :initial-element 0d0)))

(defun copy-pose (pose)
  "A fresh copy of POSE."
  (copy-seq pose))

(defun dof-index (skeleton joint-name dof-name &optional (errorp t))
  "The index in SKELETON's poses of JOINT-NAME's DOF DOF-NAME (names compared
case-insensitively).  When there is none: a SKELETON-ERROR, or NIL without ERRORP."
  (check-argument 'dof-index 'skeleton skeleton #'skeleton-p "a skeleton (from load-skeleton)")
  (check-argument 'dof-index 'joint-name joint-name #'string-designator-p "a joint's name (a symbol or string)")
  (check-argument 'dof-index 'dof-name dof-name #'string-designator-p "a DOF's name (a symbol or string)")
  (let* ((joint (find-joint skeleton joint-name errorp))
         (position (and joint (position (string dof-name) (body-joint-dofs joint)
                                        :key (lambda (dof) (string (body-dof-name dof)))
                                        :test #'string-equal))))
    (cond (position (+ (body-joint-dof-start joint) position))
          (errorp (skeleton-fail (list joint-name dof-name) "joint ~A of skeleton ~A has no DOF ~A~@[ (it has ~{~A~^ ~})~]"
                                 (lisp-text joint-name) (lisp-text (skeleton-name skeleton))
                                 (lisp-text dof-name)
                                 (and joint (mapcar (lambda (dof) (lisp-text (body-dof-name dof)))
                                                    (body-joint-dofs joint)))))
          (t nil))))

(defun joint-dof-indices (joint)
  "The pose indices of JOINT's DOFs, in file order."
  (loop for i from (body-joint-dof-start joint)
        repeat (length (body-joint-dofs joint))
        collect i))

(defun skeleton-dof (skeleton index)
  "The joint and the BODY-DOF at pose INDEX of SKELETON, as two values."
  (loop for joint across (skeleton-joints skeleton)
        for start = (body-joint-dof-start joint)
        when (< index (+ start (length (body-joint-dofs joint))))
          return (values joint (nth (- index start) (body-joint-dofs joint)))))

;;;# Limits

(defun clamp-pose (skeleton pose)
  "Clamp every angle of POSE into its DOF's limits, in place; return POSE."
  (check-argument 'clamp-pose 'skeleton skeleton #'skeleton-p "a skeleton (from load-skeleton)")
  (check-argument 'clamp-pose 'pose pose (lambda (x) (pose-of-p skeleton x)) (pose-phrase skeleton))
  (%clamp-pose skeleton pose))

(defvar *channel-limits* (make-hash-table :test #'eq :weakness :key :synchronized t)
  "Per skeleton, its channels' least and greatest values as two double-float vectors.")

(defun skeleton-channel-limits (skeleton)
  "The least and greatest value of each of SKELETON's pose channels (CHANNEL-LIMITS), as a cons of two vectors, made once."
  (or (gethash skeleton *channel-limits*)
      (setf (gethash skeleton *channel-limits*)
            (let* ((count (skeleton-channel-count skeleton))
                   (low (make-array count :element-type 'double-float :initial-element 0d0))
                   (high (make-array count :element-type 'double-float :initial-element 1d0)))
              (loop for joint across (skeleton-joints skeleton)
                    do (loop for dof in (body-joint-dofs joint)
                             for i from (body-joint-dof-start joint)
                             do (setf (aref low i) (float (body-dof-min dof) 1d0)
                                      (aref high i) (float (body-dof-max dof) 1d0))))
              (cons low high)))))

(defun %clamp-pose (skeleton pose)
  "CLAMP-POSE of a known POSE of SKELETON."
  (declare (type pose pose))
  (destructuring-bind (low . high) (skeleton-channel-limits skeleton)
    (declare (type (simple-array double-float (*)) low high))
    (dotimes (i (min (length pose) (length low)) pose)
      (setf (aref pose i) (max (aref low i) (min (aref high i) (aref pose i)))))))

(defun channel-limits (skeleton index)
  "The least and greatest value of SKELETON's pose channel INDEX, two values:
its DOF's limits in degrees, or 0 and 1 for a morph target's weight."
  (if (>= index (skeleton-dof-count skeleton))
      (values 0d0 1d0)
      (let ((dof (nth-value 1 (skeleton-dof skeleton index))))
        (values (float (body-dof-min dof) 1d0) (float (body-dof-max dof) 1d0)))))

(defun pose-within-limits-p (skeleton pose &optional (tolerance 1d-9))
  "True when every angle of POSE lies within its DOF's limits, give or take TOLERANCE degrees."
  (check-argument 'pose-within-limits-p 'skeleton skeleton #'skeleton-p "a skeleton (from load-skeleton)")
  (check-argument 'pose-within-limits-p 'pose pose
                  (lambda (x) (and (vectorp x) (= (length x) (skeleton-channel-count skeleton))
                                   (every #'finite-number-p x)))
                  (format nil "a vector of ~D finite angles, a pose of skeleton ~A"
                          (skeleton-channel-count skeleton) (lisp-text (skeleton-name skeleton))))
  (check-real 'pose-within-limits-p 'tolerance tolerance :minimum 0)
  (loop for joint across (skeleton-joints skeleton)
        always (loop for dof in (body-joint-dofs joint)
                     for i from (body-joint-dof-start joint)
                     always (<= (- (body-dof-min dof) tolerance) (aref pose i)
                                (+ (body-dof-max dof) tolerance)))))

;;;# Transforms

(defun dof-rotation (dof degrees)
  "The unit quaternion turning DEGREES about DOF's axis."
  (destructuring-bind (x y z) (dof-axis-vector dof)
    (quat-from-axis-angle (vec3 (float x 1d0) (float y 1d0) (float z 1d0))
                          (* (float degrees 1d0) (/ pi 180)))))

(defun joint-local-rotation (joint pose)
  "JOINT's rotation relative to its parent in POSE: the product of its DOF
rotations in file order, as a new unit quaternion."
  (declare #.*anim-optimize* (type pose pose))
  ;; Every DOF turns about a principal axis: (cos h, sin h along it), h half
  ;; the angle, multiplied on the right in place; one quaternion made.
  (let ((w 1d0) (x 0d0) (y 0d0) (z 0d0))
    (declare (type double-float w x y z))
    (loop for dof in (body-joint-dofs joint)
          for i of-type fixnum from (body-joint-dof-start joint)
          do (let* ((h (* (aref pose i) (/ pi 360)))
                    (c (cos h))
                    (axis (body-dof-axis dof))
                    (s (if (member axis '(:-x :-y :-z)) (- (sin h)) (sin h))))
               (declare (type double-float h c s))
               (ecase axis
                 ((:x :-x) (psetf w (- (* w c) (* x s)) x (+ (* x c) (* w s))
                                  y (+ (* y c) (* z s)) z (- (* z c) (* y s))))
                 ((:y :-y) (psetf w (- (* w c) (* y s)) x (- (* x c) (* z s))
                                  y (+ (* y c) (* w s)) z (+ (* z c) (* x s))))
                 ((:z :-z) (psetf w (- (* w c) (* z s)) x (+ (* x c) (* y s))
                                  y (- (* y c) (* x s)) z (+ (* z c) (* w s)))))))
    (quat w x y z)))

(defun joint-offset (joint)
  "JOINT's centre relative to its parent's centre (to the origin, for the root), as a vec3."
  (let ((center (body-joint-center joint))
        (parent (body-joint-parent joint)))
    (flet ((coordinate (i)
             (- (svref center i) (if parent (svref (body-joint-center parent) i) 0d0))))
      (vec3 (coordinate 0) (coordinate 1) (coordinate 2)))))

(defun pose-world-transforms (skeleton pose &key (placement (identity-transform)) result)
  "The world transform of each joint of SKELETON in POSE, as a simple-vector of
MAT4s indexed like SKELETON-JOINTS (stored into RESULT when given).  PLACEMENT
is the body's own world transform (its scene object's).  A joint's transform
maps its rest-frame offsets from its centre to world points, so its
translation is where the joint is."
  (check-argument 'pose-world-transforms 'skeleton skeleton #'skeleton-p "a skeleton (from load-skeleton)")
  (check-argument 'pose-world-transforms 'pose pose (lambda (x) (pose-of-p skeleton x)) (pose-phrase skeleton))
  (check-argument 'pose-world-transforms :placement placement (lambda (x) (typep x 'mat4)) "a MAT4 (a 4x4 double-float array)")
  (if result
      (check-argument 'pose-world-transforms :result result
                      (lambda (x) (and (simple-vector-p x) (= (length x) (length (skeleton-joints skeleton)))
                                       (every (lambda (m) (typep m 'mat4)) x)))
                      (format nil "NIL or a simple-vector of ~D MAT4s" (length (skeleton-joints skeleton))))
      (setf result (map 'simple-vector (lambda (joint) (declare (ignore joint)) (identity-transform))
                        (skeleton-joints skeleton))))
  (%pose-world-transforms skeleton pose placement result))

(defstruct (posing-tables (:constructor %make-posing-tables (offsets parents dof-starts dof-ends axes)))
  "A skeleton's joints as typed arrays, so posing each frame walks no lists
and boxes no floats: per joint its OFFSETS from its parent (x y z, 3 per
joint), its PARENTS' indices (-1 for the root), and the range DOF-STARTS to
DOF-ENDS of its DOFs; per DOF its AXES code (0 1 2 about x y z, 3 4 5 about
-x -y -z)."
  (offsets nil :type (simple-array double-float (*)) :read-only t)
  (parents nil :type (simple-array fixnum (*)) :read-only t)
  (dof-starts nil :type (simple-array fixnum (*)) :read-only t)
  (dof-ends nil :type (simple-array fixnum (*)) :read-only t)
  (axes nil :type (simple-array (integer 0 5) (*)) :read-only t))

(defun make-posing-tables (skeleton)
  "SKELETON's POSING-TABLES."
  (let* ((joints (skeleton-joints skeleton))
         (count (length joints))
         (offsets (make-array (* 3 count) :element-type 'double-float))
         (parents (make-array count :element-type 'fixnum))
         (starts (make-array count :element-type 'fixnum))
         (ends (make-array count :element-type 'fixnum))
         (axes (make-array (skeleton-dof-count skeleton) :element-type '(integer 0 5))))
    (loop for joint across joints
          for j from 0
          for offset = (joint-offset joint)
          for parent = (body-joint-parent joint)
          do (setf (aref offsets (* 3 j)) (vec3-x offset)
                   (aref offsets (+ (* 3 j) 1)) (vec3-y offset)
                   (aref offsets (+ (* 3 j) 2)) (vec3-z offset)
                   (aref parents j) (if parent (body-joint-index parent) -1)
                   (aref starts j) (body-joint-dof-start joint)
                   (aref ends j) (+ (body-joint-dof-start joint) (length (body-joint-dofs joint))))
             (loop for dof in (body-joint-dofs joint)
                   for i from (body-joint-dof-start joint)
                   do (setf (aref axes i) (position (body-dof-axis dof) '(:x :y :z :-x :-y :-z)))))
    (%make-posing-tables offsets parents starts ends axes)))

(declaim (inline skeleton-posing-tables))
(defun skeleton-posing-tables (skeleton)
  "SKELETON's POSING-TABLES, made on first use (a loaded skeleton's joints do not change)."
  (or (skeleton-posing skeleton)
      (setf (skeleton-posing skeleton) (make-posing-tables skeleton))))

(declaim (inline %set-joint-local-transform))
(defun %set-joint-local-transform (local tables pose j)
  "Fill the MAT4 LOCAL with joint J's transform relative to its parent in
POSE, from SKELETON's POSING-TABLES: its rotation the product of its DOF
rotations (as JOINT-LOCAL-ROTATION), its translation its offset."
  (declare (type mat4 local) (type posing-tables tables) (type pose pose) (type fixnum j))
  (let ((starts (posing-tables-dof-starts tables))
        (ends (posing-tables-dof-ends tables))
        (axes (posing-tables-axes tables))
        (offsets (posing-tables-offsets tables))
        (half-degree (/ pi 360))
        (w 1d0) (x 0d0) (y 0d0) (z 0d0))
    (declare (type double-float half-degree w x y z))
    ;; Each DOF turns about a principal axis: (cos h, sin h along it), h half
    ;; the angle, multiplied on the right.
    (loop for i of-type fixnum from (aref starts j) below (aref ends j)
          do (let* ((axis (aref axes i))
                    (h (* (aref pose i) half-degree))
                    (c (cos h))
                    (s (if (>= axis 3) (- (sin h)) (sin h))))
               (declare (type double-float h c s))
               (case (if (>= axis 3) (- axis 3) axis)
                 (0 (psetf w (- (* w c) (* x s)) x (+ (* x c) (* w s))
                           y (+ (* y c) (* z s)) z (- (* z c) (* y s))))
                 (1 (psetf w (- (* w c) (* y s)) x (- (* x c) (* z s))
                           y (+ (* y c) (* w s)) z (+ (* z c) (* x s))))
                 (t (psetf w (- (* w c) (* z s)) x (+ (* x c) (* y s))
                           y (- (* y c) (* x s)) z (+ (* z c) (* w s)))))))
    (%set-rotation-from-components local w x y z)
    (let ((k (* 3 j)))
      (setf (aref local 0 3) (aref offsets k)
            (aref local 1 3) (aref offsets (+ k 1))
            (aref local 2 3) (aref offsets (+ k 2))
            (aref local 3 0) 0d0 (aref local 3 1) 0d0 (aref local 3 2) 0d0 (aref local 3 3) 1d0))
    local))

(defun %pose-world-transforms (skeleton pose placement result)
  "POSE-WORLD-TRANSFORMS of arguments known to be right (a body's own, each
frame).  Conses nothing: each joint's local transform is built in place from
SKELETON's typed POSING-TABLES."
  (declare #.*anim-optimize* (type pose pose) (type mat4 placement) (type simple-vector result))
  (let* ((tables (skeleton-posing-tables skeleton))
         (parents (posing-tables-parents tables))
         (local (make-array '(4 4) :element-type 'double-float :initial-element 0d0)))
    (declare (dynamic-extent local))
    (dotimes (j (length parents) result)
      (%set-joint-local-transform local tables pose j)
      (let ((parent (aref parents j)))
        (transform-compose (if (< parent 0) placement (svref result parent)) local (svref result j))))))

(defun joint-world-position (transforms joint)
  "Where JOINT is in the world, from TRANSFORMS (see POSE-WORLD-TRANSFORMS), as a new vec3."
  (check-argument 'joint-world-position 'joint joint #'body-joint-p "a joint of a skeleton (from find-joint)")
  (check-argument 'joint-world-position 'transforms transforms
                  (lambda (x) (and (simple-vector-p x) (> (length x) (body-joint-index joint))
                                   (typep (svref x (body-joint-index joint)) 'mat4)))
                  "a simple-vector of MAT4s, one per joint (from pose-world-transforms)")
  (transform-translation (svref transforms (body-joint-index joint))))

(defun joint-world-transform (skeleton pose joint &optional (placement (identity-transform)))
  "The world transform of JOINT alone in POSE, walking its parent chain from
PLACEMENT; cheaper than POSE-WORLD-TRANSFORMS when one joint is wanted.
SKELETON is JOINT's (its typed tables make the walk cons only the result),
or NIL."
  (if (null skeleton)
      (let ((chain (loop for j = joint then (body-joint-parent j) while j collect j))
            (world (transform-compose placement (identity-transform))))
        (dolist (j (nreverse chain) world)
          (transform-compose world (make-transform :rotation (joint-local-rotation j pose)
                                                   :translation (joint-offset j))
                             world)))
      (let* ((tables (skeleton-posing-tables skeleton))
             (parents (posing-tables-parents tables))
             (world (transform-compose placement (identity-transform)))
             (local (make-array '(4 4) :element-type 'double-float :initial-element 0d0)))
        (declare (dynamic-extent local) (type pose pose))
        (labels ((walk (j)
                   (declare (type fixnum j))
                   (let ((parent (aref parents j)))
                     (when (>= parent 0) (walk parent)))
                   (transform-compose world (%set-joint-local-transform local tables pose j) world)))
          (walk (body-joint-index joint)))
        world)))
