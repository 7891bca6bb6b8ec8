;;;; weight-shift.lisp -- idle life's weight shifts: a body standing at rest
;;;; moves its weight from one side to the other every few seconds, the trunk
;;;; leaning a little and the head staying upright.  Any op on the spine
;;;; overrides it.

(in-package #:player.body)

(defclass weight-shift-driver (driver)
  ((lean :initform nil :accessor weight-shift-lean :documentation "The lowest spine joint's z DOF.")
   (head :initform nil :accessor weight-shift-head :documentation "The head's z DOF, or NIL.")
   (leans :initform '() :accessor weight-shift-leans :documentation "(INDEX . LEAN) of the last two shifts."))
  (:documentation "Performs :weight-shift: every :period seconds the trunk eases,
over :transition seconds, to a lean toward alternate sides of seeded size."))

(define-motor-function :weight-shift weight-shift-driver
  "Idle weight shifts: every :period seconds the trunk (the lowest spine joint)
eases to a lean of up to :amplitude degrees toward the other side, the head
staying upright; idle life, yielding to any op on the spine."
  (:amplitude :non-negative 1.5 "the most degrees the trunk leans")
  (:period :positive 5 "seconds between shifts")
  (:transition :positive 1.5 "seconds a shift takes")
  (:seed :non-negative 3 "an integer choosing the sizes of the shifts")
  (:priority :real 0 "arbitration priority (idle life owns no channel)"))

(defmethod driver-additive-p ((driver weight-shift-driver)) t)
(defmethod driver-idle-p ((driver weight-shift-driver)) t)

(defmethod driver-setup ((driver weight-shift-driver))
  (unless (integerp (driver-arg driver :seed))
    (driver-frame-fail driver ":seed must be an integer, not ~A" (lisp-text (driver-arg driver :seed))))
  (let* ((trunk (lowest-spine-joint driver))
         (head (skeleton-role (driver-skeleton driver) :head))
         (lean (or (first-dof-about trunk :z)
                   (driver-frame-fail driver "the spine joint ~A has no DOF about z"
                                      (lisp-text (body-joint-name trunk))))))
    (setf (weight-shift-lean driver) lean
          (weight-shift-head driver) (and head (not (eq head trunk)) (first-dof-about head :z)))
    (remove nil (list lean (weight-shift-head driver)))))

(defun weight-shift-lean-at (driver index)
  "The lean (degrees) after the INDEX-th shift: 0 before the first, then
alternating sides, each between half and all of :amplitude."
  (if (zerop index)
      0d0
      (let ((cached (assoc index (weight-shift-leans driver))))
        (if cached
            (cdr cached)
            (let ((lean (* (if (oddp index) 1d0 -1d0) (driver-real driver :amplitude)
                           (+ 0.75d0 (* 0.25d0 (seeded-unit (driver-stream-seed driver 0) index))))))
              ;; The two in use are kept: SplitMix64 works in bignums.
              (setf (weight-shift-leans driver)
                    (list* (cons index lean) (subseq (weight-shift-leans driver) 0
                                                     (min 1 (length (weight-shift-leans driver))))))
              lean)))))

(defmethod driver-drive ((driver weight-shift-driver) time pose)
  (let* ((period (driver-real driver :period))
         (local (max 0d0 (driver-local-time driver time)))
         (index (floor local period))
         (u (ramp (- local (* index period)) 0d0 (driver-real driver :transition)))
         (from (weight-shift-lean-at driver (max 0 (1- index))))
         (lean (+ from (* u (- (weight-shift-lean-at driver index) from)))))
    (incf (aref pose (weight-shift-lean driver)) lean)
    (when (weight-shift-head driver)
      (decf (aref pose (weight-shift-head driver)) lean))))
