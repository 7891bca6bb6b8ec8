;;;; morphs.lisp -- an imported mesh's morph targets (blend shapes) and the
;;;; animations of their weights, copied and checked (import.lisp and
;;;; animations.lisp call these).  A target is kept as its difference from
;;;; the mesh (3 floats a vertex), which is what blending adds: a mesh with
;;;; weights w_k is base + sum w_k delta_k.

(in-package #:player.model)

(defun copy-morph-targets (mesh base vertex-count)
  "The MORPH-TARGETs of the aiMesh MESH, whose positions are BASE (a
FLOAT-VECTOR of VERTEX-COUNT vertices): each aiAnimMesh's positions minus
BASE.  A target whose vertex count differs from the mesh's, or without
positions, or with a value that is not finite, is a MODEL-ERROR."
  (let* ((count (cffi:foreign-slot-value mesh '(:struct %ai-mesh) 'num-anim-meshes))
         (array (foreign-array (cffi:foreign-slot-value mesh '(:struct %ai-mesh) 'anim-meshes) count "morph targets")))
    (loop for i below count
          for target = (cffi:mem-aref array :pointer i)
          collect (progn
                    (when (cffi:null-pointer-p target) (fail "Assimp gave a NULL among a mesh's morph targets"))
                    (let ((name (slot-string target '%ai-anim-mesh 'name))
                          (vertices (cffi:foreign-slot-value target '(:struct %ai-anim-mesh) 'vertices))
                          (n (cffi:foreign-slot-value target '(:struct %ai-anim-mesh) 'num-vertices)))
                      (unless (= n vertex-count)
                        (fail "morph target ~S has ~D vertices, its mesh ~D" name n vertex-count))
                      (when (cffi:null-pointer-p vertices)
                        (fail "morph target ~S has no positions" name))
                      (let ((positions (copy-floats vertices n 3 3 "a morph target's positions")))
                        (dotimes (k (length positions))
                          (decf (aref positions k) (aref base k)))
                        (make-morph-target (if (string= name "") (format nil "target ~D" i) name)
                                           positions)))))))

(defun ai-morph-channels (animation)
  "The aiMeshMorphAnim pointers of ANIMATION, as a list."
  (pointer-list animation '(:struct %ai-animation) 'num-morph-mesh-channels 'morph-mesh-channels
                "morph animation channels"))

(defun import-morph-channel (channel ticks-per-second meshes-of)
  "The MORPH-CHANNEL of the aiMeshMorphAnim CHANNEL, or NIL when it names no
node holding meshes.  MESHES-OF maps a node's (or mesh's) name to (MESH-INDEX
. TARGET-COUNT) entries."
  (let* ((name (slot-string channel '%ai-mesh-morph-anim 'name))
         ;; Assimp names the node, sometimes with "*N" after it for its Nth mesh.
         (entries (or (gethash name meshes-of)
                      (gethash (subseq name 0 (or (position #\* name) (length name))) meshes-of)))
         (targets (reduce #'max entries :key #'cdr :initial-value 0))
         (count (cffi:foreign-slot-value channel '(:struct %ai-mesh-morph-anim) 'num-keys))
         (keys (foreign-array (cffi:foreign-slot-value channel '(:struct %ai-mesh-morph-anim) 'keys) count "morph keys")))
    (when (and entries (plusp targets))
      (when (> (incf *key-count* (* count targets)) *model-key-limit*)
        (fail "its animations have more than ~:D keys" *model-key-limit*))
      (let ((times (make-array count :element-type 'double-float))
            (weights (make-array (* count targets) :element-type 'double-float :initial-element 0d0)))
        (dotimes (i count)
          (let* ((key (cffi:mem-aptr keys '(:struct %ai-mesh-morph-key) i))
                 (time (cffi:foreign-slot-value key '(:struct %ai-mesh-morph-key) 'time))
                 (n (cffi:foreign-slot-value key '(:struct %ai-mesh-morph-key) 'num-values-and-weights))
                 (values (foreign-array (cffi:foreign-slot-value key '(:struct %ai-mesh-morph-key) 'values) n "morph key targets"))
                 (key-weights (foreign-array (cffi:foreign-slot-value key '(:struct %ai-mesh-morph-key) 'weights) n "morph key weights")))
            (unless (and (finite-double-p time) (>= time 0))
              (fail "a morph animation has a key whose time is negative or not finite"))
            (setf (aref times i) (/ time ticks-per-second))
            (dotimes (k n)
              (let ((target (cffi:mem-aref values :unsigned-int k))
                    (weight (cffi:mem-aref key-weights :double k)))
                (unless (< target targets)
                  (fail "a morph key names target ~D of a mesh with ~D" target targets))
                (unless (finite-double-p weight)
                  (fail "a morph key's weight is not finite"))
                (setf (aref weights (+ (* i targets) target)) weight)))))
        ;; A node and its mesh may both name the mesh: drive it once.
        (make-morph-channel name (remove-duplicates (mapcar #'car entries)) times weights targets)))))
