;;;; euler.lisp -- a rotation as the angles of an imported joint's three DOFs.
;;;; An imported joint turns about x, then y, then z of its parent's rest frame
;;;; (JOINT-LOCAL-ROTATION multiplies the DOFs' rotations in order: Rx Ry Rz),
;;;; so a clip's rotations are decomposed the same way.

(in-package #:player.rig)

(declaim (inline %quat-to-xyz-degrees))

(defun %quat-to-xyz-degrees (w x y z)
  "The angles (A B C), in degrees, with Rx(A) Ry(B) Rz(C) = the unit quaternion
W X Y Z; three values.  B lies in [-90, 90], A and C in [-180, 180]; at B =
+-90 (gimbal lock) C is 0 and A takes the whole turn."
  (declare (type double-float w x y z) (optimize (speed 3) (safety 1)))
  ;; The rotation matrix's entries that R = Rx(a) Ry(b) Rz(c) makes simple:
  ;; r02 = sin b, r12 = -sin a cos b, r22 = cos a cos b, r01 = -cos b sin c,
  ;; r00 = cos b cos c.
  (let* ((r02 (* 2d0 (+ (* x z) (* w y))))
         (r12 (* 2d0 (- (* y z) (* w x))))
         (r22 (- 1d0 (* 2d0 (+ (* x x) (* y y)))))
         (r01 (* 2d0 (- (* x y) (* w z))))
         (r00 (- 1d0 (* 2d0 (+ (* y y) (* z z)))))
         (degrees (/ 180d0 pi)))
    (if (< (abs r02) (- 1d0 1d-12))
        (values (* degrees (atan (- r12) r22))
                (* degrees (asin (max -1d0 (min 1d0 r02))))
                (* degrees (atan (- r01) r00)))
        ;; cos b = 0: only a + c (or a - c) is defined; put it all in a.
        (let ((r21 (* 2d0 (+ (* y z) (* w x))))
              (r11 (- 1d0 (* 2d0 (+ (* x x) (* z z))))))
          (values (* degrees (atan r21 r11))
                  (if (plusp r02) 90d0 -90d0)
                  0d0)))))

(defun quat-to-xyz-degrees (q)
  "The angles about x, y and z, in degrees, whose rotations Rx Ry Rz make the
unit quaternion Q (a QUAT); three values (see %QUAT-TO-XYZ-DEGREES)."
  (check-argument 'quat-to-xyz-degrees 'q q (lambda (x) (and (finite-quat-p x) (plusp (qnorm x))))
                  "a nonzero quat of finite numbers")
  (let ((q (qnormalize q)))
    (%quat-to-xyz-degrees (quat-w q) (quat-x q) (quat-y q) (quat-z q))))

;;;# Any order of axes

;;; A Player joint of its own (a shipped skeleton's) turns about one to three
;;; signed axes in a declared order, so a clip played on it needs the
;;; decomposition in that order.  It is QUAT-TO-EULER's (src/body/bvh.lisp),
;;; inlined and without consing, since the clip driver runs it per joint per frame.

(declaim (inline %quat-to-euler-degrees))

(defun %quat-to-euler-degrees (w x y z i j k)
  "The angles (A B C), in degrees, with R(I, A) R(J, B) R(K, C) = the unit
quaternion W X Y Z, where I J K (0 for x, 1 for y, 2 for z) are a permutation
of the axes, the first outermost; three values.  B lies in [-90, 90], A and C
in [-180, 180]; at gimbal lock C takes what A leaves, as in QUAT-TO-EULER."
  (declare (type double-float w x y z) (type (integer 0 2) i j k) (optimize (speed 3) (safety 1)))
  (let ((r (make-array 9 :element-type 'double-float)))
    (declare (dynamic-extent r))
    (setf (aref r 0) (- 1d0 (* 2d0 (+ (* y y) (* z z))))
          (aref r 1) (* 2d0 (- (* x y) (* w z)))
          (aref r 2) (* 2d0 (+ (* x z) (* w y)))
          (aref r 3) (* 2d0 (+ (* x y) (* w z)))
          (aref r 4) (- 1d0 (* 2d0 (+ (* x x) (* z z))))
          (aref r 5) (* 2d0 (- (* y z) (* w x)))
          (aref r 6) (* 2d0 (- (* x z) (* w y)))
          (aref r 7) (* 2d0 (+ (* y z) (* w x)))
          (aref r 8) (- 1d0 (* 2d0 (+ (* x x) (* y y)))))
    (flet ((m (row column) (aref r (+ (* 3 row) column))))
      (declare (inline m))
      ;; Relabelled so (I J K) reads (x y z); an odd permutation is a
      ;; reflection, which reverses every angle (see QUAT-TO-EULER).
      (let* ((sign (if (= (mod (- j i) 3) 1) 1d0 -1d0))
             (a (atan (- (m j k)) (m k k)))
             (b (atan (m i k) (sqrt (+ (expt (m i i) 2) (expt (m i j) 2)))))
             (ca (cos a)) (sa (sin a))
             (c (atan (+ (* ca (m j i)) (* sa (m k i)))
                      (+ (* ca (m j j)) (* sa (m k j)))))
             (degrees (* sign (/ 180d0 pi))))
        (values (* degrees a) (* degrees b) (* degrees c))))))
