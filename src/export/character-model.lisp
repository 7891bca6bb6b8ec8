;;;; character-model.lisp -- a Player body as a MODEL the glTF writer takes:
;;;; one model joint per skeleton joint, and the meshes the body is drawn
;;;; with, skinned to those joints.
;;;;
;;;; The frames.  A Player joint's rest frame has the world's axes, its origin
;;;; at the joint's centre (PLAYER.BODY's convention), so each model joint
;;;; rests at its centre minus its parent's, unrotated, and its inverse bind
;;;; is a translation by minus its centre.  A mesh is written at rest in the
;;;; body's space; a pose then moves a vertex by the joint's world transform
;;;; times that inverse bind, which is exactly how Player poses it.

(in-package #:player.export)

(defun export-joint-name (skeleton joint)
  "The name JOINT of SKELETON takes in the file: an imported model's joints
keep their own (so a round trip meets the same names), Player's own are
written lower-case, as the BVH writer writes them."
  (let ((name (symbol-name (body-joint-name joint))))
    (if (skeleton-rig skeleton) name (string-downcase name))))

(defun doubles (&rest values)
  "A fresh double-float vector of VALUES."
  (map '(simple-array double-float (*)) (lambda (x) (float x 1d0)) values))

(defun inverse-bind (center)
  "The inverse bind of a joint resting at CENTER: the translation by -CENTER,
16 doubles row-major (the model layer's convention)."
  (doubles 1 0 0 (- (svref center 0))
           0 1 0 (- (svref center 1))
           0 0 1 (- (svref center 2))
           0 0 0 1))

(defun skeleton-model-joints (skeleton &key (first 0) (prefix ""))
  "The MODEL-JOINTs of SKELETON, in its joint order: named by
EXPORT-JOINT-NAME after PREFIX, their parents' indices counted from FIRST
\(where the first of them will stand in the model's joints), resting at
their centres relative to their parents'."
  (map 'list (lambda (joint)
               (let ((parent (body-joint-parent joint))
                     (center (body-joint-center joint)))
                 (make-joint (concatenate 'string prefix (export-joint-name skeleton joint))
                             (and parent (+ first (body-joint-index parent)))
                             (map '(simple-array double-float (*))
                                  (lambda (c p) (float (- c p) 1d0))
                                  center (if parent (body-joint-center parent) #(0 0 0)))
                             (doubles 1 0 0 0)
                             (doubles 1 1 1)
                             (inverse-bind (body-joint-center joint)))))
       (skeleton-joints skeleton)))

(defun index-vector (length)
  "A fresh vector of LENGTH 32-bit indices, all 0."
  (make-array length :element-type '(unsigned-byte 32) :initial-element 0))

;;;# Player's own bodies: the render layer's rigid parts

(defun rgba-colours (rgb)
  "RGB colours (3 floats a vertex) as RGBA, opaque."
  (let ((rgba (make-array (* 4 (floor (length rgb) 3)) :element-type 'single-float :initial-element 1f0)))
    (dotimes (v (floor (length rgb) 3) rgba)
      (replace rgba rgb :start1 (* 4 v) :start2 (* 3 v) :end2 (* 3 (1+ v))))))

(defun body-parts-mesh (skeleton name first)
  "SKELETON drawn as the renderer draws it (MAKE-BODY-MESH), as one MODEL-MESH
named NAME: each part's vertices at its joint's centre plus their offsets,
weighted 1 to that joint (model index FIRST + its skeleton index)."
  (let* ((body-mesh (make-body-mesh skeleton))
         (positions (copy-seq (body-mesh-positions body-mesh)))
         (count (floor (length positions) 3))
         (joints (index-vector (* 4 count)))
         (weights (make-array (* 4 count) :element-type 'double-float :initial-element 0d0))
         (used '()))
    (loop for joint across (body-mesh-joints body-mesh)
          for start across (body-mesh-starts body-mesh)
          for end across (body-mesh-ends body-mesh)
          for center = (body-joint-center (svref (skeleton-joints skeleton) joint))
          do (pushnew (+ first joint) used)
             (loop for v from start below end
                   do (dotimes (axis 3)
                        (incf (aref positions (+ (* 3 v) axis)) (float (svref center axis) 1f0)))
                      (setf (aref joints (* 4 v)) (+ first joint)
                            (aref weights (* 4 v)) 1d0)))
    (make-model-mesh :name name :positions positions
                     :normals (copy-seq (body-mesh-normals body-mesh))
                     :colours (rgba-colours (body-mesh-colours body-mesh))
                     :triangles (coerce (body-mesh-indices body-mesh) '(simple-array (unsigned-byte 32) (*)))
                     :joints joints :weights weights
                     :bones (coerce (sort used #'<) '(simple-array (unsigned-byte 32) (*)))
                     :holder first)))

;;;# Imported models: their own meshes at rest in Player's space

(defun skin-model-morphs (skin skeleton palette rest)
  "SKIN's morph targets at rest in Player's space, as MORPH-TARGETs named as
SKELETON names them: each target's deltas are where the rest pose with that
target alone at weight 1 puts the vertices (skinned by PALETTE, the rest
pose's) less REST, where the rest pose puts them.  Skinning is affine per
vertex, so a reader adding the deltas at any weight meets Player's vertices."
  (let ((dofs (skeleton-dof-count skeleton)))
    (loop for (index . nil) in (skin-morphs skin)
          collect (let ((pose (make-pose skeleton))
                        (moved (make-array (length rest) :element-type 'single-float)))
                    (setf (aref pose index) 1d0)
                    (skin-vertices skin palette moved nil pose)
                    (dotimes (k (length moved))
                      (decf (aref moved k) (aref rest k)))
                    (make-morph-target (svref (skeleton-morphs skeleton) (- index dofs)) moved)))))

(defun skin-model-mesh (skin skeleton transforms first)
  "SKIN's mesh at rest in Player's space (posed by the rest TRANSFORMS of
SKELETON), with its morph targets, its vertices weighted to the skeleton's
joints (model index FIRST + theirs)."
  (let* ((mesh (skin-mesh skin))
         (count (model-mesh-vertex-count mesh))
         (palette (skin-palette-matrices skin transforms))
         (positions (make-array (* 3 count) :element-type 'single-float))
         (normals (and (model-mesh-normals mesh) (make-array (* 3 count) :element-type 'single-float)))
         (joints (index-vector (* 4 count)))
         (weights (make-array (* 4 count) :element-type 'double-float :initial-element 0d0)))
    (skin-vertices skin palette positions normals)
    (dotimes (i (* 4 count))
      (let ((weight (aref (skin-weights skin) i)))
        (when (plusp weight)
          (setf (aref joints i) (+ first (aref (skin-palette-joints skin) (aref (skin-slots skin) i)))
                (aref weights i) (float weight 1d0)))))
    (let ((morphs (skin-model-morphs skin skeleton palette positions)))
      (make-model-mesh :name (model-mesh-name mesh) :positions positions :normals normals
                       :uvs (model-mesh-uvs mesh) :colours (model-mesh-colours mesh)
                       :triangles (model-mesh-triangles mesh) :joints joints :weights weights
                       :bones (map '(simple-array (unsigned-byte 32) (*)) (lambda (j) (+ first j))
                                   (remove-duplicates (skin-palette-joints skin)))
                       :holder (+ first (aref (skin-palette-joints skin) 0))
                       :texture (model-mesh-texture mesh)
                       :embedded-texture (model-mesh-embedded-texture mesh)
                       :morph-targets (mapcar #'morph-target-name morphs) :morphs morphs))))

(defun skeleton-model-meshes (skeleton name first)
  "The MODEL-MESHes that draw SKELETON (NAME names a mesh of Player's own
bodies), skinned to its joints counted from FIRST: an imported model's own
meshes when it has any, else the renderer's rigid parts."
  (let ((rig (skeleton-rig skeleton)))
    (if (and rig (rig-skins rig))
        (let ((rest (pose-world-transforms skeleton (make-pose skeleton))))
          (mapcar (lambda (skin) (skin-model-mesh skin skeleton rest first)) (rig-skins rig)))
        (list (body-parts-mesh skeleton name first)))))

(defun character-model (skeleton &key (file ""))
  "A MODEL of SKELETON at rest, without animations: its joints
\(SKELETON-MODEL-JOINTS) and the meshes it is drawn with
\(SKELETON-MODEL-MESHES).  FILE names the model."
  (check-argument 'character-model 'skeleton skeleton #'skeleton-p "a skeleton")
  (make-model file (skeleton-model-meshes skeleton (string-downcase (string (skeleton-name skeleton))) 0)
              (coerce (skeleton-model-joints skeleton) 'simple-vector) '()))
