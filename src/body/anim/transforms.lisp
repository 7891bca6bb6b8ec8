;;;; transforms.lisp -- 3x3 and 4x4 matrices, rigid transforms and hierarchies.

(in-package #:player.body)

;;;# Matrices and rigid transforms

(deftype mat3 ()
  "A 3x3 matrix, row-major, of double-floats."
  '(simple-array double-float (3 3)))

(deftype mat4 ()
  "A 4x4 rigid transform (rotation and translation), row-major, acting on column
vectors: the rotation is the upper-left 3x3, the translation the last column,
the last row (0 0 0 1)."
  '(simple-array double-float (4 4)))

(defun bounded-anim-text (object)
  "ANIM-TEXT of OBJECT when it is a tree of bounded depth; else BOUNDED-LISP-TEXT,
so a circular form in an error message cannot hang the report.  Float traps
are masked, so a NaN prints as nan."
  (sb-int:with-float-traps-masked (:invalid :overflow :inexact :divide-by-zero)
    (if (bounded-form-p object) (anim-text object) (bounded-lisp-text object 160))))

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
            (write-list-text object out (lambda (element stream)
                                          (write-string (anim-text element) stream)))))
    (t (lisp-text object))))

(defun quat-to-matrix (q)
  "The 3x3 rotation matrix of unit quaternion Q, new: M v = (qrotate Q v)."
  (declare #.*anim-optimize* (type quat q))
  (let ((m (make-array '(3 3) :element-type 'double-float)))
    (%set-rotation-from-quat m q)
    m))

(declaim (inline %set-rotation-from-components))
(defun %set-rotation-from-components (m w x y z)
  "Write the rotation of the unit quaternion (W X Y Z) into the upper-left 3x3
of matrix M (3x3 or 4x4)."
  (declare #.*anim-optimize* (type (simple-array double-float (* *)) m)
           (type double-float w x y z))
  (let ((xx (* x x)) (yy (* y y)) (zz (* z z))
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

(defun %set-rotation-from-quat (m q)
  "Write the rotation of unit quaternion Q into the upper-left 3x3 of matrix M (3x3 or 4x4)."
  (declare #.*anim-optimize* (type (simple-array double-float (* *)) m) (type quat q))
  (%set-rotation-from-components m (quat-w q) (quat-x q) (quat-y q) (quat-z q)))

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
  (declare #.*anim-optimize* (type mat4 a b result))
  ;; Unrolled, every entry read before any is written (RESULT may be A or B).
  (macrolet ((compose ()
               (let ((as (loop for i below 3 collect (loop for j below 4 collect (gensym (format nil "A~D~D" i j)))))
                     (bs (loop for i below 3 collect (loop for j below 4 collect (gensym (format nil "B~D~D" i j))))))
                 `(let (,@(loop for i below 3 nconc (loop for j below 4 collect `(,(nth j (nth i as)) (aref a ,i ,j))))
                        ,@(loop for i below 3 nconc (loop for j below 4 collect `(,(nth j (nth i bs)) (aref b ,i ,j)))))
                    (declare (type double-float ,@(reduce #'append as) ,@(reduce #'append bs)))
                    (setf ,@(loop for i below 3
                                  nconc (loop for j below 4
                                              collect `(aref result ,i ,j)
                                              collect `(+ (* ,(nth 0 (nth i as)) ,(nth j (nth 0 bs)))
                                                          (* ,(nth 1 (nth i as)) ,(nth j (nth 1 bs)))
                                                          (* ,(nth 2 (nth i as)) ,(nth j (nth 2 bs)))
                                                          ;; 0d0 as before unrolling: a -0d0 sum prints as 0.
                                                          ,(if (= j 3) (nth 3 (nth i as)) 0d0)))))))))
    (compose))
  (setf (aref result 3 0) 0d0 (aref result 3 1) 0d0
        (aref result 3 2) 0d0 (aref result 3 3) 1d0)
  result)

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

(defun world-transforms (parents locals &optional worlds)
  "The world transforms of a hierarchy, stored into the simple-vector WORLDS of
MAT4s (new by default) and returned; see %WORLD-TRANSFORMS.  Signals an
ARGUMENT-ERROR for PARENTS that is not a vector, LOCALS that is not a vector of
as many MAT4s, or WORLDS that is not a simple-vector of as many MAT4s."
  (check-argument 'world-transforms 'parents parents #'vectorp
                  "a vector of parent indices (NIL or -1 for a root)" 'anim-argument-error)
  (check-argument 'world-transforms 'locals locals
                  (lambda (x) (and (vectorp x) (= (length x) (length parents))
                                   (every (lambda (m) (typep m 'mat4)) x)))
                  (format nil "a vector of ~D MAT4s, one per parent" (length parents)) 'anim-argument-error)
  (when worlds
    (check-argument 'world-transforms 'worlds worlds
                    (lambda (x) (and (simple-vector-p x) (= (length x) (length locals))
                                     (every (lambda (m) (typep m 'mat4)) x)))
                    (format nil "NIL or a simple-vector of ~D MAT4s" (length locals)) 'anim-argument-error))
  (%world-transforms parents locals
                     (or worlds (map 'simple-vector (lambda (m) (declare (ignore m)) (identity-transform))
                                     locals))))

(defun %world-transforms (parents locals worlds)
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
