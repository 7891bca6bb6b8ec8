;;;; matrices.lisp -- the affine 4x4 matrices a rig needs beyond the body's
;;;; rigid ones: a model's node transforms carry scale, and its placement in
;;;; Player's space scales too.  Matrices are MAT4 arrays (row-major, acting on
;;;; column vectors); Assimp's 16-double row-major vectors convert directly.

(in-package #:player.rig)

(defun row-major-matrix (values)
  "The MAT4 of VALUES, 16 doubles row-major (Assimp's aiMatrix4x4 order)."
  (let ((m (identity-transform)))
    (dotimes (i 16 m)
      (setf (row-major-aref m i) (float (aref values i) 1d0)))))

(defun matrix-row-major (m)
  "The 16 doubles of the MAT4 M, row-major, as a fresh vector."
  (let ((values (make-array 16 :element-type 'double-float)))
    (dotimes (i 16 values)
      (setf (aref values i) (row-major-aref m i)))))

(defun trs-matrix (translation rotation scale)
  "The MAT4 T R S of a TRANSLATION (x y z), a ROTATION (unit quaternion w x y
z) and a SCALE (x y z), each a vector of doubles, as a node's transform."
  (let ((m (make-transform :rotation (qnormalize (make-quat (aref rotation 0) (aref rotation 1)
                                                            (aref rotation 2) (aref rotation 3)))
                           :translation (make-vec3 (aref translation 0) (aref translation 1)
                                                   (aref translation 2)))))
    (dotimes (column 3 m)
      (dotimes (row 3)
        (setf (aref m row column) (* (aref m row column) (aref scale column)))))))

(defun affine* (a b)
  "The affine product A B of two MAT4s (apply B, then A), as a new MAT4."
  (let ((product (identity-transform)))
    (dotimes (row 3 product)
      (dotimes (column 4)
        (setf (aref product row column)
              (+ (loop for k below 3 sum (* (aref a row k) (aref b k column)))
                 (if (= column 3) (aref a row 3) 0d0)))))))

(defun affine-inverse (m)
  "The inverse of the affine MAT4 M (any invertible 3x3 part), as a new MAT4;
an ERROR for a singular one (a node scaled to nothing)."
  (flet ((at (i j) (aref m i j)))
    (let* ((c00 (- (* (at 1 1) (at 2 2)) (* (at 1 2) (at 2 1))))
           (c01 (- (* (at 1 2) (at 2 0)) (* (at 1 0) (at 2 2))))
           (c02 (- (* (at 1 0) (at 2 1)) (* (at 1 1) (at 2 0))))
           (det (+ (* (at 0 0) c00) (* (at 0 1) c01) (* (at 0 2) c02)))
           (inverse (identity-transform)))
      (when (< (abs det) 1d-300)
        (error 'player-error-with-message :message "a joint's transform is singular (scaled to nothing)"))
      (let ((adjugate
              (make-array '(3 3) :element-type 'double-float
                                 :initial-contents
                                 (list (list c00 (- (* (at 0 2) (at 2 1)) (* (at 0 1) (at 2 2)))
                                             (- (* (at 0 1) (at 1 2)) (* (at 0 2) (at 1 1))))
                                       (list c01 (- (* (at 0 0) (at 2 2)) (* (at 0 2) (at 2 0)))
                                             (- (* (at 0 2) (at 1 0)) (* (at 0 0) (at 1 2))))
                                       (list c02 (- (* (at 0 1) (at 2 0)) (* (at 0 0) (at 2 1)))
                                             (- (* (at 0 0) (at 1 1)) (* (at 0 1) (at 1 0))))))))
        (dotimes (i 3)
          (dotimes (j 3)
            (setf (aref inverse i j) (/ (aref adjugate i j) det))))
        (dotimes (i 3 inverse)
          (setf (aref inverse i 3)
                (- (loop for k below 3 sum (* (aref inverse i k) (at k 3))))))))))

(defun affine-point (m x y z)
  "The point (X Y Z) moved by the affine MAT4 M, as a vec3."
  (make-vec3 (+ (* (aref m 0 0) x) (* (aref m 0 1) y) (* (aref m 0 2) z) (aref m 0 3))
             (+ (* (aref m 1 0) x) (* (aref m 1 1) y) (* (aref m 1 2) z) (aref m 1 3))
             (+ (* (aref m 2 0) x) (* (aref m 2 1) y) (* (aref m 2 2) z) (aref m 2 3))))

(defun translation-matrix (vector)
  "The MAT4 translating by the vec3 VECTOR."
  (make-transform :translation vector))
