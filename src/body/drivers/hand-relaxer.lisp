;;;; hand-relaxer.lisp -- Pantomime's HandRelaxer: fingers no driver holds ease
;;;; into a relaxed curl, the little finger curling most, the thumb least, as
;;;; a hand at rest does.  Idle life: a hand shape or grasp overrides it.

(in-package #:player.body)

(defparameter *relaxed-curl-shares* '(0.5d0 0.8d0 1d0 1.15d0 1.3d0)
  "How much of the relaxed curl each finger of a :fingers role takes, thumb
first: a resting hand's cascade, the little finger most flexed.")

(defclass hand-relaxer-driver (driver)
  ((curls :initform '() :accessor hand-relaxer-curls
          :documentation "Per channel, its relaxed angle."))
  (:documentation "Performs :hand-relaxer: each finger's curl DOF eases, over
:duration, to its share of :curl, wherever no other driver holds it."))

(define-motor-function :hand-relaxer hand-relaxer-driver
  "The HandRelaxer: fingers no driver holds ease into a relaxed curl of about
:curl degrees (the little finger more, the thumb less); idle life, yielding to
any op on the fingers (Pantomime's handrelaxer)."
  (:side (:member :left :right :both) :both "which hand")
  (:curl :non-negative 25 "degrees the middle finger curls at rest")
  (:duration :positive 1.0 "seconds the fingers take to relax, at the start and when an op lets go")
  (:priority :real 0 "arbitration priority (idle life owns no channel)"))

(defmethod driver-additive-p ((driver hand-relaxer-driver)) t)
(defmethod driver-idle-p ((driver hand-relaxer-driver)) t)
(defmethod driver-yield-seconds ((driver hand-relaxer-driver)) (driver-real driver :duration))

(defun finger-curl-index (joint)
  "The pose index of JOINT's curl: its DOF called curl, else its first."
  (let ((curl (body-joint-dof joint 'curl)))
    (+ (body-joint-dof-start joint) (if curl (position curl (body-joint-dofs joint)) 0))))

(defmethod driver-setup ((driver hand-relaxer-driver))
  (let* ((roles (ecase (driver-arg driver :side)
                  (:left '(:left-fingers)) (:right '(:right-fingers))
                  (:both '(:left-fingers :right-fingers))))
         (fingers (loop for role in roles append (ensure-list (role-joint driver role))))
         (curl (driver-real driver :curl)))
    (setf (hand-relaxer-curls driver)
          (loop for finger in fingers
                for k from 0
                for share = (nth (mod k 5) *relaxed-curl-shares*)
                for index = (finger-curl-index finger)
                collect (multiple-value-bind (low high) (channel-limits (driver-skeleton driver) index)
                          (max low (min high (* share curl))))))
    (mapcar #'finger-curl-index fingers)))

(defmethod driver-drive ((driver hand-relaxer-driver) time pose)
  (let ((u (eased-fraction (driver-local-time driver time) 0 (driver-arg driver :duration))))
    (loop for index in (driver-channels driver)
          for curl in (hand-relaxer-curls driver)
          do (incf (aref pose index) (* u (- curl (aref pose index)))))))
