;;;; gltf-numbers.lisp -- the model's doubles as the glTF file's numbers:
;;;; 32-bit floats (checked finite and in range, since a double past
;;;; single-float's range has no float to become), quaternions reordered from
;;;; the model's w x y z to glTF's x y z w and made unit length, and 4x4
;;;; matrices from Assimp's row-major order to glTF's column-major.

(in-package #:player.model)

(declaim (inline single))
(defun single (x what)
  "The double X as a single-float; a MODEL-WRITE-ERROR naming WHAT when X is
not finite or too large for a 32-bit float."
  (declare (type double-float x))
  (unless (finite-double-p x)
    (write-fail "~A hold a value that is not finite (NaN or infinite)" what))
  (unless (<= (abs x) most-positive-single-float)
    (write-fail "~A hold ~A, too large for a 32-bit float" what x))
  (coerce x 'single-float))

(defun singles (doubles what)
  "DOUBLES (a DOUBLE-VECTOR) as a fresh FLOAT-VECTOR (see SINGLE for WHAT)."
  (declare (type double-vector doubles))
  (let ((floats (make-array (length doubles) :element-type 'single-float)))
    (dotimes (i (length doubles) floats)
      (setf (aref floats i) (single (aref doubles i) what)))))

(defun unit-xyzw (rotations start what)
  "The quaternion at START of ROTATIONS (w x y z) as x y z w made unit
length, four doubles; a MODEL-WRITE-ERROR naming WHAT when it is not finite
or has no length to divide by."
  (declare (type double-vector rotations) (type fixnum start))
  (let ((w (aref rotations start)) (x (aref rotations (+ start 1)))
        (y (aref rotations (+ start 2))) (z (aref rotations (+ start 3))))
    (unless (every #'finite-double-p (list w x y z))
      (write-fail "~A hold a value that is not finite (NaN or infinite)" what))
    (let ((norm (sqrt (+ (* w w) (* x x) (* y y) (* z z)))))
      (unless (> norm 1d-12)
        (write-fail "~A hold a quaternion of length 0, which is no rotation" what))
      (values (/ x norm) (/ y norm) (/ z norm) (/ w norm)))))

(defun node-rotation (rotation what)
  "The quaternion ROTATION (w x y z) as glTF writes a node's: x y z w, unit length, a DOUBLE-VECTOR."
  (multiple-value-bind (x y z w) (unit-xyzw rotation 0 what)
    (make-array 4 :element-type 'double-float :initial-contents (list x y z w))))

(defun rotation-singles (rotations what)
  "ROTATIONS (w x y z per key) as glTF's rotation keys: x y z w, unit length, a FLOAT-VECTOR."
  (declare (type double-vector rotations))
  (let ((floats (make-array (length rotations) :element-type 'single-float)))
    (loop for start from 0 below (length rotations) by 4
          do (multiple-value-bind (x y z w) (unit-xyzw rotations start what)
               (setf (aref floats start) (coerce x 'single-float)
                     (aref floats (+ start 1)) (coerce y 'single-float)
                     (aref floats (+ start 2)) (coerce z 'single-float)
                     (aref floats (+ start 3)) (coerce w 'single-float))))
    floats))

(defun column-major (matrix)
  "The 4x4 MATRIX (16 doubles, row-major as Assimp keeps them) in glTF's
column-major order: element (row r, column c) moves from 4r+c to 4c+r."
  (let ((transposed (make-array 16 :element-type 'double-float)))
    (dotimes (r 4 transposed)
      (dotimes (c 4)
        (setf (aref transposed (+ (* 4 c) r)) (aref matrix (+ (* 4 r) c)))))))
