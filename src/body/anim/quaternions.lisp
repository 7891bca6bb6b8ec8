;;;; quaternions.lisp -- unit quaternions and their interpolation (slerp, squad).

(in-package #:player.body)

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

(defun finite-quat-p (x)
  "Is X a QUAT whose components are finite (no NaN, no infinity)?"
  (and (quat-p x)
       (finite-number-p (quat-w x)) (finite-number-p (quat-x x))
       (finite-number-p (quat-y x)) (finite-number-p (quat-z x))))

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

(declaim (ftype (function (quat quat double-float) quat) %qslerp qnlerp %qslerp-long)
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
Nearly parallel A and B fall back to normalized lerp.  U is a finite real.
Signals an ARGUMENT-ERROR for anything else."
  (check-argument 'qslerp 'a a #'finite-quat-p "a quaternion with finite components"
                  'anim-argument-error)
  (check-argument 'qslerp 'b b #'finite-quat-p "a quaternion with finite components"
                  'anim-argument-error)
  (check-argument 'qslerp 'u u #'finite-number-p "a finite real" 'anim-argument-error)
  (%qslerp a b (float u 1d0)))

(defun %qslerp (a b u)
  "QSLERP without the argument checks, for the animation engine's inner loops."
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
with control points S1 and S2 (see %QSQUAD).  U is a finite real.  Signals an
ARGUMENT-ERROR for anything else."
  (check-argument 'qsquad 'q1 q1 #'finite-quat-p "a quaternion with finite components"
                  'anim-argument-error)
  (check-argument 'qsquad 'q2 q2 #'finite-quat-p "a quaternion with finite components"
                  'anim-argument-error)
  (check-argument 'qsquad 's1 s1 #'finite-quat-p "a quaternion with finite components"
                  'anim-argument-error)
  (check-argument 'qsquad 's2 s2 #'finite-quat-p "a quaternion with finite components"
                  'anim-argument-error)
  (check-argument 'qsquad 'u u #'finite-number-p "a finite real" 'anim-argument-error)
  (%qsquad q1 q2 s1 s2 (float u 1d0)))

(defun %qsquad (q1 q2 s1 s2 u)
  "Spherical quadrangle interpolation from unit quaternion Q1 (U = 0) to Q2 (U = 1)
with control points S1 and S2 (from SQUAD-CONTROL-POINT):
slerp(slerp(Q1, Q2, U), slerp(S1, S2, U), 2U(1-U)). Successive segments sharing
control points join with continuous angular velocity."
  (declare #.*anim-optimize* (type quat q1 q2 s1 s2) (type double-float u))
  (%qslerp-long (%qslerp-long q1 q2 u) (%qslerp-long s1 s2 u) (* 2d0 u (- 1d0 u))))
