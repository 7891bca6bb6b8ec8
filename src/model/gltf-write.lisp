;;;; gltf-write.lisp -- WRITE-GLTF: a MODEL as a glTF 2.0 file, .glb or
;;;; .gltf by the file's name (containers in gltf-files.lisp).
;;;;
;;;; The document, in the order a reader meets it:
;;;;   nodes     first one per joint, same index, with its rest translation,
;;;;             rotation (x y z w) and scale and its children; then one per
;;;;             mesh, at the scene's root with no transform (a skinned mesh's
;;;;             own transform is ignored by the specification; and the model
;;;;             keeps none for a mesh, whose vertices are in model space), named
;;;;             after the mesh but never like a joint, which a reader
;;;;             matching bones by name would take it for;
;;;;   scene     the root joints, then the mesh nodes;
;;;;   meshes    one primitive of triangles each (points when it has none):
;;;;             POSITION with its min and max, NORMAL, TEXCOORD_0 (V flipped:
;;;;             glTF's origin is the top left, Assimp's the bottom left),
;;;;             COLOR_0, JOINTS_0 and WEIGHTS_0 when skinned, indices;
;;;;             morph targets (gltf-morphs.lisp);
;;;;   skins     gltf-skins.lisp; materials gltf-materials.lisp;
;;;;   animations gltf-animations.lisp;
;;;;   accessors, bufferViews, one buffer (gltf-buffer.lisp).
;;;; Everything is built in memory and checked before the file is touched.

(in-package #:player.model)

;;;# Nodes

(defun joint-children (joints)
  "For each of JOINTS, the indices of its children, in order."
  (let ((children (make-array (length joints) :initial-element '())))
    (loop for index from (1- (length joints)) downto 0
          for parent = (joint-parent (aref joints index))
          when parent do (push index (aref children parent)))
    children))

(defun joint-node (joint children)
  "The glTF node of JOINT with CHILDREN (node indices)."
  (let ((name (joint-name joint)))
    (flet ((what (part) (format nil "the ~A of joint ~S" part name)))
      (json-object "name" (and (string/= name "") name)
                   "children" children
                   "translation" (joint-translation joint)
                   "rotation" (node-rotation (joint-rotation joint) (what "rotation"))
                   "scale" (joint-scale joint)))))

(defun unique-name (name taken)
  "NAME, or NAME with \" mesh\" and then a number added, so that it is not in
the EQUAL hash table TAKEN; recorded there."
  (let ((unique (loop for candidate = name then (format nil "~A mesh~@[ ~D~]" name (and (> n 1) n))
                      for n from 1
                      unless (gethash candidate taken) return candidate)))
    (setf (gethash unique taken) t)
    unique))

(defun mesh-node-names (model)
  "For each of MODEL's meshes, the name of its node: the mesh's (\"mesh\" when
it has none), made unlike every joint's name and every other mesh node's."
  (let ((taken (make-hash-table :test 'equal)))
    (loop for joint across (model-joints model) do (setf (gethash (joint-name joint) taken) t))
    (mapcar (lambda (mesh)
              (unique-name (if (string= (model-mesh-name mesh) "") "mesh" (model-mesh-name mesh)) taken))
            (model-meshes model))))

;;;# Meshes

(defun uv-singles (uvs)
  "UVS (u v per vertex, origin at the bottom left) as glTF's, origin at the top left: v becomes 1 - v."
  (let ((flipped (copy-seq uvs)))
    (loop for i from 1 below (length flipped) by 2
          do (setf (aref flipped i) (- 1.0 (aref flipped i))))
    flipped))

(defun unit-normals (normals what)
  "NORMALS made unit length, as glTF asks; one of length 0 becomes (0 0 1).
A MODEL-WRITE-ERROR naming WHAT when one is not finite."
  (let ((unit (copy-seq normals)))
    (unless (every #'finite-single-p unit)
      (write-fail "~A hold a value that is not finite (NaN or infinite)" what))
    (loop for i from 0 below (length unit) by 3
          do (let ((length (sqrt (+ (expt (aref unit i) 2) (expt (aref unit (+ i 1)) 2) (expt (aref unit (+ i 2)) 2)))))
               (if (> length 1e-20)
                   (loop for k from i below (+ i 3) do (setf (aref unit k) (/ (aref unit k) length)))
                   (setf (aref unit i) 0.0 (aref unit (+ i 1)) 0.0 (aref unit (+ i 2)) 1.0))))
    unit))

(defun mesh-attributes (buffer mesh skin-joints joint-count)
  "The attributes object of MESH's primitive, its data stored in BUFFER;
SKIN-JOINTS are its skin's joints (NIL when it is not skinned)."
  (let ((name (model-mesh-name mesh)))
    (flet ((what (part) (format nil "the ~A of mesh ~S" part name)))
      (json-object
       "POSITION" (add-floats buffer (model-mesh-positions mesh) 3 (what "positions")
                              :target +gltf-array-buffer+ :bounds t)
       "NORMAL" (and (model-mesh-normals mesh)
                     (add-floats buffer (unit-normals (model-mesh-normals mesh) (what "normals")) 3 (what "normals")
                                 :target +gltf-array-buffer+))
       "TEXCOORD_0" (and (model-mesh-uvs mesh)
                         (add-floats buffer (uv-singles (model-mesh-uvs mesh)) 2 (what "UVs") :target +gltf-array-buffer+))
       "COLOR_0" (and (model-mesh-colours mesh)
                      (add-floats buffer (model-mesh-colours mesh) 4 (what "colours") :target +gltf-array-buffer+))
       "JOINTS_0" (and skin-joints
                       (add-joint-indices buffer (skin-joint-slots mesh skin-joints joint-count)))
       "WEIGHTS_0" (and skin-joints
                        (add-floats buffer (skin-weight-singles mesh) 4 (what "skin weights")
                                    :target +gltf-array-buffer+))))))

(defun mesh-object (buffer mesh material skin-joints joint-count)
  "MESH as a glTF mesh of one primitive with MATERIAL (an index), its data
stored in BUFFER; triangles, or points when it has no triangle."
  (let ((triangles (plusp (length (model-mesh-triangles mesh)))))
    (apply #'json-object
           "name" (and (string/= (model-mesh-name mesh) "") (model-mesh-name mesh))
           "primitives" (list (json-object "attributes" (mesh-attributes buffer mesh skin-joints joint-count)
                                           "indices" (and triangles (add-indices buffer (model-mesh-triangles mesh)))
                                           "targets" (morph-target-objects buffer mesh)
                                           "material" material
                                           "mode" (if triangles 4 0)))
           (morph-mesh-members mesh))))

;;;# The document

(defun gltf-members (model buffer embed-textures)
  "The members of MODEL's glTF document but its buffer, as alternating keys
and values, its binary data stored in BUFFER (texture files embedded when
EMBED-TEXTURES)."
  (let* ((joints (model-joints model))
         (joint-count (length joints))
         (children (joint-children joints))
         (looks (make-gltf-looks embed-textures))
         (meshes '()) (skins '()) (mesh-nodes '()))
    (loop for mesh in (model-meshes model)
          for name in (mesh-node-names model)
          for index from 0
          for skin-joints = (and (model-mesh-joints mesh) (skin-joint-indices mesh joint-count))
          do (push (mesh-object buffer mesh (mesh-material looks buffer mesh) skin-joints joint-count) meshes)
             (when skin-joints (push (add-skin buffer joints skin-joints) skins))
             (push (json-object "name" name "mesh" index "skin" (and skin-joints (1- (length skins))))
                   mesh-nodes))
    (append
     (list "asset" (json-object "version" "2.0" "generator" "Player")
           "scene" 0
           "scenes" (list (json-object "nodes" (append (loop for joint across joints for index from 0
                                                             unless (joint-parent joint) collect index)
                                                       (loop for index from joint-count
                                                             repeat (length mesh-nodes) collect index))))
           "nodes" (append (loop for joint across joints for index from 0
                                 collect (joint-node joint (aref children index)))
                           (reverse mesh-nodes))
           "meshes" (reverse meshes)
           "skins" (reverse skins))
     (looks-members looks)
     (list "animations" (animation-objects buffer model)))))

(defun gltf-document (model glb embed-textures)
  "MODEL's glTF document (see JSON-OBJECT) and its buffer's octets: for a
.glb (GLB true) the buffer has no URI, the octets going in the BIN chunk;
for a .gltf it is a data: URI."
  (let* ((buffer (make-gltf-buffer))
         (members (gltf-members model buffer embed-textures))
         (binary (buffer-contents buffer)))
    (when (>= (length binary) (expt 2 32))
      (write-fail "its buffer needs ~:D bytes, more than glTF's 4 GiB" (length binary)))
    (values (apply #'json-object
                   (append members
                           (list "accessors" (reverse (buffer-accessors buffer))
                                 "bufferViews" (reverse (buffer-views buffer))
                                 "buffers" (and (plusp (length binary))
                                                (list (json-object "byteLength" (length binary)
                                                                   "uri" (and (not glb) (data-uri binary))))))))
            binary)))

(defun gltf-container (path)
  "Which file PATH's type asks for: :GLB or :GLTF; else a MODEL-WRITE-ERROR."
  (let ((type (pathname-type (pathname path))))
    (cond ((and type (string-equal type "glb")) :glb)
          ((and type (string-equal type "gltf")) :gltf)
          (t (write-fail "a glTF file's name ends in .glb (binary) or .gltf (text), not ~:[nothing~;.~:*~A~]" type)))))

(defun write-gltf (model path &key (textures t))
  "Write MODEL as a glTF 2.0 file at PATH and return PATH: binary (.glb) or
JSON text with its buffer embedded as base64 (.gltf), by PATH's type; either
way one file.  Joints become nodes with their rest transforms; meshes their
vertices, normals, UVs, colours, triangles and skins (one per skinned mesh);
morph targets their displacements and names; clips animations with LINEAR
keys, morph weights included.  With TEXTURES (the default) each mesh's
texture file, PNG or JPEG, is embedded; with NIL every mesh gets a plain
material.  The file is written whole to a new file beside PATH, then renamed
over it, so a failure leaves PATH as it was.  Signals a MODEL-WRITE-ERROR (a
MODEL-ERROR) naming PATH when its type is neither, when MODEL holds a number
that is not finite or too large for a float, key times that do not increase,
a skin of more than 65,535 joints, a texture that is missing or neither PNG
nor JPEG, vectors whose lengths disagree; or when the file cannot be
created.  An ARGUMENT-ERROR when MODEL is not a model."
  (check-argument 'write-gltf 'model model #'model-p "a model")
  (check-argument 'write-gltf 'path path #'pathname-designator-p *path-phrase*)
  (let* ((*model-output* path)
         (container (gltf-container path)))
    (check-model-shape model)
    (multiple-value-bind (document binary) (gltf-document model (eq container :glb) (and textures t))
      (write-octets-atomically path (if (eq container :glb)
                                        (glb-octets (json-text document) binary)
                                        (utf-8-octets (json-text document)))))))
