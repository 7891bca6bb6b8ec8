;;;; reach.lisp -- the REACH driver: move a hand (or a wing tip) to a point by
;;;; inverse kinematics of its arm, within the joint limits, easing there from
;;;; where the arm was.  A point out of reach is reached as near as the arm
;;;; goes, and the driver says how far short it fell.

(in-package #:player.body)

(defparameter *reach-report-distance* 1d-3
  "Metres: a reach that ends further than this from its target reports it.")

(defclass reach-driver (driver)
  ((chain :accessor reach-chain
          :documentation "The ARM-CHAIN of the arm, from DRIVER-SETUP.")
   (start-angles :initform nil :accessor reach-start-angles
                 :documentation "The channels' angles when the reach began, in channel order.")
   (scratch :initform nil :accessor reach-scratch
            :documentation "A pose to solve in, reused.")
   (solved-for :initform nil :accessor reach-solved-for
               :documentation "What the last solution was for: the target in the
shoulder's parent frame, then the held angles that shape the arm.")
   (solution :initform nil :accessor reach-solution
             :documentation "The last solution, an angle vector of the chain.")
   (distance :initform nil :accessor reach-distance
             :documentation "How far the last solution left the effector from the target, metres."))
  (:documentation "Performs :reach.  DRIVE solves the arm for the target where it
is at that time, seeded by the angles at the start, so a moving target is
followed; a solution is kept while the target and the arm's frame stay put,
which makes a still target cost one solve."))

(define-motor-function :reach reach-driver
    "Reach a hand (a wing tip, for a bird) to a target by inverse kinematics of the arm."
  (:arm (:member :left :right) :right "which arm")
  (:target (:or :target :zone) :required "the point to reach, or (:zone NAME) of McNeill's gesture space")
  (:space (:member :world :gesture) :world "the space of a (:point X Y Z) target: :gesture is Pantomime's gesture space")
  (:swivel :angle 0 "degrees the elbow swings outward about the shoulder-hand line (Pantomime's phi)")
  (:twist (:or :angle (:member nil)) nil "degrees of forearm twist (Pantomime's rho); NIL keeps it")
  (:duration :positive 0.6 "seconds to move from where the arm is to the reach")
  (:hold :boolean t "stay at the target until stopped; NIL ends the reach on arrival")
  (:priority :real 40 "arbitration priority; higher wins"))

(defun reach-roles (driver)
  "The arm and hand roles of DRIVER's arm: two keywords."
  (ecase (driver-arg driver :arm)
    (:left (values :left-arm :left-hand))
    (:right (values :right-arm :right-hand))))

(defmethod driver-setup ((driver reach-driver))
  (multiple-value-bind (arm-role hand-role) (reach-roles driver)
    (let ((arm (role-joint driver arm-role)))
      (multiple-value-bind (chain problem)
          (make-arm-chain (first arm) (second arm) (role-joint driver hand-role))
        (unless chain
          (motor-fail (motor-call-frame (driver-call driver)) "skeleton ~A cannot reach with its ~A: ~A"
                      (lisp-text (skeleton-name (driver-skeleton driver))) (lisp-text arm-role) problem))
        (setf (reach-chain driver) chain)
        (append (joint-dof-indices (first arm)) (joint-dof-indices (second arm)))))))

(defmethod driver-begin ((driver reach-driver) pose time)
  (declare (ignore time))
  (setf (reach-start-angles driver)
        (map 'angle-vector (lambda (i) (aref pose i)) (driver-channels driver))
        (reach-scratch driver) (copy-pose pose)
        (reach-solution driver) (make-array (arm-chain-size (reach-chain driver))
                                            :element-type 'double-float)
        (reach-solved-for driver) nil))

(defmethod driver-end-time ((driver reach-driver))
  (unless (driver-arg driver :hold)
    (+ (driver-start driver) (gesture-seconds driver :duration))))

(defun reach-held-joints (chain)
  "The joints from CHAIN's effector's parent up to (not including) its elbow:
their angles shape the arm but the reach does not drive them."
  (loop for joint = (body-joint-parent (arm-chain-effector chain)) then (body-joint-parent joint)
        until (eq joint (arm-chain-elbow chain))
        collect joint))

(defun reach-key (driver local pose)
  "What a solution depends on besides the start angles: the target LOCAL in
the shoulder's parent frame and the angles in POSE of the held joints."
  (let ((key (list (vec3-x local) (vec3-y local) (vec3-z local))))
    (dolist (joint (reach-held-joints (reach-chain driver)) key)
      (dolist (i (joint-dof-indices joint))
        (push (aref pose i) key)))))

(defun reach-solve (driver pose)
  "DRIVER's solution now: the chain's angles reaching the target where it is
at the time being composed, from the angles at the start, POSE (being
composed) giving the frame of the arm and the held joints.  Reuses the last
solution while nothing it depends on has moved."
  (let* ((chain (reach-chain driver))
         (body (driver-body driver))
         (target (reach-target-point driver pose))
         (local (transform-point
                 (transform-invert (arm-chain-parent-transform chain pose (object-world-transform body)
                                                               (driver-skeleton driver)))
                 target))
         (key (reach-key driver local pose)))
    (unless (equal key (reach-solved-for driver))
      ;; Seed with the start angles, so the solution depends on the target only.
      (let ((scratch (reach-scratch driver)))
        (replace scratch pose)
        (loop for i in (driver-channels driver)
              for angle across (reach-start-angles driver)
              do (setf (aref scratch i) angle))
        (setf (reach-distance driver)
              (nth-value 1 (solve-arm-chain-local chain scratch local (reach-solution driver)))
              (reach-solved-for driver) key)
        (unless (zerop (driver-arg driver :swivel))
          (swivel-arm chain scratch (reach-solution driver) local
                      (driver-real driver :swivel) (arm-side driver)))))
    (reach-solution driver)))

(defmethod driver-drive ((driver reach-driver) time pose)
  (let* ((solution (reach-solve driver pose))
         (u (ramp time (driver-start driver) (gesture-seconds driver :duration)))
         (start (reach-start-angles driver))
         (twist (driver-arg driver :twist))
         (twist-index (and twist (forearm-twist-index (reach-chain driver)))))
    ;; Channels not solved (the elbow's twist) stay at their start angles, or turn to :twist.
    (loop for i in (driver-channels driver)
          for k from 0
          for from = (aref start k)
          for j = (position i (arm-chain-indices (reach-chain driver)))
          do (setf (aref pose i)
                   (cond (j (+ from (* u (- (aref solution j) from))))
                         ((eql i twist-index) (+ from (* u (- (to-double twist) from))))
                         (t from))))
    pose))

(defmethod driver-report ((driver reach-driver))
  (let ((distance (reach-distance driver)))
    (when (and distance (> distance *reach-report-distance*))
      (format nil "reach ~A: target out of reach, ~,3F m short"
              (lisp-text (driver-arg driver :arm)) distance))))

(defmethod driver-channel-sets ((driver reach-driver))
  ;; The shoulder and elbow solve as one chain: half an arm reaches nowhere.
  (list (driver-channels driver)))
