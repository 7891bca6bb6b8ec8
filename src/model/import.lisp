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
    (handler-case (with-open-file (in path :element-type '(unsigned-byte 8))
                    (when (zerop (file-length in))
                      (model-fail file "~A file is empty" what)))
      (file-error () (model-fail file "~A file cannot be read" what)))
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

;;;# Crashes inside Assimp
;;; Assimp (Debian's 5.2.5, built with its assertions on) trusts some of what a
;;; file says: fuzzed glTF 1.0 and .x files make it read past its buffers (a
;;; memory fault) or fail an ai_assert, whose handler prints to stderr and
;;; calls abort().  No check of ours before the call catches them all (`make
;;; fuzz` measures how often), so the call itself is guarded:
;;;  - a memory fault inside it (SBCL signals MEMORY-FAULT-ERROR) becomes one
;;;    MODEL-ERROR, SBCL's corruption warning captured with the rest of what
;;;    C printed to stderr meanwhile;
;;;  - a failed ai_assert calls our callback instead of abort(), which unwinds
;;;    out of Assimp as one MODEL-ERROR naming the assertion.  Assimp 5.2 keeps
;;;    its handler in a static pointer that Assimp::aiAssertViolation jumps
;;;    through (`jmp *handler(%rip)`), and Debian does not export
;;;    setAiAssertHandler, so the pointer is found from that one instruction
;;;    and set only when the instruction is exactly that (else asserts abort as
;;;    before).  SIGABRT itself cannot be caught from Lisp: SBCL's runtime owns
;;;    it and calls lose().
;;; Unwinding skips Assimp's destructors (its import leaks) and a memory fault
;;; may leave its heap broken, so the error says to treat the process as
;;; suspect; the CLI exits right after it.

(define-condition assimp-assertion (error)
  ((expression :initarg :expression :reader assimp-assertion-expression))
  (:documentation "Internal: an ai_assert failed inside a guarded call into Assimp."))

(cffi:defcallback assimp-assert-handler :void ((expression :pointer) (file :pointer) (line :int))
  (error 'assimp-assertion
         :expression (format nil "~A (~A:~D)" (c-message expression)
                             (let ((name (or (c-message file) "?"))) (subseq name (1+ (or (position #\/ name :from-end t) -1))))
                             line)))

(defvar *assert-handler-installed* nil "Whether Assimp's assertions call ASSIMP-ASSERT-HANDLER.")

(defun install-assert-handler ()
  "Point Assimp's assertion handler at ASSIMP-ASSERT-HANDLER, when
aiAssertViolation is the one indirect jump through it; true when it now is."
  (or *assert-handler-installed*
      (let ((violation (cffi:foreign-symbol-pointer "_ZN6Assimp17aiAssertViolationEPKcS1_i")))
        (when (and violation
                   (= #xFF (cffi:mem-aref violation :uint8 0))
                   (= #x25 (cffi:mem-aref violation :uint8 1)))
          ;; jmp *disp32(%rip): the slot is at the next instruction (6 bytes on) plus disp32.
          (let ((slot (cffi:inc-pointer violation (+ 6 (cffi:mem-ref violation :int32 2)))))
            (setf (cffi:mem-ref slot :pointer) (cffi:callback assimp-assert-handler)
                  *assert-handler-installed* t))))))

(defvar *assimp-lock* (bt:make-lock "player assimp")
  "Held around each import: Assimp's error string is one global, and a guarded
call redirects the process's file descriptor 2.")

(defun captured-text (fd)
  "The first line of what was written to the file descriptor FD (a temporary
file), at most 300 bytes, as one line; NIL when nothing was."
  (sb-posix:lseek fd 0 sb-posix:seek-set)
  (let* ((octets (make-array 300 :element-type '(unsigned-byte 8)))
         (count (sb-sys:with-pinned-objects (octets)
                  (sb-unix:unix-read fd (sb-sys:vector-sap octets) (length octets)))))
    (when (and count (plusp count))
      (let ((text (sb-ext:octets-to-string octets :end count :external-format '(:utf-8 :replacement #\?))))
        (string-trim " " (substitute-if #\Space (lambda (c) (< (char-code c) 32))
                                        (subseq text 0 (or (position #\Newline text) (length text)))))))))

(defun echo-captured (fd)
  "Copy what was written to the temporary file FD to the real stderr (an
import that went well keeps whatever Assimp printed)."
  (sb-posix:lseek fd 0 sb-posix:seek-set)
  (let ((octets (make-array 4096 :element-type '(unsigned-byte 8))))
    (loop for count = (sb-sys:with-pinned-objects (octets)
                        (sb-unix:unix-read fd (sb-sys:vector-sap octets) (length octets)))
          while (and count (plusp count))
          do (sb-unix:unix-write 2 octets 0 count))))

(defun call-guarding-assimp (thunk)
  "THUNK's value, THUNK being a call into Assimp made with stderr captured, a
memory fault or a failed assertion inside it made one MODEL-ERROR naming *MODEL-FILE*."
  (install-assert-handler)
  (finish-output *error-output*)
  (multiple-value-bind (capture name) (sb-posix:mkstemp "/tmp/player-assimp-XXXXXX")
    (sb-posix:unlink name)
    (let ((saved (sb-posix:dup 2)) (crash nil) (value nil))
      (sb-posix:dup2 capture 2)
      (unwind-protect
           (handler-case (setf value (funcall thunk))
             (sb-sys:memory-fault-error ()
               (setf crash "Assimp crashed reading it (a memory fault); the file is broken, and this process's memory is suspect"))
             (assimp-assertion (e)
               (setf crash (format nil "Assimp's own check failed reading it: ~A" (assimp-assertion-expression e)))))
        (sb-posix:dup2 saved 2)
        (sb-posix:close saved)
        (unless crash (echo-captured capture))
        (sb-posix:close capture))
      (when crash (fail "~A" crash))
      value)))

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
