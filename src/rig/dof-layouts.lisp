;;;; dof-layouts.lisp -- how a clip's rotation becomes the angles of one
;;;; joint's own DOFs.  An imported joint turns about x, y and z in that
;;;; order (the fast path, EULER.LISP's %QUAT-TO-XYZ-DEGREES); a joint of a
;;;; Player skeleton (humanoid.lisp, parrot.lisp) has 1 to 3 DOFs about signed
;;;; axes in a declared order, with limits.  Its LAYOUT says how to decompose a
;;;; rotation D for it: Tait-Bryan in the order of its DOF axes, the axes it
;;;; lacks appended (x, y, z order) and their angles dropped -- what the joint
;;;; cannot do -- an angle about a negative axis negated, each clamped to its
;;;; DOF's limits.  JOINT-LOCAL-ROTATION multiplies the DOF rotations in the
;;;; same order, so for a rotation the joint can make the angles are exact.

(in-package #:player.rig)

(defstruct (dof-layout (:constructor %make-dof-layout))
  "A joint's decomposition: AXES, the three axis indices (0 x, 1 y, 2 z) in
order, its own DOFs' first; COUNT, how many DOFs it has (the angles kept);
per kept angle its SIGN (-1 about a negative axis) and limits MINS and MAXS
\(degrees)."
  (axes (make-array 3 :element-type 'fixnum :initial-contents '(0 1 2)) :type (simple-array fixnum (3)))
  (count 3 :type (integer 0 3))
  (signs (make-array 3 :element-type 'double-float :initial-element 1d0) :type (simple-array double-float (3)))
  (mins (make-array 3 :element-type 'double-float :initial-element -180d0) :type (simple-array double-float (3)))
  (maxs (make-array 3 :element-type 'double-float :initial-element 180d0) :type (simple-array double-float (3))))

(defun axis-line-index (axis)
  "0, 1 or 2 for the signed DOF AXIS keyword (:x or :-x is 0...)."
  (ecase axis ((:x :-x) 0) ((:y :-y) 1) ((:z :-z) 2)))

(defun xyz-joint-p (joint)
  "Does JOINT turn about +x, +y and +z in that order, each a full turn either
way, as an imported joint does unless :limits narrows it?  Such a joint takes
the fast path (no layout): no clamp is needed."
  (and (equal (mapcar #'body-dof-axis (body-joint-dofs joint)) '(:x :y :z))
       (every (lambda (dof) (and (<= (body-dof-min dof) -180) (>= (body-dof-max dof) 180)))
              (body-joint-dofs joint))))

(defun joint-dof-layout (joint)
  "The DOF-LAYOUT of the skeleton JOINT, or NIL when it is an x/y/z joint
\(XYZ-JOINT-P), whose angles need no layout."
  (unless (xyz-joint-p joint)
    (let* ((dofs (body-joint-dofs joint))
           (own (mapcar (lambda (dof) (axis-line-index (body-dof-axis dof))) dofs))
           (layout (%make-dof-layout :count (length dofs))))
      (replace (dof-layout-axes layout) (append own (remove-if (lambda (i) (member i own)) '(0 1 2))))
      (loop for dof in dofs
            for n from 0
            do (setf (aref (dof-layout-signs layout) n)
                     (if (member (body-dof-axis dof) '(:-x :-y :-z)) -1d0 1d0)
                     (aref (dof-layout-mins layout) n) (float (body-dof-min dof) 1d0)
                     (aref (dof-layout-maxs layout) n) (float (body-dof-max dof) 1d0)))
      layout)))

(declaim (ftype (function (dof-layout double-float double-float double-float double-float doubles fixnum)
                          (values))
                layout-angles))

(defun layout-angles (layout w x y z out offset)
  "Write the angles of LAYOUT's DOFs for the unit quaternion W X Y Z into OUT
from OFFSET, clamped to their limits; 0 in the slots of the axes it lacks
\(three slots in all)."
  (declare (optimize (speed 3) (safety 1)))
  (let ((axes (dof-layout-axes layout)))
    (multiple-value-bind (a b c)
        (%quat-to-euler-degrees w x y z (aref axes 0) (aref axes 1) (aref axes 2))
      (flet ((put (n angle)
               (declare (type fixnum n) (type double-float angle))
               (setf (aref out (+ offset n))
                     (if (< n (dof-layout-count layout))
                         (max (aref (dof-layout-mins layout) n)
                              (min (aref (dof-layout-maxs layout) n)
                                   (* (aref (dof-layout-signs layout) n) angle)))
                         0d0))))
        (declare (inline put))
        (put 0 a) (put 1 b) (put 2 c))))
  (values))

;;;# A clip's angles, joint by joint

(defun clip-layouts (clip skeleton)
  "Per track of CLIP, the DOF-LAYOUT of its joint in SKELETON (NIL for an x/y/z
joint), as a simple-vector; NIL when every joint is x/y/z (the fast path)."
  (let ((layouts (map 'simple-vector (lambda (track)
                                       (joint-dof-layout (svref (skeleton-joints skeleton) (track-joint track))))
                      (clip-tracks clip))))
    (and (some #'identity layouts) layouts)))

(defun clip-dof-angles (clip time layouts out)
  "The angles (degrees) of CLIP's joints at TIME, three slots per track as
CLIP-ANGLES gives them, but each track decomposed by its entry of LAYOUTS (see
CLIP-LAYOUTS): a DOF-LAYOUT's joint gets its own DOFs' angles, in their order,
clamped, then zeros; NIL means x, y and z.  Stored into OUT and returned."
  (declare (type simple-vector layouts) (type doubles out))
  (let ((time (float time 1d0)))
    (loop for track across (clip-tracks clip)
          for layout across layouts
          for offset of-type fixnum from 0 by 3
          do (if layout
                 (multiple-value-bind (w x y z) (sample-track-quat track time)
                   (layout-angles layout w x y z out offset))
                 (sample-track-angles track time out offset)))
    out))
