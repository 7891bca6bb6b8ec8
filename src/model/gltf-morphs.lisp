;;;; gltf-morphs.lisp -- a mesh's morph targets (blend shapes) and the
;;;; animations of their weights, as glTF 2.0 writes them: each target a
;;;; POSITION displacement accessor (with the min and max the specification
;;;; asks of POSITION) in the primitive's `targets`, their names in the mesh's
;;;; `extras.targetNames` (the convention Blender, three.js and Assimp read),
;;;; their default weights 0 in its `weights`; and each MORPH-CHANNEL one
;;;; `weights` channel per mesh node it drives, its output TARGETS values a key.

(in-package #:player.model)

(defun morph-target-objects (buffer mesh)
  "The `targets` of MESH's primitive, each target's deltas stored in BUFFER;
NIL when MESH has no morph target.  A MODEL-WRITE-ERROR when a target's
deltas are not one per vertex."
  (loop for target in (model-mesh-morphs mesh)
        unless (= (length (morph-target-deltas target)) (length (model-mesh-positions mesh)))
          do (write-fail "morph target ~S of mesh ~S has ~D delta values for ~D vertices"
                         (morph-target-name target) (model-mesh-name mesh)
                         (length (morph-target-deltas target)) (floor (length (model-mesh-positions mesh)) 3))
        collect (json-object "POSITION"
                             (add-floats buffer (morph-target-deltas target) 3
                                         (format nil "the deltas of morph target ~S of mesh ~S"
                                                 (morph-target-name target) (model-mesh-name mesh))
                                         :target +gltf-array-buffer+ :bounds t))))

(defun morph-mesh-members (mesh)
  "The members a mesh with morph targets adds to its glTF mesh: `weights`,
every target's default weight (0), and `extras` naming the targets; NIL when
MESH has none."
  (let ((targets (model-mesh-morphs mesh)))
    (and targets
         (list "weights" (make-list (length targets) :initial-element 0)
               "extras" (json-object "targetNames" (mapcar #'morph-target-name targets))))))

(defun mesh-morph-weights (channel count what)
  "CHANNEL's weights (a MORPH-CHANNEL) as floats, COUNT a key: the first
COUNT of its TARGET-COUNT, a target it does not key weighing 0."
  (let* ((keys (length (morph-channel-times channel)))
         (stride (morph-channel-target-count channel))
         (weights (morph-channel-weights channel))
         (floats (make-array (* keys count) :element-type 'single-float :initial-element 0.0)))
    (dotimes (key keys floats)
      (dotimes (target (min count stride))
        (setf (aref floats (+ (* key count) target))
              (single (aref weights (+ (* key stride) target)) what))))))

(defun morph-channel-samplers (buffer animation meshes joint-count shared)
  "For each mesh node ANIMATION's morph channels drive, (NODE INPUT OUTPUT):
its node index (the mesh nodes follow the JOINT-COUNT joint nodes, in the
order of MESHES, the model's meshes) and the accessors of its key times
\(shared through SHARED, see ADD-KEY-TIMES) and weights, stored in BUFFER.
A mesh without morph targets is left out: glTF has no weights to drive."
  (loop for channel in (model-animation-morph-channels animation)
        for what = (format nil "the morph weight keys of ~S in animation ~S"
                           (morph-channel-node channel) (model-animation-name animation))
        nconc (loop for index in (morph-channel-meshes channel)
                    for count = (length (model-mesh-morphs (nth index meshes)))
                    when (and (plusp count) (plusp (length (morph-channel-times channel))))
                      collect (list (+ joint-count index)
                                    (add-key-times buffer (key-time-singles (morph-channel-times channel) what) shared)
                                    (add-floats buffer (mesh-morph-weights channel count what) 1 what)))))
