;;;; bvh.lisp -- writing a body's motion as a Biovision Hierarchy (BVH) file,
;;;; and QUAT-TO-EULER, the Euler decomposition it (and the reach IK) needs.

(in-package #:player.body)

;;; ---------------------------------------------------------------------------
;;; The format we write
;;;
;;; A BVH file is a HIERARCHY section (the skeleton) and a MOTION section (one
;;; line of channel values per frame).  The choices made here:
;;;
;;; - Units are metres (Player's units), not BVH's customary centimetres or
;;;   inches; Blender's importer has a scale option for that.  Axes are
;;;   Player's: +y up, +z the figure's front, +x its left.
;;; - ROOT is the skeleton's root joint, JOINT every other joint, in
;;;   SKELETON-JOINTS order (depth first, children in file order), named as the
;;;   skeleton file spells them, in lower case (l_shoulder, humanoid-root).
;;; - OFFSET is JOINT-OFFSET: the joint's centre minus its parent's; the
;;;   root's OFFSET is its centre.  A leaf joint gets an End Site, a stub of
;;;   (max radius 0.02 m) pointing from its parent through it, so every bone
;;;   has a direction and a non-zero length.
;;; - Every joint has three rotation channels: its DOF axes in file order
;;;   (unsigned: a DOF about :-x is an Xrotation holding minus its angle),
;;;   then the axes it lacks, always zero.  BVH composes a joint's channels
;;;   in listed order, the first outermost (R = R(ch1) R(ch2) R(ch3)), which
;;;   is how JOINT-LOCAL-ROTATION composes DOFs, so these values are the pose's
;;;   angles themselves.
;;; - The root also has Xposition Yposition Zposition first.  They hold where
;;;   the root is in the world: the body's placement applied to the root's
;;;   centre (absolute, as Blender and most readers take them, not added to
;;;   OFFSET).  Its rotation channels hold placement rotation times the root's
;;;   local rotation, decomposed by QUAT-TO-EULER in its channel order.
;;; - Numbers have six decimals (1e-6 m, 1e-6 degrees), no exponent, a point
;;;   whatever the locale, and no "-0.000000".

(defparameter *bvh-end-site-length* 0.02d0
  "The shortest End Site stub, in metres; a leaf's stub is its radius when longer.")

(define-condition bvh-error (anim-error)
  ()
  (:documentation "A BVH file cannot be written: bad frames or placements, or an
unwritable path.  FORM is the offending value or path."))

(define-condition bvh-argument-error (argument-error bvh-error)
  ()
  (:documentation "WRITE-BVH or WRITE-BVH-FILE was given a bad argument: both an
ARGUMENT-ERROR (naming the function and argument) and a BVH-ERROR."))

;;; ---------------------------------------------------------------------------
;;; Euler angles

(defun axis-index (axis)
  "0, 1 or 2 for the axis keyword AXIS (:x, :y or :z)."
  (ecase axis (:x 0) (:y 1) (:z 2)))

(defun quat-to-euler (q axes)
  "Euler angles in degrees for the unit quaternion Q, as three values (A1 A2 A3)
with Q = R(AXIS1, A1) R(AXIS2, A2) R(AXIS3, A3): AXES is a list of three
distinct axis keywords among :x :y :z, composed in listed order with the first
outermost (intrinsic order: turn about AXIS1, then about the new AXIS2, then
about the newer AXIS3), as BVH channels and JOINT-LOCAL-ROTATION compose.
A1 and A3 lie in [-180, 180], A2 in [-90, 90]; away from gimbal lock the
angles are unique.  At gimbal lock (A2 = +-90) only A1 +- A3 is determined:
A1 is taken from the (ill-conditioned) matrix entries and A3 is computed from
what A1 leaves, so recomposing the angles gives Q back to rounding error even
there.  To turn a wanted local rotation into a joint's DOF angles, pass the
joint's DOF axis lines (DOF-AXIS-LINE) completed to three axes, as
BVH-JOINT-AXES does, negate the angles of :-x/:-y/:-z DOFs, and read the
angles of the added axes as what the joint cannot do.  Signals a plain ERROR
(a programming mistake, not a PLAYER-ERROR) when AXES is not a permutation of
(:x :y :z)."
  (unless (and (= (length axes) 3)
               (equal (sort (mapcar #'axis-index axes) #'<) '(0 1 2)))
    (error "QUAT-TO-EULER needs a permutation of (:x :y :z), not ~S" axes))
  (let* ((m (quat-to-matrix (qnormalize q)))
         (i (axis-index (first axes)))
         (j (axis-index (second axes)))
         (k (axis-index (third axes)))
         ;; Relabel the axes so that (i j k) becomes (x y z).  For an odd
         ;; permutation the relabelling is a reflection, which reverses every
         ;; rotation's sense: decompose as X-Y-Z, then negate the angles.
         (sign (if (member (list i j k) '((0 1 2) (1 2 0) (2 0 1)) :test #'equal) 1d0 -1d0))
         (index (vector i j k)))
    (flet ((m (row column) (aref m (svref index row) (svref index column))))
      ;; With M = Rx(a) Ry(b) Rz(c): row 0 is (cb cc, -cb sc, sb); column 2 is
      ;; (sb, -sa cb, ca cb); and Rx(a)^T M = Ry(b) Rz(c) has row 1 (sc, cc, 0).
      (let* ((a (atan (- (m 1 2)) (m 2 2)))
             (b (atan (m 0 2) (sqrt (+ (expt (m 0 0) 2) (expt (m 0 1) 2)))))
             (ca (cos a)) (sa (sin a))
             (c (atan (+ (* ca (m 1 0)) (* sa (m 2 0)))
                      (+ (* ca (m 1 1)) (* sa (m 2 1))))))
        (flet ((degrees (radians) (* sign radians (/ 180d0 pi))))
          (values (degrees a) (degrees b) (degrees c)))))))

;;; ---------------------------------------------------------------------------
;;; Channels

(defun bvh-joint-axes (joint)
  "The axes of JOINT's three BVH rotation channels: its DOF axes (unsigned) in
file order, then the missing ones in x, y, z order."
  (let ((axes (mapcar #'dof-axis-line (body-joint-dofs joint))))
    (append axes (remove-if (lambda (axis) (member axis axes)) '(:x :y :z)))))

(defun bvh-joint-angles (joint pose)
  "The values of JOINT's rotation channels in POSE (see BVH-JOINT-AXES), as a list
of degrees: each DOF's angle, negated for a negative axis, then zeros."
  (let ((angles (loop for dof in (body-joint-dofs joint)
                      for i from (body-joint-dof-start joint)
                      collect (if (member (body-dof-axis dof) '(:-x :-y :-z))
                                  (- (aref pose i))
                                  (aref pose i)))))
    (append angles (make-list (- 3 (length angles)) :initial-element 0d0))))

(defun bvh-root-values (root pose placement)
  "The six channel values of ROOT in POSE under the MAT4 PLACEMENT: its world
position, then the Euler angles of placement rotation times its local rotation."
  (let ((position (transform-point placement (joint-offset root)))
        (rotation (q* (transform-rotation placement) (joint-local-rotation root pose))))
    (list* (vec3-x position) (vec3-y position) (vec3-z position)
           (multiple-value-list (quat-to-euler rotation (bvh-joint-axes root))))))

;;; ---------------------------------------------------------------------------
;;; Output

(defun write-bvh-number (number stream &optional (decimals 6))
  "Write the real NUMBER to STREAM rounded to DECIMALS decimals: digits, a point,
digits, never an exponent, never a negative zero, whatever the printer settings."
  (let* ((scale (expt 10 decimals))
         (units (round (* (rational number) scale))))
    (multiple-value-bind (whole fraction) (floor (abs units) scale)
      (format stream "~:[~;-~]~D.~v,'0D" (minusp units) whole decimals fraction))))

(defun write-bvh-triple (stream x y z)
  "Write the reals X Y Z to STREAM, separated by spaces."
  (write-bvh-number x stream) (write-char #\Space stream)
  (write-bvh-number y stream) (write-char #\Space stream)
  (write-bvh-number z stream))

(defun bvh-joint-name (joint)
  "JOINT's name as the file spells it: lower case."
  (string-downcase (symbol-name (body-joint-name joint))))

(defun bvh-end-site (joint)
  "The End Site offset of the leaf JOINT, as a vec3: a stub along its bone (from
its parent through it), or up when that bone has no length."
  (let* ((bone (joint-offset joint))
         (direction (if (or (null (body-joint-parent joint)) (< (vnorm bone) 1d-9))
                        (vec3 0d0 1d0 0d0)
                        (vnormalize bone))))
    (v* direction (max *bvh-end-site-length* (float (body-joint-radius joint) 1d0)))))

(defun write-bvh-joint (stream joint depth)
  "Write JOINT and its descendants to STREAM as BVH hierarchy text indented DEPTH levels."
  (let ((indent (make-string (* 2 depth) :initial-element #\Space))
        (offset (joint-offset joint))
        (root-p (null (body-joint-parent joint))))
    (format stream "~A~:[JOINT~;ROOT~] ~A~%~A{~%" indent root-p (bvh-joint-name joint) indent)
    (format stream "~A  OFFSET " indent)
    (write-bvh-triple stream (vec3-x offset) (vec3-y offset) (vec3-z offset))
    (format stream "~%~A  CHANNELS ~D~:[~; Xposition Yposition Zposition~]~{ ~Arotation~}~%"
            indent (if root-p 6 3) root-p (mapcar #'symbol-name (bvh-joint-axes joint)))
    (if (body-joint-children joint)
        (dolist (child (body-joint-children joint))
          (write-bvh-joint stream child (1+ depth)))
        (let ((end (bvh-end-site joint)))
          (format stream "~A  End Site~%~A  {~%~A    OFFSET " indent indent indent)
          (write-bvh-triple stream (vec3-x end) (vec3-y end) (vec3-z end))
          (format stream "~%~A  }~%" indent)))
    (format stream "~A}~%" indent)))

(defun check-bvh-arguments (function skeleton frames frame-time placements)
  "Signal a BVH-ARGUMENT-ERROR of FUNCTION unless SKELETON is a skeleton, FRAMES
a sequence of its poses (finite angles), FRAME-TIME a positive number of
seconds and PLACEMENTS NIL or as many MAT4s as there are FRAMES."
  (flet ((fail (argument value expected)
           (argument-fail function argument value expected 'bvh-argument-error))
         (sequence-p (x) (or (vectorp x) (alexandria:proper-list-p x))))
    (unless (skeleton-p skeleton)
      (fail 'skeleton skeleton "a skeleton (from load-skeleton)"))
    (let ((count (skeleton-channel-count skeleton)))
      (unless (and (sequence-p frames)
                   (every (lambda (pose) (and (vectorp pose) (= (length pose) count)
                                              (every #'finite-number-p pose)))
                          frames))
        (fail 'frames frames (format nil "a sequence of frames, each a pose of ~D finite angles for skeleton ~A"
                                     count (lisp-text (skeleton-name skeleton))))))
    (unless (and (finite-number-p frame-time) (< 0 frame-time *max-seconds*))
      (fail :frame-time frame-time "a positive number of seconds"))
    (when placements
      (unless (and (sequence-p placements) (= (length placements) (length frames))
                   (every (lambda (placement) (typep placement 'mat4)) placements))
        (fail :placements placements
              (format nil "NIL or a sequence of ~D MAT4s, one per frame" (length frames)))))))

(defun write-bvh (stream skeleton frames &key (frame-time (/ 1d0 30)) placements)
  "Write the motion FRAMES of SKELETON to STREAM as a BVH file (see the top of
bvh.lisp for the conventions).  FRAMES is a sequence of poses; PLACEMENTS, when
given, a parallel sequence of MAT4s, the body's world placement at each frame
(identity by default); FRAME-TIME the seconds between frames.  Signals a
BVH-ERROR for a frame that is not a pose of SKELETON, a placement that is not a
MAT4, a count mismatch or a FRAME-TIME that is not a positive real."
  (unless (and (streamp stream) (output-stream-p stream))
    (argument-fail 'write-bvh 'stream stream "an output stream" 'bvh-argument-error))
  (check-bvh-arguments 'write-bvh skeleton frames frame-time placements)
  (let ((joints (skeleton-joints skeleton))
        (frames (coerce frames 'vector))
        (placements (and placements (coerce placements 'vector)))
        (identity (identity-transform)))
    (format stream "HIERARCHY~%")
    (write-bvh-joint stream (skeleton-root skeleton) 0)
    (format stream "MOTION~%Frames: ~D~%Frame Time: " (length frames))
    (write-bvh-number frame-time stream 8)
    (terpri stream)
    (loop for index from 0 below (length frames)
          for pose = (map 'pose (lambda (angle) (float angle 1d0)) (aref frames index))
          for placement = (if placements (aref placements index) identity)
          do (loop for joint across joints
                   for values = (if (body-joint-parent joint)
                                    (bvh-joint-angles joint pose)
                                    (bvh-root-values joint pose placement))
                   for first = t then nil
                   do (dolist (value values)
                        (unless first (write-char #\Space stream))
                        (setf first nil)
                        (write-bvh-number value stream)))
             (terpri stream))
    (values)))

(defun write-bvh-file (path skeleton frames &key (frame-time (/ 1d0 30)) placements)
  "Write FRAMES of SKELETON to the file PATH as BVH (see WRITE-BVH), replacing
any file there and creating missing directories; return PATH's truename.
Signals a BVH-ERROR naming PATH when it cannot be written, and as WRITE-BVH."
  ;; Check before touching the file, so bad frames leave no half-written file.
  (unless (pathname-designator-p path)
    (argument-fail 'write-bvh-file 'path path *path-phrase* 'bvh-argument-error))
  (check-bvh-arguments 'write-bvh-file skeleton frames frame-time placements)
  (handler-case
      (progn
        (ensure-directories-exist path)
        (with-atomic-output-file (out path :make-directories t)
          (write-bvh out skeleton frames :frame-time frame-time :placements placements))
        (truename path))
    ((or io-error file-error stream-error) (condition)
      ;; The path is in the message; a trailing " in FORM" would read oddly here.
      (error 'bvh-error
             :message (format nil "cannot write the BVH file ~A: ~A" (namestring path)
                              (condition-reason condition))))))
