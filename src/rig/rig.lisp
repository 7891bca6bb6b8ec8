;;;; rig.lisp -- an imported model as a Player skeleton.  Each of the model's
;;;; joints becomes a joint of the skeleton, at its rest position in Player's
;;;; space (metres, +y up, the figure standing on y = 0), with three DOFs
;;;; about x, y and z of the rest frame and wide limits, so every driver and
;;;; clip can move it.  The RIG, hung on the skeleton, keeps what the skin,
;;;; the clips and the export need: the model, its placement, each joint's
;;;; rest orientation.
;;;;
;;;; The frames.  A Player joint turns about axes of its parent's rest frame,
;;;; which is the world's (PLAYER.BODY's convention); a model's joint has its
;;;; own rest orientation G (in Player's space).  A model's local rotation Q
;;;; of joint j under parent p is therefore the Player rotation
;;;; D = G_p Q G_j^-1: the identity at rest, and composing the Ds down a chain
;;;; turns every joint's rest frame exactly as the Qs turn the model's.

(in-package #:player.rig)

(define-condition rig-error (spec-error)
  ()
  (:report report-spec-error-safely)
  (:documentation "A model cannot be made a character: a role, limit, clip or
option that does not fit it.  FORM is the offending option or clause."))

(defun rig-fail (form control &rest arguments)
  "Signal a RIG-ERROR about FORM with a message from CONTROL and ARGUMENTS."
  (error 'rig-error :form form :message (apply #'format nil control arguments)))

(defstruct (rig (:constructor %make-rig))
  "What a skeleton made from a MODEL keeps of it: PLACEMENT, the MAT4 from the
model's space to Player's (scale, up axis, standing on y = 0), and SCALE;
per model joint its rest world matrix in the model's space (WORLD-REST), its
rest orientation in Player's space (REST-ROTATIONS, quats) and its parent's
(PARENT-ROTATIONS: the placement's for the root), and its skeleton joint's
index (JOINT-MAP); the SKINS, one per mesh; the CLIPS by name; BOUNDS, the
bind pose's (MIN . MAX) vec3s in Player's space."
  model
  placement
  (scale 1d0 :type double-float)
  (world-rest #() :type simple-vector)
  (rest-rotations #() :type simple-vector)
  (parent-rotations #() :type simple-vector)
  (joint-map #() :type simple-vector)
  (skins '() :type list)
  (clips (make-hash-table :test #'equalp) :type hash-table)
  (bounds nil)
  ;; The pose index of the first morph target's weight (the skeleton's DOF count).
  (morph-base 0 :type fixnum))

(defmethod print-object ((rig rig) stream)
  (print-unreadable-object (rig stream :type t)
    (format stream "~A, ~D joints" (file-namestring (model-file (rig-model rig)))
            (length (model-joints (rig-model rig))))))

(defparameter *imported-dof-range* 180
  "The limit, in degrees either way, of an imported joint's DOFs unless :limits narrows it.")

;;;# Names

(defun unique-joint-names (model)
  "A vector of the names MODEL's joints take in the skeleton: their own, with
#2, #3... added to a name an earlier joint has already (skeletons compare
names case-insensitively), and \"joint N\" for an empty one."
  (let ((seen (make-hash-table :test #'equalp)))
    (map 'simple-vector
         (lambda (joint)
           (let* ((base (if (string= (joint-name joint) "")
                            (format nil "joint ~D" (hash-table-count seen))
                            (joint-name joint)))
                  (name (loop for n from 1
                              for candidate = (if (= n 1) base (format nil "~A#~D" base n))
                              unless (gethash candidate seen) return candidate)))
             (setf (gethash name seen) t)
             name))
         (model-joints model))))

;;;# Rest frames

(defun model-world-rest (model)
  "Each of MODEL's joints' world matrix at rest, in the model's space (MAT4s)."
  (let* ((joints (model-joints model))
         (worlds (make-array (length joints))))
    (loop for joint across joints
          for i from 0
          for local = (trs-matrix (joint-translation joint) (joint-rotation joint) (joint-scale joint))
          do (setf (svref worlds i)
                   (if (joint-parent joint) (affine* (svref worlds (joint-parent joint)) local) local)))
    worlds))

(defun up-rotation (up)
  "The rotation taking a model whose up axis is UP (:y or :z) to Player's +y up."
  (ecase up
    (:y (quat))
    ;; -90 degrees about x: z-up becomes y-up, and a z-up tool's front (-y) becomes +z.
    (:z (quat-from-axis-angle (make-vec3 1 0 0) (- (/ pi 2))))))

(defun joint-rest-rotations (model up)
  "Two vectors: each joint's rest orientation in Player's space (the up
rotation times its ancestors' and its own rest rotations), and its parent's
(the up rotation for a root)."
  (let* ((joints (model-joints model))
         (up-quat (up-rotation up))
         (own (make-array (length joints)))
         (parents (make-array (length joints))))
    (loop for joint across joints
          for i from 0
          for parent = (if (joint-parent joint) (svref own (joint-parent joint)) up-quat)
          for rotation = (joint-rotation joint)
          do (setf (svref parents i) parent
                   (svref own i) (qnormalize (q* parent (qnormalize (make-quat (aref rotation 0) (aref rotation 1)
                                                                               (aref rotation 2) (aref rotation 3)))))))
    (values own parents)))
