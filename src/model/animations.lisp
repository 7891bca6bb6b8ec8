;;;; animations.lisp -- an imported scene's animations: each clip's keys,
;;;; copied and checked, with times in seconds (import.lisp calls these).

(in-package #:player.model)

;;;# Animations

(defun copy-keys (keys count width ticks-per-second what)
  "The COUNT keys at KEYS (aiVectorKey or aiQuatKey) as two DOUBLE-VECTORs:
their times in seconds and their values, WIDTH each."
  (foreign-array keys count what)
  (let ((times (make-array count :element-type 'double-float))
        (values (make-array (* count width) :element-type 'double-float)))
    (dotimes (i count)
      (let* ((key (cffi:mem-aptr keys '(:struct %ai-key) i))
             (time (cffi:foreign-slot-value key '(:struct %ai-key) 'time))
             (value (cffi:foreign-slot-pointer key '(:struct %ai-key) 'value)))
        (unless (finite-double-p time) (fail "an animation has a key whose time is not finite"))
        (when (minusp time) (fail "an animation has a key before its start (at ~A ticks)" time))
        (setf (aref times i) (/ time ticks-per-second))
        (dotimes (k width)
          (let ((x (cffi:mem-aref value :float k)))
            (unless (finite-single-p x) (fail "an animation's ~A hold a value that is not finite" what))
            (setf (aref values (+ (* i width) k)) (float x 1d0))))))
    (values times values)))

(defun import-channel (channel ticks-per-second joint-index)
  "The CHANNEL (an aiNodeAnim) as a CHANNEL struct; JOINT-INDEX maps node names to joints."
  (flet ((keys (count-slot keys-slot width what)
           (let ((count (cffi:foreign-slot-value channel '(:struct %ai-node-anim) count-slot)))
             (when (> (incf *key-count* count) *model-key-limit*)
               (fail "its animations have more than ~:D keys" *model-key-limit*))
             (copy-keys (cffi:foreign-slot-value channel '(:struct %ai-node-anim) keys-slot)
                        count width ticks-per-second what))))
    (multiple-value-call #'make-channel
      (values (gethash (slot-string channel '%ai-node-anim 'node-name) joint-index))
      (keys 'num-position-keys 'position-keys 3 "position keys")
      (keys 'num-rotation-keys 'rotation-keys 4 "rotation keys")
      (keys 'num-scaling-keys 'scaling-keys 3 "scale keys"))))

(defun ai-animation-channels (animation)
  "The aiNodeAnim pointers of ANIMATION, as a list."
  (pointer-list animation '(:struct %ai-animation) 'num-channels 'channels "animation channels"))

(defun import-animation (animation joint-index &optional (meshes-of (make-hash-table :test 'equal)))
  "The ANIMATION (an aiAnimation) as an ANIMATION struct, times in seconds:
ticks over ticks per second, Assimp's 0 ticks per second meaning 25.  Its
duration covers its last key, should the file's be shorter.  MESHES-OF maps
node and mesh names to the meshes whose morph weights it may animate (see
IMPORT-MORPH-CHANNEL)."
  (let* ((ticks (cffi:foreign-slot-value animation '(:struct %ai-animation) 'duration))
         (rate (cffi:foreign-slot-value animation '(:struct %ai-animation) 'ticks-per-second))
         (ticks-per-second (if (and (finite-double-p rate) (plusp rate)) rate 25d0))
         (name (slot-string animation '%ai-animation 'name)))
    (unless (and (finite-double-p ticks) (>= ticks 0))
      (fail "animation ~S has a duration that is negative or not finite" name))
    (let* ((channels (mapcar (lambda (channel) (import-channel channel ticks-per-second joint-index))
                             (ai-animation-channels animation)))
           (last-key (loop for channel in channels
                           maximize (max (last-time (channel-position-times channel))
                                         (last-time (channel-rotation-times channel))
                                         (last-time (channel-scale-times channel)))))
           (morph-channels (loop for channel in (ai-morph-channels animation)
                                 for imported = (import-morph-channel channel ticks-per-second meshes-of)
                                 when imported collect imported))
           (last-morph-key (loop for channel in morph-channels
                                 maximize (last-time (morph-channel-times channel)))))
      (make-model-animation name (max (/ ticks ticks-per-second) last-key last-morph-key)
                            channels morph-channels))))

(defun last-time (times)
  "The largest of TIMES (a DOUBLE-VECTOR), or 0 when there are none."
  (reduce #'max times :initial-value 0d0))
