;;;; breathing.lisp -- breathing, Pantomime's example of a continuous process
;;;; ("the scheduler starts the breathing driver on initialization and sets an
;;;; initial breathing rate ... turns up the breathing rate" when nervous): the
;;;; chest lifts and settles, the head keeping level, at a rate and depth a
;;;; script may change while it runs.  Idle life: any op on the chest overrides it.

(in-package #:player.body)

(defclass breathing-driver (driver)
  ((chest :initform nil :accessor breathing-chest
          :documentation "The pose index of the lowest spine joint's x DOF (it lifts the chest).")
   (head :initform nil :accessor breathing-head
         :documentation "The pose index of the head's x DOF (it keeps the gaze level), or NIL.")
   (anchor :initform nil :accessor breathing-anchor
           :documentation "When the rate last changed (or the first time driven), or NIL.")
   (phase :initform 0d0 :accessor breathing-phase :documentation "Breaths taken by the anchor (cycles).")
   (rate :initform 0d0 :accessor breathing-rate :documentation "Breaths a minute since the anchor.")
   (depth-time :initform nil :accessor breathing-depth-time :documentation "When the depth asked for last changed.")
   (depth-from :initform 0d0 :accessor breathing-depth-from :documentation "The depth then.")
   (depth-to :initform 0d0 :accessor breathing-depth-to :documentation "The depth asked for since."))
  (:documentation "Performs :breathe.  A new rate takes over from the breaths
taken so far, so the pace changes without a jump; a new depth is eased to
over about a second.  Between changes the angles are a function of the time
alone; a change is seen at the first time driven after it (a script's :set
at its cue's time), and a performance replays from the start, so the same
inputs give the same angles."))

(define-motor-function :breathe breathing-driver
  "Breathe: the chest (the lowest spine joint) lifts by :depth degrees at the top
of each breath and settles, the head keeping level; idle life, yielding to any
op on those joints.  Without :rate or :depth it follows the body's properties
breathing-rate and breathing-depth, which a script may set while it runs."
  (:rate (:or :positive (:member nil)) nil "breaths a minute; NIL follows the body's breathing-rate (14)")
  (:depth (:or :non-negative (:member nil)) nil "degrees the chest lifts; NIL follows the body's breathing-depth (1)")
  (:idle :boolean t "idle life: yield to any op on the chest; NIL adds the breaths onto whatever holds it")
  (:priority :real 0 "arbitration priority (idle life owns no channel)"))

(defmethod driver-additive-p ((driver breathing-driver)) t)
(defmethod driver-idle-p ((driver breathing-driver)) (driver-arg driver :idle))

(defun first-dof-about (joint line)
  "The pose index of JOINT's first DOF about LINE (:x, :y or :z), or NIL."
  (let ((position (position line (body-joint-dofs joint) :key #'dof-axis-line)))
    (and position (+ (body-joint-dof-start joint) position))))

(defun lowest-spine-joint (driver)
  "The joint that carries DRIVER's trunk: the first of its :spine role, or the
skeleton's root when that is a neck (a bird's: within *NECK-LENGTH* of the
head), so the arms move with it; a MOTOR-ERROR without a :spine."
  (let ((spine (first (ensure-list (role-joint driver :spine))))
        (head (skeleton-role (driver-skeleton driver) :head)))
    (if (and head (<= (vdistance (apply #'make-vec3 (coerce (body-joint-center spine) 'list))
                                 (apply #'make-vec3 (coerce (body-joint-center head) 'list)))
                      *neck-length*))
        (skeleton-root (driver-skeleton driver))
        spine)))

(defmethod driver-setup ((driver breathing-driver))
  (let* ((chest (lowest-spine-joint driver))
         (head (skeleton-role (driver-skeleton driver) :head))
         (chest-index (or (first-dof-about chest :x)
                          (driver-frame-fail driver "the spine joint ~A has no DOF about x"
                                             (lisp-text (body-joint-name chest))))))
    (setf (breathing-chest driver) chest-index
          (breathing-head driver) (and head (not (eq head chest)) (first-dof-about head :x)))
    (remove nil (list chest-index (breathing-head driver)))))

(defun breathing-setting (driver key property)
  "DRIVER's :rate or :depth (KEY), or else its body's PROPERTY now, as a double-float."
  (let ((value (driver-arg driver key)))
    (to-double (or value (property-value (driver-body driver) property)))))

(defun advance-breathing (driver time)
  "Take in DRIVER's rate and depth at TIME: a changed one starts from here.
Returns the phase (cycles) and the depth at TIME."
  (let ((rate (breathing-setting driver :rate 'breathing-rate))
        (depth (breathing-setting driver :depth 'breathing-depth)))
    (cond ((null (breathing-anchor driver))
           ;; The first breath begins at the start, whenever the body is first looked at.
           (setf (breathing-anchor driver) (float (driver-start driver) 1d0) (breathing-rate driver) rate
                 (breathing-depth-time driver) time
                 (breathing-depth-from driver) depth (breathing-depth-to driver) depth))
          (t
           (unless (= rate (breathing-rate driver))
             (setf (breathing-phase driver) (breathing-phase-at driver time)
                   (breathing-anchor driver) time
                   (breathing-rate driver) rate))
           (unless (= depth (breathing-depth-to driver))
             (setf (breathing-depth-from driver) (breathing-depth-at driver time)
                   (breathing-depth-time driver) time
                   (breathing-depth-to driver) depth))))
    (values (breathing-phase-at driver time) (breathing-depth-at driver time))))

(defun breathing-phase-at (driver time)
  "Breaths DRIVER has taken by TIME at its current rate since its anchor."
  (+ (breathing-phase driver) (/ (* (breathing-rate driver) (- time (breathing-anchor driver))) 60d0)))

(defun breathing-depth-at (driver time)
  "DRIVER's depth at TIME, easing exponentially (a second's time constant) to the one asked for."
  (let ((to (breathing-depth-to driver)))
    (+ to (* (exp (- (max 0d0 (- time (breathing-depth-time driver))))) (- (breathing-depth-from driver) to)))))

(defun breath-lift (phase)
  "How far into a breath the chest is at PHASE (cycles): 0 at rest, 1 at the top."
  (* 0.5d0 (- 1d0 (cos (* 2 pi phase)))))

(defmethod driver-drive ((driver breathing-driver) time pose)
  (multiple-value-bind (phase depth) (advance-breathing driver (float time 1d0))
   (let ((lift (* depth (breath-lift phase) (driver-weight driver))))
    ;; Inhaling extends the spine (a negative x: flexion is positive), the
    ;; head tips forward as much, so the face stays where it looked.
    (decf (aref pose (breathing-chest driver)) lift)
    (when (breathing-head driver)
      (incf (aref pose (breathing-head driver)) lift)))))
