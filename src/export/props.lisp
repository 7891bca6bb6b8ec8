;;;; props.lisp -- the props of a performance (the note, the desk, balls),
;;;; sampled like the bodies: each prop's world place at every frame, and
;;;; whether it was visible.  In the file a prop is one node of its own, with
;;;; its mesh skinned wholly to it, so every glTF reader moves it (a mesh
;;;; merely hung on an animated node is not moved by every importer).  A prop
;;;; drawn as a model (a MODEL-PROP) gives its model's meshes, textures kept.

(in-package #:player.export)

(defstruct (baked-prop (:constructor %make-baked-prop
                           (object frames
                            &aux (translations (make-array (* 3 frames) :element-type 'double-float))
                                 (rotations (make-array (* 4 frames) :element-type 'double-float))
                                 (scales (make-array (* 3 frames) :element-type 'double-float
                                                                  :initial-element 0d0)))))
  "One prop of a performance sampled at FRAMES frames: its scene OBJECT;
TRANSLATIONS and ROTATIONS, its world place per frame (3 and 4 doubles a
frame); SCALES, (1 1 1) at a frame where it is visible, else (0 0 0): glTF
cannot hide a node, so a hidden prop shrinks to nothing."
  object (frames 0 :type fixnum)
  (translations nil :type (simple-array double-float (*)))
  (rotations nil :type (simple-array double-float (*)))
  (scales nil :type (simple-array double-float (*))))

(defun exported-prop-p (object)
  "Is the scene OBJECT a prop the file holds (not a body, camera or light)?"
  (eq (object-kind object) :prop))

(defun store-place (baked object from to)
  "Store OBJECT's world place now as frames FROM to TO (exclusive) of BAKED,
and its visibility as frame TO - 1's."
  (let* ((world (object-world-transform object))
         (at (transform-translation world))
         (visible (property-value object 'visible)))
    (loop for frame from from below to
          do (setf (aref (baked-prop-translations baked) (* 3 frame)) (vec3-x at)
                   (aref (baked-prop-translations baked) (+ 1 (* 3 frame))) (vec3-y at)
                   (aref (baked-prop-translations baked) (+ 2 (* 3 frame))) (vec3-z at))
             (store-quat (transform-rotation world) (baked-prop-rotations baked) frame))
    (fill (baked-prop-scales baked) (if visible 1d0 0d0) :start (* 3 (1- to)) :end (* 3 to))))

(defun sample-props (props scene frame frames)
  "Record the place of every prop of SCENE at FRAME into the hash table PROPS
\(object -> BAKED-PROP of FRAMES frames); a prop first seen now takes this
place for the frames before it too, hidden there."
  (dolist (object (scene-objects scene))
    (when (exported-prop-p object)
      (let ((baked (gethash object props)))
        (if baked
            (store-place baked object frame (1+ frame))
            (let ((new (setf (gethash object props) (%make-baked-prop object frames))))
              ;; Earlier frames did not show it: there it stays hidden (scale 0).
              (store-place new object 0 (1+ frame))))))))

(defun prop-name (baked)
  "The name of BAKED's node: the prop's own, lower case, after \"prop/\"."
  (format nil "prop/~A" (string-downcase (string (object-name (baked-prop-object baked))))))

(defun prop-model-joint (baked)
  "BAKED's node as a MODEL-JOINT: a root resting where it is at the first
frame, whose inverse bind is the identity (its mesh is in its own frame)."
  (make-joint (prop-name baked) nil
              (subseq (baked-prop-translations baked) 0 3)
              (subseq (baked-prop-rotations baked) 0 4)
              (doubles 1 1 1)
              (doubles 1 0 0 0  0 1 0 0  0 0 1 0  0 0 0 1)))

(defun weighted-to (joint count)
  "JOINTS and WEIGHTS (4 a vertex) for COUNT vertices, each wholly on JOINT."
  (let ((joints (index-vector (* 4 count)))
        (weights (make-array (* 4 count) :element-type 'double-float :initial-element 0d0)))
    (dotimes (v count (values joints weights))
      (setf (aref joints (* 4 v)) joint (aref weights (* 4 v)) 1d0))))

(defun prop-model-mesh (baked joint)
  "BAKED's mesh as the renderer draws it, in the prop's frame, weighted 1 to
the model joint JOINT."
  (let* ((body-mesh (prop-body-mesh (object-prop-mesh (baked-prop-object baked))))
         (count (floor (length (body-mesh-positions body-mesh)) 3)))
    (multiple-value-bind (joints weights) (weighted-to joint count)
      (make-model-mesh :name (prop-name baked) :positions (copy-seq (body-mesh-positions body-mesh))
                       :normals (copy-seq (body-mesh-normals body-mesh))
                       :colours (rgba-colours (body-mesh-colours body-mesh))
                       :triangles (coerce (body-mesh-indices body-mesh) '(simple-array (unsigned-byte 32) (*)))
                       :joints joints :weights weights
                       :bones (make-array 1 :element-type '(unsigned-byte 32) :initial-element joint)
                       :holder joint))))

(defun prop-skin-mesh (baked skin joint)
  "The MODEL-MESH of SKIN, one mesh of BAKED's prop model, its vertices in
the prop's frame (placed, scaled) and weighted 1 to the model joint JOINT;
its UVs, colours and texture (embedded or a file) as the model has them."
  (let* ((mesh (skin-mesh skin))
         (count (model-mesh-vertex-count mesh))
         (positions (make-array (* 3 count) :element-type 'single-float))
         (normals (and (model-mesh-normals mesh) (make-array (* 3 count) :element-type 'single-float))))
    (skin-vertices skin (skin-palette-matrices skin (vector (identity-transform))) positions normals)
    (multiple-value-bind (joints weights) (weighted-to joint count)
      (make-model-mesh :name (format nil "~A/~A" (prop-name baked) (model-mesh-name mesh))
                       :positions positions :normals normals
                       :uvs (model-mesh-uvs mesh) :colours (model-mesh-colours mesh)
                       :triangles (model-mesh-triangles mesh) :joints joints :weights weights
                       :bones (make-array 1 :element-type '(unsigned-byte 32) :initial-element joint)
                       :holder joint :texture (model-mesh-texture mesh)
                       :embedded-texture (model-mesh-embedded-texture mesh)))))

(defun prop-model-meshes (baked joint)
  "The MODEL-MESHes of BAKED's prop, weighted to the model joint JOINT: a
prop drawn as a model gives its model's meshes, any other its one mesh."
  (let ((object (baked-prop-object baked)))
    (if (typep object 'model-prop)
        (mapcar (lambda (skin) (prop-skin-mesh baked skin joint))
                (prop-model-skins (model-prop-model object)))
        (list (prop-model-mesh baked joint)))))

(defun prop-channel (baked joint times)
  "BAKED's keys as the MODEL-CHANNEL of the model joint JOINT."
  (make-channel joint times (baked-prop-translations baked) times (baked-prop-rotations baked)
                times (baked-prop-scales baked)))
