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
