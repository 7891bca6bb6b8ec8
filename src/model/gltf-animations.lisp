;;;; gltf-animations.lisp -- a model's animation clips as glTF animations:
;;;; one per clip, one LINEAR sampler and channel per animated joint and path
;;;; (translation, rotation, scale) that has keys, and per mesh node whose
;;;; morph weights it keys (gltf-morphs.lisp).
;;;;
;;;; Key times are stored as 32-bit floats and must stay at or after 0 and
;;;; strictly increasing once stored, as the specification asks; times that do
;;;; not are a MODEL-WRITE-ERROR, not silently reordered.  Clips often key
;;;; every joint at the same times, so equal time vectors share one input
;;;; accessor.  glTF has no duration of its own: a clip lasts until its last
;;;; key, and a clip without a single key cannot be written at all (an
;;;; animation needs a channel), so such a clip is left out.

(in-package #:player.model)

(defparameter *gltf-paths*
  (list (list "translation" #'channel-position-times #'channel-positions)
        (list "rotation" #'channel-rotation-times #'channel-rotations)
        (list "scale" #'channel-scale-times #'channel-scales))
  "The animated paths glTF knows, each with the channel's readers of its key times and values.")

(defun key-time-singles (times what)
  "TIMES (seconds, a DOUBLE-VECTOR) as floats; a MODEL-WRITE-ERROR naming
WHAT unless they are at or after 0 and strictly increasing as floats."
  (let ((floats (singles times what)))
    (when (and (plusp (length floats)) (minusp (aref floats 0)))
      (write-fail "~A start before 0 s (~A s)" what (aref floats 0)))
    (loop for i from 1 below (length floats)
          unless (< (aref floats (1- i)) (aref floats i))
            do (write-fail "~A are not strictly increasing (~A s, then ~A s)"
                           what (aref floats (1- i)) (aref floats i)))
    floats))

(defun add-key-times (buffer floats shared)
  "The index of an input accessor of the key times FLOATS: the one already
in the hash table SHARED (EQUALP on the floats) or a new one, with min and
max as the specification asks of animation inputs."
  (or (gethash floats shared)
      (setf (gethash floats shared) (add-floats buffer floats 1 "key times" :bounds t))))

(defun key-value-singles (path values what)
  "The key VALUES of PATH (a name of *GLTF-PATHS*) as glTF stores them, floats."
  (if (string= path "rotation")
      (rotation-singles values what)
      (singles values what)))

(defun animation-object (buffer animation joints meshes shared)
  "ANIMATION as a glTF animation whose keys are stored in BUFFER (JOINTS, the
model's, name its channels in messages; MESHES, the model's, have the nodes
its morph weights drive; SHARED holds the input accessors so far), or NIL
when it has no key.  A MODEL-WRITE-ERROR when two channels animate one
joint's path."
  (let ((samplers '()) (channels '()) (targets (make-hash-table :test 'equal))
        (clip (model-animation-name animation)))
    (dolist (channel (model-animation-channels animation))
      (loop for (path times-of values-of) in *gltf-paths*
            for times = (funcall times-of channel)
            for joint = (channel-joint channel)
            for what = (format nil "the ~A keys of joint ~S in animation ~S"
                               path (joint-name (aref joints joint)) clip)
            when (plusp (length times))
              do (when (gethash (cons joint path) targets)
                   (write-fail "animation ~S has two channels for the ~A of joint ~S" clip path (joint-name (aref joints joint))))
                 (setf (gethash (cons joint path) targets) t)
                 (let ((input (add-key-times buffer (key-time-singles times what) shared))
                       (output (add-floats buffer (key-value-singles path (funcall values-of channel) what)
                                           (if (string= path "rotation") 4 3) what)))
                   (push (json-object "input" input "output" output "interpolation" "LINEAR") samplers)
                   (push (json-object "sampler" (length channels)
                                      "target" (json-object "node" joint "path" path))
                         channels))))
    (loop for (node input output) in (morph-channel-samplers buffer animation meshes (length joints) shared)
          do (push (json-object "input" input "output" output "interpolation" "LINEAR") samplers)
             (push (json-object "sampler" (length channels) "target" (json-object "node" node "path" "weights"))
                   channels))
    (when channels
      (json-object "name" (and (string/= clip "") clip)
                   "channels" (nreverse channels)
                   "samplers" (nreverse samplers)))))

(defun animation-objects (buffer model)
  "MODEL's animations as glTF animations, their keys stored in BUFFER; clips without a key left out."
  (let ((shared (make-hash-table :test 'equalp)))
    (loop for animation in (model-animations model)
          for object = (animation-object buffer animation (model-joints model) (model-meshes model) shared)
          when object collect object)))
