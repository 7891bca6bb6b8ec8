;;;; direct.lisp -- Pantomime's DirectDriver: ease DOFs to given angles and
;;;; hold them.  Also the helpers the pose-based drivers share: failing with a
;;;; MOTOR-ERROR that names the frame, and resolving pose clauses for a body.

(in-package #:player)

;;;# Helpers for drivers

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

;;;# The direct driver

(defun first-time-after (times time)
  "The index of the first of the increasing TIMES (a simple-vector) after TIME, by bisection."
  (let ((low 0) (high (length times)))
    (loop while (< low high)
          do (let ((middle (floor (+ low high) 2)))
               (if (<= (svref times middle) time)
                   (setf low (1+ middle))
                   (setf high middle))))
    low))

(defclass direct-driver (driver)
  ((targets :initform '() :accessor direct-targets
            :documentation "(INDEX . DEGREES) per driven DOF, sorted by index.")
   (from :initform nil :accessor direct-from
         :documentation "The angles of the targets' DOFs at the start."))
  (:documentation "Eases its DOFs from their angles at the start to TARGETS
\(smoothstep over :duration), then holds them until stopped."))

(define-motor-function :direct direct-driver
  "Ease some DOFs from where they are to given angles over :duration (ease-in-out), then hold them."
  (:set :list :required
   "the targets, ((JOINT-OR-ROLE DOF DEGREES [DOF DEGREES ...]) ...); a role sets each of its joints")
  (:duration :non-negative 0.3 "seconds to reach the targets")
  (:priority :real 10 "arbitration priority; higher wins"))

(defmethod driver-setup ((driver direct-driver))
  (setf (direct-targets driver) (driver-resolve-clauses driver (driver-arg driver :set)))
  (mapcar #'car (direct-targets driver)))

(defmethod driver-begin ((driver direct-driver) pose time)
  (declare (ignore time))
  (setf (direct-from driver) (capture-angles pose (mapcar #'car (direct-targets driver)))))

(defmethod driver-drive ((driver direct-driver) time pose)
  (let ((u (eased-fraction (driver-local-time driver time) 0 (driver-arg driver :duration)))
        (from (direct-from driver)))
    (loop for (index . target) in (direct-targets driver)
          for start across from
          do (setf (aref pose index) (+ start (* u (- target start)))))))

(defmethod driver-default-blend ((driver direct-driver))
  ;; It eases from the angles it captured at its start: a crossfade would only slow it.
  0d0)
