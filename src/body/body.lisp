;;;; body.lisp -- a character in a scene: a skeleton, its pose, the arbitrator
;;;; of its DOF channels and the drivers that move it.  BODY-EVALUATE composes
;;;; the pose for a time: drivers start and finish in time order, each channel
;;;; takes its owner's angle, crossfading from the angle it had when the owner
;;;; changed; a channel nobody drives holds its last angle; additive drivers
;;;; (idle noise) add on top; joint limits clamp the result.

(in-package #:player.body)

(defparameter *default-blend-time* 0.2d0
  "Seconds a change of a channel's owner crossfades over, unless a call gives :blend.")

(defclass body (scene-object)
  ((skeleton :initarg :skeleton :reader body-skeleton)
   (scene :initarg :scene :initform nil :accessor body-scene
          :documentation "The scene targets are resolved in, or NIL.")
   (arbitrator :reader body-arbitrator)
   (blend-time :initarg :blend-time :initform *default-blend-time* :reader body-blend-time)
   (pose :reader body-pose :documentation "The final pose at BODY-TIME: clamped, additive drivers added.")
   (base :reader body-base :documentation "The composed pose before additive drivers.")
   (held :reader body-held :documentation "Per channel, the angle it had at its last change of owner.")
   (owners :reader body-owners :documentation "Per channel, its owner, or NIL.")
   (handovers :reader body-handovers :documentation "Per channel, the time of its last change of owner.")
   (blends :reader body-blends :documentation "Per channel, that change's crossfade seconds
\(for a settling channel nobody drives: the seconds its settling takes).")
   (target :reader body-target :documentation "The settled pose: where settling channels go (settling.lisp).")
   (settling :reader body-settling
             :documentation "Per channel, true when, driven by nobody, it eases to the settled pose instead of holding.")
   (last-owners :reader body-last-owners :documentation "Per channel, the last driver that owned it, or NIL.")
   (sharers :reader body-sharers
            :documentation "Per channel, the drivers of equal priority its owner blends with (itself first), or NIL.")
   (shared :initform nil :accessor body-shared-p :documentation "True when some channel has sharers.")
   (sharing :initform (make-hash-table :test 'eq) :reader body-sharing
            :documentation "SHARERS-CHANNELS' table: each driver among some channel's sharers -> those channels.")
   (sharing-stale :initform t :accessor body-sharing-stale-p
                  :documentation "True when the sharers changed since SHARING was made.")
   (share-sums :reader body-share-sums :documentation "Per channel, the weighted sum of its sharers' angles.")
   (share-weights :reader body-share-weights :documentation "Per channel, the sum of its sharers' weights.")
   (scratch :reader body-scratch :documentation "Per channel, room for an angle an idle driver is about to change.")
   (transforms :reader body-transforms :documentation "The joints' world transforms at BODY-TIME.")
   (pending :initform '() :accessor body-pending :documentation "Drivers not yet started, by start time.")
   (active :initform '() :accessor body-active :documentation "Started drivers, least precedence first.")
   (serial :initform 0 :accessor body-serial)
   (recompose :initform nil :accessor body-recompose-p
              :documentation "True when the pose at the time last composed changed since:
a channel handed over or let go with no crossfade, an additive driver started or ended.")
   (gaze-starts :initform (make-array 8 :element-type 'double-float :adjustable t :fill-pointer 0)
                :reader body-gaze-starts
                :documentation "When each gaze driver started, increasing, each time once: a
blink driver blinks at those after its own start (one record, read by every blink driver
with a binary search, where each scanning the active drivers made many blinks cubic).")
   (seed :initarg :seed :initform 0 :accessor body-seed
         :documentation "Mixed into the seeds of random drivers (blink), so a run can be varied.")
   (reports :initform '() :accessor body-reports :documentation "(TIME DRIVER TEXT) of finished drivers, newest first.")
   (time :initform nil :accessor body-time :documentation "The time last evaluated, or NIL.")
   (birth :initform nil :accessor body-birth
          :documentation "The first time evaluated: drivers starting then set the initial pose, with no crossfade."))
  (:default-initargs :kind :body)
  (:documentation "A character: a scene object with a skeleton and drivers.  Its
POSITION and ROTATION place the skeleton's rest frame in the world."))

(defun body-p (x)
  "Is X a body?"
  (typep x 'body))

(defmethod initialize-instance :after ((body body) &key)
  (let* ((skeleton (body-skeleton body))
         (count (skeleton-channel-count skeleton)))
    (flet ((angles () (make-pose skeleton))
           (slots (initial) (make-array count :initial-element initial)))
      (setf (slot-value body 'arbitrator) (make-arbitrator :blend-time (body-blend-time body))
            (slot-value body 'pose) (angles)
            (slot-value body 'base) (angles)
            (slot-value body 'held) (angles)
            (slot-value body 'owners) (slots nil)
            (slot-value body 'target) (angles)
            ;; A channel nobody ever drove is settled: it follows the settled pose.
            (slot-value body 'settling) (slots t)
            (slot-value body 'last-owners) (slots nil)
            (slot-value body 'sharers) (slots nil)
            (slot-value body 'share-sums) (angles)
            (slot-value body 'share-weights) (angles)
            (slot-value body 'scratch) (angles)
            (slot-value body 'handovers) (make-array count :element-type 'double-float
                                                           :initial-element 0d0)
            (slot-value body 'blends) (make-array count :element-type 'double-float
                                                        :initial-element 0d0)
            (slot-value body 'transforms)
            (pose-world-transforms skeleton (body-pose body))))
    (define-body-properties body)))

(defun make-body (name skeleton &key scene (position (vec3)) (rotation (quat))
                                     (blend-time *default-blend-time*))
  "A body called NAME with SKELETON (a SKELETON or a name for LOAD-SKELETON) in
its rest pose, placed at POSITION with ROTATION, added to SCENE when given."
  (check-argument 'make-body 'name name #'string-designator-p "a body's name (a symbol or string)")
  (check-argument 'make-body 'skeleton skeleton
                  (lambda (x) (or (skeleton-p x) (symbolp x) (pathname-designator-p x)))
                  "a skeleton (from load-skeleton), or a name or path for load-skeleton")
  (check-argument 'make-body :scene scene (lambda (x) (or (null x) (typep x 'scene))) "NIL or a scene")
  (check-argument 'make-body :position position #'finite-vec3-p "a vec3 of finite numbers")
  (check-argument 'make-body :rotation rotation
                  (lambda (x) (and (finite-quat-p x) (plusp (qnorm x))))
                  "a nonzero quat of finite numbers")
  (check-real 'make-body :blend-time blend-time :minimum 0 :maximum *max-seconds*)
  (when (and scene (find-object scene name nil))
    (argument-fail 'make-body 'name name "a name no object of the scene has yet"))
  (let ((body (make-instance 'body :name name
                                   :skeleton (if (skeleton-p skeleton) skeleton (load-skeleton skeleton))
                                   :scene scene :position position :rotation rotation
                                   :blend-time (float blend-time 1d0))))
    (when scene (add-object scene body))
    body))

(defmethod object-joint-transform ((body body) joint-name)
  (svref (body-transforms body)
         (body-joint-index (find-joint (body-skeleton body) joint-name t))))

;;;# Drivers in time

(defun body-add-driver (body driver)
  "Schedule DRIVER (made for BODY by MAKE-DRIVER) to start at its start time."
  (check-argument 'body-add-driver 'body body #'body-p "a body (from make-body)")
  (check-argument 'body-add-driver 'driver driver
                  (lambda (x) (and (typep x 'driver) (eq (driver-body x) body)))
                  "a driver made for this body (by make-driver)")
  (setf (body-pending body)
        (merge 'list (body-pending body) (list driver) #'< :key #'driver-start))
  driver)

(defun body-stop-driver (body driver time)
  "Make DRIVER, pending or active, stop at TIME (or earlier if it ends by itself)."
  (check-argument 'body-stop-driver 'body body #'body-p "a body (from make-body)")
  (check-argument 'body-stop-driver 'driver driver
                  (lambda (x) (and (typep x 'driver) (eq (driver-body x) body)))
                  "a driver made for this body (by make-driver)")
  (check-seconds 'body-stop-driver 'time time)
  (setf (driver-stop driver) (if (driver-stop driver) (min time (driver-stop driver)) time)
        (driver-finish driver) (driver-finish-time driver)))

(defun next-body-event (body time)
  "The next start or finish at or before TIME, as (values KIND DRIVER WHEN), finishes first."
  (let ((finish nil) (finish-time nil))
    (dolist (driver (body-active body))
      (let ((when (driver-finish driver)))
        (when (and when (<= when time) (or (null finish-time) (< when finish-time)))
          (setf finish driver finish-time when))))
    (let ((start (first (body-pending body))))
      (cond ((and finish (or (null start) (<= finish-time (driver-start start))))
             (values :finish finish finish-time))
            ((and start (<= (driver-start start) time))
             (values :start start (driver-start start)))
            (t nil)))))

(defun driver-precedes-p (body a b)
  "Does A write before B when composing (so B wins a channel both drive)?
Lower priority first; between equals, the later request first unless it
usurps; a slave just before its master."
  (declare (ignore body))
  (let ((pa (driver-priority a)) (pb (driver-priority b)))
    (cond ((/= pa pb) (< pa pb))
          ((> (driver-sequence a) (driver-sequence b)) (not (driver-arg a :usurp)))
          (t (and (driver-arg b :usurp) t)))))

(defun start-driver (body driver time)
  "Start DRIVER at TIME: it captures the pose, requests its channels (its slaves
too) and joins the active drivers."
  (setf (body-pending body) (if (eq driver (first (body-pending body)))
                                (rest (body-pending body))
                                (remove driver (body-pending body))))
  (driver-begin driver (body-base body) time)
  (note-gaze-start body driver time)
  (let ((arbitrator (body-arbitrator body))
        (blend (if (and (body-birth body) (= time (body-birth body)))
                   0d0
                   (or (driver-arg driver :blend) (driver-default-blend driver) (body-blend-time body)))))
    (dolist (d (cons driver (slave-drivers driver)))
      ;; A slave sorts just before its master, so a master sees its slave's angles.
      (setf (driver-sequence d) (+ (incf (body-serial body)) (if (eq d driver) 0.5 0))
            (driver-finish d) (driver-finish-time d))
      (unless (eq d driver)
        (add-slave arbitrator driver d))
      (unless (driver-additive-p d)
        (request-channels arbitrator d (driver-channels d)
                          :priority (driver-priority driver) :time time :blend blend
                          :usurp (driver-arg driver :usurp)))
      (setf (body-active body)
            (merge 'list (body-active body) (list d)
                   (lambda (a b) (driver-precedes-p body a b)))))))

(defun note-gaze-start (body driver time)
  "Record TIME among BODY's gaze starts when DRIVER is a gaze driver."
  (when (eq (motor-call-function (driver-call driver)) :gaze)
    (let ((starts (body-gaze-starts body))
          (time (float time 1d0)))
      (unless (and (plusp (fill-pointer starts)) (= time (aref starts (1- (fill-pointer starts)))))
        (vector-push-extend time starts)))))

(defun note-instant-change (body channel time)
  "CHANNEL of BODY was just stamped at TIME: when it moves at once (no
crossfade, or one stamped before TIME), the pose composed at TIME is stale."
  (when (or (<= (aref (body-blends body) channel) 0d0)
            (/= (aref (body-handovers body) channel) time))
    (setf (body-recompose-p body) t)))

(defun finish-driver (body driver time)
  "End DRIVER (and its slaves) at TIME, releasing their channels."
  (let ((arbitrator (body-arbitrator body))
        (blend (or (driver-arg driver :blend) (driver-default-blend driver) (body-blend-time body))))
    (dolist (d (cons driver (slave-drivers driver)))
      (release-driver arbitrator d :time time :blend blend)
      (setf (body-active body) (remove d (body-active body))))
    (let ((report (driver-report driver)))
      (when report (push (list time driver report) (body-reports body))))))

(defun refresh-owners (body time)
  "Re-read each channel's owner; where it changed, hold the angle the channel
has now and stamp the crossfade.  A channel a driver takes holds when let go
until told to settle; one let go while settling starts settling now."
  (let ((arbitrator (body-arbitrator body)))
    (dotimes (i (length (body-owners body)))
      (let ((owner (channel-owner arbitrator i)))
        (unless (eq owner (svref (body-owners body) i))
          (multiple-value-bind (handover blend) (channel-handover arbitrator i)
            (setf (svref (body-owners body) i) owner
                  (aref (body-held body) i) (aref (body-base body) i)
                  (aref (body-handovers body) i) (float (or handover time) 1d0)
                  (aref (body-blends body) i) (float blend 1d0))
            (cond (owner (setf (svref (body-last-owners body) i) owner
                               (svref (body-settling body) i) nil))
                  ((svref (body-settling body) i)
                   (setf (aref (body-blends body) i)
                         (settle-seconds (channel-travel body i)))))
            (note-instant-change body i time)))))
    (refresh-sharers body time)))

;;;# Composition

(defun compose-pose (body time)
  "Compose BODY's pose for TIME from its active drivers; update its transforms."
  (let* ((skeleton (body-skeleton body))
         (base (body-base body))
         (pose (body-pose body))
         (held (body-held body))
         (owners (body-owners body))
         (time (float time 1d0)))
    (declare (type pose base pose held))
    (replace base held)
    (setf (body-time body) time)
    (unless (body-birth body)
      (setf (body-birth body) time))
    ;; Geometric drivers read the pose so far, so each sees the writes of those before it.
    (if (body-shared-p body)
        (drive-sharing body time base)
        (dolist (driver (body-active body))
          (unless (driver-additive-p driver)
            (drive-owned driver time base))))
    (let ((blends (body-blends body))
          (handovers (body-handovers body))
          (settling (body-settling body))
          (target (body-target body)))
      (declare (type (simple-array double-float (*)) blends handovers) (type pose target)
               (type simple-vector settling owners))
      (dotimes (i (length base))
        (let* ((blend (aref blends i))
               (since (- time (aref handovers i)))
               (from (aref held i)))
          (declare (type double-float blend since from))
          (cond ((svref owners i)
                 (let ((u (if (<= blend 0d0) 1d0 (min 1d0 (max 0d0 (/ since blend))))))
                   (setf (aref base i) (+ from (* u (- (aref base i) from))))))
                ;; As SETTLING-VALUE: held, or eased toward the settled pose.
                ((svref settling i)
                 (setf (aref base i)
                       (+ from (* (if (<= blend 0d0) 1d0 (minimum-jerk (/ since blend)))
                                  (- (aref target i) from)))))
                (t (setf (aref base i) from))))))
    (%clamp-pose skeleton base)
    (replace pose base)
    (dolist (driver (body-active body))
      (when (driver-additive-p driver)
        (if (driver-idle-p driver)
            (drive-idle-layer body driver time pose)
            (driver-drive driver time pose))))
    (%clamp-pose skeleton pose)
    (limit-joint-speeds body pose time)
    (%pose-world-transforms skeleton pose (object-world-transform body) (body-transforms body))
    pose))

(defun body-evaluate (body time)
  "BODY's pose at TIME (seconds, not before the last time evaluated): drivers
start and finish in order up to TIME, then the pose is composed.  Returns the
pose (owned by BODY; copy it to keep it).  TIME before the last time evaluated
is an ARGUMENT-ERROR: make a fresh body to go back."
  (check-argument 'body-evaluate 'body body #'body-p "a body (from make-body)")
  (check-seconds 'body-evaluate 'time time)
  (when (and (body-time body) (< time (body-time body)))
    (argument-fail 'body-evaluate 'time time
                   (format nil "a time not before ~A, when body ~A was last evaluated (make a fresh body to go back)"
                           (format-number (body-time body)) (lisp-text (object-name body)))))
  (let ((composed nil))
    (loop
      (multiple-value-bind (kind driver when) (next-body-event body time)
        (unless kind (return))
        ;; Many drivers starting at one instant: composing again at the same
        ;; time gives the same pose (drivers are pure in time), unless what
        ;; happened since changed it there (RECOMPOSE-P); composing for each
        ;; made them quadratic.
        (unless (and composed (= when composed) (not (body-recompose-p body)))
          (compose-pose body when)
          (setf composed when (body-recompose-p body) nil))
        (when (driver-additive-p driver)
          (setf (body-recompose-p body) t))
        (ecase kind
          (:start (start-driver body driver when)
           (take-channel-sets body driver))
          (:finish (finish-driver body driver when)))
        (lose-channel-sets body when)
        (refresh-owners body when)))
    ;; Composed at TIME already, before what started then, and unchanged by it.
    (if (and composed (= time composed) (not (body-recompose-p body)))
        (body-pose body)
        (compose-pose body time))))

(defun body-joint-position (body joint-name)
  "Where BODY's joint JOINT-NAME (or the joint of a role keyword) is, at the last evaluation."
  (check-argument 'body-joint-position 'body body #'body-p "a body (from make-body)")
  (check-argument 'body-joint-position 'joint-name joint-name #'string-designator-p
                  "a joint's name (a symbol or string) or a role keyword")
  (let ((joint (if (keywordp joint-name)
                   (let ((filled (skeleton-role (body-skeleton body) joint-name)))
                     (cond ((body-joint-p filled) filled)
                           ((and (consp filled) (body-joint-p (car (last filled)))) (car (last filled)))
                           (t (skeleton-fail joint-name "skeleton ~A fills no role ~A"
                                             (lisp-text (skeleton-name (body-skeleton body)))
                                             (lisp-text joint-name)))))
                   (find-joint (body-skeleton body) joint-name t))))
    (joint-world-position (body-transforms body) joint)))

;;;# Targets

(defun target-joint (body name form)
  "BODY's joint called NAME, or filling the role NAME (a keyword); a MOTOR-ERROR naming FORM otherwise."
  (let* ((skeleton (body-skeleton body))
         (joint (if (keywordp name) (skeleton-role skeleton name) (find-joint skeleton name))))
    (cond ((body-joint-p joint) joint)
          ((and (consp joint) (body-joint-p (car (last joint)))) (car (last joint)))
          (t (motor-fail form "body ~A has no joint or role ~A" (lisp-text (object-name body))
                         (lisp-text name))))))

(defun target-object (body name form)
  "The scene object NAME (:self is BODY) for the target FORM."
  (cond ((eq name :self) body)
        ((null (body-scene body))
         (motor-fail form "body ~A is in no scene, so it cannot find ~A"
                     (lisp-text (object-name body)) (lisp-text name)))
        (t (or (find-object (body-scene body) name nil)
               (motor-fail form "the scene has no object ~A" (lisp-text name))))))

(defun resolve-target (target body &optional pose)
  "The world point TARGET (a :target form) names, seen from BODY.  A joint of
BODY itself is placed by POSE when given (the pose being composed), else by
BODY's last evaluation.  An :offset is in the frame of the joint or object;
a :point is in the frame BODY's parent gives (the world when it has none)."
  (check-argument 'resolve-target 'body body #'body-p "a body (from make-body)")
  (check-argument 'resolve-target 'target target #'target-form-p
                  "a target: (:point x y z), (:object name) or (:joint object joint), each with an optional :offset (x y z)")
  (when pose
    (check-argument 'resolve-target 'pose pose (lambda (x) (pose-of-p (body-skeleton body) x))
                    (pose-phrase (body-skeleton body))))
  (%resolve-target target body pose))

(defun %resolve-target (target body &optional pose)
  "RESOLVE-TARGET of arguments known to be right: a driver's checked call, its body's pose."
  (destructuring-bind (kind &rest arguments) target
    (let* ((offset-form (getf (member :offset target) :offset))
           (offset (if offset-form (apply #'make-vec3 offset-form) (vec3)))
           (frame
             (ecase kind
               ;; A point is in the space BODY stands in: the world, or the
               ;; stage a cast member's scene hangs from (src/cast/).
               (:point (transform-compose (parent-world-transform body)
                                          (make-transform :translation (apply #'make-vec3 (subseq arguments 0 3)))))
               (:object (object-world-transform (target-object body (first arguments) target)))
               (:joint
                (let ((object (target-object body (first arguments) target)))
                  (unless (typep object 'body)
                    (motor-fail target "~A is not a body, so it has no joints"
                                (lisp-text (first arguments))))
                  (let ((joint (target-joint object (second arguments) target)))
                    (if (and pose (eq object body))
                        (joint-world-transform (body-skeleton body) pose joint
                                               (object-world-transform body))
                        (svref (body-transforms object) (body-joint-index joint)))))))))
      (transform-point frame offset))))
