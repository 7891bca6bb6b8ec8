;;;; idle.lisp -- idle life: the small restless drift of a body that is
;;;; "not able to sit still" (Pantomime's idle drivers).  An additive driver:
;;;; seeded Perlin noise, a few degrees on each DOF of some joints, added on
;;;; top of whatever the other drivers composed.

(in-package #:player.body)

(defclass idle-driver (driver)
  ((noises :initform #() :accessor idle-noises
           :documentation "Per channel, a noise control of local time."))
  (:documentation "Adds seeded Perlin noise to the DOFs of some joints: each DOF
drifts independently, within :amplitude degrees, as a pure function of time."))

(define-motor-function :idle idle-driver
  "Idle drift: add seeded Perlin noise of :amplitude degrees to every DOF of :joints,
on top of the other drivers (additive; it owns no channel)."
  (:amplitude :non-negative 2.0 "the most degrees any DOF drifts")
  (:frequency :positive 0.3 "about how many times a second the drift changes direction")
  (:seed :real 0 "an integer; the same seed drifts the same way")
  (:joints :list (:spine :head) "the roles and joint names whose DOFs drift")
  (:fade :non-negative 0.5 "seconds the drift fades in over from the start, so it begins at 0")
  (:priority :real 0 "arbitration priority (idle life yields to everything)"))

(defmethod driver-additive-p ((driver idle-driver))
  t)

(defmethod driver-background-p ((driver idle-driver))
  t)

(defun idle-joints (driver)
  "The joints DRIVER's :joints names, each once; a MOTOR-ERROR for an unknown one."
  (let ((skeleton (driver-skeleton driver))
        (names (driver-arg driver :joints)))
    (unless (and (alexandria:proper-list-p names) names (every #'symbolp names))
      (driver-frame-fail driver ":joints must be a nonempty list of roles and joint names, not ~A"
                         (lisp-text names)))
    (remove-duplicates
     (loop for name in names
           for found = (if (keywordp name) (skeleton-role skeleton name) (find-joint skeleton name))
           unless found
             do (driver-frame-fail driver "skeleton ~A has no ~:[joint~;role~] ~A"
                                   (lisp-text (skeleton-name skeleton)) (keywordp name)
                                   (lisp-text name))
           append (alexandria:ensure-list found))
     :from-end t)))

(defmethod driver-setup ((driver idle-driver))
  (let ((seed (driver-arg driver :seed)))
    (unless (integerp seed)
      (driver-frame-fail driver ":seed must be an integer, not ~A" (lisp-text seed)))
    (let ((channels (mapcan #'joint-dof-indices (idle-joints driver))))
      ;; Each DOF its own noise stream: the seed hashed with the DOF's index.
      (setf (idle-noises driver)
            (map 'simple-vector
                 (lambda (index)
                   (make-noise-control :seed (hash32 (logxor (hash32 seed) (* 7919 (1+ index))))
                                       :amplitude (driver-arg driver :amplitude)
                                       :frequency (driver-arg driver :frequency)))
                 channels))
      channels)))

(defmethod driver-drive ((driver idle-driver) time pose)
  (let* ((local (driver-local-time driver time))
         (fade (eased-fraction local 0 (driver-arg driver :fade))))
    (loop for index in (driver-channels driver)
          for noise across (idle-noises driver)
          do (incf (aref pose index) (* fade (control-value noise local))))))
