;;;; scene-mesh.lisp -- what a renderer draws of a scene: the props' meshes (the
;;;; note, a floor, boxes, balls) and a posed, coloured vertex buffer for each
;;;; visible body and prop, built once and updated in place frame after frame.

(in-package #:player.render)

;;;# Props

(defparameter *prop-kinds* '(("NOTE" . :note) ("FLOOR" . :floor) ("BALL" . :sphere))
  "The mesh kind of a prop whose name contains the key; any other prop is a :box.")

(defparameter *prop-looks*
  '((:note :size (0.09 0.12 0.003) :colour (0.97 0.94 0.84))
    (:floor :size 4 :colour (0.55 0.56 0.52))
    (:box :size 0.1 :colour (0.7 0.7 0.7))
    (:sphere :size 0.1 :colour (0.8 0.2 0.2)))
  "Each prop kind's default :size (metres) and :colour (R G B).")

(defun size-list (size &optional (flat nil))
  "SIZE (a real, a vec3, or a list of two or three reals) as a list of three
reals.  A real is a cube's edge, or with FLAT (a card, a floor) the width of a
3:4 rectangle; a missing third is FLAT's thickness."
  (let ((list (typecase size
                (vec3 (list (vec3-x size) (vec3-y size) (vec3-z size)))
                (real (if flat (list size (* 4/3 size)) (list size size size)))
                (t size))))
    (if (and flat (= (length list) 2)) (append list (list flat)) list)))

(defun make-prop-mesh (kind &optional properties)
  "The coloured MESH of a prop of KIND in the prop's own frame, centred on its
origin.  KIND is :note (a thin card in the x-y plane, facing +z), :floor (a
square in the x-z plane at y = 0, facing up), :box or :sphere (diameter SIZE).
PROPERTIES is a plist that may give :size (metres: a real, a vec3 or a list of
reals) and :colour (R G B); the defaults are in *PROP-LOOKS*."
  (let* ((defaults (or (rest (assoc kind *prop-looks*))
                       (error 'player-error-with-message
                              :message (format nil "unknown prop mesh kind ~A (known: ~{~A~^ ~})"
                                               (lisp-text kind) (mapcar #'car *prop-looks*)))))
         (raw-size (getf properties :size (getf defaults :size)))
         (colour (getf properties :colour (getf defaults :colour))))
    (paint-mesh (ecase kind
                  (:note (make-box-mesh (size-list raw-size 0.003)))
                  (:floor (let ((size (size-list raw-size)))
                            (make-quad-mesh (first size) (car (last size)))))
                  (:box (make-box-mesh (size-list raw-size)))
                  (:sphere (make-sphere-mesh (/ (first (size-list raw-size)) 2)
                                             :slices 16 :stacks 10)))
                colour)))

(defun prop-mesh-kind (object)
  "The prop mesh kind of the scene object OBJECT, from its name (*PROP-KINDS*)."
  (or (cdr (assoc-if (lambda (key) (search key (string (object-name object)) :test #'char-equal))
                     *prop-kinds*))
      :box))

(defun object-prop-mesh (object)
  "The mesh of the prop OBJECT, sized and coloured by its SIZE and COLOUR
properties when it has them."
  (flet ((property (name)
           (and (property-type object name nil) (property-value object name))))
    (make-prop-mesh (prop-mesh-kind object)
                    (loop for (key name) in '((:size size) (:colour colour))
                          for value = (property name)
                          when value nconc (list key value)))))

(defun prop-body-mesh (mesh)
  "A BODY-MESH of the coloured MESH as one rigid part on 'joint' 0, so a prop
poses like a body whose only transform is the prop's world transform."
  (parts-body-mesh nil (list (make-mesh-part 0 :prop mesh nil))))

;;;# Scenes

(defstruct (scene-mesh (:constructor make-scene-mesh (object body-mesh vertices)))
  "What a renderer draws for one scene OBJECT (NIL for the floor): its BODY-MESH
and VERTICES, the interleaved buffer (+VERTEX-FLOATS+ per vertex) SCENE-MESHES
poses in place; the indices are SCENE-MESH-INDICES."
  object body-mesh (vertices nil :type float-vector))

(defun scene-mesh-indices (scene-mesh)
  "The triangle indices of SCENE-MESH's vertex buffer (they never change)."
  (body-mesh-indices (scene-mesh-body-mesh scene-mesh)))

(defun make-scene-mesh-cache ()
  "A cache for SCENE-MESHES: pass the same one every frame, so meshes and
buffers are built once and only posed afterwards."
  (make-hash-table :test #'eq))

(defun drawable-p (object)
  "Is OBJECT a visible body or prop?"
  (and (member (object-kind object) '(:body :prop))
       (property-value object 'visible)))

(defun cached-scene-mesh (object cache)
  "OBJECT's SCENE-MESH from CACHE, made on first use; bodies with one skeleton
share its BODY-MESH, each with its own buffer.  A body whose skeleton has a
rig (an imported model), or a MODEL-PROP, is drawn from its skins
\(MAKE-SKINNED-SCENE-MESH)."
  (or (gethash object cache)
      (and (typep object 'body) (skeleton-rig (body-skeleton object))
           (setf (gethash object cache)
                 (make-skinned-scene-mesh object (rig-skins (skeleton-rig (body-skeleton object))))))
      ;; A prop drawn as a model: its meshes are skins of one joint, the prop.
      (and (typep object 'model-prop)
           (setf (gethash object cache)
                 (make-skinned-scene-mesh object (prop-model-skins (model-prop-model object)))))
      (let ((body-mesh (if (typep object 'body)
                           (let ((skeleton (body-skeleton object)))
                             (or (gethash skeleton cache)
                                 (setf (gethash skeleton cache) (make-body-mesh skeleton))))
                           (prop-body-mesh (object-prop-mesh object)))))
        (setf (gethash object cache)
              (make-scene-mesh object body-mesh (make-body-mesh-buffer body-mesh))))))

(defgeneric pose-scene-mesh (scene-mesh transforms)
  (:documentation "Pose SCENE-MESH in place by TRANSFORMS (joint world MAT4s); return SCENE-MESH."))

(defmethod pose-scene-mesh ((scene-mesh scene-mesh) transforms)
  (pose-body-mesh (scene-mesh-body-mesh scene-mesh) transforms (scene-mesh-vertices scene-mesh))
  scene-mesh)

(defun floor-scene-mesh (size cache)
  "The SCENE-MESH of a floor SIZE metres across (T: the default) at y = 0."
  (or (gethash :floor cache)
      (let ((body-mesh (prop-body-mesh
                        (make-prop-mesh :floor (and (realp size) (list :size size))))))
        (setf (gethash :floor cache)
              (pose-scene-mesh (make-scene-mesh nil body-mesh (make-body-mesh-buffer body-mesh))
                               (vector (identity-transform)))))))

(defun scene-meshes (scene &key (cache (make-scene-mesh-cache)) floor)
  "A SCENE-MESH for each visible body and prop of SCENE, in scene order, posed
where they are now: a body by its joints at its last BODY-EVALUATE, a prop by
its world transform (following the joint it hangs from).  With FLOOR (T or a
size in metres) a floor comes first.  Keep CACHE (from MAKE-SCENE-MESH-CACHE)
between frames: the buffers are then reused, so hold on to a frame's buffers
only until the next call."
  (let ((meshes (loop for object in (scene-objects scene)
                      when (drawable-p object)
                        collect (pose-scene-mesh (cached-scene-mesh object cache)
                                                 (if (typep object 'body)
                                                     (body-transforms object)
                                                     (vector (object-world-transform object)))))))
    (if floor (cons (floor-scene-mesh floor cache) meshes) meshes)))
