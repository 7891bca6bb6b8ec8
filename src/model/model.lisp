;;;; model.lisp -- an imported model as Lisp data: meshes with their skins,
;;;; the joint tree, animation clips and morph target names.  Everything is
;;;; copied out of Assimp's scene before it is released; no foreign pointer
;;;; survives an import.  Geometry is single-float (what GL draws), skin
;;;; weights, transforms and keys double-float.

(in-package #:player.model)

(deftype float-vector () "A flat vector of single-floats (3 per position, 2 per UV...)." '(simple-array single-float (*)))
(deftype double-vector () "A flat vector of double-floats." '(simple-array double-float (*)))
(deftype index-vector () "A flat vector of vertex or joint indices." '(simple-array (unsigned-byte 32) (*)))

(defstruct (embedded-texture (:constructor make-embedded-texture (name octets image)) (:predicate nil) (:copier nil))
  "A texture embedded in a model file: its NAME, Assimp's \"*N\"; OCTETS, the
bytes of the image file it is (PNG, JPEG...), or NIL for one the file holds
as raw texels; IMAGE, what decoding it gave at import: the IMAGE (RGBA), or
the IMAGE-ERROR saying why not."
  (name "" :type string)
  (octets nil :type (or null (simple-array (unsigned-byte 8) (*))))
  (image nil))

(defstruct (morph-target (:constructor make-morph-target (name deltas)))
  "One morph target of a mesh: its NAME and its position DELTAS from the
mesh (a FLOAT-VECTOR, 3 per vertex)."
  (name "" :type string)
  (deltas nil :type float-vector))

(defstruct (morph-channel (:constructor make-morph-channel (node meshes times weights target-count)))
  "The keys of the morph weights of the meshes a node holds in an animation:
NODE, the node's (or mesh's) name; MESHES, the indices of the model's meshes
it drives; TIMES in seconds; WEIGHTS, TARGET-COUNT per key (a target a key
does not name weighs 0)."
  (node "" :type string)
  (meshes '() :type list)
  (times nil :type double-vector)
  (weights nil :type double-vector)
  (target-count 0 :type (integer 0)))

(defstruct model-mesh
  "One mesh: its NAME; POSITIONS and NORMALS (3 per vertex), UVS (the first
UV set, 2 per vertex) and COLOURS (the first colour set, RGBA), each NIL when
absent; TRIANGLES (3 vertex indices each); for a skinned mesh, JOINTS and
WEIGHTS (4 per vertex: joint indices into the model's joints and weights
summing to 1, unused slots weight 0), else NIL; BONES, the joint indices of
the mesh's own bones; HOLDER, the joint its node is or hangs below (what an
unskinned vertex follows); TRANSFORM, its node's world matrix at rest (16
doubles, row-major, the scene's space: where its vertices are for an unskinned
mesh); TEXTURE, its diffuse texture's path resolved against the
model's folder (or \"*N\" for a texture embedded in the file, then
EMBEDDED-TEXTURE is that texture, the model's too), or NIL;
MORPH-TARGETS, the names of its morph targets, and MORPHS, the MORPH-TARGETs
themselves (names and position deltas)."
  (name "" :type string)
  (positions nil :type float-vector)
  (normals nil :type (or null float-vector))
  (uvs nil :type (or null float-vector))
  (colours nil :type (or null float-vector))
  (triangles nil :type index-vector)
  (joints nil :type (or null index-vector))
  (weights nil :type (or null double-vector))
  (bones nil :type index-vector)
  (holder 0 :type (integer 0))
  (transform nil :type (or null double-vector))
  (texture nil :type (or null string))
  (embedded-texture nil :type (or null embedded-texture))
  (morph-targets '() :type list)
  (morphs '() :type list))

(defun model-mesh-vertex-count (mesh)
  "How many vertices MESH has."
  (floor (length (model-mesh-positions mesh)) 3))

(defun model-mesh-triangle-count (mesh)
  "How many triangles MESH has."
  (floor (length (model-mesh-triangles mesh)) 3))

(defstruct (model-joint (:conc-name joint-) (:constructor make-joint (name parent translation rotation scale inverse-bind)))
  "A joint of the skeleton: its NAME (the node's), the index of its PARENT
joint (NIL for the root), its rest local transform as TRANSLATION (x y z),
ROTATION (a unit quaternion w x y z) and SCALE (x y z), and for a bone its
INVERSE-BIND matrix (16 doubles, row-major as Assimp writes it: model space to
the bone's space), else NIL."
  (name "" :type string)
  (parent nil :type (or null (integer 0)))
  (translation nil :type double-vector)
  (rotation nil :type double-vector)
  (scale nil :type double-vector)
  (inverse-bind nil :type (or null double-vector)))

(defstruct (model-channel (:conc-name channel-) (:constructor make-channel (joint position-times positions rotation-times rotations
                                                scale-times scales)))
  "One joint's keys in a clip: JOINT, its index; POSITION-TIMES, ROTATION-TIMES
and SCALE-TIMES in seconds from the clip's start, with POSITIONS (3 per key),
ROTATIONS (w x y z per key) and SCALES (3 per key)."
  (joint 0 :type (integer 0))
  (position-times nil :type double-vector)
  (positions nil :type double-vector)
  (rotation-times nil :type double-vector)
  (rotations nil :type double-vector)
  (scale-times nil :type double-vector)
  (scales nil :type double-vector))

(defstruct (model-animation (:constructor make-model-animation (name duration channels &optional morph-channels)))
  "An animation clip: its NAME (\"\" when the file gives none), its DURATION in
seconds, its CHANNELS, one per animated joint, and its MORPH-CHANNELS, the
keys of morph target weights (see morphs.lisp)."
  (name "" :type string)
  (duration 0d0 :type double-float)
  (channels '() :type list)
  (morph-channels '() :type list))

(defstruct (model (:constructor make-model (file meshes joints animations &optional (embedded-textures #()))))
  "A model imported from FILE (its truename, a string): its MESHES, its JOINTS
(a vector, parents before children; the skeleton is the nodes that are bones
or are animated, and their ancestors up to the scene's root), its
ANIMATIONS and its EMBEDDED-TEXTURES (a vector of EMBEDDED-TEXTURE, the
Nth being the texture its meshes call \"*N\")."
  (file "" :type string)
  (meshes '() :type list)
  (joints #() :type simple-vector)
  (animations '() :type list)
  (embedded-textures #() :type simple-vector))

(defun model-vertex-count (model)
  "How many vertices MODEL's meshes have together."
  (reduce #'+ (model-meshes model) :key #'model-mesh-vertex-count))

(defun model-triangle-count (model)
  "How many triangles MODEL's meshes have together."
  (reduce #'+ (model-meshes model) :key #'model-mesh-triangle-count))

(defun model-bone-count (model)
  "How many bones MODEL's meshes have together (a joint that skins two meshes counts twice, as Assimp counts)."
  (reduce #'+ (model-meshes model) :key (lambda (mesh) (length (model-mesh-bones mesh)))))

(defun model-textures (model)
  "The distinct texture paths MODEL's meshes use, in order."
  (remove-duplicates (remove nil (mapcar #'model-mesh-texture (model-meshes model)))
                     :test #'string= :from-end t))

(defun model-morph-targets (model)
  "The distinct morph target names of MODEL's meshes, in order."
  (remove-duplicates (mapcan (lambda (mesh) (copy-list (model-mesh-morph-targets mesh))) (model-meshes model))
                     :test #'string= :from-end t))

(defun find-model-joint (model name)
  "The index of MODEL's joint called NAME, or NIL."
  (position name (model-joints model) :key #'joint-name :test #'string=))
