;;;; math.lisp -- 3D math for animation: vectors, unit quaternions, rigid transforms.
;;;; Everything is double-float. A function NAME returns a fresh object; its
;;;; partner NNAME (as 3d-vectors' v+ / nv+) writes into its first argument
;;;; and returns it without consing.

(in-package #:player)

(eval-when (:compile-toplevel :load-toplevel :execute)
  (defparameter *anim-optimize* '(optimize (speed 2) (safety 1) (debug 1))
    "The one optimize form every function in the animation math uses (#.*anim-optimize*).
Safety stays at 1: argument types are checked, so a wrong argument signals a
TYPE-ERROR instead of corrupting memory."))

;;;# Errors

(define-condition anim-error (player-error)
  ((message :initarg :message :reader anim-error-message)
   (form :initarg :form :reader anim-error-form
         :documentation "The offending form or value, when there is one."))
  (:report (lambda (condition stream)
             (write-string (anim-error-message condition) stream)
             (when (slot-boundp condition 'form)
               (format stream " in ~A"
                       (truncate-text (anim-text (anim-error-form condition)) 160)))))
  (:documentation "Root of the errors of the animation engine (hierarchies, controls).
FORM, when bound, is the offending form or value."))

(defun anim-fail (class form control &rest arguments)
  "Signal an ANIM-ERROR of CLASS about FORM, with a message from CONTROL and ARGUMENTS."
  (error class :form form :message (apply #'format nil control arguments)))

;;;# Vectors

(declaim (inline vec3 vec3-x vec3-y vec3-z (setf vec3-x) (setf vec3-y) (setf vec3-z)))
(defstruct (vec3 (:constructor vec3 (&optional (x 0d0) (y 0d0) (z 0d0)))
                 (:copier copy-vec3))
  "A 3D vector or point. Make one with (VEC3 X Y Z); the slots are double-floats."
  (x 0d0 :type double-float)
  (y 0d0 :type double-float)
  (z 0d0 :type double-float))

(defun make-vec3 (x y z)
  "A VEC3 of the reals X, Y and Z, coerced to double-float."
  (vec3 (float x 1d0) (float y 1d0) (float z 1d0)))

(declaim (ftype (function (vec3 vec3) vec3) v+ v- nv+ nv- vcross nvset)
         (ftype (function (vec3 double-float) vec3) v* nv*)
         (ftype (function (vec3 vec3) double-float) vdot vdistance)
         (ftype (function (vec3) double-float) vnorm vnorm-squared)
         (ftype (function (vec3) vec3) vnormalize nvnormalize vnegate nvnegate)
         (ftype (function (vec3 vec3 double-float) vec3) vlerp)
         (inline v+ v- nv+ nv- v* nv* vdot vnorm-squared vnorm vcross nvset
                 vnegate nvnegate vlerp vdistance))

(defun nvset (target source)
  "Copy the coordinates of vector SOURCE into vector TARGET; return TARGET."
  (declare #.*anim-optimize*)
  (setf (vec3-x target) (vec3-x source)
        (vec3-y target) (vec3-y source)
        (vec3-z target) (vec3-z source))
  target)

(defun v+ (a b)
  "The sum of vectors A and B, as a new vector."
  (declare #.*anim-optimize*)
  (vec3 (+ (vec3-x a) (vec3-x b)) (+ (vec3-y a) (vec3-y b)) (+ (vec3-z a) (vec3-z b))))

(defun nv+ (a b)
  "Add vector B to vector A in place; return A."
  (declare #.*anim-optimize*)
  (incf (vec3-x a) (vec3-x b))
  (incf (vec3-y a) (vec3-y b))
  (incf (vec3-z a) (vec3-z b))
  a)

(defun v- (a b)
  "The difference A - B of vectors A and B, as a new vector."
  (declare #.*anim-optimize*)
  (vec3 (- (vec3-x a) (vec3-x b)) (- (vec3-y a) (vec3-y b)) (- (vec3-z a) (vec3-z b))))

(defun nv- (a b)
  "Subtract vector B from vector A in place; return A."
  (declare #.*anim-optimize*)
  (decf (vec3-x a) (vec3-x b))
  (decf (vec3-y a) (vec3-y b))
  (decf (vec3-z a) (vec3-z b))
  a)

(defun v* (v s)
  "Vector V scaled by the double-float S, as a new vector."
  (declare #.*anim-optimize*)
  (vec3 (* s (vec3-x v)) (* s (vec3-y v)) (* s (vec3-z v))))

(defun nv* (v s)
  "Scale vector V by the double-float S in place; return V."
  (declare #.*anim-optimize*)
  (setf (vec3-x v) (* s (vec3-x v))
        (vec3-y v) (* s (vec3-y v))
        (vec3-z v) (* s (vec3-z v)))
  v)

(defun vnegate (v)
  "The vector -V, new."
  (declare #.*anim-optimize*)
  (vec3 (- (vec3-x v)) (- (vec3-y v)) (- (vec3-z v))))

(defun nvnegate (v)
  "Negate vector V in place; return V."
  (declare #.*anim-optimize*)
  (nv* v -1d0))

(defun vdot (a b)
  "The dot product of vectors A and B."
  (declare #.*anim-optimize*)
  (+ (* (vec3-x a) (vec3-x b)) (* (vec3-y a) (vec3-y b)) (* (vec3-z a) (vec3-z b))))

(defun vcross (a b)
  "The cross product A x B of vectors A and B, as a new vector."
  (declare #.*anim-optimize*)
  (let ((ax (vec3-x a)) (ay (vec3-y a)) (az (vec3-z a))
        (bx (vec3-x b)) (by (vec3-y b)) (bz (vec3-z b)))
    (vec3 (- (* ay bz) (* az by))
          (- (* az bx) (* ax bz))
          (- (* ax by) (* ay bx)))))

(defun vnorm-squared (v)
  "The squared Euclidean length of vector V."
  (declare #.*anim-optimize*)
  (vdot v v))

(defun vnorm (v)
  "The Euclidean length of vector V."
  (declare #.*anim-optimize*)
  (sqrt (the (double-float 0d0) (vdot v v))))

(defun vdistance (a b)
  "The distance between points A and B."
  (declare #.*anim-optimize*)
  (let ((dx (- (vec3-x a) (vec3-x b)))
        (dy (- (vec3-y a) (vec3-y b)))
        (dz (- (vec3-z a) (vec3-z b))))
    (sqrt (the (double-float 0d0) (+ (* dx dx) (* dy dy) (* dz dz))))))

(defun nvnormalize (v)
  "Scale vector V to unit length in place and return it; a zero vector stays zero."
  (declare #.*anim-optimize*)
  (let ((n (vnorm v)))
    (if (zerop n) v (nv* v (/ n)))))

(defun vnormalize (v)
  "Vector V scaled to unit length, as a new vector; a zero vector gives a zero vector."
  (declare #.*anim-optimize*)
  (nvnormalize (copy-vec3 v)))

(defun vlerp (a b u)
  "The point (1-U)A + UB between vectors A and B, as a new vector."
  (declare #.*anim-optimize*)
  (vec3 (+ (vec3-x a) (* u (- (vec3-x b) (vec3-x a))))
        (+ (vec3-y a) (* u (- (vec3-y b) (vec3-y a))))
        (+ (vec3-z a) (* u (- (vec3-z b) (vec3-z a))))))

;;;# Unit quaternions

(declaim (inline quat quat-w quat-x quat-y quat-z
                 (setf quat-w) (setf quat-x) (setf quat-y) (setf quat-z)))
(defstruct (quat (:constructor quat (&optional (w 1d0) (x 0d0) (y 0d0) (z 0d0)))
                 (:copier copy-quat))
  "A quaternion W + Xi + Yj + Zk; rotations are unit quaternions. (QUAT) is the identity."
  (w 1d0 :type double-float)
  (x 0d0 :type double-float)
  (y 0d0 :type double-float)
  (z 0d0 :type double-float))

(defun make-quat (w x y z)
  "The quaternion of the reals W, X, Y, Z, coerced to double-float (not normalized)."
  (quat (float w 1d0) (float x 1d0) (float y 1d0) (float z 1d0)))

(declaim (ftype (function (quat quat) quat) q* nq* nqset)
         (ftype (function (quat quat) double-float) qdot)
         (ftype (function (quat) double-float) qnorm)
         (ftype (function (quat) quat) qconjugate nqconjugate qnormalize nqnormalize
                qnegate nqnegate qinverse)
         (ftype (function (quat vec3) vec3) qrotate nqrotate)
         (inline qdot q* nq* qconjugate nqconjugate nqset qnorm qnegate nqnegate))

(defun nqset (target source)
  "Copy the components of quaternion SOURCE into TARGET; return TARGET."
  (declare #.*anim-optimize*)
  (setf (quat-w target) (quat-w source)
        (quat-x target) (quat-x source)
        (quat-y target) (quat-y source)
        (quat-z target) (quat-z source))
  target)

(defun qdot (a b)
  "The 4D dot product of quaternions A and B (the cosine of half the angle between rotations)."
  (declare #.*anim-optimize*)
  (+ (* (quat-w a) (quat-w b)) (* (quat-x a) (quat-x b))
     (* (quat-y a) (quat-y b)) (* (quat-z a) (quat-z b))))

(defun qnorm (q)
  "The length of quaternion Q (1 for a rotation)."
  (declare #.*anim-optimize*)
  (sqrt (the (double-float 0d0) (qdot q q))))

(defmacro %quat-product ((aw ax ay az) (bw bx by bz) receiver)
  "Call RECEIVER (a function name or lambda form) on the four components of the
Hamilton product of the quaternions given by components (AW AX AY AZ) and (BW BX BY BZ)."
  `(,@(if (symbolp receiver) `(,receiver) `(funcall ,receiver))
    (- (* ,aw ,bw) (* ,ax ,bx) (* ,ay ,by) (* ,az ,bz))
    (+ (* ,aw ,bx) (* ,ax ,bw) (* ,ay ,bz) (- (* ,az ,by)))
    (+ (* ,aw ,by) (- (* ,ax ,bz)) (* ,ay ,bw) (* ,az ,bx))
    (+ (* ,aw ,bz) (* ,ax ,by) (- (* ,ay ,bx)) (* ,az ,bw))))

(defun q* (a b)
  "The Hamilton product A B of quaternions A and B, new: the rotation B, then A."
  (declare #.*anim-optimize*)
  (%quat-product ((quat-w a) (quat-x a) (quat-y a) (quat-z a))
                 ((quat-w b) (quat-x b) (quat-y b) (quat-z b))
                 quat))

(defun nq* (a b)
  "Set quaternion A to the product A B of quaternions A and B; return A. B may be A."
  (declare #.*anim-optimize*)
  (let ((aw (quat-w a)) (ax (quat-x a)) (ay (quat-y a)) (az (quat-z a))
        (bw (quat-w b)) (bx (quat-x b)) (by (quat-y b)) (bz (quat-z b)))
    (%quat-product (aw ax ay az) (bw bx by bz)
                   (lambda (w x y z)
                     (setf (quat-w a) w (quat-x a) x (quat-y a) y (quat-z a) z)))
    a))

(defun qconjugate (q)
  "The conjugate of quaternion Q, new; for a unit quaternion, its inverse rotation."
  (declare #.*anim-optimize*)
  (quat (quat-w q) (- (quat-x q)) (- (quat-y q)) (- (quat-z q))))

(defun nqconjugate (q)
  "Conjugate quaternion Q in place; return Q."
  (declare #.*anim-optimize*)
  (setf (quat-x q) (- (quat-x q)) (quat-y q) (- (quat-y q)) (quat-z q) (- (quat-z q)))
  q)

(defun qnegate (q)
  "The quaternion -Q, new: the same rotation as Q from the other hemisphere."
  (declare #.*anim-optimize*)
  (quat (- (quat-w q)) (- (quat-x q)) (- (quat-y q)) (- (quat-z q))))

(defun nqnegate (q)
  "Negate quaternion Q in place; return Q."
  (declare #.*anim-optimize*)
  (setf (quat-w q) (- (quat-w q)) (quat-x q) (- (quat-x q))
        (quat-y q) (- (quat-y q)) (quat-z q) (- (quat-z q)))
  q)

(defun nqnormalize (q)
  "Scale quaternion Q to unit length in place and return it; a zero Q becomes the identity."
  (declare #.*anim-optimize*)
  (let ((n (qnorm q)))
    (if (zerop n)
        (setf (quat-w q) 1d0 (quat-x q) 0d0 (quat-y q) 0d0 (quat-z q) 0d0)
        (let ((s (/ n)))
          (setf (quat-w q) (* s (quat-w q)) (quat-x q) (* s (quat-x q))
                (quat-y q) (* s (quat-y q)) (quat-z q) (* s (quat-z q)))))
    q))

(defun qnormalize (q)
  "Quaternion Q scaled to unit length, new; a zero Q gives the identity."
  (declare #.*anim-optimize*)
  (nqnormalize (copy-quat q)))

(defun qinverse (q)
  "The inverse of the nonzero quaternion Q, new (its conjugate over its squared norm)."
  (declare #.*anim-optimize*)
  (let ((s (/ (qdot q q))))
    (quat (* s (quat-w q)) (- (* s (quat-x q))) (- (* s (quat-y q))) (- (* s (quat-z q))))))

(defun quat-from-axis-angle (axis angle)
  "The unit quaternion rotating by ANGLE radians (a real) about the vector AXIS
(normalized here; a zero AXIS gives the identity), right-handed."
  (declare #.*anim-optimize* (type vec3 axis))
  (let ((n (vnorm axis))
        (half (* 0.5d0 (float angle 1d0))))
    (if (zerop n)
        (quat)
        (let ((s (/ (sin half) n)))
          (quat (cos half) (* s (vec3-x axis)) (* s (vec3-y axis)) (* s (vec3-z axis)))))))

(defun quat-to-axis-angle (q)
  "The rotation of unit quaternion Q as two values: a unit axis vector and an
angle in [0, pi] radians. The identity gives the X axis and 0."
  (declare #.*anim-optimize* (type quat q))
  (let* ((q (if (minusp (quat-w q)) (qnegate q) q))
         (s (sqrt (the (double-float 0d0)
                       (+ (* (quat-x q) (quat-x q)) (* (quat-y q) (quat-y q))
                          (* (quat-z q) (quat-z q)))))))
    (if (< s 1d-15)
        (values (vec3 1d0 0d0 0d0) 0d0)
        (values (vec3 (/ (quat-x q) s) (/ (quat-y q) s) (/ (quat-z q) s))
                (* 2d0 (atan s (quat-w q)))))))

(defun quat-from-euler (x y z)
  "The unit quaternion for Euler angles X, Y, Z (reals, radians) applied in the
order X, then Y, then Z about the fixed world axes (extrinsic X-Y-Z, which is
the same as intrinsic Z-Y'-X'': yaw Z, pitch Y, roll X). Equal to
(q* (rotation about Z by Z) (q* (rotation about Y by Y) (rotation about X by X)))."
  (declare #.*anim-optimize*)
  (let* ((hx (* 0.5d0 (float x 1d0))) (hy (* 0.5d0 (float y 1d0))) (hz (* 0.5d0 (float z 1d0)))
         (cx (cos hx)) (sx (sin hx)) (cy (cos hy)) (sy (sin hy)) (cz (cos hz)) (sz (sin hz)))
    (quat (+ (* cz cy cx) (* sz sy sx))
          (- (* cz cy sx) (* sz sy cx))
          (+ (* cz sy cx) (* sz cy sx))
          (- (* sz cy cx) (* cz sy sx)))))

(defmacro %quat-rotation ((qw qx qy qz) (vx vy vz) receiver)
  "Call RECEIVER on the three components of the vector (VX VY VZ) rotated by the
unit quaternion (QW QX QY QZ): v + 2w(u x v) + 2u x (u x v), with u = (QX QY QZ)."
  (with-gensyms (tx ty tz)
    `(let* ((,tx (* 2d0 (- (* ,qy ,vz) (* ,qz ,vy))))
            (,ty (* 2d0 (- (* ,qz ,vx) (* ,qx ,vz))))
            (,tz (* 2d0 (- (* ,qx ,vy) (* ,qy ,vx)))))
       (,@(if (symbolp receiver) `(,receiver) `(funcall ,receiver))
        (+ ,vx (* ,qw ,tx) (- (* ,qy ,tz) (* ,qz ,ty)))
        (+ ,vy (* ,qw ,ty) (- (* ,qz ,tx) (* ,qx ,tz)))
        (+ ,vz (* ,qw ,tz) (- (* ,qx ,ty) (* ,qy ,tx)))))))

(defun qrotate (q v)
  "Vector V rotated by the unit quaternion Q (q v q*), as a new vector."
  (declare #.*anim-optimize*)
  (%quat-rotation ((quat-w q) (quat-x q) (quat-y q) (quat-z q))
                  ((vec3-x v) (vec3-y v) (vec3-z v))
                  vec3))

(defun nqrotate (q v)
  "Rotate vector V by the unit quaternion Q in place; return V."
  (declare #.*anim-optimize*)
  (let ((vx (vec3-x v)) (vy (vec3-y v)) (vz (vec3-z v)))
    (%quat-rotation ((quat-w q) (quat-x q) (quat-y q) (quat-z q)) (vx vy vz)
                    (lambda (x y z) (setf (vec3-x v) x (vec3-y v) y (vec3-z v) z)))
    v))

(defun quat-angle (a b)
  "The angle in [0, pi] radians of the smallest rotation taking unit quaternion A to B."
  (declare #.*anim-optimize* (type quat a b))
  ;; 2 atan2(|vector part of a* b|, |scalar part|): accurate near 0 and pi, unlike acos.
  (let* ((d (q* (qconjugate a) b))
         (s (sqrt (the (double-float 0d0)
                       (+ (* (quat-x d) (quat-x d)) (* (quat-y d) (quat-y d))
                          (* (quat-z d) (quat-z d)))))))
    (* 2d0 (atan s (abs (quat-w d))))))

;;;## Interpolation

(declaim (ftype (function (quat quat double-float) quat) qslerp qnlerp %qslerp-long)
         (ftype (function (quat) quat) qlog qexp))

(defun qnlerp (a b u)
  "The normalized linear interpolation (1-U)A + UB of quaternions A and B, new (no hemisphere flip)."
  (declare #.*anim-optimize*)
  (let ((v (- 1d0 u)))
    (nqnormalize (quat (+ (* v (quat-w a)) (* u (quat-w b)))
                       (+ (* v (quat-x a)) (* u (quat-x b)))
                       (+ (* v (quat-y a)) (* u (quat-y b)))
                       (+ (* v (quat-z a)) (* u (quat-z b)))))))

(defun %qslerp-long (a b u)
  "Spherical interpolation from unit quaternion A (U = 0) to B (U = 1) along the
great arc through them, without choosing the shorter way round (SQUAD needs this)."
  (declare #.*anim-optimize*)
  (let ((d (qdot a b)))
    (if (> (abs d) (- 1d0 1d-8))
        ;; Nearly parallel (theta < 1.5e-4): sin(theta) ~ 0, and nlerp is exact to ~1e-12 there.
        (qnlerp a b u)
        (let* ((s (sqrt (the (double-float 0d0) (max 0d0 (- 1d0 (* d d))))))
               (theta (atan s d))
               (ka (/ (sin (* (- 1d0 u) theta)) s))
               (kb (/ (sin (* u theta)) s)))
          (quat (+ (* ka (quat-w a)) (* kb (quat-w b)))
                (+ (* ka (quat-x a)) (* kb (quat-x b)))
                (+ (* ka (quat-y a)) (* kb (quat-y b)))
                (+ (* ka (quat-z a)) (* kb (quat-z b))))))))

(defun qslerp (a b u)
  "Spherical linear interpolation from unit quaternion A (U = 0) to B (U = 1), new,
at constant angular speed along the shortest path: B is negated when A . B < 0.
Nearly parallel A and B fall back to normalized lerp."
  (declare #.*anim-optimize*)
  (%qslerp-long a (if (minusp (qdot a b)) (qnegate b) b) u))

(defun qlog (q)
  "The logarithm of unit quaternion Q: the pure quaternion (0, theta n) where Q = (cos theta, sin theta n)."
  (declare #.*anim-optimize*)
  (let* ((x (quat-x q)) (y (quat-y q)) (z (quat-z q))
         (s (sqrt (the (double-float 0d0) (+ (* x x) (* y y) (* z z))))))
    (if (< s 1d-12)
        (quat 0d0 x y z)
        (let ((k (/ (atan s (quat-w q)) s)))
          (quat 0d0 (* k x) (* k y) (* k z))))))

(defun qexp (q)
  "The exponential of the pure quaternion Q = (0, v): (cos |v|, sin |v| v/|v|), a unit quaternion."
  (declare #.*anim-optimize*)
  (let* ((x (quat-x q)) (y (quat-y q)) (z (quat-z q))
         (a (sqrt (the (double-float 0d0) (+ (* x x) (* y y) (* z z))))))
    (if (< a 1d-12)
        (nqnormalize (quat 1d0 x y z))
        (let ((k (/ (sin a) a)))
          (quat (cos a) (* k x) (* k y) (* k z))))))

(defun squad-control-point (previous q next)
  "The SQUAD intermediate control point at unit quaternion Q between its
neighbours PREVIOUS and NEXT (Shoemake): q exp(-(log(q* next) + log(q* previous)) / 4).
The three should lie in one hemisphere (see QSLERP)."
  (declare #.*anim-optimize* (type quat previous q next))
  (let* ((inverse (qconjugate q))
         (a (qlog (q* inverse next)))
         (b (qlog (q* inverse previous))))
    (q* q (qexp (quat 0d0
                      (* -0.25d0 (+ (quat-x a) (quat-x b)))
                      (* -0.25d0 (+ (quat-y a) (quat-y b)))
                      (* -0.25d0 (+ (quat-z a) (quat-z b))))))))

(defun qsquad (q1 q2 s1 s2 u)
  "Spherical quadrangle interpolation from unit quaternion Q1 (U = 0) to Q2 (U = 1)
with control points S1 and S2 (from SQUAD-CONTROL-POINT):
slerp(slerp(Q1, Q2, U), slerp(S1, S2, U), 2U(1-U)). Successive segments sharing
control points join with continuous angular velocity."
  (declare #.*anim-optimize* (type quat q1 q2 s1 s2) (type double-float u))
  (%qslerp-long (%qslerp-long q1 q2 u) (%qslerp-long s1 s2 u) (* 2d0 u (- 1d0 u))))

;;;# Matrices and rigid transforms

(deftype mat3 ()
  "A 3x3 matrix, row-major, of double-floats."
  '(simple-array double-float (3 3)))

(deftype mat4 ()
  "A 4x4 rigid transform (rotation and translation), row-major, acting on column
vectors: the rotation is the upper-left 3x3, the translation the last column,
the last row (0 0 0 1)."
  '(simple-array double-float (4 4)))

(defun anim-text (object)
  "OBJECT as text for messages: vectors as (vec3 X Y Z), quaternions as
(quat W X Y Z), lists element by element, anything else as LISP-TEXT."
  (typecase object
    (vec3 (format nil "(vec3 ~A ~A ~A)" (format-number (vec3-x object))
                  (format-number (vec3-y object)) (format-number (vec3-z object))))
    (quat (format nil "(quat ~A ~A ~A ~A)" (format-number (quat-w object))
                  (format-number (quat-x object)) (format-number (quat-y object))
                  (format-number (quat-z object))))
    (cons (with-output-to-string (out)
            (write-char #\( out)
            (loop for (head . tail) on object
                  do (write-string (anim-text head) out)
                     (typecase tail
                       (null)
                       (cons (write-char #\Space out))
                       (t (format out " . ~A" (anim-text tail)))))
            (write-char #\) out)))
    (t (lisp-text object))))

(defun quat-to-matrix (q)
  "The 3x3 rotation matrix of unit quaternion Q, new: M v = (qrotate Q v)."
  (declare #.*anim-optimize* (type quat q))
  (let ((m (make-array '(3 3) :element-type 'double-float)))
    (%set-rotation-from-quat m q)
    m))

(defun %set-rotation-from-quat (m q)
  "Write the rotation of unit quaternion Q into the upper-left 3x3 of matrix M (3x3 or 4x4)."
  (declare #.*anim-optimize* (type (simple-array double-float (* *)) m) (type quat q))
  (let* ((w (quat-w q)) (x (quat-x q)) (y (quat-y q)) (z (quat-z q))
         (xx (* x x)) (yy (* y y)) (zz (* z z))
         (xy (* x y)) (xz (* x z)) (yz (* y z))
         (wx (* w x)) (wy (* w y)) (wz (* w z)))
    (setf (aref m 0 0) (- 1d0 (* 2d0 (+ yy zz)))
          (aref m 0 1) (* 2d0 (- xy wz))
          (aref m 0 2) (* 2d0 (+ xz wy))
          (aref m 1 0) (* 2d0 (+ xy wz))
          (aref m 1 1) (- 1d0 (* 2d0 (+ xx zz)))
          (aref m 1 2) (* 2d0 (- yz wx))
          (aref m 2 0) (* 2d0 (- xz wy))
          (aref m 2 1) (* 2d0 (+ yz wx))
          (aref m 2 2) (- 1d0 (* 2d0 (+ xx yy))))
    m))

(defun matrix-to-quat (m)
  "The unit quaternion (with w >= 0) of the rotation in the upper-left 3x3 of
matrix M (a MAT3 or MAT4), by Shepperd's method."
  (declare #.*anim-optimize* (type (simple-array double-float (* *)) m))
  (let* ((m00 (aref m 0 0)) (m11 (aref m 1 1)) (m22 (aref m 2 2))
         (trace (+ m00 m11 m22))
         (q (cond ((> trace 0d0)
                   (let ((s (* 2d0 (sqrt (the (double-float 0d0) (+ 1d0 trace))))))
                     (quat (* 0.25d0 s)
                           (/ (- (aref m 2 1) (aref m 1 2)) s)
                           (/ (- (aref m 0 2) (aref m 2 0)) s)
                           (/ (- (aref m 1 0) (aref m 0 1)) s))))
                  ((and (> m00 m11) (> m00 m22))
                   (let ((s (* 2d0 (sqrt (the (double-float 0d0) (max 0d0 (- (+ 1d0 m00) m11 m22)))))))
                     (quat (/ (- (aref m 2 1) (aref m 1 2)) s)
                           (* 0.25d0 s)
                           (/ (+ (aref m 0 1) (aref m 1 0)) s)
                           (/ (+ (aref m 0 2) (aref m 2 0)) s))))
                  ((> m11 m22)
                   (let ((s (* 2d0 (sqrt (the (double-float 0d0) (max 0d0 (- (+ 1d0 m11) m00 m22)))))))
                     (quat (/ (- (aref m 0 2) (aref m 2 0)) s)
                           (/ (+ (aref m 0 1) (aref m 1 0)) s)
                           (* 0.25d0 s)
                           (/ (+ (aref m 1 2) (aref m 2 1)) s))))
                  (t
                   (let ((s (* 2d0 (sqrt (the (double-float 0d0) (max 0d0 (- (+ 1d0 m22) m00 m11)))))))
                     (quat (/ (- (aref m 1 0) (aref m 0 1)) s)
                           (/ (+ (aref m 0 2) (aref m 2 0)) s)
                           (/ (+ (aref m 1 2) (aref m 2 1)) s)
                           (* 0.25d0 s)))))))
    (when (minusp (quat-w q)) (nqnegate q))
    (nqnormalize q)))

(defun mat3-apply (m v)
  "The vector M V for the 3x3 matrix M and vector V, new."
  (declare #.*anim-optimize* (type mat3 m) (type vec3 v))
  (let ((x (vec3-x v)) (y (vec3-y v)) (z (vec3-z v)))
    (vec3 (+ (* (aref m 0 0) x) (* (aref m 0 1) y) (* (aref m 0 2) z))
          (+ (* (aref m 1 0) x) (* (aref m 1 1) y) (* (aref m 1 2) z))
          (+ (* (aref m 2 0) x) (* (aref m 2 1) y) (* (aref m 2 2) z)))))

(defun identity-transform ()
  "A new identity MAT4."
  (declare #.*anim-optimize*)
  (let ((m (make-array '(4 4) :element-type 'double-float :initial-element 0d0)))
    (dotimes (i 4 m) (setf (aref m i i) 1d0))))

(defun make-transform (&key (rotation (quat)) (translation (vec3)))
  "A new MAT4 that rotates by the unit quaternion ROTATION, then translates by
the vector TRANSLATION: p -> R p + t."
  (declare #.*anim-optimize* (type quat rotation) (type vec3 translation))
  (let ((m (identity-transform)))
    (%set-rotation-from-quat m rotation)
    (setf (aref m 0 3) (vec3-x translation)
          (aref m 1 3) (vec3-y translation)
          (aref m 2 3) (vec3-z translation))
    m))

(defun transform-translation (m)
  "The translation of MAT4 M, as a new vector."
  (declare #.*anim-optimize* (type mat4 m))
  (vec3 (aref m 0 3) (aref m 1 3) (aref m 2 3)))

(defun transform-rotation (m)
  "The rotation of MAT4 M, as a new unit quaternion."
  (declare #.*anim-optimize* (type mat4 m))
  (matrix-to-quat m))

(declaim (ftype (function (mat4 mat4 &optional mat4) mat4) transform-compose)
         (ftype (function (mat4 &optional mat4) mat4) transform-invert))

(defun transform-compose (a b &optional (result (identity-transform)))
  "The rigid transform A B (apply B, then A) of MAT4s A and B, stored into the
MAT4 RESULT (new by default; it may be A or B) and returned. Conses nothing
when RESULT is given."
  (declare #.*anim-optimize*)
  (let ((tmp (make-array 12 :element-type 'double-float)))
    (declare (dynamic-extent tmp))
    (dotimes (i 3)
      (dotimes (j 4)
        (setf (aref tmp (+ (* 4 i) j))
              (+ (* (aref a i 0) (aref b 0 j))
                 (* (aref a i 1) (aref b 1 j))
                 (* (aref a i 2) (aref b 2 j))
                 (if (= j 3) (aref a i 3) 0d0)))))
    (dotimes (i 3)
      (dotimes (j 4)
        (setf (aref result i j) (aref tmp (+ (* 4 i) j)))))
    (setf (aref result 3 0) 0d0 (aref result 3 1) 0d0
          (aref result 3 2) 0d0 (aref result 3 3) 1d0)
    result))

(defun transform-invert (m &optional (result (identity-transform)))
  "The inverse of the rigid MAT4 M (rotation R^T, translation -R^T t), stored
into the MAT4 RESULT (new by default; it may be M) and returned."
  (declare #.*anim-optimize*)
  (let ((tx (aref m 0 3)) (ty (aref m 1 3)) (tz (aref m 2 3)))
    ;; Transpose the rotation in place-safe order: swap the off-diagonal pairs.
    (dotimes (i 3)
      (setf (aref result i i) (aref m i i)))
    (loop for (i j) in '((0 1) (0 2) (1 2))
          do (let ((mij (aref m i j)) (mji (aref m j i)))
               (setf (aref result i j) mji (aref result j i) mij)))
    (dotimes (i 3)
      (setf (aref result i 3)
            (- (+ (* (aref result i 0) tx) (* (aref result i 1) ty) (* (aref result i 2) tz)))))
    (setf (aref result 3 0) 0d0 (aref result 3 1) 0d0
          (aref result 3 2) 0d0 (aref result 3 3) 1d0)
    result))

(declaim (ftype (function (mat4 vec3) vec3) transform-point transform-vector
                ntransform-point ntransform-vector))

(defun ntransform-point (m p)
  "Move point P by MAT4 M in place (R p + t); return P."
  (declare #.*anim-optimize*)
  (let ((x (vec3-x p)) (y (vec3-y p)) (z (vec3-z p)))
    (setf (vec3-x p) (+ (* (aref m 0 0) x) (* (aref m 0 1) y) (* (aref m 0 2) z) (aref m 0 3))
          (vec3-y p) (+ (* (aref m 1 0) x) (* (aref m 1 1) y) (* (aref m 1 2) z) (aref m 1 3))
          (vec3-z p) (+ (* (aref m 2 0) x) (* (aref m 2 1) y) (* (aref m 2 2) z) (aref m 2 3)))
    p))

(defun transform-point (m p)
  "Point P moved by MAT4 M (R p + t), as a new vector."
  (declare #.*anim-optimize*)
  (ntransform-point m (copy-vec3 p)))

(defun ntransform-vector (m v)
  "Rotate direction V by the rotation of MAT4 M in place (no translation); return V."
  (declare #.*anim-optimize*)
  (let ((x (vec3-x v)) (y (vec3-y v)) (z (vec3-z v)))
    (setf (vec3-x v) (+ (* (aref m 0 0) x) (* (aref m 0 1) y) (* (aref m 0 2) z))
          (vec3-y v) (+ (* (aref m 1 0) x) (* (aref m 1 1) y) (* (aref m 1 2) z))
          (vec3-z v) (+ (* (aref m 2 0) x) (* (aref m 2 1) y) (* (aref m 2 2) z)))
    v))

(defun transform-vector (m v)
  "Direction V rotated by the rotation of MAT4 M (no translation), as a new vector."
  (declare #.*anim-optimize*)
  (ntransform-vector m (copy-vec3 v)))

(defun world-transforms (parents locals &optional
                                          (worlds (map 'simple-vector
                                                       (lambda (m) (declare (ignore m))
                                                         (identity-transform))
                                                       locals)))
  "The world transforms of a hierarchy, stored into the simple-vector WORLDS of
MAT4s (new by default) and returned. PARENTS is a vector of each node's parent
index, or NIL (or -1) for a root, with every parent before its children; LOCALS
is a vector of the nodes' MAT4s relative to their parents. WORLDS[i] =
WORLDS[parent] LOCALS[i]; a root's world is its local. Conses nothing when
WORLDS is given. Signals an ANIM-ERROR when a parent does not precede its child."
  (declare #.*anim-optimize* (type vector parents locals) (type simple-vector worlds))
  (dotimes (i (length locals) worlds)
    (let ((parent (aref parents i))
          (local (aref locals i))
          (world (svref worlds i)))
      (declare (type mat4 local world))
      (cond ((or (null parent) (eql parent -1))
             (dotimes (r 4)
               (dotimes (c 4)
                 (setf (aref world r c) (aref local r c)))))
            ((and (typep parent 'fixnum) (< -1 parent i))
             (transform-compose (svref worlds parent) local world))
            (t (anim-fail 'anim-error parent
                          "node ~D's parent is not the index of an earlier node" i))))))
