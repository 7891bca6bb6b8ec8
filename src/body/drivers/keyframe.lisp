;;;; keyframe.lisp -- Pantomime's keyframe and shape drivers (ArmKFMotion,
;;;; HandShape): play a list of timed poses, interpolated per DOF by keys
;;;; controls; and :pose, the shorthand that eases into one named pose.

(in-package #:player.body)

(defclass keyframe-driver (driver)
  ((times :initform '() :accessor keyframe-times
          :documentation "Key times in seconds from the start, increasing, the first 0.")
   (keys :initform '() :accessor keyframe-keys
         :documentation "Per key, :START or its (INDEX . DEGREES) entries.")
   (controls :initform #() :accessor keyframe-controls
             :documentation "Per channel, a keys control of local time, made in DRIVER-BEGIN.")
   (limits :initform #() :accessor keyframe-limits
           :documentation "Per channel, its DOF's limits (MIN . MAX) in degrees."))
  (:documentation "Plays timed poses: each DOF any key names follows a keys control
through the keys' angles; a key that does not name a DOF keeps the previous
key's angle for it (the start angle before the first key)."))

(define-motor-function :keyframe keyframe-driver
  "Play timed poses, interpolating every DOF they name; ends after the last key unless :loop or :hold."
  (:keys :list :required
   "((SECONDS POSE) ...), seconds from the start, increasing; POSE is a pose name from the body's library, clauses ((JOINT-OR-ROLE DOF DEGREES ...) ...), or :start (the pose at the start); without a key at 0 the first key is eased into from the start pose")
  (:interpolation (:member :step :linear :ease :ease-in-out :catmull-rom) :ease
   "how angles move between keys: :ease (ease-in-out, resting at each key), :linear, :step, :catmull-rom")
  (:loop :boolean nil "repeat from the start after the last key, forever")
  (:hold :boolean nil "after the last key keep holding it until stopped, instead of ending")
  (:repeat (:or :positive (:member nil)) nil "play the keys this many times (a whole number), then end or hold")
  (:priority :real 10 "arbitration priority; higher wins"))

(defclass pose-driver (keyframe-driver)
  ()
  (:documentation "The :pose shorthand: a keyframe driver easing from the start
pose into one named pose and holding it."))

(define-motor-function :pose pose-driver
  "Ease from where the body is into a named pose of its pose library over :duration, then hold it."
  (:name :symbol :required "the pose's name in the body's pose library")
  (:duration :non-negative 0.5 "seconds to reach the pose")
  (:priority :real 10 "arbitration priority; higher wins"))

;;;# What a call asks for

(defgeneric keyframe-key-forms (driver)
  (:documentation "DRIVER's keys as written: ((SECONDS POSE) ...).")
  (:method ((driver keyframe-driver)) (driver-arg driver :keys))
  (:method ((driver pose-driver))
    (let ((duration (driver-arg driver :duration))
          (name (driver-arg driver :name)))
      (if (zerop duration)
          `((0 ,name))
          `((0 :start) (,duration ,name))))))

(defgeneric keyframe-interpolation (driver)
  (:documentation "The KEYS-CONTROL interpolation mode of DRIVER's channels.")
  (:method ((driver keyframe-driver))
    (let ((mode (driver-arg driver :interpolation)))
      (if (eq mode :ease) :ease-in-out mode)))
  (:method ((driver pose-driver)) :ease-in-out))

(defgeneric keyframe-loop-p (driver)
  (:documentation "Does DRIVER repeat its keys forever?")
  (:method ((driver keyframe-driver)) (driver-arg driver :loop))
  (:method ((driver pose-driver)) nil))

(defgeneric keyframe-hold-p (driver)
  (:documentation "Does DRIVER hold its last key until stopped?")
  (:method ((driver keyframe-driver)) (driver-arg driver :hold))
  (:method ((driver pose-driver)) t))

;;;# The protocol

(defun parse-keyframe-key (driver key)
  "KEY, (SECONDS POSE), as (SECONDS . :START-or-ENTRIES); a MOTOR-ERROR when malformed."
  (unless (and (alexandria:proper-list-p key) (= (length key) 2) (realp (first key)))
    (driver-frame-fail driver "a key is written (SECONDS POSE), not ~A" (lisp-text key)))
  (destructuring-bind (time pose) key
    (cons time
          (cond ((eq pose :start) :start)
                ((and pose (symbolp pose)) (driver-resolve-pose driver pose))
                (t (driver-resolve-clauses driver pose))))))

(defmethod driver-setup ((driver keyframe-driver))
  (let ((forms (keyframe-key-forms driver))
        (repeat (keyframe-repeat driver)))
    (when (and repeat (not (integerp repeat)))
      (driver-frame-fail driver ":repeat must be a whole number of times, not ~A" (lisp-text repeat)))
    (when (and repeat (keyframe-loop-p driver))
      (driver-frame-fail driver ":repeat and :loop t contradict each other: give one"))
    (unless (and (alexandria:proper-list-p forms) forms)
      (driver-frame-fail driver ":keys must be a nonempty list of (SECONDS POSE) keys"))
    (let ((keys (mapcar (lambda (key) (parse-keyframe-key driver key)) forms)))
      (check-increasing-times driver (mapcar #'car keys) "key times")
      ;; Ease into the first key from wherever the body is.
      (unless (zerop (car (first keys)))
        (push (cons 0 :start) keys))
      (setf (keyframe-times driver) (mapcar (lambda (key) (float (car key) 1d0)) keys)
            (keyframe-keys driver) (mapcar #'cdr keys))
      (let ((channels (sort (remove-duplicates (loop for entries in (keyframe-keys driver)
                                                     unless (eq entries :start)
                                                       append (mapcar #'car entries)))
                            #'<)))
        (setf (keyframe-limits driver)
              (map 'simple-vector
                   (lambda (index)
                     (multiple-value-bind (low high) (channel-limits (driver-skeleton driver) index)
                       (cons low high)))
                   channels))
        channels))))

(defun channel-key-values (keys index start)
  "The angle of channel INDEX at each of KEYS, holding the previous key's angle
where a key does not name it, START at :start keys and before the first."
  (let ((current start))
    (loop for entries in keys
          do (setf current (if (eq entries :start)
                               start
                               (let ((entry (assoc index entries)))
                                 (if entry (cdr entry) current))))
          collect current)))

(defmethod driver-begin ((driver keyframe-driver) pose time)
  (declare (ignore time))
  (let ((times (keyframe-times driver))
        (interpolation (keyframe-interpolation driver))
        (looping (keyframe-loop-p driver)))
    (setf (keyframe-controls driver)
          (map 'simple-vector
               (lambda (index)
                 (make-keys-control (mapcar #'cons times
                                            (channel-key-values (keyframe-keys driver) index
                                                                (aref pose index)))
                                    :interpolation interpolation :loop looping))
               (driver-channels driver)))))

(defgeneric keyframe-repeat (driver)
  (:documentation "How many times DRIVER plays its keys, or NIL for once (or for ever, with :loop).")
  (:method ((driver keyframe-driver)) (driver-arg driver :repeat))
  (:method ((driver pose-driver)) nil))

(defun keyframe-cycle-time (driver local)
  "LOCAL (seconds from DRIVER's start) within its keys: with :repeat N, the time
into the current repetition, the last key's time once all N are played."
  (let ((repeat (keyframe-repeat driver))
        (length (car (last (keyframe-times driver)))))
    (cond ((or (null repeat) (<= length 0d0)) local)
          ((>= local (* repeat length)) length)
          (t (mod local length)))))

(defmethod driver-drive ((driver keyframe-driver) time pose)
  (let ((local (keyframe-cycle-time driver (driver-local-time driver time))))
    (loop for index in (driver-channels driver)
          for control across (keyframe-controls driver)
          for (low . high) across (keyframe-limits driver)
          ;; Catmull-Rom may overshoot a key; aim within the limits all the same.
          do (setf (aref pose index) (max low (min high (control-value control local)))))))

(defmethod driver-end-time ((driver keyframe-driver))
  (unless (or (keyframe-loop-p driver) (keyframe-hold-p driver))
    (+ (driver-start driver) (* (or (keyframe-repeat driver) 1) (car (last (keyframe-times driver)))))))

(defmethod driver-default-blend ((driver pose-driver))
  ;; It eases from the angles it captured at its start: a crossfade would only slow it.
  0d0)

(defmethod driver-default-blend ((driver keyframe-driver))
  ;; Keys that begin from the captured start pose need no crossfade; a first
  ;; key at 0 that jumps to a pose keeps the body's, so nothing pops.
  (and (eq (first (keyframe-keys driver)) :start) 0d0))

(defmethod driver-channel-sets ((driver keyframe-driver))
  ;; Each limb's chain moves as one: keys that shape an arm lose it whole.
  (let ((skeleton (driver-skeleton driver)))
    (loop for role in '(:left-arm :right-arm :left-leg :right-leg)
          for joints = (ensure-list (skeleton-role skeleton role))
          for set = (remove-if-not (lambda (index) (member (skeleton-dof skeleton index) joints))
                                   (driver-channels driver))
          when (rest set) collect set)))
