;;;; clips.lisp -- animation clips as Player rotations.  A CLIP holds, for each
;;;; joint it moves, keys of the joint's rotation D relative to its parent's
;;;; rest frame (see rig.lisp), so sampling a clip is a slerp between two keys
;;;; and a decomposition into the joint's three DOF angles.  Because D is the
;;;; model's rotation times constant rotations on either side, slerping the Ds
;;;; gives exactly the D of the slerped model rotations: a clip plays the
;;;; file's motion as the file's own interpolation would.

(in-package #:player.rig)

(deftype doubles () "A flat vector of doubles." '(simple-array double-float (*)))

(defstruct (clip-track (:conc-name track-) (:constructor make-track (joint times quats)))
  "One joint's keys in a clip: JOINT, its skeleton index; TIMES in seconds from
the clip's start, increasing; QUATS, w x y z per key, each key's sign chosen
so that consecutive keys are within 180 degrees (slerp takes the short way)."
  (joint 0 :type fixnum)
  (times nil :type doubles)
  (quats nil :type doubles))

(defstruct (motion-clip (:conc-name clip-) (:constructor make-motion-clip (name duration tracks &key root-times root-offsets source morph-tracks)))
  "A clip: NAME (a string), DURATION (seconds), TRACKS (a simple-vector of
TRACKs, by increasing joint), and the root's travel: ROOT-TIMES and
ROOT-OFFSETS (x y z per key, metres in Player's space from where the root
rests), or NIL when the clip does not move it; MORPH-TRACKS, the weights of
morph targets it keys, (POSE-INDEX TIMES WEIGHTS) each.  SOURCE says where it
came from."
  (name "" :type string)
  (duration 0d0 :type double-float)
  (tracks #() :type simple-vector)
  (root-times nil :type (or null doubles))
  (root-offsets nil :type (or null doubles))
  (morph-tracks '() :type list)
  (source nil))

(defmethod print-object ((clip motion-clip) stream)
  (print-unreadable-object (clip stream :type t)
    (format stream "~S, ~A s, ~D joints" (clip-name clip) (format-number (clip-duration clip))
            (length (clip-tracks clip)))))

(defun clip-name-from-animation (name)
  "An animation's NAME as a clip name: lower case, each run of characters other
than letters and digits turned to one -, none at either end; \"animation\" for
an empty one."
  (let* ((words (with-output-to-string (out)
                  (loop with dash = nil
                        for char across (string-downcase name)
                        do (if (alphanumericp char)
                               (progn (when dash (write-char #\- out)) (setf dash nil) (write-char char out))
                               (setf dash t)))))
         (trimmed (string-left-trim "-" words)))
    (if (string= trimmed "") "animation" trimmed)))

(defun clip-joint-indices (clip)
  "The skeleton joint indices CLIP moves, increasing."
  (map 'list #'track-joint (clip-tracks clip)))

(defun find-clip (rig name &optional errorp)
  "RIG's clip called NAME (a string or symbol, case-insensitively); NIL, or a
RIG-ERROR listing the clips when ERRORP."
  (or (gethash (string name) (rig-clips rig))
      (and errorp (rig-fail name "~A has no clip ~A (clips: ~{~A~^ ~})"
                            (file-namestring (model-file (rig-model rig))) (lisp-text name)
                            (rig-clip-names rig)))))

(defun rig-clip-names (rig)
  "The names of RIG's clips, sorted."
  (sort (mapcar #'string-downcase (hash-table-keys (rig-clips rig))) #'string<))

;;;# Keys

(defun sample-keys (times values width time)
  "The value at TIME of keys (TIMES, VALUES WIDTH wide) linearly interpolated,
held before the first and after the last, as a fresh list of WIDTH doubles.
For rotations (WIDTH 4) the interpolation is a slerp."
  (let ((n (length times)))
    (flet ((key (i) (loop for k below width collect (aref values (+ (* i width) k)))))
      (cond ((or (= n 1) (<= time (aref times 0))) (key 0))
            ((>= time (aref times (1- n))) (key (1- n)))
            (t (let* ((i (1- (or (position-if (lambda (x) (> x time)) times) n)))
                      (u (/ (- time (aref times i)) (- (aref times (1+ i)) (aref times i)))))
                 (if (= width 4)
                     (let ((q (qslerp (apply #'make-quat (key i)) (apply #'make-quat (key (1+ i))) u)))
                       (list (quat-w q) (quat-x q) (quat-y q) (quat-z q)))
                     (mapcar (lambda (a b) (+ a (* u (- b a)))) (key i) (key (1+ i))))))))))

(defun keys-between (times values width start end)
  "The keys of TIMES and VALUES (WIDTH wide) from START to END, as two lists:
times from 0, and values; exact samples at START and END bound them."
  (let ((inside (loop for time across times for i from 0
                      when (< start time end) collect i)))
    (values (append (list 0d0) (mapcar (lambda (i) (- (aref times i) start)) inside)
                    (and (> end start) (list (- end start))))
            (append (list (sample-keys times values width start))
                    (mapcar (lambda (i) (loop for k below width collect (aref values (+ (* i width) k)))) inside)
                    (and (> end start) (list (sample-keys times values width end)))))))

(defun player-rotation-keys (rig joint quats)
  "The model rotations QUATS (lists w x y z) of RIG's model joint JOINT as
Player rotations D = G_parent Q G_joint^-1, each within 180 degrees of the one before."
  (let ((parent (svref (rig-parent-rotations rig) joint))
        (inverse (qconjugate* (svref (rig-rest-rotations rig) joint)))
        (previous nil))
    (loop for q in quats
          collect (let ((d (qnormalize (q* (q* parent (qnormalize (apply #'make-quat q))) inverse))))
                    (when (and previous (minusp (+ (* (quat-w d) (quat-w previous)) (* (quat-x d) (quat-x previous))
                                                   (* (quat-y d) (quat-y previous)) (* (quat-z d) (quat-z previous)))))
                      (setf d (make-quat (- (quat-w d)) (- (quat-x d)) (- (quat-y d)) (- (quat-z d)))))
                    (setf previous d)))))

(defun qconjugate* (q)
  "The conjugate of the unit quaternion Q, a new QUAT (its inverse)."
  (make-quat (quat-w q) (- (quat-x q)) (- (quat-y q)) (- (quat-z q))))

(defun doubles (list)
  "LIST of reals (or of lists of reals, flattened) as a DOUBLES vector."
  (let ((flat (if (and list (listp (first list))) (apply #'append list) list)))
    (map 'doubles (lambda (x) (float x 1d0)) flat)))

;;;# Clips from animations

(defun root-travel (rig animation start end)
  "The root's travel in ANIMATION between START and END: two values, times
and x y z offsets in Player's space from the root's rest position, taken from
the highest joint with position keys; NIL when no joint has any."
  (let* ((model (rig-model rig))
         (channels (remove-if (lambda (channel) (zerop (length (channel-position-times channel))))
                              (model-animation-channels animation)))
         (depth (lambda (channel)
                  (loop for j = (channel-joint channel) then (joint-parent (svref (model-joints model) j))
                        while j count t)))
         (top (first (sort (copy-list channels) #'< :key depth))))
    (when top
      (let* ((joint (channel-joint top))
             (parent (joint-parent (svref (model-joints model) joint)))
             (frame (affine* (rig-placement rig)
                             (if parent (svref (rig-world-rest rig) parent) (identity-transform))))
             (rest (joint-translation (svref (model-joints model) joint))))
        (multiple-value-bind (times values)
            (keys-between (channel-position-times top) (channel-positions top) 3 start end)
          (values (doubles times)
                  (doubles (mapcar (lambda (p)
                                     ;; The displacement from rest, in the parent's frame, to Player's space.
                                     (let ((d (list (- (first p) (aref rest 0)) (- (second p) (aref rest 1))
                                                    (- (third p) (aref rest 2)))))
                                       (loop for row below 3
                                             collect (loop for k below 3 sum (* (aref frame row k) (nth k d))))))
                                   values))))))))

(defun morph-tracks (rig animation start end)
  "The (POSE-INDEX TIMES WEIGHTS) of each morph target ANIMATION keys between
START and END, times from 0; one per target, the first channel naming it winning."
  (let ((model (rig-model rig))
        (tracks '()))
    (dolist (channel (model-animation-morph-channels animation) (nreverse tracks))
      (let ((count (morph-channel-target-count channel)))
        (dolist (mesh-index (morph-channel-meshes channel))
          (loop for target in (model-mesh-morphs (nth mesh-index (model-meshes model)))
                for k below count
                for index = (+ (rig-morph-base rig)
                               (position (morph-target-name target) (model-morph-targets model) :test #'string=))
                unless (find index tracks :key #'first)
                  do (let ((weights (make-array (length (morph-channel-times channel)) :element-type 'double-float)))
                       (dotimes (i (length weights))
                         (setf (aref weights i) (aref (morph-channel-weights channel) (+ (* i count) k))))
                       (multiple-value-bind (times values)
                           (keys-between (morph-channel-times channel) weights 1 start end)
                         (push (list index (doubles times) (doubles values)) tracks)))))))))

(defun clip-morph-weight (track time)
  "The weight a morph TRACK, (POSE-INDEX TIMES WEIGHTS), keys at TIME, linearly
interpolated and held outside its keys."
  (destructuring-bind (index times weights) track
    (declare (ignore index))
    (first (sample-keys times weights 1 time))))

(defun make-animation-clip (rig animation &key name (start 0d0) end source)
  "The CLIP of RIG's model's ANIMATION from START to END seconds (default: all
of it), named NAME (default: the animation's, see CLIP-NAME-FROM-ANIMATION)."
  (let* ((end (float (or end (model-animation-duration animation)) 1d0))
         (start (float start 1d0))
         (tracks (loop for channel in (model-animation-channels animation)
                       when (plusp (length (channel-rotation-times channel)))
                         collect (multiple-value-bind (times quats)
                                     (keys-between (channel-rotation-times channel) (channel-rotations channel)
                                                   4 start end)
                                   (make-track (svref (rig-joint-map rig) (channel-joint channel))
                                               (doubles times)
                                               (doubles (mapcar (lambda (q) (list (quat-w q) (quat-x q) (quat-y q) (quat-z q)))
                                                                (player-rotation-keys rig (channel-joint channel) quats))))))))
    (multiple-value-bind (root-times root-offsets) (root-travel rig animation start end)
      (make-motion-clip (or name (clip-name-from-animation (model-animation-name animation)))
                 (- end start)
                 (coerce (sort tracks #'< :key #'track-joint) 'simple-vector)
                 :root-times root-times :root-offsets root-offsets
                 :morph-tracks (morph-tracks rig animation start end)
                 :source (or source (format nil "~A, animation ~S" (file-namestring (model-file (rig-model rig)))
                                            (model-animation-name animation)))))))

;;;# Sampling

(declaim (inline sample-track-quat))

(defun sample-track-quat (track time)
  "TRACK's rotation at TIME (seconds from the clip's start, held outside its
keys): the slerp of the two keys around it, as four values w x y z."
  (declare (type clip-track track) (type double-float time) (optimize (speed 3) (safety 1)))
  (let* ((times (track-times track))
         (quats (track-quats track))
         (n (length times)))
    (if (or (= n 1) (<= time (aref times 0)) (>= time (aref times (1- n))))
        (let ((k (if (or (= n 1) (<= time (aref times 0))) 0 (* 4 (1- n)))))
          (values (aref quats k) (aref quats (+ k 1)) (aref quats (+ k 2)) (aref quats (+ k 3))))
        ;; Binary search for the key interval [lo, lo + 1] holding TIME.
        (let ((lo 0) (hi (1- n)))
          (declare (type fixnum lo hi))
          (loop while (> (- hi lo) 1)
                do (let ((mid (ash (+ lo hi) -1)))
                     (if (<= (aref times mid) time) (setf lo mid) (setf hi mid))))
          (let* ((u (/ (- time (aref times lo)) (- (aref times hi) (aref times lo))))
                 (a (* 4 lo)) (b (* 4 hi))
                 (cosine (+ (* (aref quats a) (aref quats b)) (* (aref quats (+ a 1)) (aref quats (+ b 1)))
                            (* (aref quats (+ a 2)) (aref quats (+ b 2))) (* (aref quats (+ a 3)) (aref quats (+ b 3)))))
                 (cosine (max -1d0 (min 1d0 cosine))))
            (declare (type double-float u cosine))
            (multiple-value-bind (ka kb)
                (if (> cosine 0.9995d0)
                    (values (- 1d0 u) u)    ; nearly equal: lerp, renormalised below
                    (let* ((angle (acos cosine)) (sine (sin angle)))
                      (values (/ (sin (* (- 1d0 u) angle)) sine) (/ (sin (* u angle)) sine))))
              (declare (type double-float ka kb))
              (let* ((w (+ (* ka (aref quats a)) (* kb (aref quats b))))
                     (x (+ (* ka (aref quats (+ a 1))) (* kb (aref quats (+ b 1)))))
                     (y (+ (* ka (aref quats (+ a 2))) (* kb (aref quats (+ b 2)))))
                     (z (+ (* ka (aref quats (+ a 3))) (* kb (aref quats (+ b 3)))))
                     (norm (sqrt (+ (* w w) (* x x) (* y y) (* z z)))))
                (values (/ w norm) (/ x norm) (/ y norm) (/ z norm)))))))))

(declaim (ftype (function (clip-track double-float doubles fixnum) (values)) sample-track-angles))

(defun sample-track-angles (track time out offset)
  "Write TRACK's three DOF angles (degrees) at TIME (seconds from the clip's
start, held outside its keys) into OUT at OFFSET."
  (declare (optimize (speed 3) (safety 1)))
  (multiple-value-bind (w x y z) (sample-track-quat track time)
    (multiple-value-bind (a b c) (%quat-to-xyz-degrees w x y z)
      (setf (aref out offset) a (aref out (+ offset 1)) b (aref out (+ offset 2)) c)))
  (values))

(defun clip-angles (clip time &optional (out (make-array (* 3 (length (clip-tracks clip)))
                                                         :element-type 'double-float)))
  "The DOF angles (degrees) of every joint CLIP moves at TIME seconds from its
start (held before 0 and after its end): three per track (x y z), in track
order, stored into OUT and returned."
  (let ((time (float time 1d0)))
    (loop for track across (clip-tracks clip)
          for offset of-type fixnum from 0 by 3
          do (sample-track-angles track time out offset))
    out))

(defun clip-root-offset (clip time)
  "Where CLIP has moved its root at TIME from where the root rests, a vec3 in
Player's space (zero for a clip that does not move it)."
  (if (clip-root-times clip)
      (apply #'make-vec3 (sample-keys (clip-root-times clip) (clip-root-offsets clip) 3 (float time 1d0)))
      (vec3)))

;;;# The clips of a rig

(defun add-rig-clip (rig clip form)
  "Add CLIP to RIG's clips; a RIG-ERROR about FORM when its name is taken."
  (when (find-clip rig (clip-name clip))
    (rig-fail form "two clips are called ~A" (clip-name clip)))
  (setf (gethash (clip-name clip) (rig-clips rig)) clip))

(defun add-animation-clips (rig)
  "Make each animation of RIG's model a clip under its CLIP-NAME-FROM-ANIMATION
name (with -2, -3... after a name taken already)."
  (dolist (animation (model-animations (rig-model rig)) rig)
    (let ((base (clip-name-from-animation (model-animation-name animation))))
      (add-rig-clip rig (make-animation-clip rig animation
                                             :name (loop for n from 1
                                                         for name = (if (= n 1) base (format nil "~A-~D" base n))
                                                         unless (find-clip rig name) return name))
                    animation))))

(defun clip-animation (rig designator form)
  "The animation of RIG's model DESIGNATOR names (its name, or its index from
0); the only one when DESIGNATOR is NIL.  A RIG-ERROR about FORM otherwise."
  (let ((animations (model-animations (rig-model rig)))
        (file (file-namestring (model-file (rig-model rig)))))
    (cond ((null animations) (rig-fail form "~A has no animations to cut a clip from" file))
          ((integerp designator)
           (or (and (< -1 designator (length animations)) (nth designator animations))
               (rig-fail form "~A has animations 0 to ~D, not ~D" file (1- (length animations)) designator)))
          ((or (stringp designator) (and designator (symbolp designator)))
           (or (find (string designator) animations :key #'model-animation-name :test #'string-equal)
               (find (string designator) animations
                     :key (lambda (a) (clip-name-from-animation (model-animation-name a))) :test #'string-equal)
               (rig-fail form "~A has no animation ~A (animations: ~{~S~^ ~})" file (lisp-text designator)
                         (mapcar #'model-animation-name animations))))
          ((null designator)
           (if (rest animations)
               (rig-fail form "~A has ~D animations: say which with :animation NAME-OR-INDEX" file (length animations))
               (first animations)))
          (t (rig-fail form ":animation is an animation's name or index, not ~A" (lisp-text designator))))))

(defun cut-clip (rig form)
  "Add to RIG the clip FORM, (NAME :from FRAME :to FRAME :fps N [:animation
NAME-OR-INDEX]), cut out of an animation by frame range: frames count from 0
at the animation's start, N a second.  A RIG-ERROR for a malformed form or a
range outside the animation."
  (unless (and (alexandria:proper-list-p form) (first form) (symbolp (first form))
               (not (keywordp (first form))) (evenp (length (rest form))))
    (rig-fail form "a clip is written (NAME :from FRAME :to FRAME :fps N [:animation NAME-OR-INDEX])"))
  (destructuring-bind (&key (from nil from-p) (to nil to-p) (fps nil fps-p) animation &allow-other-keys) (rest form)
    (let ((unknown (loop for key in (rest form) by #'cddr
                         unless (member key '(:from :to :fps :animation)) collect key)))
      (when unknown
        (rig-fail form "clip ~A: unknown option ~A (known: :from :to :fps :animation)"
                  (lisp-text (first form)) (lisp-text (first unknown)))))
    (unless (and from-p to-p fps-p)
      (rig-fail form "clip ~A needs :from, :to and :fps" (lisp-text (first form))))
    (unless (and (realp from) (realp to) (<= 0 from to) (realp fps) (< 0 fps 100000))
      (rig-fail form "clip ~A: :from and :to are frames with 0 <= FROM <= TO, :fps a positive rate"
                (lisp-text (first form))))
    (let* ((animation (clip-animation rig animation form))
           (start (/ from fps 1d0))
           (end (/ to fps 1d0))
           (length (model-animation-duration animation)))
      (when (> end (+ length 1d-9))
        (rig-fail form "clip ~A: frame ~A at ~A fps is ~A s, past the end of animation ~S (~A s, frame ~A)"
                  (lisp-text (first form)) (format-number to) (format-number fps) (format-number end)
                  (model-animation-name animation) (format-number length) (format-number (* length fps))))
      (add-rig-clip rig (make-animation-clip rig animation :name (string-downcase (first form))
                                                           :start start :end (min end length))
                    form))))
