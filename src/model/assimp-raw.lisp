;;;; assimp-raw.lisp -- libassimp (Assimp 5.2.5, C API) bound raw: the library
;;;; loaded on first use, the %-named functions of cimport.h and the structs of
;;;; scene.h, mesh.h, anim.h and types.h with their offsets on x86-64 (checked
;;;; with offsetof against the installed headers; ai_real is float, and aiBone
;;;; has mArmature and mNode, as Debian builds it).  Nothing here checks
;;;; anything: import.lisp is the checked layer.

(in-package #:player.model)

;;;# The library

(defvar *assimp-library-names* '("libassimp.so.5")
  "Sonames tried, in order, for Assimp (the versioned name: the unversioned one
comes only with the -dev package).")

(defvar *assimp-library* nil
  "The CFFI library Assimp was loaded from, once loaded.")

(defun load-assimp-library (file)
  "Make sure libassimp is loaded, once.  Signals MODEL-LIBRARY-MISSING about
FILE, naming the Debian package libassimp5, when it is not installed."
  (or *assimp-library*
      (setf *assimp-library*
            (or (load-first-foreign-library *assimp-library-names*)
                (error 'model-library-missing
                       :file file :package "libassimp5"
                       :message (format nil "importing models needs Assimp, which is not installed: install the Debian package libassimp5 (tried ~{~A~^, ~})"
                                        *assimp-library-names*))))))

(defmacro with-assimp-traps-masked (&body body)
  "Run BODY with SBCL's floating-point traps masked: Assimp computes with
NaNs and infinities inside (degenerate normals, empty bounding boxes)."
  `(sb-int:with-float-traps-masked (:invalid :divide-by-zero :overflow :inexact)
     ,@body))

;;;# Constants (postprocess.h, scene.h, material.h, types.h)

(defconstant +ai-process-join-identical-vertices+ #x2 "aiProcess_JoinIdenticalVertices: one vertex for equal ones.")
(defconstant +ai-process-triangulate+ #x8 "aiProcess_Triangulate: polygons cut into triangles.")
(defconstant +ai-process-limit-bone-weights+ #x200 "aiProcess_LimitBoneWeights: at most 4 bones a vertex (AI_LMW_MAX_WEIGHTS).")
(defconstant +ai-process-validate-data-structure+ #x400 "aiProcess_ValidateDataStructure: Assimp checks its own scene.")
(defconstant +ai-process-sort-by-p-type+ #x8000 "aiProcess_SortByPType: one primitive type a mesh.")
(defconstant +ai-texture-type-diffuse+ 1 "aiTextureType_DIFFUSE.")
(defconstant +ai-texture-type-base-color+ 12 "glTF 2's base colour, where its diffuse map goes.")
(defconstant +ai-return-success+ 0 "aiReturn_SUCCESS.")
(defconstant +ai-string-capacity+ 1024 "MAXLEN: an aiString's bytes, its NUL included.")

;;;# Structs

(cffi:defcstruct (%ai-string :size 1028)
  (length :uint32 :offset 0)
  (data :char :count 1024 :offset 4))

(cffi:defcstruct (%ai-scene :size 1168)
  (flags :unsigned-int :offset 0)
  (root-node :pointer :offset 8)
  (num-meshes :unsigned-int :offset 16)
  (meshes :pointer :offset 24)
  (num-materials :unsigned-int :offset 32)
  (materials :pointer :offset 40)
  (num-animations :unsigned-int :offset 48)
  (animations :pointer :offset 56)
  (num-textures :unsigned-int :offset 64)
  (textures :pointer :offset 72))              ; aiTexture*[num-textures]

;;; An embedded texture: MHEIGHT 0 means DATA holds MWIDTH bytes of a
;;; compressed file (PNG, JPEG...; FORMAT-HINT its extension), else DATA holds
;;; MWIDTH x MHEIGHT aiTexels, 4 bytes each in the order B G R A.
(cffi:defcstruct (%ai-texture :size 1064)
  (width :unsigned-int :offset 0)
  (height :unsigned-int :offset 4)
  (format-hint :char :count 9 :offset 8)
  (data :pointer :offset 24)
  (filename (:struct %ai-string) :offset 32))

(cffi:defcstruct (%ai-node :size 1144)
  (name (:struct %ai-string) :offset 0)
  (transformation :float :count 16 :offset 1028) ; row-major a1..a4 b1.. c1.. d1..
  (parent :pointer :offset 1096)
  (num-children :unsigned-int :offset 1104)
  (children :pointer :offset 1112)
  (num-meshes :unsigned-int :offset 1120)
  (meshes :pointer :offset 1128))               ; unsigned int[num-meshes]

(cffi:defcstruct (%ai-mesh :size 1320)
  (primitive-types :unsigned-int :offset 0)
  (num-vertices :unsigned-int :offset 4)
  (num-faces :unsigned-int :offset 8)
  (vertices :pointer :offset 16)                ; aiVector3D[num-vertices]
  (normals :pointer :offset 24)
  (colors :pointer :count 8 :offset 48)         ; aiColor4D*[8]
  (texture-coords :pointer :count 8 :offset 112) ; aiVector3D*[8]
  (num-uv-components :unsigned-int :count 8 :offset 176)
  (faces :pointer :offset 208)                  ; aiFace[num-faces]
  (num-bones :unsigned-int :offset 216)
  (bones :pointer :offset 224)                  ; aiBone*[num-bones]
  (material-index :unsigned-int :offset 232)
  (name (:struct %ai-string) :offset 236)
  (num-anim-meshes :unsigned-int :offset 1264)
  (anim-meshes :pointer :offset 1272))          ; aiAnimMesh*[num-anim-meshes]

(cffi:defcstruct (%ai-face :size 16)
  (num-indices :unsigned-int :offset 0)
  (indices :pointer :offset 8))

(cffi:defcstruct (%ai-bone :size 1120)
  (name (:struct %ai-string) :offset 0)
  (num-weights :unsigned-int :offset 1028)
  (weights :pointer :offset 1048)               ; aiVertexWeight[num-weights]
  (offset-matrix :float :count 16 :offset 1056))

(cffi:defcstruct (%ai-vertex-weight :size 8)
  (vertex-id :unsigned-int :offset 0)
  (weight :float :offset 4))

(cffi:defcstruct (%ai-anim-mesh :size 1200)
  (name (:struct %ai-string) :offset 0)
  (vertices :pointer :offset 1032)              ; aiVector3D[num-vertices]: the target's positions
  (normals :pointer :offset 1040)               ; its normals, or NULL
  (num-vertices :unsigned-int :offset 1192)
  (weight :float :offset 1196))

(cffi:defcstruct (%ai-animation :size 1096)
  (name (:struct %ai-string) :offset 0)
  (duration :double :offset 1032)               ; in ticks
  (ticks-per-second :double :offset 1040)       ; 0 when the file does not say
  (num-channels :unsigned-int :offset 1048)
  (channels :pointer :offset 1056)              ; aiNodeAnim*[num-channels]
  (num-morph-mesh-channels :unsigned-int :offset 1080)
  (morph-mesh-channels :pointer :offset 1088))  ; aiMeshMorphAnim*[num-morph-mesh-channels]

;;; aiMeshMorphAnim: the node (or mesh) it animates, and its keys.
(cffi:defcstruct (%ai-mesh-morph-anim :size 1040)
  (name (:struct %ai-string) :offset 0)
  (num-keys :unsigned-int :offset 1028)
  (keys :pointer :offset 1032))                 ; aiMeshMorphKey[num-keys]

;;; aiMeshMorphKey: at TIME (ticks), the targets VALUES (indices) have WEIGHTS.
(cffi:defcstruct (%ai-mesh-morph-key :size 32)
  (time :double :offset 0)
  (values :pointer :offset 8)                   ; unsigned int[num-values-and-weights]
  (weights :pointer :offset 16)                 ; double[num-values-and-weights]
  (num-values-and-weights :unsigned-int :offset 24))

(cffi:defcstruct (%ai-node-anim :size 1080)
  (node-name (:struct %ai-string) :offset 0)
  (num-position-keys :unsigned-int :offset 1028)
  (position-keys :pointer :offset 1032)         ; aiVectorKey[]
  (num-rotation-keys :unsigned-int :offset 1040)
  (rotation-keys :pointer :offset 1048)         ; aiQuatKey[]
  (num-scaling-keys :unsigned-int :offset 1056)
  (scaling-keys :pointer :offset 1064))         ; aiVectorKey[]

;;; aiVectorKey and aiQuatKey: a double time (ticks), then 3 floats (x y z)
;;; or 4 (w x y z); 24 bytes each.
(cffi:defcstruct (%ai-key :size 24)
  (time :double :offset 0)
  (value :float :count 4 :offset 8))

;;;# Functions (cimport.h, material.h)

(cffi:defcfun ("aiImportFile" %ai-import-file) :pointer
  (file :string) (flags :unsigned-int))
(cffi:defcfun ("aiReleaseImport" %ai-release-import) :void (scene :pointer))
(cffi:defcfun ("aiGetErrorString" %ai-get-error-string) :pointer) ; read with C-MESSAGE
(cffi:defcfun ("aiDecomposeMatrix" %ai-decompose-matrix) :void
  (matrix :pointer) (scaling :pointer) (rotation :pointer) (position :pointer))
(cffi:defcfun ("aiGetMaterialTexture" %ai-get-material-texture) :int
  (material :pointer) (type :int) (index :unsigned-int) (path :pointer)
  (mapping :pointer) (uv-index :pointer) (blend :pointer) (op :pointer)
  (map-mode :pointer) (flags :pointer))
