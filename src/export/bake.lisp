;;;; bake.lisp -- a played performance sampled into keys: for every body,
;;;; every joint's local rotation and the root's world place at each frame.
;;;; What the glTF animation holds, so nothing here knows about files.

(in-package #:player.export)

(defun make-joint-keys (skeleton frames width)
  "A vector holding, per joint of SKELETON, a double vector of WIDTH values per frame of FRAMES."
  (map 'simple-vector (lambda (joint) (declare (ignore joint))
                        (make-array (* width frames) :element-type 'double-float))
       (skeleton-joints skeleton)))

(defstruct (baked-body (:constructor %make-baked-body
                           (name skeleton frames
                            &aux (rotations (make-joint-keys skeleton frames 4))
                                 (root-translations (make-array (* 3 frames) :element-type 'double-float))
                                 (root-rotations (make-array (* 4 frames) :element-type 'double-float))
                                 (morph-weights (make-array (* (length (skeleton-morphs skeleton)) frames)
                                                            :element-type 'double-float)))))
  "One body of a performance sampled at FRAMES frames: its NAME and SKELETON;
ROTATIONS, per joint a vector of 4 doubles per frame (w x y z, the joint's
local rotation, JOINT-LOCAL-ROTATION); ROOT-TRANSLATIONS and ROOT-ROTATIONS,
the root joint's world place per frame (3 and 4 doubles a frame): the
body's placement carrying the root's centre and rotation; MORPH-WEIGHTS, the
weights of the skeleton's morph targets (SKELETON-MORPHS) per frame."
  name skeleton (frames 0 :type fixnum)
  (rotations #() :type simple-vector)
  (root-translations nil :type (simple-array double-float (*)))
  (root-rotations nil :type (simple-array double-float (*)))
  (morph-weights nil :type (simple-array double-float (*))))

(defun store-quat (q keys frame)
  "Store the quaternion Q as frame FRAME's four values (w x y z) of KEYS."
  (let ((base (* 4 frame)))
    (setf (aref keys base) (quat-w q) (aref keys (+ base 1)) (quat-x q)
          (aref keys (+ base 2)) (quat-y q) (aref keys (+ base 3)) (quat-z q))))

(defun sample-body (baked body frame)
  "Record BODY's pose and place at FRAME into BAKED."
  (let* ((skeleton (baked-body-skeleton baked))
         (pose (body-pose body))
         (placement (object-world-transform body))
         (root (find-if-not #'body-joint-parent (skeleton-joints skeleton))))
    (loop for joint across (skeleton-joints skeleton)
          for keys across (baked-body-rotations baked)
          do (store-quat (joint-local-rotation joint pose) keys frame))
    ;; The morph weights are the pose's channels after its DOFs.
    (let ((count (length (skeleton-morphs skeleton))))
      (replace (baked-body-morph-weights baked) pose
               :start1 (* count frame) :start2 (skeleton-dof-count skeleton)))
    ;; The root as a glTF node: the placement times the root's local
    ;; transform (its centre, its rotation), so the file needs no extra node.
    (let* ((root-local (make-transform :rotation (joint-local-rotation root pose)
                                       :translation (apply #'vec3 (coerce (body-joint-center root) 'list))))
           (world (transform-compose placement root-local))
           (at (transform-translation world))
           (base (* 3 frame)))
      (setf (aref (baked-body-root-translations baked) base) (vec3-x at)
            (aref (baked-body-root-translations baked) (+ base 1)) (vec3-y at)
            (aref (baked-body-root-translations baked) (+ base 2)) (vec3-z at))
      (store-quat (transform-rotation world) (baked-body-root-rotations baked) frame))))

(defun scene-bodies (scene)
  "The bodies among SCENE's objects, in order."
  (remove-if-not (lambda (object) (typep object 'body)) (scene-objects scene)))

(defun bake-simulation (simulation)
  "Sample SIMULATION (from SIMULATE, or a scene's from SIMULATE-SCENE) at each
of its frames.  Returns a list of BAKED-BODYs, one per body of its scene, in
scene order, and a list of BAKED-PROPs, one per prop seen in any frame.
Frame I is at SIMULATION-FRAME-TIMES' Ith time, as RENDER and SIMULATE sample."
  (check-argument 'bake-simulation 'simulation simulation #'simulation-p "a simulation (from simulate)")
  (let ((frames (simulation-frame-count simulation))
        (bodies '())
        (props (make-hash-table :test 'eq))
        (prop-order '()))
    (map-simulation-frames
     (lambda (index time scene)
       (declare (ignore time))
       (when (zerop index)
         (setf bodies (mapcar (lambda (body)
                                (cons body (%make-baked-body (object-name body) (body-skeleton body) frames)))
                              (scene-bodies scene))))
       ;; A body is the same object every frame; one added later is not exported.
       (loop for (body . record) in bodies
             do (sample-body record body index))
       (sample-props props scene index frames)
       (dolist (object (scene-objects scene))
         (when (and (gethash object props) (not (member object prop-order)))
           (push object prop-order))))
     simulation)
    (values (mapcar #'cdr bodies)
            (mapcar (lambda (object) (gethash object props)) (reverse prop-order)))))

(defun baked-frame-count (baked)
  "How many frames BAKED (a BAKED-BODY) holds."
  (baked-body-frames baked))
