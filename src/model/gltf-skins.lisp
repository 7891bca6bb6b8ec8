;;;; gltf-skins.lisp -- a skinned mesh's skin in glTF: the skin's joints,
;;;; their inverse bind matrices, and each vertex's JOINTS_0 and WEIGHTS_0.
;;;;
;;;; Each skinned mesh gets its own skin, whose joints are the mesh's bones
;;;; (the joints with an inverse bind matrix that skin it) and any joint a
;;;; vertex follows with weight but that is no bone (the importer's fallback
;;;; for a vertex no bone moves), in the model's order, so parents come first.
;;;; A reader that imports the file back (Assimp does) makes one bone of each
;;;; skin joint, so the model's bone count is kept.  JOINTS_0 holds indices
;;;; into that skin's joints, not the model's: a slot of weight 0 holds 0, as
;;;; the specification asks.  A joint with no inverse bind matrix of its own
;;;; gets the inverse of its rest transform in model space, which leaves its
;;;; vertices where they are at rest.

(in-package #:player.model)

(defconstant +skin-joint-limit+ 65536
  "One more than the most joints a skin may have: JOINTS_0 is written as UNSIGNED_SHORT.")

(defun skin-joint-indices (mesh joint-count)
  "The model indices (ascending) of MESH's skin joints: its bones and the
joints a vertex follows with weight more than 0; JOINT-COUNT is the model's."
  (let ((used (make-array joint-count :element-type 'bit :initial-element 0))
        (joints (model-mesh-joints mesh))
        (weights (model-mesh-weights mesh)))
    (loop for joint across (model-mesh-bones mesh) do (setf (aref used joint) 1))
    (dotimes (slot (length joints))
      (when (plusp (aref weights slot)) (setf (aref used (aref joints slot)) 1)))
    (let ((indices (coerce (loop for joint below joint-count when (= 1 (aref used joint)) collect joint)
                           'index-vector)))
      (when (>= (length indices) +skin-joint-limit+)
        (write-fail "mesh ~S is skinned by ~:D joints, more than a glTF skin's ~:D"
                    (model-mesh-name mesh) (length indices) (1- +skin-joint-limit+)))
      indices)))

;;;# Inverse bind matrices of joints without one

(defun matrix-product (a b)
  "The product A B of two 4x4 matrices (16 doubles each, row-major)."
  (let ((product (make-array 16 :element-type 'double-float :initial-element 0d0)))
    (dotimes (r 4 product)
      (dotimes (c 4)
        (setf (aref product (+ (* 4 r) c))
              (loop for k below 4 sum (* (aref a (+ (* 4 r) k)) (aref b (+ (* 4 k) c)))))))))

(defun inverse-local-matrix (joint)
  "The inverse of JOINT's rest local transform T R S, as S^-1 R^T T^-1
(16 doubles, row-major); a MODEL-WRITE-ERROR when a scale is 0."
  (let ((matrix (make-array 16 :element-type 'double-float :initial-element 0d0))
        (scale (joint-scale joint))
        (translation (joint-translation joint)))
    (multiple-value-bind (x y z w) (unit-xyzw (joint-rotation joint) 0 (format nil "the rotation of joint ~S" (joint-name joint)))
      ;; R (row-major) of the unit quaternion, then row i of S^-1 R^T is column i of R over s_i.
      (let ((rotation (vector (- 1 (* 2 (+ (* y y) (* z z)))) (* 2 (- (* x y) (* w z))) (* 2 (+ (* x z) (* w y)))
                              (* 2 (+ (* x y) (* w z))) (- 1 (* 2 (+ (* x x) (* z z)))) (* 2 (- (* y z) (* w x)))
                              (* 2 (- (* x z) (* w y))) (* 2 (+ (* y z) (* w x))) (- 1 (* 2 (+ (* x x) (* y y)))))))
        (dotimes (i 3)
          (let ((s (aref scale i)))
            (unless (> (abs s) 1d-12)
              (write-fail "joint ~S has a scale of 0, so it has no inverse bind matrix" (joint-name joint)))
            (dotimes (j 3)
              (setf (aref matrix (+ (* 4 i) j)) (/ (aref rotation (+ (* 3 j) i)) s)))
            (setf (aref matrix (+ (* 4 i) 3))
                  (- (loop for j below 3 sum (* (aref matrix (+ (* 4 i) j)) (aref translation j)))))))
        (setf (aref matrix 15) 1d0)
        matrix))))

(defun rest-inverse-bind (joints index)
  "The inverse of joint INDEX's rest transform in model space (the product of
its ancestors' local transforms and its own), row-major: L_k^-1 ... L_root^-1."
  (loop with inverse = (inverse-local-matrix (aref joints index))
        for parent = (joint-parent (aref joints index)) then (joint-parent (aref joints parent))
        while parent
        do (setf inverse (matrix-product inverse (inverse-local-matrix (aref joints parent))))
        finally (return inverse)))

(defun inverse-bind-singles (joints skin-joints)
  "The inverse bind matrices of SKIN-JOINTS (indices into JOINTS), column-major, 16 floats each."
  (let ((floats (make-array (* 16 (length skin-joints)) :element-type 'single-float)))
    (loop for joint across skin-joints
          for start from 0 by 16
          do (let ((matrix (column-major (or (joint-inverse-bind (aref joints joint))
                                             (rest-inverse-bind joints joint)))))
               (replace floats (singles matrix (format nil "the inverse bind matrix of joint ~S"
                                                       (joint-name (aref joints joint))))
                        :start1 start)))
    floats))

(defun skin-tree-root (joints index)
  "The root of the joint tree holding joint INDEX."
  (loop for parent = (joint-parent (aref joints index))
        while parent do (setf index parent)
        finally (return index)))

(defun add-skin (buffer joints skin-joints)
  "The glTF skin of SKIN-JOINTS (indices into the model's JOINTS, which are
also their node indices), its inverse bind matrices stored in BUFFER; its
skeleton is the root of their tree when they share one."
  (let ((roots (remove-duplicates (map 'list (lambda (joint) (skin-tree-root joints joint)) skin-joints))))
    (json-object "inverseBindMatrices" (add-floats buffer (inverse-bind-singles joints skin-joints) 16
                                                   "inverse bind matrices")
                 "skeleton" (and (= 1 (length roots)) (first roots))
                 "joints" skin-joints)))

;;;# Each vertex's joints and weights

(defun skin-joint-slots (mesh skin-joints joint-count)
  "MESH's JOINTS_0: for each of its 4 slots a vertex, the index into
SKIN-JOINTS of the joint it names, or 0 where its weight is 0."
  (let ((skin-index (make-array joint-count :element-type 'fixnum :initial-element 0))
        (joints (model-mesh-joints mesh))
        (weights (model-mesh-weights mesh))
        (slots (make-array (length (model-mesh-joints mesh)) :element-type '(unsigned-byte 16))))
    (loop for joint across skin-joints for i from 0
          do (setf (aref skin-index joint) i))
    (dotimes (slot (length joints) slots)
      (setf (aref slots slot) (if (plusp (aref weights slot)) (aref skin-index (aref joints slot)) 0)))))

(defun skin-weight-singles (mesh)
  "MESH's WEIGHTS_0: each vertex's 4 weights divided by their sum, as
floats; a MODEL-WRITE-ERROR for a weight that is negative or not finite, or
a vertex whose weights are all 0."
  (let* ((weights (model-mesh-weights mesh))
         (floats (make-array (length weights) :element-type 'single-float)))
    (loop for base from 0 below (length weights) by 4
          do (let ((sum 0d0))
               (loop for slot from base below (+ base 4)
                     for weight = (aref weights slot)
                     do (unless (and (finite-double-p weight) (>= weight 0d0))
                          (write-fail "mesh ~S has a skin weight that is negative or not finite" (model-mesh-name mesh)))
                        (incf sum weight))
               (unless (plusp sum)
                 (write-fail "vertex ~D of mesh ~S has skin weights that are all 0" (floor base 4) (model-mesh-name mesh)))
               (loop for slot from base below (+ base 4)
                     do (setf (aref floats slot) (coerce (/ (aref weights slot) sum) 'single-float)))))
    floats))
