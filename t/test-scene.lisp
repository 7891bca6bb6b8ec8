;;;; test-scene.lisp -- the scene hierarchy (typed properties, world transforms,
;;;; reparenting) and how a body composes its drivers (ownership, crossfades,
;;;; held angles, limits).

(in-package #:player-tests)

(def-suite* scene :in player-tests)

(defun near-vec (a b &optional (tolerance 1d-9))
  "Are vec3s A and B within TOLERANCE of each other?"
  (< (player.body::vdistance a b) tolerance))

(defun prop (scene name &rest initargs)
  "Add a prop called NAME to SCENE."
  (player::add-object scene (apply #'make-instance 'player::scene-object
                                   :name name :kind :prop initargs)))

(test properties-are-typed
  (let* ((scene (make-instance 'player::scene))
         (note (prop scene 'note)))
    (player::define-property note 'colour :colour (player.body::make-vec3 1 1 0.8))
    (player::define-property note 'weight :number 3)
    (is (= 3d0 (player::property-value note 'weight)))
    (setf (player::property-value note 'weight) 4)
    (is (= 4d0 (player::property-value note 'weight)))
    (signals player::anim-error (setf (player::property-value note 'weight) (player::vec3)))
    (signals player::anim-error (setf (player::property-value note 'visible) 3))
    (signals player::anim-error (player::property-value note 'no-such-property))
    (signals player::anim-error (player::define-property note 'mood :feeling 1))
    ;; A rotation is stored normalized.
    (setf (player::property-value note 'rotation) (player.body::make-quat 2 0 0 0))
    (is (= 1d0 (player.body::quat-w (player::property-value note 'rotation))))
    (is (= 4d0 (player::property-value note 'weight)) "a rejected value changes nothing")))

(test world-transforms-follow-the-hierarchy
  (let* ((scene (make-instance 'player::scene))
         (table (prop scene 'table :position (player.body::make-vec3 1 0 0)
                                   :rotation (player.body::quat-from-axis-angle (player.body::make-vec3 0 1 0) (/ pi 2))))
         (note (prop scene 'note :position (player.body::make-vec3 0 0.7 1))))
    (setf (player::object-parent note) table)
    ;; Turning the table 90 degrees about y takes the note's +z offset to +x.
    (is (near-vec (player.body::make-vec3 2 0.7 0) (player::object-world-position note)))
    (setf (player::property-value table 'position) (player.body::make-vec3 0 0 0))
    (is (near-vec (player.body::make-vec3 1 0.7 0) (player::object-world-position note)))))

(test reparenting-keeps-the-world-position
  (let* ((scene (make-instance 'player::scene))
         (table (prop scene 'table :position (player.body::make-vec3 1 0 0)))
         (note (prop scene 'note :position (player.body::make-vec3 0 0.7 0.2)))
         (body (player::make-body 'peedy 'parrot :scene scene :position (player.body::make-vec3 0 0.7 0))))
    (setf (player::object-parent note) table)
    (player::body-evaluate body 0)
    (let ((before (player::object-world-position note)))
      (player::reparent-object note (cons body 'r_primaries))
      (is (near-vec before (player::object-world-position note) 1d-9))
      (is (equal (cons body 'r_primaries) (player::object-parent note)))
      ;; Now it moves with the body.
      (setf (player::property-value body 'position) (player.body::make-vec3 0 1.7 0))
      (player::body-evaluate body 1)
      (is (near-vec (player.body::v+ before (player.body::make-vec3 0 1 0)) (player::object-world-position note) 1d-6)))
    (signals player::anim-error (player::reparent-object body note) "a cycle is refused")
    (signals player::skeleton-error (player::reparent-object note (cons body 'no-such-joint)))
    (is (equal (cons body 'r_primaries) (player::object-parent note))
        "a refused reparent changes nothing")))

(test scene-lookups-report-names
  (let ((scene (make-instance 'player::scene)))
    (prop scene 'note)
    (signals player::anim-error (prop scene 'note))
    (signals player::anim-error (player::find-object scene 'camera))
    (is (null (player::find-object scene 'camera nil)))
    (signals player::anim-error (make-instance 'player::scene-object :name 'x :kind :planet))))

;;;# Body composition

(defclass constant-test-driver (player::driver) ()
  (:documentation "Drives one DOF to a constant angle: the simplest driver, for composition tests."))

(player::define-motor-function :test-constant constant-test-driver
  "Hold one DOF at an angle (tests only)."
  (:joint :symbol :required "the joint")
  (:dof :symbol :required "the DOF")
  (:angle :angle 0 "degrees")
  (:additive :boolean nil "add instead of owning"))

(defmethod player::driver-setup ((driver constant-test-driver))
  (list (player::dof-index (player.body::driver-skeleton driver)
                           (player::driver-arg driver :joint) (player::driver-arg driver :dof))))

(defmethod player::driver-additive-p ((driver constant-test-driver))
  (player::driver-arg driver :additive))

(defmethod player::driver-drive ((driver constant-test-driver) time pose)
  (declare (ignore time))
  (let ((i (first (player.body::driver-channels driver))))
    (if (player::driver-additive-p driver)
        (incf (aref pose i) (player::driver-arg driver :angle))
        (setf (aref pose i) (float (player::driver-arg driver :angle) 1d0)))))

(defun elbow-driver (body angle start &rest options)
  "Schedule on BODY a constant driver of the left elbow's flexion at ANGLE from START."
  (destructuring-bind (&key stop (priority 10) additive) options
    (player::body-add-driver
     body (player::make-driver
           (player::parse-motor-frame (list :test-constant :joint 'l_elbow :dof :x :angle angle
                                            :priority priority :additive additive))
           body start :stop stop))))

(defun elbow-angle (body time)
  "The left elbow's flexion of BODY at TIME."
  (aref (player::body-evaluate body time)
        (player::dof-index (player::body-skeleton body) 'l_elbow :x)))

(test composition-blends-usurps-and-holds
  (let ((body (player::make-body 'bob 'humanoid :blend-time 0.2)))
    (elbow-driver body -90 1 :stop 3)
    (elbow-driver body -30 2 :stop 2.5 :priority 20)
    (is (= 0 (elbow-angle body 0.5)))
    (is (< (abs (- -45 (elbow-angle body 1.1))) 1d-4) "crossfade from rest halfway")
    (is (= -90 (elbow-angle body 1.5)))
    (is (< (abs (- -60 (elbow-angle body 2.1))) 1d-4) "the higher priority usurps, blending")
    (is (= -30 (elbow-angle body 2.4)))
    (is (< (abs (- -60 (elbow-angle body 2.6))) 1d-4) "the usurped driver gets the channel back")
    (is (= -90 (elbow-angle body 5)) "a released channel holds its last angle")))

(test composition-clamps-and-adds
  (let ((body (player::make-body 'bob 'humanoid :blend-time 0)))
    (elbow-driver body 45 0)
    (is (= 0 (elbow-angle body 1)) "limits clamp: the elbow cannot hyperextend")
    (elbow-driver body -100 2 :priority 20)
    (elbow-driver body -10 2 :additive t)
    (is (= -110 (elbow-angle body 3)) "an additive driver adds after composition")
    (is (player::pose-within-limits-p (player::body-skeleton body) (player::body-pose body)))))

(test bodies-do-not-go-back-in-time
  (let ((body (player::make-body 'bob 'parrot)))
    (player::body-evaluate body 2)
    (signals player:player-error (player::body-evaluate body 1))))

(test motor-frames-are-checked
  (dolist (frame '((:test-constant :joint l_elbow :dof :x :angle "x")
                   (:test-constant :joint l_elbow :dof :x :angel 3)
                   (:test-constant :dof :x)
                   (:test-constant :joint l_elbow :dof :x :dof :y)
                   (:no-such-function)
                   (:test-constant :joint)
                   "gaze"
                   (:test-constant :joint l_elbow :dof :x :priority "high")))
    (let ((condition (handler-case (progn (player::parse-motor-frame frame) nil)
                       (player::motor-error (c) c))))
      (is-true condition "~S is refused" frame)
      (when condition
        (is (search (player.base::lisp-text (if (consp frame) (first frame) frame))
                    (princ-to-string condition))
            "the message names the frame: ~A" condition)))))
