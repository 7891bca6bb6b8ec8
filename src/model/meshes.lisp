;;;; meshes.lisp -- an imported scene's meshes copied and checked: triangles,
;;;; skins (four weights a vertex), UVs and colours, materials' textures, morph
;;;; target names (import.lisp's COPY-SCENE calls COPY-MESH).

(in-package #:player.model)

;;;# Meshes

(defun pointer-list (object struct count-slot array-slot what)
  "The pointers of OBJECT's (a STRUCT, e.g. '(:struct %ai-scene)) array
ARRAY-SLOT of COUNT-SLOT elements, as a list; the array checked with
FOREIGN-ARRAY, a NULL among them a MODEL-ERROR naming WHAT."
  (let ((count (cffi:foreign-slot-value object struct count-slot))
        (array (cffi:foreign-slot-value object struct array-slot)))
    (foreign-array array count what)
    (loop for i below count
          for element = (cffi:mem-aref array :pointer i)
          do (when (cffi:null-pointer-p element) (fail "Assimp gave a NULL among its ~A" what))
          collect element)))

(defun scene-array (scene count-slot array-slot what)
  "The elements (pointers) of SCENE's array ARRAY-SLOT of COUNT-SLOT elements, as a list."
  (pointer-list scene '(:struct %ai-scene) count-slot array-slot what))

(defun mesh-bone-pointers (mesh)
  "MESH's aiBone pointers, as a list."
  (pointer-list mesh '(:struct %ai-mesh) 'num-bones 'bones "bones"))

(defun copy-triangles (mesh vertex-count)
  "MESH's faces as triangles (an INDEX-VECTOR, 3 per triangle): triangles as
they are, polygons as fans, points and lines dropped (they are not drawn as
surfaces).  A MODEL-ERROR when an index is not one of the VERTEX-COUNT vertices."
  (let* ((count (cffi:foreign-slot-value mesh '(:struct %ai-mesh) 'num-faces))
         (faces (foreign-array (cffi:foreign-slot-value mesh '(:struct %ai-mesh) 'faces) count "faces"))
         (triangles (loop for i below count
                          sum (max 0 (- (cffi:foreign-slot-value (cffi:mem-aptr faces '(:struct %ai-face) i)
                                                                 '(:struct %ai-face) 'num-indices)
                                        2))))
         (vector (make-array (* 3 triangles) :element-type '(unsigned-byte 32)))
         (fill 0))
    (when (> triangles *model-triangle-limit*)
      (fail "a mesh has ~:D triangles, more than the limit of ~:D" triangles *model-triangle-limit*))
    (dotimes (i count vector)
      (let* ((face (cffi:mem-aptr faces '(:struct %ai-face) i))
             (n (cffi:foreign-slot-value face '(:struct %ai-face) 'num-indices))
             (indices (foreign-array (cffi:foreign-slot-value face '(:struct %ai-face) 'indices) n "face indices")))
        (flet ((vertex (k)
                 (let ((index (cffi:mem-aref indices :unsigned-int k)))
                   (unless (< index vertex-count)
                     (fail "a face names vertex ~D of a mesh with ~D" index vertex-count))
                   index)))
          (loop for k from 1 below (1- n)
                do (setf (aref vector fill) (vertex 0)
                         (aref vector (+ fill 1)) (vertex k)
                         (aref vector (+ fill 2)) (vertex (1+ k)))
                   (incf fill 3)))))))

(defun add-influence (joints weights vertex joint weight)
  "Record that JOINT moves VERTEX with WEIGHT in the 4 slots of JOINTS and
WEIGHTS, keeping the 4 largest weights."
  (let* ((base (* 4 vertex))
         (smallest (loop with best = base
                         for slot from base below (+ base 4)
                         when (< (aref weights slot) (aref weights best)) do (setf best slot)
                         finally (return best))))
    (when (> weight (aref weights smallest))
      (setf (aref joints smallest) joint
            (aref weights smallest) weight))))

(defun copy-skin (bones vertex-count joint-index fallback)
  "The skin of a mesh with BONES (aiBone pointers) and VERTEX-COUNT vertices:
JOINTS and WEIGHTS, 4 per vertex, weights normalised to sum 1; a vertex no
bone moves follows the joint FALLBACK (the mesh's node's).  JOINT-INDEX maps
a bone's name to its joint."
  (let ((joints (make-array (* 4 vertex-count) :element-type '(unsigned-byte 32) :initial-element 0))
        (weights (make-array (* 4 vertex-count) :element-type 'double-float :initial-element 0d0)))
    (dolist (bone bones)
      (let* ((joint (gethash (slot-string bone '%ai-bone 'name) joint-index))
             (count (cffi:foreign-slot-value bone '(:struct %ai-bone) 'num-weights))
             (array (foreign-array (cffi:foreign-slot-value bone '(:struct %ai-bone) 'weights) count "bone weights")))
        (dotimes (i count)
          (let* ((record (cffi:mem-aptr array '(:struct %ai-vertex-weight) i))
                 (vertex (cffi:foreign-slot-value record '(:struct %ai-vertex-weight) 'vertex-id))
                 (weight (cffi:foreign-slot-value record '(:struct %ai-vertex-weight) 'weight)))
            (unless (< vertex vertex-count)
              (fail "bone ~A weighs vertex ~D of a mesh with ~D" (slot-string bone '%ai-bone 'name) vertex vertex-count))
            (unless (and (finite-single-p weight) (>= weight 0))
              (fail "bone ~A has a weight that is negative or not finite" (slot-string bone '%ai-bone 'name)))
            (add-influence joints weights vertex joint (float weight 1d0))))))
    (dotimes (vertex vertex-count)
      (let* ((base (* 4 vertex))
             (sum (loop for slot from base below (+ base 4) sum (aref weights slot))))
        (if (plusp sum)
            (loop for slot from base below (+ base 4) do (setf (aref weights slot) (/ (aref weights slot) sum)))
            (setf (aref joints base) fallback (aref weights base) 1d0))))
    (values joints weights)))

(defun mesh-channel (mesh slot index stride width what)
  "MESH's INDEXth array in SLOT (colours or UVs) as a FLOAT-VECTOR of WIDTH of
each STRIDE floats, or NIL when the mesh has none."
  (let ((pointer (cffi:mem-aref (cffi:foreign-slot-pointer mesh '(:struct %ai-mesh) slot) :pointer index)))
    (unless (cffi:null-pointer-p pointer)
      (copy-floats pointer (cffi:foreign-slot-value mesh '(:struct %ai-mesh) 'num-vertices) stride width what))))

(defun material-texture (material directory)
  "The diffuse (or glTF base colour) texture path of MATERIAL, resolved
against DIRECTORY (\"*N\", a texture embedded in the file, as it is), or NIL."
  (cffi:with-foreign-object (path '(:struct %ai-string))
    (loop for type in (list +ai-texture-type-diffuse+ +ai-texture-type-base-color+)
          when (= +ai-return-success+
                  (with-assimp-traps-masked
                    (%ai-get-material-texture material type 0 path
                                              (cffi:null-pointer) (cffi:null-pointer) (cffi:null-pointer)
                                              (cffi:null-pointer) (cffi:null-pointer) (cffi:null-pointer))))
            do (let ((text (substitute #\/ #\\ (ai-string path))))
                 (return (cond ((string= text "") nil)
                               ((char= (char text 0) #\*) text)
                               (t (or (ignore-errors
                                       (namestring (merge-pathnames (uiop:parse-unix-namestring text) directory)))
                                      text))))))))

(defun morph-target-names (mesh)
  "The names of MESH's morph targets (aiAnimMesh), \"target N\" for an unnamed one."
  (let* ((count (cffi:foreign-slot-value mesh '(:struct %ai-mesh) 'num-anim-meshes))
         (array (foreign-array (cffi:foreign-slot-value mesh '(:struct %ai-mesh) 'anim-meshes) count "morph targets")))
    (loop for i below count
          for target = (cffi:mem-aref array :pointer i)
          for name = (if (cffi:null-pointer-p target) "" (slot-string target '%ai-anim-mesh 'name))
          collect (if (string= name "") (format nil "target ~D" i) name))))

(defun copy-mesh (mesh materials directory joint-index fallback transform)
  "The MODEL-MESH copied from the aiMesh at MESH.  MATERIALS is the scene's
list of aiMaterial pointers, DIRECTORY the model's folder, JOINT-INDEX maps
bone names to joints, FALLBACK is the joint its unweighted vertices follow,
TRANSFORM its node's world matrix at rest."
  (let* ((vertex-count (cffi:foreign-slot-value mesh '(:struct %ai-mesh) 'num-vertices))
         (positions (foreign-array (cffi:foreign-slot-value mesh '(:struct %ai-mesh) 'vertices) vertex-count "vertices"))
         (normals (cffi:foreign-slot-value mesh '(:struct %ai-mesh) 'normals))
         (material (cffi:foreign-slot-value mesh '(:struct %ai-mesh) 'material-index))
         (bones (mesh-bone-pointers mesh)))
    (multiple-value-bind (joints weights)
        (when bones (copy-skin bones vertex-count joint-index fallback))
      (let ((base (copy-floats positions vertex-count 3 3 "a mesh's vertex positions")))
      (make-model-mesh
       :name (slot-string mesh '%ai-mesh 'name)
       :positions base
       :morphs (copy-morph-targets mesh base vertex-count)
       :normals (unless (cffi:null-pointer-p normals)
                  (copy-floats normals vertex-count 3 3 "a mesh's normals"))
       :uvs (mesh-channel mesh 'texture-coords 0 3 2 "a mesh's UVs")
       :colours (mesh-channel mesh 'colors 0 4 4 "a mesh's vertex colours")
       :triangles (copy-triangles mesh vertex-count)
       :joints joints :weights weights
       :bones (map 'index-vector (lambda (bone) (gethash (slot-string bone '%ai-bone 'name) joint-index)) bones)
       :holder fallback :transform transform
       :texture (when (< material (length materials))
                  (material-texture (nth material materials) directory))
       :morph-targets (morph-target-names mesh))))))
