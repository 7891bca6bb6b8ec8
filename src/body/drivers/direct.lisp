;;;; direct.lisp -- Pantomime's DirectDriver: ease DOFs to given angles and
;;;; hold them.

(in-package #:player.body)

;;;# The direct driver

(deftype times-vector ()
  "Increasing seconds, as a driver keeps them for bisection."
  '(simple-array double-float (*)))

(defun first-time-after (times time)
  "The index of the first of the increasing TIMES (a TIMES-VECTOR) after TIME, by bisection."
  (declare (type times-vector times))
  (let ((time (float time 1d0)) (low 0) (high (length times)))
    (declare (type double-float time) (type fixnum low high))
    (loop while (< low high)
          do (let ((middle (floor (+ low high) 2)))
               (if (<= (aref times middle) time)
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
