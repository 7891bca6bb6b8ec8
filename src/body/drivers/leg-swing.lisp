;;;; leg-swing.lisp -- idle life for a figure sitting awake: its folded legs
;;;; swing, one after the other (Persona's idle Peedy "will sit down, wave his
;;;; legs, and eventually fall asleep").  The body tells whether it sits and
;;;; is awake from its own composed pose: knees folded, lids open; so legs
;;;; stop waving when he stands up or his lids grow heavy.  Any op on the
;;;; legs overrides it.

(in-package #:player.body)

(defparameter *sitting-knee-degrees* '(25d0 . 40d0)
  "Knee flexion (degrees) from which a figure counts as sitting, fully by the second.")

(defparameter *drowsy-lid-degrees* '(30d0 . 50d0)
  "Upper-lid closing (degrees) from which a figure counts as drowsy, fully by the second.")

(defclass leg-swing-driver (driver)
  ((knees :initform '() :accessor leg-swing-knees :documentation "The left and right knees' x DOFs.")
   (lids :initform '() :accessor leg-swing-lids :documentation "The upper lids' closing DOFs, or NIL."))
  (:documentation "Performs :swing-legs: while the knees are folded and the lids
open, the knees swing in opposite phase by :amplitude degrees every :period seconds."))

(define-motor-function :swing-legs leg-swing-driver
  "Idle leg swings: while the body sits (knees folded) and is awake (lids open),
its legs swing one after the other; idle life, yielding to any op on the legs."
  (:amplitude :non-negative 10 "degrees each knee swings either way")
  (:period :positive 2.4 "seconds of one swing of both legs")
  (:priority :real 0 "arbitration priority (idle life owns no channel)"))

(defmethod driver-additive-p ((driver leg-swing-driver)) t)
(defmethod driver-idle-p ((driver leg-swing-driver)) t)

(defmethod driver-setup ((driver leg-swing-driver))
  (setf (leg-swing-knees driver)
        (loop for role in '(:left-leg :right-leg)
              for knee = (second (ensure-list (role-joint driver role)))
              collect (or (and knee (first-dof-about knee :x))
                          (driver-frame-fail driver "the ~A has no knee turning about x" (lisp-text role))))
        (leg-swing-lids driver)
        (loop for role in '(:left-upper-lid :right-upper-lid)
              for lid = (skeleton-role (driver-skeleton driver) role)
              when lid collect (first-dof-about lid :x)))
  (leg-swing-knees driver))

(defun between-fraction (value limits)
  "0 at or below (CAR LIMITS), 1 at or above (CDR LIMITS), smooth between."
  (smoothstep (max 0d0 (min 1d0 (/ (- value (car limits)) (- (cdr limits) (car limits)))))))

(defun sitting-awake (driver)
  "How much DRIVER's body sits awake, 0 to 1, from its pose before idle life."
  (let ((base (body-base (driver-body driver))))
    (* (reduce #'min (leg-swing-knees driver)
               :key (lambda (index) (between-fraction (abs (aref base index)) *sitting-knee-degrees*)))
       (- 1d0 (reduce #'max (remove nil (leg-swing-lids driver)) :initial-value 0d0
                      :key (lambda (index) (between-fraction (aref base index) *drowsy-lid-degrees*)))))))

(defmethod driver-drive ((driver leg-swing-driver) time pose)
  (let ((swing (* (driver-real driver :amplitude) (sitting-awake driver)
                  (sin (* 2 pi (/ (driver-local-time driver time) (driver-real driver :period)))))))
    (destructuring-bind (left right) (leg-swing-knees driver)
      (incf (aref pose left) swing)
      (decf (aref pose right) swing))))
