;;;; import.lisp -- IMPORT-MODEL, the checked layer over assimp-raw.lisp: the
;;;; file is checked before Assimp sees it, Assimp's scene is copied into the
;;;; Lisp structs of model.lisp and released, and everything taken from C is
;;;; checked on the way (indices in range, numbers finite, counts within the
;;;; limits of conditions.lisp).  Any failure is one MODEL-ERROR naming the file.

(in-package #:player.model)

(defparameter *model-post-processing*
  '(:triangulate :join-identical-vertices :limit-bone-weights :sort-by-primitive-type)
  "The Assimp post-processing steps IMPORT-MODEL asks for by default.  UVs are
not flipped: they stay as the file has them (origin bottom left, as GL reads
textures).  Assimp's validation always runs too.")

(defparameter *post-processing-flags*
  `((:triangulate . ,+ai-process-triangulate+)
    (:join-identical-vertices . ,+ai-process-join-identical-vertices+)
    (:limit-bone-weights . ,+ai-process-limit-bone-weights+)
    (:sort-by-primitive-type . ,+ai-process-sort-by-p-type+))
  "Each post-processing step IMPORT-MODEL knows, with its aiProcess flag.")

(defun post-processing-flags (steps)
  "The aiProcess flags for the post-processing STEPS (keywords of
*POST-PROCESSING-FLAGS*), with Assimp's own validation of the scene always on."
  (reduce #'logior steps
          :key (lambda (step)
                 (or (cdr (assoc step *post-processing-flags*))
                     (error 'player-error-with-message
                            :message (format nil "no post-processing step ~S (known: ~{~S~^ ~})"
                                             step (mapcar #'car *post-processing-flags*)))))
          :initial-value +ai-process-validate-data-structure+))

(defvar *model-file* nil
  "While a model is imported: the file as given, which every MODEL-ERROR names.")

(defvar *key-count* 0 "While a model is imported: the animation keys copied so far.")

(defun fail (control &rest arguments)
  "Signal a MODEL-ERROR about the model being imported (*MODEL-FILE*)."
  (apply #'model-fail *model-file* control arguments))

;;;# The file, before Assimp sees it

(defun check-readable-file (file what)
  "FILE's truename when it is a readable, non-empty file; else a MODEL-ERROR
naming FILE, which is WHAT (\"the model\", \"the texture\")."
  (let ((path (ignore-errors (probe-file file))))
    (cond ((null path) (model-fail file "~A file does not exist" what))
          ((null (pathname-name path)) (model-fail file "~A is a folder, not a file" what)))
    ;; Opened without blocking and checked regular: a FIFO or device never hangs us.
    (handler-case (with-input-file (in path :element-type '(unsigned-byte 8))
                    (when (zerop (file-length in))
                      (model-fail file "~A file is empty" what)))
      (io-error (e) (model-fail file "~A file cannot be read: ~A" what (io-error-reason e))))
    path))

;;;# Reading C data, checked

(declaim (inline finite-single-p finite-double-p))
(defun finite-single-p (x)
  "Is the single-float X neither NaN nor infinite?  (Tested on its bits, so a
NaN never reaches a comparison that could trap.)"
  (/= 255 (ldb (byte 8 23) (sb-kernel:single-float-bits x))))

(defun finite-double-p (x)
  "Is the double-float X neither NaN nor infinite?"
  (/= 2047 (ldb (byte 11 20) (sb-kernel:double-float-high-bits x))))

(defun ai-string (pointer)
  "The text of the aiString at POINTER (UTF-8, its length bounded by the struct)."
  (let* ((length (min (cffi:foreign-slot-value pointer '(:struct %ai-string) 'length)
                      (1- +ai-string-capacity+)))
         (data (cffi:foreign-slot-pointer pointer '(:struct %ai-string) 'data))
         (octets (make-array length :element-type '(unsigned-byte 8))))
    (dotimes (i length)
      (setf (aref octets i) (cffi:mem-aref data :uint8 i)))
    (sb-ext:octets-to-string octets :external-format '(:utf-8 :replacement #\?))))

(defun slot-string (pointer type slot)
  "The aiString in SLOT of the struct TYPE at POINTER."
  (ai-string (cffi:foreign-slot-pointer pointer (list :struct type) slot)))

(defun foreign-array (pointer count what)
  "POINTER, the C array of COUNT elements holding WHAT; a MODEL-ERROR when it
is NULL but COUNT says there is something there."
  (when (and (plusp count) (cffi:null-pointer-p pointer))
    (fail "Assimp gave ~D ~A but no array holding them" count what))
  pointer)

(defun copy-floats (pointer count stride width what)
  "A FLOAT-VECTOR of WIDTH floats from each of the COUNT records of STRIDE
floats at POINTER; a MODEL-ERROR naming WHAT when one is not finite."
  (declare (type (unsigned-byte 32) count) (type (integer 1 16) stride width))
  (let ((vector (make-array (* count width) :element-type 'single-float)))
    (dotimes (i count vector)
      (dotimes (k width)
        (let ((x (cffi:mem-aref pointer :float (+ (* i stride) k))))
          (unless (finite-single-p x)
            (fail "~A hold a value that is not finite (NaN or infinite)" what))
          (setf (aref vector (+ (* i width) k)) x))))))

(defun copy-matrix (pointer what)
  "The 16 floats of the aiMatrix4x4 at POINTER as a DOUBLE-VECTOR (row-major)."
  (map 'double-vector (lambda (x) (float x 1d0)) (copy-floats pointer 1 16 16 what)))

;;;# The scene

(defun name-table (names)
  "An EQUAL hash table holding NAMES (strings) as keys."
  (let ((table (make-hash-table :test 'equal)))
    (dolist (name names table) (setf (gethash name table) t))))

(defun mesh-nodes (nodes mesh-count)
  "For each of MESH-COUNT meshes, the index of the first of NODES that holds it, or NIL."
  (let ((holders (make-array mesh-count :initial-element nil)))
    (loop for (pointer) across nodes
          for node from 0
          for count = (cffi:foreign-slot-value pointer '(:struct %ai-node) 'num-meshes)
          for array = (foreign-array (cffi:foreign-slot-value pointer '(:struct %ai-node) 'meshes) count "node meshes")
          do (dotimes (i count)
               (let ((mesh (cffi:mem-aref array :unsigned-int i)))
                 (unless (< mesh mesh-count) (fail "a node names mesh ~D of ~D" mesh mesh-count))
                 (unless (aref holders mesh) (setf (aref holders mesh) node)))))
    holders))

(defun nearest-joint (nodes joint-of node)
  "The joint of NODE or of its nearest ancestor that is a joint, or 0."
  (loop while node
        do (when (aref joint-of node) (return (aref joint-of node)))
           (setf node (third (aref nodes node)))
        finally (return 0)))

(defun check-vertex-total (meshes)
  "A MODEL-ERROR when MESHES (aiMesh pointers) have more vertices than *MODEL-VERTEX-LIMIT*."
  (let ((total (loop for mesh in meshes sum (cffi:foreign-slot-value mesh '(:struct %ai-mesh) 'num-vertices))))
    (when (> total *model-vertex-limit*)
      (fail "it has ~:D vertices, more than the limit of ~:D" total *model-vertex-limit*))))

(defun copy-scene (scene path)
  "The MODEL copied from the aiScene at SCENE, imported from PATH."
  (let ((root (cffi:foreign-slot-value scene '(:struct %ai-scene) 'root-node))
        (meshes (scene-array scene 'num-meshes 'meshes "meshes"))
        (materials (scene-array scene 'num-materials 'materials "materials"))
        (animations (scene-array scene 'num-animations 'animations "animations"))
        (inverse-binds (make-hash-table :test 'equal)))
    (when (cffi:null-pointer-p root) (fail "its scene has no nodes"))
    (check-vertex-total meshes)
    (dolist (mesh meshes)
      (dolist (bone (mesh-bone-pointers mesh))
        (let ((name (slot-string bone '%ai-bone 'name)))
          (unless (gethash name inverse-binds)
            (setf (gethash name inverse-binds)
                  (copy-matrix (cffi:foreign-slot-pointer bone '(:struct %ai-bone) 'offset-matrix)
                               "a bone's inverse bind matrix"))))))
    (let* ((nodes (scene-nodes root))
           (animated (loop for animation in animations
                           nconc (mapcar (lambda (channel) (slot-string channel '%ai-node-anim 'node-name))
                                         (ai-animation-channels animation))))
           (names (name-table (append (alexandria:hash-table-keys inverse-binds) animated))))
      (dolist (name (alexandria:hash-table-keys names))
        (unless (find name nodes :key #'second :test #'string=)
          (fail "a bone or animation channel names ~S, which no node of its scene is called" name)))
      (multiple-value-bind (joint-of joint-count) (joint-nodes nodes names)
        (when (> joint-count *model-joint-limit*)
          (fail "its skeleton has ~:D joints, more than the limit of ~:D" joint-count *model-joint-limit*))
        (let ((joints (make-joints nodes joint-of inverse-binds))
              (joint-index (make-hash-table :test 'equal))
              (holders (mesh-nodes nodes (length meshes)))
              (*key-count* 0))
          (loop for joint across joints for i from 0
                do (unless (gethash (joint-name joint) joint-index)
                     (setf (gethash (joint-name joint) joint-index) i)))
          (let ((textures (copy-embedded-textures
                           (scene-array scene 'num-textures 'textures "embedded textures") path))
                (meshes-of (node-meshes-table nodes holders meshes)))
            (make-model (namestring path)
                        (attach-embedded-textures
                         (loop for mesh in meshes for i from 0
                               collect (copy-mesh mesh materials (uiop:pathname-directory-pathname path) joint-index
                                                  (nearest-joint nodes joint-of (aref holders i))
                                                  (node-world-matrix nodes (aref holders i))))
                         textures)
                        joints
                        (mapcar (lambda (animation) (import-animation animation joint-index meshes-of))
                                animations)
                        textures)))))))

(defun node-meshes-table (nodes holders meshes)
  "A table from each node's name, and each mesh's, to the (MESH-INDEX .
TARGET-COUNT) of the meshes it holds (or is) that have morph targets: what a
morph animation channel names.  HOLDERS gives each mesh's node."
  (let ((table (make-hash-table :test 'equal)))
    (loop for mesh in meshes
          for index from 0
          for targets = (cffi:foreign-slot-value mesh '(:struct %ai-mesh) 'num-anim-meshes)
          for holder = (aref holders index)
          when (plusp targets)
            do (when holder
                 (push (cons index targets) (gethash (second (aref nodes holder)) table)))
               (push (cons index targets) (gethash (slot-string mesh '%ai-mesh 'name) table)))
    table))

(defun assimp-error-string ()
  "Assimp's message about the last import that failed."
  (let ((text (c-message (with-assimp-traps-masked (%ai-get-error-string)))))
    (if (and text (string/= text "")) text "no reason given")))

(defun import-model (file &key (post-processing *model-post-processing*) texture
                            (vertex-limit *model-vertex-limit*) (triangle-limit *model-triangle-limit*)
                            (joint-limit *model-joint-limit*) (key-limit *model-key-limit*))
  "Import the model FILE (glTF, FBX, COLLADA, .x, BVH... whatever Assimp
reads) as a MODEL, applying the Assimp POST-PROCESSING steps (keywords of
*POST-PROCESSING-FLAGS*; default *MODEL-POST-PROCESSING*).  TEXTURE, when
given, is a texture file that replaces every mesh's diffuse texture.  The
limits default to *MODEL-VERTEX-LIMIT*, *MODEL-TRIANGLE-LIMIT*,
*MODEL-JOINT-LIMIT* and *MODEL-KEY-LIMIT*.  Signals MODEL-ERROR, naming the
file, when it is missing, unreadable or refused by Assimp, when what it holds
is not finite or is past a limit; MODEL-LIBRARY-MISSING when Assimp is not
installed."
  (let* ((*model-file* file)
         (path (check-readable-file file "the model"))
         (texture-path (and texture (namestring (check-readable-file texture "the texture"))))
         (flags (post-processing-flags post-processing))
         (*model-vertex-limit* vertex-limit) (*model-triangle-limit* triangle-limit)
         (*model-joint-limit* joint-limit) (*model-key-limit* key-limit))
    (load-assimp-library file)
    (let ((scene (bt:with-lock-held (*assimp-lock*)
                   (let ((scene (call-guarding-assimp
                                 (lambda ()
                                   (with-assimp-traps-masked
                                     (%ai-import-file (uiop:native-namestring path) flags))))))
                     (when (cffi:null-pointer-p scene)
                       (fail "Assimp cannot read it: ~A" (string-right-trim ". " (assimp-error-string))))
                     scene))))
      (let ((model (unwind-protect (copy-scene scene path)
                     (with-assimp-traps-masked (%ai-release-import scene)))))
        (when texture-path
          (dolist (mesh (model-meshes model))
            (setf (model-mesh-texture mesh) texture-path
                  (model-mesh-embedded-texture mesh) nil)))
        model))))
