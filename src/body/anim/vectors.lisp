;;;; vectors.lisp -- 3D math for animation, part 1: the shared optimize form,
;;;; the error root, and vectors (quaternions.lisp and transforms.lisp follow).
;;;; Everything is double-float. A function NAME returns a fresh object; its
;;;; partner NNAME (as 3d-vectors' v+ / nv+) writes into its first argument
;;;; and returns it without consing.

(in-package #:player.body)

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
                       (truncate-text (bounded-anim-text (anim-error-form condition)) 160)))))
  (:documentation "Root of the errors of the animation engine (hierarchies, controls).
FORM, when bound, is the offending form or value."))

(define-condition anim-argument-error (argument-error anim-error)
  ()
  (:documentation "A function of the animation engine was called with a bad
argument: both an ARGUMENT-ERROR (naming the function and argument) and an ANIM-ERROR."))

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

(defun finite-vec3-p (x)
  "Is X a VEC3 whose coordinates are finite (no NaN, no infinity)?"
  (and (vec3-p x)
       (finite-number-p (vec3-x x)) (finite-number-p (vec3-y x)) (finite-number-p (vec3-z x))))

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
