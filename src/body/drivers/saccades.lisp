;;;; saccades.lisp -- idle life's small saccades: the eyes jump by a few
;;;; degrees at seeded, exponentially spaced times and rest there, as eyes do
;;;; between fixations.  Any gaze or op on the eyes overrides them.

(in-package #:player.body)

(defclass saccade-driver (driver)
  ((links :initform '() :accessor saccade-links :documentation "The aim links of both eyes.")
   (offsets :initform (make-array 16 :adjustable t :fill-pointer 0) :reader saccade-offsets
            :documentation "The saccades' pitch and yaw offsets drawn so far, in pairs.")
   (times :initform (make-array 16 :adjustable t :fill-pointer 0) :reader saccade-times
          :documentation "The saccades' absolute times found so far, increasing."))
  (:documentation "Performs :saccades: both eyes jump together to seeded small
offsets of their pitch and yaw, each held until the next."))

(define-motor-function :saccades saccade-driver
  "Idle saccades: both eyes jump by up to :amplitude degrees (half that in pitch)
at seeded, exponentially distributed times, and rest there; idle life, yielding
to any gaze."
  (:amplitude :non-negative 3 "the most degrees of yaw a saccade offsets the eyes by")
  (:mean-interval :positive 1.5 "mean seconds between saccades")
  (:duration :positive 0.04 "seconds a saccade takes")
  (:seed :non-negative 2 "an integer choosing the saccades")
  (:priority :real 0 "arbitration priority (idle life owns no channel)"))

(defmethod driver-additive-p ((driver saccade-driver)) t)
(defmethod driver-idle-p ((driver saccade-driver)) t)

(defmethod driver-setup ((driver saccade-driver))
  (unless (integerp (driver-arg driver :seed))
    (driver-frame-fail driver ":seed must be an integer, not ~A" (lisp-text (driver-arg driver :seed))))
  (setf (saccade-links driver)
        (list (make-aim-link driver (role-joint driver :left-eye))
              (make-aim-link driver (role-joint driver :right-eye))))
  (aim-link-channels (saccade-links driver)))

(defun driver-stream-seed (driver salt)
  "An integer seed for DRIVER's SALT-th random stream: its :seed, its body's seed and SALT."
  (+ (* 1000003 salt) (driver-arg driver :seed) (* 7919 (body-seed (driver-body driver)))))

(defun extend-seeded-times (times start seed mean until)
  "Extend TIMES (an adjustable vector of absolute times from START, spaced by
seeded exponential intervals of MEAN seconds) past UNTIL; return it."
  (loop while (or (zerop (fill-pointer times)) (<= (aref times (1- (fill-pointer times))) until))
        do (let ((index (fill-pointer times)))
             (vector-push-extend (+ (if (zerop index) start (aref times (1- index)))
                                    (blink-interval seed index mean))
                                 times)))
  times)

(defun times-at-or-before (times time)
  "How many of the increasing TIMES (a vector with a fill pointer) are at or before TIME, by bisection."
  (let ((low 0) (high (fill-pointer times)))
    (loop while (< low high)
          do (let ((middle (floor (+ low high) 2)))
               (if (<= (aref times middle) time) (setf low (1+ middle)) (setf high middle))))
    low))

(defun seeded-unit (seed index)
  "A uniform number in [-1, 1) from SEED and INDEX."
  (- (* 2d0 (ash (splitmix64 seed index) -11) (scale-float 1d0 -53)) 1d0))

(defun saccade-offset (driver index)
  "The INDEX-th (from 1) saccade's pitch and yaw offsets; 0 and 0 for index 0."
  (if (zerop index)
      (values 0d0 0d0)
      (let ((offsets (saccade-offsets driver)))
        ;; Drawn once each: SplitMix64 works in bignums.
        (loop while (< (fill-pointer offsets) (* 2 index))
              do (let ((seed (driver-stream-seed driver 1))
                       (k (1+ (floor (fill-pointer offsets) 2)))
                       (amplitude (driver-real driver :amplitude)))
                   (vector-push-extend (* 0.5d0 amplitude (seeded-unit seed (* 2 k))) offsets)
                   (vector-push-extend (* amplitude (seeded-unit seed (1+ (* 2 k)))) offsets)))
        (values (aref offsets (- (* 2 index) 2)) (aref offsets (- (* 2 index) 1))))))

(defmethod driver-drive ((driver saccade-driver) time pose)
  (let* ((times (extend-seeded-times (saccade-times driver) (float (driver-start driver) 1d0)
                                     (driver-stream-seed driver 0) (driver-real driver :mean-interval) time))
         (count (times-at-or-before times time))
         (u (if (zerop count) 1d0 (ramp time (aref times (1- count)) (driver-real driver :duration)))))
    (multiple-value-bind (from-pitch from-yaw) (saccade-offset driver (max 0 (1- count)))
      (multiple-value-bind (to-pitch to-yaw) (saccade-offset driver count)
        (dolist (link (saccade-links driver))
          (incf (aref pose (aim-link-pitch-index link))
                (* (dof-sign (aim-link-pitch-dof link)) (+ from-pitch (* u (- to-pitch from-pitch)))))
          (incf (aref pose (aim-link-yaw-index link))
                (* (dof-sign (aim-link-yaw-dof link)) (+ from-yaw (* u (- to-yaw from-yaw))))))))))
