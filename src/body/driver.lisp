;;;; driver.lisp -- the driver protocol: Pantomime's BaseDriver.  A driver
;;;; performs one motor-function call on one body: it names the DOF channels it
;;;; drives, captures what it needs from the pose at its start, and writes
;;;; target angles for any later time.  The body arbitrates, blends and clamps.
;;;; Below the protocol, the helpers every driver class shares: errors that
;;;; name the call, pose clauses, local time and easing, DOF limits.

(in-package #:player.body)

(defclass driver ()
  ((body :initarg :body :reader driver-body
         :documentation "The body this driver moves.")
   (call :initarg :call :reader driver-call
         :documentation "The checked MOTOR-CALL it performs.")
   (start :initarg :start :reader driver-start
          :documentation "Absolute time (seconds) it starts.")
   (stop :initarg :stop :initform nil :accessor driver-stop
         :documentation "Absolute time its script stops it, or NIL.")
   (finish :initform nil :accessor driver-finish
           :documentation "DRIVER-FINISH-TIME, kept from its start (and its stop's change), so
a body looking for the next end among many drivers reads a slot, not a generic function.")
   (channels :initform '() :accessor driver-channels
             :documentation "The pose indices it drives, from DRIVER-SETUP.")
   (sequence :initform 0 :accessor driver-sequence
             :documentation "When it started in its body, for the order of composition.")
   (reals :initform '() :accessor driver-reals
          :documentation "(KEY . DOUBLE) of the numeric parameters DRIVER-REAL has converted: once, not per frame.")
   (mood :initform 0d0 :accessor driver-mood
         :documentation "Its body's mood when it was made (mood.lisp): how it performs.")
   (lost :initform '() :accessor driver-lost
         :documentation "Channels a higher priority took since the body last looked (ON-CHANNEL-LOSS).")
   (released :initform '() :accessor driver-released
             :documentation "Channels it handed over with their set: its writes there are undone."))
  (:documentation "Base class of drivers.  A subclass implements DRIVER-SETUP and
DRIVER-DRIVE, and where it needs them DRIVER-BEGIN, DRIVER-END-TIME,
DRIVER-ADDITIVE-P, SLAVE-DRIVERS and DRIVER-REPORT."))

(defmethod print-object ((driver driver) stream)
  (print-unreadable-object (driver stream :type t :identity t)
    (format stream "~A from ~A" (lisp-text (motor-call-function (driver-call driver)))
            (format-number (driver-start driver)))))

(defun driver-arg (driver key)
  "The value of DRIVER's motor-call parameter KEY."
  (check-argument 'driver-arg 'driver driver (lambda (x) (typep x 'driver)) "a driver (from make-driver)")
  (check-argument 'driver-arg 'key key #'keywordp "a parameter's name (a keyword)")
  (motor-arg (driver-call driver) key))

(defmethod driver-priority ((driver driver))
  (driver-arg driver :priority))

(defun driver-skeleton (driver)
  "The skeleton of DRIVER's body."
  (body-skeleton (driver-body driver)))

;;;# The protocol

(defgeneric driver-setup (driver)
  (:documentation "Check DRIVER against its body's skeleton and return the pose
indices it drives.  Called once, when the driver is made; may signal
MOTOR-ERROR (the skeleton lacks a role, say)."))

(defgeneric driver-begin (driver pose time)
  (:documentation "DRIVER starts at TIME; POSE is its body's pose then (read it,
do not keep it).  Capture what DRIVE needs, such as where the eyes looked.")
  (:method ((driver driver) pose time)
    (declare (ignore pose time))
    nil))

(defgeneric driver-drive (driver time pose)
  (:documentation "Write DRIVER's target angles (degrees) for absolute TIME into
its channels of POSE.  A pure function of TIME, what DRIVER-BEGIN captured and
the scene at TIME: the same time gives the same angles."))

(defgeneric driver-end-time (driver)
  (:documentation "The absolute time DRIVER finishes on its own, or NIL when it
runs until its script stops it.")
  (:method ((driver driver))
    nil))

(defgeneric driver-additive-p (driver)
  (:documentation "True for a driver that adds offsets to the composed pose (idle
noise) instead of owning its channels through arbitration.")
  (:method ((driver driver))
    nil))

(defgeneric driver-idle-p (driver)
  (:documentation "True for a driver of idle life (breathing, saccades, the blink
reflex run as idle life): additive, it moves only channels no other driver
holds, fading out where one takes them, so any op overrides it.")
  (:method ((driver driver))
    nil))

(defgeneric driver-background-p (driver)
  (:documentation "True for motion that only textures the rest (idle noise, idle
life): an op playing it claims none of its channels.  Defaults to DRIVER-IDLE-P.")
  (:method ((driver driver))
    (driver-idle-p driver)))

(defgeneric driver-channel-sets (driver)
  (:documentation "Lists of DRIVER's channels that move together (an arm's chain,
the head and neck): taken together and lost together.  When a higher priority
takes one channel of a set, DRIVER's :on-channel-loss says what follows:
:hand-over gives up the whole set, :end ends DRIVER.  NIL (the default): every
channel stands alone.")
  (:method ((driver driver))
    nil))

(defun driver-weight (driver)
  "How much DRIVER counts where it blends with equals, or how much of an additive motion it adds."
  (driver-real driver :weight))

(defmethod on-channel-loss ((driver driver) channel new-owner)
  ;; The body decides at once what follows (LOSE-CHANNEL-SETS): it knows the time.
  (declare (ignore new-owner))
  (pushnew channel (driver-lost driver)))

(defgeneric slave-drivers (driver)
  (:documentation "The slave drivers DRIVER made in DRIVER-BEGIN (BaseDriver's
master/slave: gaze drives the head for large shifts).  They start with their
master, take its priority and end with it.")
  (:method ((driver driver))
    nil))

(defgeneric driver-default-blend (driver)
  (:documentation "Seconds DRIVER's changes of channel owner crossfade over when
its call gives no :blend; NIL (the default) for the body's blend time.  A
driver that starts from the angles it captured needs no crossfade: 0.")
  (:method ((driver driver))
    nil))

(defgeneric driver-report (driver)
  (:documentation "NIL, or a line of text about how DRIVER went that a presenter
should show (a reach that fell short, say).")
  (:method ((driver driver))
    nil))

(defun make-driver (call body start &key stop)
  "A driver performing the MOTOR-CALL CALL on BODY from START (until STOP, when
given), set up against BODY's skeleton.  START and STOP are finite numbers of
seconds, STOP not before START."
  (check-argument 'make-driver 'call call #'motor-call-p "a motor call (from parse-motor-frame)")
  (check-argument 'make-driver 'body body #'body-p "a body (from make-body)")
  (check-seconds 'make-driver 'start start)
  (when stop (check-seconds 'make-driver :stop stop :minimum start))
  (let* ((function (find-motor-function (motor-call-function call)))
         (driver (make-instance (motor-function-driver-class function)
                                :call call :body body :start start :stop stop)))
    (setf (driver-mood driver) (body-mood body)
          (driver-channels driver) (driver-setup driver))
    driver))

(defun gesture-amplitude (driver key)
  "DRIVER's numeric parameter KEY, an amplitude, scaled by the mood it was made in."
  (* (driver-real driver key) (+ 1d0 (* *mood-amplitude-range* (driver-mood driver)))))

(defun gesture-seconds (driver key)
  "DRIVER's numeric parameter KEY, a duration, shortened (or lengthened) by the mood it was made in."
  (/ (driver-real driver key) (+ 1d0 (* *mood-speed-range* (driver-mood driver)))))

(defun driver-finish-time (driver)
  "When DRIVER ends: the earlier of its own end and its stop, or NIL."
  (let ((end (driver-end-time driver))
        (stop (driver-stop driver)))
    (cond ((and end stop) (min end stop))
          (t (or end stop)))))

;;;# Helpers for driver classes

(defun role-joint (driver role &optional (errorp t))
  "The joint (or joint list) filling ROLE in DRIVER's skeleton; a MOTOR-ERROR
naming DRIVER's frame when the skeleton leaves ROLE unfilled, unless ERRORP is NIL."
  (or (skeleton-role (driver-skeleton driver) role)
      (and errorp
           (let ((skeleton (driver-skeleton driver)))
             (motor-fail (motor-call-frame (driver-call driver))
                         "skeleton ~A~@[ (the model ~A)~] has no ~A (motor function ~A needs it)"
                         (lisp-text (skeleton-name skeleton))
                         ;; An imported model's skeleton: name the file the user gave.
                         (and (skeleton-rig skeleton) (skeleton-source skeleton)
                              (file-namestring (skeleton-source skeleton)))
                         (lisp-text role)
                         (lisp-text (motor-call-function (driver-call driver))))))))

(defun ramp (time start duration)
  "0 before START, rising smoothly (smoothstep) to 1 at START + DURATION."
  (if (<= duration 0)
      (if (>= time start) 1d0 0d0)
      (smoothstep (max 0d0 (min 1d0 (/ (- time start) duration))))))

(defun driver-frame-fail (driver control &rest arguments)
  "Signal a MOTOR-ERROR about DRIVER's frame, the message starting with its function's name."
  (let ((call (driver-call driver)))
    (motor-fail (motor-call-frame call) "motor function ~A: ~?"
                (lisp-text (motor-call-function call)) control arguments)))

(defmacro with-pose-errors-as-motor-errors ((driver) &body body)
  "Run BODY; a POSE-ERROR it signals becomes a MOTOR-ERROR about DRIVER's frame,
so a bad call is reported as the call it is."
  `(handler-case (progn ,@body)
     (pose-error (condition)
       (driver-frame-fail ,driver "~A" condition))))

(defun driver-resolve-clauses (driver clauses)
  "The (INDEX . DEGREES) entries of the pose CLAUSES in DRIVER's skeleton,
:include and :mirror finding poses in its body's pose library; a MOTOR-ERROR
for clauses that do not fit."
  (unless (and (alexandria:proper-list-p clauses) clauses)
    (driver-frame-fail driver "~A is not a list of pose clauses ((JOINT-OR-ROLE DOF DEGREES ...) ...)"
                 (lisp-text clauses)))
  (with-pose-errors-as-motor-errors (driver)
    (resolve-clauses clauses (driver-skeleton driver)
                     :library (body-pose-library (driver-body driver)))))

(defun driver-resolve-pose (driver name)
  "The (INDEX . DEGREES) entries of the pose NAME from DRIVER's body's pose library."
  (with-pose-errors-as-motor-errors (driver)
    (resolve-pose (find-pose (body-pose-library (driver-body driver)) name)
                  (driver-skeleton driver))))

(defun driver-local-time (driver time)
  "TIME as seconds since DRIVER's start, a double-float."
  (- (float time 1d0) (float (driver-start driver) 1d0)))

(defun eased-fraction (local start duration)
  "RAMP of the local time LOCAL from START over DURATION, all taken as double-floats."
  (ramp local (float start 1d0) (float duration 1d0)))

(defun capture-angles (pose indices)
  "The angles of POSE at INDICES, as a fresh vector of double-floats."
  (map '(simple-array double-float (*)) (lambda (index) (aref pose index)) indices))

(defun check-increasing-times (driver times what)
  "Signal a MOTOR-ERROR unless TIMES is a nonempty list of reals >= 0, strictly increasing; WHAT names them."
  (unless (and (alexandria:proper-list-p times) times (every #'realp times)
               (every (lambda (time) (>= time 0)) times))
    (driver-frame-fail driver "~A must be seconds >= 0 from the start, not ~A" what (lisp-text times)))
  (loop for (earlier later) on times
        while later
        unless (< earlier later)
          do (driver-frame-fail driver "~A must increase: ~A comes after ~A" what
                          (format-number later) (format-number earlier))))

(defun dof-sign (dof)
  "1 for a DOF turning about a positive axis, -1 about a negative one."
  (if (member (body-dof-axis dof) '(:-x :-y :-z)) -1d0 1d0))

(defun clamp-to-dof (dof angle)
  "ANGLE (degrees) clamped into DOF's limits."
  (max (float (body-dof-min dof) 1d0) (min (float (body-dof-max dof) 1d0) angle)))

(defun driver-real (driver key)
  "DRIVER's numeric parameter KEY as a double-float at its written value (a
:duration of 0.6 is 0.6d0, not the single-float's 0.6000000238418579d0)."
  (let ((cached (assoc key (driver-reals driver) :test #'eq)))
    (if cached
        (the double-float (cdr cached))
        (let ((value (to-double (driver-arg driver key))))
          (push (cons key value) (driver-reals driver))
          value))))

(declaim (inline minimum-jerk))
(defun minimum-jerk (u)
  "The minimum-jerk profile 10u^3 - 15u^4 + 6u^5 of U clamped to [0, 1]: a
bell-shaped velocity, zero with zero acceleration at both ends."
  (let ((u (max 0d0 (min 1d0 (float u 1d0)))))
    (* u u u (+ 10d0 (* u (+ -15d0 (* 6d0 u)))))))
