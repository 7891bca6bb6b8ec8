;;;; gltf-shape.lisp -- is a MODEL whole enough to write?  An imported model
;;;; always is, but one built in Lisp (a recorded performance, a test's) may
;;;; have vectors of the wrong length or indices past the end, which would
;;;; make a file that no reader can use.  Each such fault is a
;;;; MODEL-WRITE-ERROR before anything is written; numbers that are not
;;;; finite are found later, as they are stored.

(in-package #:player.model)

(defun check-length (vector expected what)
  "A MODEL-WRITE-ERROR naming WHAT unless VECTOR has EXPECTED elements."
  (unless (= (length vector) expected)
    (write-fail "~A have ~D numbers where ~D belong" what (length vector) expected)))

(defun check-indices (indices limit what)
  "A MODEL-WRITE-ERROR naming WHAT unless every one of INDICES is below LIMIT."
  (let ((bad (find-if (lambda (index) (>= index limit)) indices)))
    (when bad (write-fail "~A name ~D, but there are only ~D" what bad limit))))

(defun check-joint-shape (joint index)
  "A MODEL-WRITE-ERROR unless JOINT, the INDEXth, has a parent before it and
vectors of 3, 4, 3 and 16 (or no) numbers."
  (let ((name (joint-name joint)))
    (when (and (joint-parent joint) (>= (joint-parent joint) index))
      (write-fail "joint ~S (~D) has the parent ~D, which is not a joint before it" name index (joint-parent joint)))
    (check-length (joint-translation joint) 3 (format nil "the translation of joint ~S" name))
    (check-length (joint-rotation joint) 4 (format nil "the rotation of joint ~S" name))
    (check-length (joint-scale joint) 3 (format nil "the scale of joint ~S" name))
    (when (joint-inverse-bind joint)
      (check-length (joint-inverse-bind joint) 16 (format nil "the inverse bind matrix of joint ~S" name)))))

(defun check-mesh-shape (mesh joint-count)
  "A MODEL-WRITE-ERROR unless MESH's vectors agree with its vertex count and
its indices name vertices and joints (of JOINT-COUNT) that exist."
  (let* ((name (model-mesh-name mesh))
         (positions (length (model-mesh-positions mesh)))
         (vertices (floor positions 3)))
    (flet ((what (part) (format nil "the ~A of mesh ~S" part name)))
      (when (or (zerop vertices) (/= positions (* 3 vertices)))
        (write-fail "mesh ~S has ~D position numbers, not 3 for each of one vertex or more" name positions))
      (loop for (vector width part) in `((,(model-mesh-normals mesh) 3 "normals") (,(model-mesh-uvs mesh) 2 "UVs")
                                         (,(model-mesh-colours mesh) 4 "colours") (,(model-mesh-joints mesh) 4 "joints")
                                         (,(model-mesh-weights mesh) 4 "weights"))
            when vector do (check-length vector (* width vertices) (what part)))
      (unless (eq (null (model-mesh-joints mesh)) (null (model-mesh-weights mesh)))
        (write-fail "mesh ~S has skin joints without weights, or weights without joints" name))
      (unless (zerop (mod (length (model-mesh-triangles mesh)) 3))
        (write-fail "mesh ~S has ~D triangle indices, not 3 a triangle" name (length (model-mesh-triangles mesh))))
      (check-indices (model-mesh-triangles mesh) vertices (what "triangles"))
      (when (model-mesh-joints mesh) (check-indices (model-mesh-joints mesh) joint-count (what "skin joints")))
      (check-indices (model-mesh-bones mesh) joint-count (what "bones")))))

(defun check-channel-shape (channel joint-count clip)
  "A MODEL-WRITE-ERROR unless CHANNEL (of the animation called CLIP) names a
joint of JOINT-COUNT and has as many values as key times for each path."
  (let ((joint (channel-joint channel)))
    (unless (< joint joint-count)
      (write-fail "animation ~S animates joint ~D, but there are only ~D" clip joint joint-count))
    (loop for (times values width path) in `((,(channel-position-times channel) ,(channel-positions channel) 3 "positions")
                                             (,(channel-rotation-times channel) ,(channel-rotations channel) 4 "rotations")
                                             (,(channel-scale-times channel) ,(channel-scales channel) 3 "scales"))
          do (check-length values (* width (length times))
                           (format nil "the ~A keys of joint ~D in animation ~S" path joint clip)))))

(defun check-model-shape (model)
  "A MODEL-WRITE-ERROR unless MODEL's joints, meshes and animations are whole:
see the head of gltf-shape.lisp."
  (let ((joints (model-joints model)))
    (loop for joint across joints for index from 0
          do (check-joint-shape joint index))
    (dolist (mesh (model-meshes model))
      (check-mesh-shape mesh (length joints)))
    (dolist (animation (model-animations model))
      (unless (finite-double-p (model-animation-duration animation))
        (write-fail "animation ~S has a duration that is not finite" (model-animation-name animation)))
      (dolist (channel (model-animation-channels animation))
        (check-channel-shape channel (length joints) (model-animation-name animation))))))
