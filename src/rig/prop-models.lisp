;;;; prop-models.lisp -- a model drawn rigidly as a prop: a cup, a chair, a
;;;; lamp brought from a file (typically one with no joints, which cannot be a
;;;; character).  Each of its meshes becomes a MESH-SKIN of one palette entry,
;;;; weighing every vertex 1 to the prop's own frame, so the renderer's and the
;;;; export's skinned paths draw it with no code of their own: the prop's
;;;; world transform is the palette's one joint.

(in-package #:player.rig)

(defstruct (prop-model (:constructor %make-prop-model (model placement scale skins)))
  "What a prop keeps of the MODEL it draws: PLACEMENT, the MAT4 from the
model's space to the prop's frame (turned so its up axis is +y, scaled,
standing on y = 0 and centred on x = z = 0), its SCALE, and SKINS, one
MESH-SKIN per mesh, each of one palette entry (joint 0: the prop)."
  model placement (scale 1d0 :type double-float) (skins '() :type list))

(defmethod print-object ((prop prop-model) stream)
  (print-unreadable-object (prop stream :type t)
    (format stream "~A, ~D mesh~:*~[es~;~:;es~]" (file-namestring (model-file (prop-model-model prop)))
            (length (prop-model-skins prop)))))

(defclass model-prop (scene-object)
  ((prop-model :initarg :prop-model :reader model-prop-model
               :documentation "The PROP-MODEL it is drawn as."))
  (:default-initargs :kind :prop)
  (:documentation "A prop of a scene drawn as an imported model's meshes, rigidly
at its place: it moves, turns, hangs from a joint and is animated as any prop."))

(defun mesh-node-matrix (mesh)
  "MESH's node transform at rest (the model's space), as a MAT4."
  (if (model-mesh-transform mesh) (row-major-matrix (model-mesh-transform mesh)) (identity-transform)))

(defun mesh-rest-points (mesh)
  "MESH's vertices in the model's space (through its node transform), as VEC3s."
  (let ((node (mesh-node-matrix mesh))
        (positions (model-mesh-positions mesh)))
    (loop for i below (model-mesh-vertex-count mesh)
          collect (affine-point node (aref positions (* 3 i)) (aref positions (+ 1 (* 3 i)))
                                (aref positions (+ 2 (* 3 i)))))))

(defun rigid-skin (mesh matrix)
  "The MESH-SKIN moving all of MESH by the one palette entry MATRIX (mesh
space to the prop's frame), on joint 0."
  (let ((count (model-mesh-vertex-count mesh)))
    (%make-skin :mesh mesh
                :palette-joints (make-array 1 :element-type 'fixnum :initial-element 0)
                :palette (vector matrix)
                :slots (make-array (* 4 count) :element-type '(unsigned-byte 16) :initial-element 0)
                :weights (let ((weights (make-array (* 4 count) :element-type 'single-float :initial-element 0f0)))
                           (loop for i from 0 below (length weights) by 4 do (setf (aref weights i) 1f0))
                           weights))))

(defun make-prop-model (model &key height scale (up :y))
  "The PROP-MODEL drawing MODEL's meshes at rest as one rigid prop: UP (:y
or :z) is the model's up axis, HEIGHT (metres) scales it to that height, or
SCALE multiplies the file's units (default: metres).  Signals RIG-ERROR for
options that do not fit, or a model with no vertices to draw."
  (check-argument 'make-prop-model 'model model #'model-p "a model (from import-model)")
  (check-model-skeleton-options height scale up)
  (let ((points (mapcan #'mesh-rest-points (model-meshes model))))
    (unless points
      (rig-fail (model-file model) "~A has no vertices to draw as a prop" (file-namestring (model-file model))))
    (multiple-value-bind (placement s) (model-placement points up height scale)
      (%make-prop-model model placement s
                        (mapcar (lambda (mesh) (rigid-skin mesh (affine* placement (mesh-node-matrix mesh))))
                                (model-meshes model))))))
