;;;; export.lisp -- EXPORT-PERFORMANCE: a played performance as one glTF file.
;;;; Every body of the simulation's scene becomes a skeleton of the model
;;;; (CHARACTER-MODEL's joints and meshes), every prop a node with its mesh
;;;; (props.lisp), and the performance one animation named "performance": per
;;;; joint its local rotation at every frame, the root's and each prop's world
;;;; place too, the weights of each mesh's morph targets, LINEAR keys at the
;;;; simulation's frame times (I/FPS seconds, the nearest frame moved onto each
;;;; critical time).

(in-package #:player.export)

(defparameter *animation-name* "performance"
  "The name of the one animation an exported performance holds.")

(defun body-channels (baked first times)
  "The MODEL-CHANNELs of BAKED (a BAKED-BODY) whose joints stand from FIRST
in the model: every joint's rotation keys, the root's translation keys too."
  (let ((none (make-array 0 :element-type 'double-float)))
    (loop for joint across (skeleton-joints (baked-body-skeleton baked))
          for keys across (baked-body-rotations baked)
          for root = (null (body-joint-parent joint))
          collect (make-channel (+ first (body-joint-index joint))
                                (if root times none)
                                (if root (baked-body-root-translations baked) none)
                                times
                                (if root (baked-body-root-rotations baked) keys)
                                none none))))

(defun body-morph-channels (baked meshes first-mesh times)
  "The MORPH-CHANNELs of BAKED (a BAKED-BODY) for its MESHES, which stand from
FIRST-MESH in the model: one per mesh with morph targets, its weights at
every frame (TIMES) in the order of the mesh's targets."
  (let* ((skeleton (baked-body-skeleton baked))
         (count (length (skeleton-morphs skeleton)))
         (dofs (skeleton-dof-count skeleton))
         (frames (baked-body-frames baked)))
    (loop for mesh in meshes
          for index from first-mesh
          for channels = (mapcar (lambda (target) (- (morph-index skeleton (morph-target-name target) t) dofs))
                                 (model-mesh-morphs mesh))
          when channels
            collect (let ((weights (make-array (* frames (length channels)) :element-type 'double-float)))
                      (dotimes (frame frames)
                        (loop for channel in channels
                              for k from 0
                              do (setf (aref weights (+ (* frame (length channels)) k))
                                       (aref (baked-body-morph-weights baked) (+ (* frame count) channel)))))
                      (make-morph-channel (model-mesh-name mesh) (list index) times weights (length channels))))))

(defun body-prefix (baked several)
  "What BAKED's joint names start with: nothing for a lone body, its name
and a slash when SEVERAL bodies share the file (so names stay distinct)."
  (if several (format nil "~A/" (string-downcase (string (baked-body-name baked)))) ""))

(defun performance-model (simulation &key (file ""))
  "SIMULATION (from SIMULATE or SIMULATE-SCENE) baked into a MODEL named FILE:
the joints and meshes of each of its bodies (CHARACTER-MODEL), a joint and
a mesh for each prop, and one animation, *ANIMATION-NAME*, keying every
frame (BAKE-SIMULATION)."
  (multiple-value-bind (bodies props) (bake-simulation simulation)
    (let* ((several (rest bodies))
           (frames (simulation-frame-count simulation))
           ;; The frames' own times: a critical time moves the nearest frame onto it.
           (times (copy-seq (simulation-frame-times simulation)))
           (joints '()) (meshes '()) (channels '()) (morph-channels '()) (first 0))
      (dolist (baked bodies)
        (let* ((skeleton (baked-body-skeleton baked))
               (prefix (body-prefix baked several))
               (own (skeleton-model-meshes skeleton (string-downcase (string (baked-body-name baked))) first)))
          (setf joints (append joints (skeleton-model-joints skeleton :first first :prefix prefix))
                morph-channels (append morph-channels (body-morph-channels baked own (length meshes) times))
                meshes (append meshes own)
                channels (append channels (body-channels baked first times)))
          (incf first (length (skeleton-joints skeleton)))))
      (dolist (baked props)
        (setf joints (append joints (list (prop-model-joint baked)))
              meshes (append meshes (prop-model-meshes baked first))
              channels (append channels (list (prop-channel baked first times))))
        (incf first))
      (make-model file meshes (coerce joints 'simple-vector)
                  (list (make-model-animation *animation-name* (aref times (1- frames)) channels
                                              morph-channels))))))

(defun export-performance (simulation path)
  "Write SIMULATION (from SIMULATE or SIMULATE-SCENE) as a glTF 2.0 file at
PATH, binary for .glb, JSON for .gltf (WRITE-GLTF): its bodies' skeletons and
meshes, and the performance as one animation (PERFORMANCE-MODEL).  Returns
PATH.  Signals an ARGUMENT-ERROR for a SIMULATION that is not one, and what
WRITE-GLTF signals (a MODEL-WRITE-ERROR for a PATH of another type, or one
that cannot be written)."
  (check-argument 'export-performance 'simulation simulation #'simulation-p "a simulation (from simulate)")
  (check-argument 'export-performance 'path path #'pathname-designator-p *path-phrase*)
  (write-gltf (performance-model simulation :file (namestring path)) path))
