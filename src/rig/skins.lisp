;;;; skins.lisp -- linear-blend skinning of an imported mesh on its skeleton.
;;;; A SKIN lists the joints that move a mesh (its palette) and, for each, the
;;;; matrix B taking the mesh's vertices to that joint's rest frame in Player's
;;;; space (offsets from the joint's centre).  At a pose, palette entry k moves
;;;; a vertex by T_j B_k, T_j being the joint's world transform from
;;;; POSE-WORLD-TRANSFORMS; a vertex is the weighted sum over its (up to) four
;;;; entries.  The renderer's vertex shader computes the same sum; this file
;;;; is the CPU's version, its fallback and its reference.

(in-package #:player.rig)

(deftype palette-slots () "Four palette slots per vertex." '(simple-array (unsigned-byte 16) (*)))
(deftype skin-weights () "Four weights per vertex, summing to 1." '(simple-array single-float (*)))

(defstruct (mesh-skin (:conc-name skin-) (:constructor %make-skin))
  "How one MESH of a model follows the skeleton: PALETTE-JOINTS, the skeleton
joint index of each palette entry; PALETTE, each entry's MAT4 B (mesh space
to the joint's rest frame, Player's space); SLOTS and WEIGHTS, four per
vertex (palette entries and their weights)."
  mesh
  (palette-joints (make-array 0 :element-type 'fixnum) :type (simple-array fixnum (*)))
  (palette #() :type simple-vector)
  (slots nil :type palette-slots)
  (weights nil :type skin-weights)
  ;; Its mesh's morph targets: (POSE-INDEX . DELTAS) each, the pose channel
  ;; holding the target's weight and its position deltas (3 per vertex).
  (morphs '() :type list))

;;;# Building

(defun mesh-palette-joints (mesh)
  "The model joints that move MESH, in first-use order: those weighing a
vertex, or the joint its node hangs from for an unskinned mesh."
  (if (model-mesh-joints mesh)
      (let ((seen '()))
        (loop for joint across (model-mesh-joints mesh)
              for weight across (model-mesh-weights mesh)
              when (and (plusp weight) (not (member joint seen)))
                do (push joint seen))
        (nreverse seen))
      (list (model-mesh-holder mesh))))

(defun mesh-bind-matrices (model mesh joints worlds)
  "For each model joint of JOINTS (MESH's palette), the MAT4 E taking MESH's
vertices to the scene's space at rest: the joint's rest world times its
inverse bind for one of the mesh's bones, else the mesh's node transform
(a vertex that follows a joint it is not bound to, an unskinned mesh)."
  (let ((node (if (model-mesh-transform mesh) (row-major-matrix (model-mesh-transform mesh)) (identity-transform))))
    (mapcar (lambda (joint)
              (let ((inverse-bind (and (find joint (model-mesh-bones mesh))
                                       (joint-inverse-bind (svref (model-joints model) joint)))))
                (if inverse-bind
                    (affine* (svref worlds joint) (row-major-matrix inverse-bind))
                    node)))
            joints)))

(defun mesh-slots-and-weights (mesh joints)
  "MESH's four palette slots and weights per vertex, JOINTS being its palette's model joints."
  (let* ((count (model-mesh-vertex-count mesh))
         (slots (make-array (* 4 count) :element-type '(unsigned-byte 16) :initial-element 0))
         (weights (make-array (* 4 count) :element-type 'single-float :initial-element 0f0)))
    (if (model-mesh-joints mesh)
        (let ((slot-of (make-hash-table)))
          (loop for joint in joints for k from 0 do (setf (gethash joint slot-of) k))
          (dotimes (i (* 4 count))
            (let ((weight (aref (model-mesh-weights mesh) i)))
              (when (plusp weight)
                (setf (aref slots i) (gethash (aref (model-mesh-joints mesh) i) slot-of)
                      (aref weights i) (float weight 1f0))))))
        (dotimes (v count) (setf (aref weights (* 4 v)) 1f0)))
    (values slots weights)))

(defun bind-rest-points (mesh binds slots weights)
  "MESH's vertices at rest in the model's space (the weighted sum of the
BINDS of each vertex's SLOTS), as a list of vec3s."
  (let ((positions (model-mesh-positions mesh)))
    (loop for v below (model-mesh-vertex-count mesh)
          collect (let ((sum (vec3)))
                    (dotimes (k 4 sum)
                      (let ((weight (aref weights (+ (* 4 v) k))))
                        (when (plusp weight)
                          (setf sum (v+ sum (v* (affine-point (svref binds (aref slots (+ (* 4 v) k)))
                                                              (aref positions (* 3 v))
                                                              (aref positions (+ (* 3 v) 1))
                                                              (aref positions (+ (* 3 v) 2)))
                                                (float weight 1d0)))))))))))

;;;# Posing

(defun skin-palette-matrices (skin transforms &optional (result (make-array (length (skin-palette skin)) :initial-element nil)))
  "The palette of SKIN at a pose: for each entry k, T_j B_k, T_j the world
transform of its joint in TRANSFORMS (a body's, from POSE-WORLD-TRANSFORMS).
Stored into RESULT (a simple-vector of MAT4s, or NIL slots filled anew)."
  (loop for joint across (skin-palette-joints skin)
        for bind across (skin-palette skin)
        for k from 0
        do (let ((target (or (svref result k) (identity-transform))))
             (transform-compose (svref transforms joint) bind target)
             (setf (svref result k) target)))
  result)

(defun morphed-positions (skin pose)
  "SKIN's mesh positions with its morph targets added at their weights in POSE
(a fresh vector), or the mesh's own positions when no weight is above 0."
  (let ((positions (model-mesh-positions (skin-mesh skin)))
        (active (and pose (remove-if-not (lambda (morph) (> (aref pose (car morph)) 0d0))
                                         (skin-morphs skin)))))
    (if (null active)
        positions
        (let ((morphed (copy-seq positions)))
          (declare (type (simple-array single-float (*)) morphed))
          (loop for (index . deltas) in active
                for weight = (float (aref pose index) 1f0)
                do (let ((deltas deltas))
                     (declare (type (simple-array single-float (*)) deltas))
                     (dotimes (k (length morphed))
                       (incf (aref morphed k) (* weight (aref deltas k))))))
          morphed))))

(defun skin-vertices (skin palette positions-out normals-out &optional pose)
  "Write SKIN's mesh vertices posed by PALETTE (from SKIN-PALETTE-MATRICES)
into POSITIONS-OUT and NORMALS-OUT (single-float vectors, 3 per vertex;
NORMALS-OUT may be NIL): linear-blend skinning, normals by the blended
linear part, renormalised.  With POSE (the body's pose), the mesh's morph
targets are first added at their weights.  Returns POSITIONS-OUT."
  (declare (type simple-vector palette) (optimize (speed 3) (safety 1)))
  (let* ((mesh (skin-mesh skin))
         (positions (morphed-positions skin pose))
         (normals (model-mesh-normals mesh))
         (slots (skin-slots skin))
         (weights (skin-weights skin)))
    (declare (type (simple-array single-float (*)) positions positions-out)
             (type palette-slots slots) (type skin-weights weights))
    (let ((blend (make-array 12 :element-type 'double-float)))
      (declare (dynamic-extent blend))
      (dotimes (v (floor (length positions) 3))
        (fill blend 0d0)
        (dotimes (k 4)
          (let ((weight (float (aref weights (+ (* 4 v) k)) 1d0)))
            (when (> weight 0d0)
              (let ((m (svref palette (aref slots (+ (* 4 v) k)))))
                (declare (type mat4 m))
                (dotimes (row 3)
                  (dotimes (column 4)
                    (incf (aref blend (+ (* 4 row) column)) (* weight (aref m row column)))))))))
        (let ((x (float (aref positions (* 3 v)) 1d0))
              (y (float (aref positions (+ (* 3 v) 1)) 1d0))
              (z (float (aref positions (+ (* 3 v) 2)) 1d0)))
          (dotimes (row 3)
            (setf (aref positions-out (+ (* 3 v) row))
                  (float (+ (* (aref blend (* 4 row)) x) (* (aref blend (+ (* 4 row) 1)) y)
                            (* (aref blend (+ (* 4 row) 2)) z) (aref blend (+ (* 4 row) 3)))
                         1f0))))
        (when (and normals normals-out)
          (let ((normals normals) (normals-out normals-out))
            (declare (type (simple-array single-float (*)) normals normals-out))
            (let* ((x (float (aref normals (* 3 v)) 1d0))
                   (y (float (aref normals (+ (* 3 v) 1)) 1d0))
                   (z (float (aref normals (+ (* 3 v) 2)) 1d0))
                   (nx (+ (* (aref blend 0) x) (* (aref blend 1) y) (* (aref blend 2) z)))
                   (ny (+ (* (aref blend 4) x) (* (aref blend 5) y) (* (aref blend 6) z)))
                   (nz (+ (* (aref blend 8) x) (* (aref blend 9) y) (* (aref blend 10) z)))
                   (length (sqrt (+ (* nx nx) (* ny ny) (* nz nz))))
                   (scale (if (> length 1d-12) (/ length) 0d0)))
              (setf (aref normals-out (* 3 v)) (float (* nx scale) 1f0)
                    (aref normals-out (+ (* 3 v) 1)) (float (* ny scale) 1f0)
                    (aref normals-out (+ (* 3 v) 2)) (float (* nz scale) 1f0))))))))
  positions-out)

(defun skin-rest-positions (skin transforms)
  "SKIN's vertices posed by the body TRANSFORMS, as a fresh single-float vector (3 per vertex)."
  (skin-vertices skin (skin-palette-matrices skin transforms)
                 (make-array (length (model-mesh-positions (skin-mesh skin))) :element-type 'single-float)
                 nil))
