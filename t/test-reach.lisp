;;;; test-reach.lisp -- the arm IK solver (ik.lisp) and the :reach driver.
;;;; Reachable targets are made as the hand's position in a random pose within
;;;; limits; unreachable ones against REACH-BRUTE-FORCE-NEAREST, a coarse
;;;; grid over the arm's DOFs written here as an independent reference.

(in-package #:player-tests)

(def-suite* reach :in player-tests)

;;; ---------------------------------------------------------------------------
;;; Helpers

(defparameter *reach-skeletons*
  (list (player::load-skeleton 'humanoid) (player::load-skeleton 'parrot))
  "The shipped skeletons, loaded once.")

(defun reach-random (low high &optional (state *random-state*))
  "A double-float uniformly in [LOW, HIGH]."
  (+ low (random (float (- high low) 1d0) state)))

(defmacro with-seeded-randomness ((seed) &body body)
  "Run BODY with *RANDOM-STATE* seeded by SEED, so a randomized test draws the
same cases whatever ran before it."
  `(let ((*random-state* (sb-ext:seed-random-state ,seed)))
     ,@body))

(defun reach-vec3-list (v)
  "The coordinates of the vec3 V as a list."
  (list (player.body::vec3-x v) (player.body::vec3-y v) (player.body::vec3-z v)))

(defun reach-arm-joints (skeleton side)
  "SIDE's (:left or :right) shoulder, elbow and hand (effector) of SKELETON."
  (destructuring-bind (shoulder elbow &rest more)
      (player::skeleton-role skeleton (if (eq side :left) :left-arm :right-arm))
    (declare (ignore more))
    (list shoulder elbow (player::skeleton-role skeleton (if (eq side :left) :left-hand :right-hand)))))

(defun reach-chain-of (skeleton side)
  "SIDE's arm chain of SKELETON."
  (values (apply #'player.body::make-arm-chain (reach-arm-joints skeleton side))))

(defun reach-grid-dofs (skeleton side)
  "The pose indices and DOFs a reach moves: the shoulder's, and the elbow's
first (its flexion; the second, a twist, is held)."
  (destructuring-bind (shoulder elbow hand) (reach-arm-joints skeleton side)
    (declare (ignore hand))
    (append (loop for dof in (player.body::body-joint-dofs shoulder)
                  for i from (player.body::body-joint-dof-start shoulder)
                  collect (cons i dof))
            (list (cons (player.body::body-joint-dof-start elbow)
                        (first (player.body::body-joint-dofs elbow)))))))

(defun reach-random-pose (skeleton side &optional (pose (player::make-pose skeleton)))
  "POSE with SIDE's reach DOFs set at random within their limits."
  (loop for (i . dof) in (reach-grid-dofs skeleton side)
        do (setf (aref pose i) (reach-random (player.body::body-dof-min dof) (player.body::body-dof-max dof))))
  pose)

(defun reach-effector-position (skeleton pose side &optional (placement (player.body::identity-transform)))
  "Where SIDE's hand is in POSE, walking the joints from PLACEMENT."
  (player.body::transform-translation
   (player.body::joint-world-transform skeleton pose (third (reach-arm-joints skeleton side)) placement)))

(defun reach-brute-force-nearest (skeleton side target &key (step 20) (pose (player::make-pose skeleton)))
  "The least distance from SIDE's hand to TARGET over a grid of STEP degrees
through the ranges of the reach DOFs (each range's ends included)."
  (let ((dofs (reach-grid-dofs skeleton side))
        (pose (player.body::copy-pose pose))
        (best most-positive-double-float))
    (labels ((values-of (dof)
               (let* ((low (player.body::body-dof-min dof)) (high (player.body::body-dof-max dof))
                      (n (max 1 (ceiling (- high low) step))))
                 (loop for k from 0 to n collect (+ low (* k (/ (- high low) n))))))
             (walk (dofs)
               (if (null dofs)
                   (setf best (min best (player.body::vdistance (reach-effector-position skeleton pose side) target)))
                   (destructuring-bind ((i . dof) &rest more) dofs
                     (dolist (angle (values-of dof))
                       (setf (aref pose i) (float angle 1d0))
                       (walk more))))))
      (walk dofs))
    best))

(defun reach-body (skeleton &rest keys)
  "A fresh body with SKELETON in a fresh scene (KEYS go to MAKE-BODY)."
  (apply #'player::make-body 'reacher skeleton :scene (make-instance 'player::scene) keys))

(defun add-reach (body frame &optional (start 0d0))
  "A driver for the motor FRAME on BODY from START, added to BODY."
  (player::body-add-driver body (player::make-driver (player::parse-motor-frame frame) body start)))

(defun run-reach-frames (body driver side until &key (fps 30) (check (constantly t)))
  "Evaluate BODY at FPS from DRIVER's start to UNTIL; on every frame check that
the composed pose and what DRIVER writes are within limits, and call CHECK
with the time and a copy of the pose.  Returns SIDE's hand position at UNTIL
and whether every frame was within limits."
  (let ((skeleton (player::body-skeleton body))
        (within t))
    (loop for k from 0
          for time = (+ (player.body::driver-start driver) (/ k fps))
          while (<= time (+ until 1d-9))
          do (let ((pose (player.body::copy-pose (player::body-evaluate body time))))
               (unless (and (player::pose-within-limits-p skeleton pose)
                            (or (not (member driver (player.body::body-active body)))
                                (player::pose-within-limits-p
                                 skeleton (player::driver-drive driver (float time 1d0) (player.body::copy-pose pose)))))
                 (setf within nil))
               (funcall check time pose)))
    (values (player::body-joint-position body (if (eq side :left) :left-hand :right-hand)) within)))

;;; ---------------------------------------------------------------------------
;;; The solver

(test decomposition-round-trips
  "JOINT-ANGLES-FOR-ROTATION inverts JOINT-LOCAL-ROTATION for every axis order
and sign, including gimbal lock; within limits it needs no clamping."
  (with-seeded-randomness (1)
    (let* ((orders '((:x :y :z) (:x :z :y) (:y :x :z) (:y :z :x) (:z :x :y) (:z :y :x)
                     (:-x :y :z) (:x :-z :y) (:-y :-z :-x)))
           (skeleton (player.body::parse-skeleton
                      `(skeleton test
                         (:joint root :parent nil :center (0 0 0))
                         ,@(loop for order in orders for k from 0
                                 collect `(:joint ,(intern (format nil "J~D" k)) :parent root :center (0 1 0)
                                                  :dofs ,(loop for axis in order collect (list axis -180 180))))))))
      (loop for joint across (player::skeleton-joints skeleton)
            when (player.body::body-joint-dofs joint)
              do (dotimes (k 50)
                   (let ((pose (player::make-pose skeleton))
                         (indices (player.body::joint-dof-indices joint)))
                     (dolist (i indices)
                       (setf (aref pose i) (reach-random -180 180)))
                     (when (< k 5) ; gimbal lock: the middle angle at +-90
                       (setf (aref pose (second indices)) (if (evenp k) 90d0 -90d0)))
                     (let ((q (player.body::joint-local-rotation joint pose)))
                       (multiple-value-bind (angles violation) (player.body::joint-angles-for-rotation joint q)
                         (loop for i in indices for angle in angles do (setf (aref pose i) angle))
                         (is (< violation 1d-6))
                         (is (< (player.body::quat-angle q (player.body::joint-local-rotation joint pose)) 1d-7)
                             "joint ~A" (player.body::body-joint-name joint)))))))
      ;; Shipped shoulders, within their limits.
      (dolist (skeleton *reach-skeletons*)
        (dolist (side '(:left :right))
          (let ((shoulder (first (reach-arm-joints skeleton side))))
            (dotimes (k 100)
              (let* ((pose (reach-random-pose skeleton side))
                     (q (player.body::joint-local-rotation shoulder pose)))
                (multiple-value-bind (angles violation) (player.body::joint-angles-for-rotation shoulder q)
                  (loop for i in (player.body::joint-dof-indices shoulder) for angle in angles
                        do (setf (aref pose i) angle))
                  (is (< violation 1d-6))
                  (is (player::pose-within-limits-p skeleton pose))
                  (is (< (player.body::quat-angle q (player.body::joint-local-rotation shoulder pose)) 1d-7))))))))
      (is (null (player.body::joint-angles-for-rotation
                 (player::find-joint (first *reach-skeletons*) 'l_elbow) (player::quat)))))))

(test hinge-closed-form
  "SOLVE-HINGE finds the angle giving a reachable distance, else the nearest within its limits."
  (with-seeded-randomness (2)
    (dotimes (k 200)
      (let* ((a (player::vec3 (reach-random -1 1) (reach-random -1 1) (reach-random -1 1)))
             (w (player::vec3 (reach-random -1 1) (reach-random -1 1) (reach-random -1 1)))
             (axis (player.body::vnormalize (player::vec3 (reach-random -1 1) (reach-random -1 1) (reach-random -1 1))))
             (angle (reach-random -170 170))
             (distance (player.body::vnorm (player.body::v+ a (player.body::qrotate (player.body::quat-from-axis-angle axis (* angle (/ pi 180))) w)))))
        (flet ((reach (degrees)
                 (player.body::vnorm (player.body::v+ a (player.body::qrotate (player.body::quat-from-axis-angle axis (* degrees (/ pi 180))) w)))))
          (let ((solved (player.body::solve-hinge a w axis 0d0 -180d0 180d0 distance)))
            (is (< (abs (- (reach solved) distance)) 1d-9)))
          ;; Limited to [0, 10]: no angle there is worse than the one chosen.
          (let ((solved (player.body::solve-hinge a w axis 5d0 0d0 10d0 distance)))
            (is (<= 0 solved 10))
            (is (loop for d from 0 to 10 by 1/4
                      always (<= (abs (- (reach solved) distance))
                                 (+ 1d-9 (abs (- (reach (float d 1d0)) distance))))))))))))

(test solver-reaches-random-targets
  "SOLVE-ARM-CHAIN reaches targets made by random arm poses, whatever the rest of
the pose and the placement, from random starting poses, keeping within limits."
  (with-seeded-randomness (3)
    (dolist (skeleton *reach-skeletons*)
      (dolist (side '(:left :right))
        (let ((chain (reach-chain-of skeleton side))
              (effector (third (reach-arm-joints skeleton side))))
          (dotimes (k 100)
            (let* ((base (player::clamp-pose skeleton
                                             (map 'player::pose (lambda (x) (declare (ignore x)) (reach-random -40 40))
                                                  (player::make-pose skeleton))))
                   (placement (player.body::make-transform
                               :rotation (player.body::quat-from-axis-angle (player::vec3 0d0 1d0 0d0) (reach-random -3 3))
                               :translation (player::vec3 (reach-random -5 5) 0d0 (reach-random -5 5))))
                   (goal (reach-random-pose skeleton side (player.body::copy-pose base)))
                   (target (reach-effector-position skeleton goal side placement))
                   (start (reach-random-pose skeleton side (player.body::copy-pose base))))
              (multiple-value-bind (solved distance) (player.body::solve-arm-chain chain start target :placement placement)
                (is (< distance 1d-4))
                (is (< (player.body::vdistance target (reach-effector-position skeleton solved side placement)) 1d-4))
                (is (player::pose-within-limits-p skeleton solved))
                ;; Only the arm moved.
                (is (loop for i below (length start)
                          always (or (find i (player.body::arm-chain-indices chain)) (= (aref start i) (aref solved i))))))
              (is (eq effector (player.body::arm-chain-effector chain))))))))))

;;; ---------------------------------------------------------------------------
;;; The driver

(test reach-random-targets
  "(a), (c): for 200 random reachable targets per arm of each skeleton, the hand
ends within 1 mm, no frame leaves the limits, and nothing is reported."
  (with-seeded-randomness (4)
    (dolist (skeleton *reach-skeletons*)
      (dolist (side '(:left :right))
        (let ((misses 0) (outside 0) (reports 0) (count (sweep-count 200 40))
              (name (format nil "~A ~A" (player.body::skeleton-name skeleton) side)))
          (dotimes (k count)
            (let* ((target (reach-effector-position skeleton (reach-random-pose skeleton side) side))
                   (body (reach-body skeleton))
                   (driver (add-reach body `(:reach :arm ,side :duration 0.5
                                                       :target (:point ,@(reach-vec3-list target))))))
              (multiple-value-bind (hand within) (run-reach-frames body driver side 0.6d0)
                (when (> (player.body::vdistance hand target) 1d-3) (incf misses))
                (unless within (incf outside))
                (when (player::driver-report driver) (incf reports)))))
          (is (= 0 misses) "~A: ~D of ~D targets missed by over 1 mm" name misses count)
          (is (= 0 outside) "~A: ~D reaches left the limits" name outside)
          (is (= 0 reports) "~A: ~D reachable targets reported" name reports))))))

(defparameter *unreachable-targets*
  '((humanoid :right (-2.0 1.4 0.5)) (humanoid :right (0.0 3.0 0.0)) (humanoid :left (0.3 1.2 -1.5))
    (humanoid :left (-0.5 1.3 -0.3)) (humanoid :right (0.4 1.0 -0.4)) (humanoid :right (-0.2 0.5 -0.3))
    (parrot :left (1.0 0.2 0.0)) (parrot :right (0.0 0.2 1.0)) (parrot :left (-0.2 0.1 -0.1))
    (parrot :right (0.06 0.35 0.05)))
  "(SKELETON SIDE (X Y Z)): points too far, or behind the back past the limits.")

(test reach-unreachable-targets
  "(b): an unreachable target is reported, and reached no worse than the best
point of a brute-force grid over the arm's DOFs."
  (loop for (name side point) in *unreachable-targets*
        for skeleton = (find name *reach-skeletons* :key #'player.body::skeleton-name :test #'string-equal)
        for target = (apply #'player.body::make-vec3 point)
        do (let* ((name name) (side side) (point point)
                  (body (reach-body skeleton))
                  (driver (add-reach body `(:reach :arm ,side :target (:point ,@point)))))
             (multiple-value-bind (hand within) (run-reach-frames body driver side 0.7d0)
               (let ((distance (player.body::vdistance hand target))
                     (reference (reach-brute-force-nearest skeleton side target)))
                 (is-true within "~A ~A ~A left the limits" name side point)
                 (is (<= distance (+ reference 1d-3))
                     "~A ~A ~A: ended ~,4F m away; the grid gets within ~,4F m" name side point distance reference)
                 (let* ((report (player::driver-report driver))
                        (end (and report (search " m short" report)))
                        (said (and end (read-from-string
                                        report t nil :start (position #\Space report :end end :from-end t)
                                                     :end end))))
                   (is (and report (search "target out of reach" report)
                            (realp said) (< (abs (- said distance)) 2d-3))
                       "~A ~A ~A: report ~S" name side point report)))))))

(test solver-beats-brute-force
  "(b) for the solver alone: for random targets anywhere around each arm, most
of them out of reach, the hand ends no further than a grid search gets."
  (with-seeded-randomness (5)
    (dolist (skeleton *reach-skeletons*)
      (dolist (side '(:left :right))
        (let ((chain (reach-chain-of skeleton side))
              (scale (if (string-equal (player.body::skeleton-name skeleton) "parrot") 0.4d0 1.5d0))
              (name (format nil "~A ~A" (player.body::skeleton-name skeleton) side)))
          (dotimes (k (sweep-count 8 3))
            (let* ((target (player::vec3 (reach-random (- scale) scale) (reach-random 0 (* 1.5 scale))
                                         (reach-random (- scale) scale)))
                   (distance (nth-value 1 (player.body::solve-arm-chain chain (player::make-pose skeleton) target)))
                   (reference (reach-brute-force-nearest skeleton side target)))
              (is (<= distance (+ reference 1d-3)) "~A ~A: ~,4F m away; the grid gets within ~,4F m"
                  name (reach-vec3-list target) distance reference))))))))

(test reach-is-smooth
  "(d): at 60 fps no channel turns more per frame than the smoothstep's steepest
slope allows (:blend 0, so the body's crossfade does not steepen it)."
  (with-seeded-randomness (6)
    (dolist (skeleton *reach-skeletons*)
      (dolist (side '(:left :right))
        (dotimes (k 20)
          (let* ((target (if (< k 15)
                             (reach-effector-position skeleton (reach-random-pose skeleton side) side)
                             (player::vec3 (reach-random -2 2) (reach-random -1 3) (reach-random -2 2))))
                 (body (reach-body skeleton))
                 (duration 0.6d0)
                 (driver (add-reach body `(:reach :arm ,side :duration ,duration :blend 0
                                                     :target (:point ,@(reach-vec3-list target)))))
                 (name (format nil "~A ~A" (player.body::skeleton-name skeleton) side))
                 (channels (player.body::driver-channels driver))
                 (frames '()))
            (run-reach-frames body driver side (+ duration 0.2d0) :fps 60
                       :check (lambda (time pose) (declare (ignore time)) (push pose frames)))
            (setf frames (nreverse frames))
            (let* ((first-pose (first frames)) (last-pose (car (last frames)))
                   (worst-ratio 0d0))
              (loop for (a b) on frames while b
                    do (dolist (i channels)
                         (let ((total (abs (- (aref last-pose i) (aref first-pose i))))
                               (step (abs (- (aref b i) (aref a i)))))
                           ;; smoothstep's slope peaks at 1.5 / duration
                           (setf worst-ratio (max worst-ratio (/ step (+ 1d-9 (* total (/ 1.5d0 duration 60)))))))))
              (is (<= worst-ratio 1.01d0) "~A: a frame stepped ~,2F times the bound" name worst-ratio))))))))

(test reach-follows-moving-target
  "A target on a moving object is followed once the reach has arrived; the
solution for a given time does not depend on what was evaluated before."
  (let* ((skeleton (first *reach-skeletons*))
         (body (reach-body skeleton))
         (ball (make-instance 'player::scene-object :name 'ball :kind :prop
                                                    :position (player::vec3 -0.35d0 1.2d0 0.3d0)))
         (driver (progn (player::add-object (player.body::body-scene body) ball)
                        (add-reach body '(:reach :target (:object ball) :duration 0.4)))))
    (loop for time from 0 to 2 by 1/30
          for where = (player::vec3 (+ -0.35d0 (* 0.1d0 (sin (* 2 time))))
                                    (+ 1.2d0 (* 0.1d0 (cos (* 3 time)))) 0.3d0)
          do (setf (player::property-value ball 'position) where)
             (is (player::pose-within-limits-p
                  skeleton (player::driver-drive driver (float time 1d0)
                                                 (player.body::copy-pose (player::body-evaluate body time)))))
             (when (> time 0.4)
               (is (< (player.body::vdistance where (player::body-joint-position body :right-hand)) 1d-3))))
    ;; Pure: the same time and scene give the same angles, whatever came before.
    (let ((pose-a (player.body::copy-pose (player::body-pose body)))
          (pose-b (player.body::copy-pose (player::body-pose body))))
      (player::driver-drive driver 1d0 pose-a)
      (player::driver-drive driver 2d0 pose-b)
      (player::driver-drive driver 1d0 pose-b)
      (is (equalp pose-a pose-b)))))

(test reach-hold-and-end
  ":hold NIL ends the reach after its duration; :hold T runs until stopped."
  (let* ((skeleton (first *reach-skeletons*))
         (body (reach-body skeleton))
         (holding (add-reach body '(:reach :target (:point -0.3 1.3 0.4)) 1))
         (ending (add-reach body '(:reach :arm :left :target (:point 2 1.3 0.4) :hold nil :duration 0.5) 1)))
    (is (null (player::driver-end-time holding)))
    (is (= 1.5 (player::driver-end-time ending)))
    (player::body-evaluate body 2)
    (is (member holding (player.body::body-active body)))
    (is (not (member ending (player.body::body-active body))))
    (is (equal '("reach :left: target out of reach, 1.283 m short")
               (mapcar #'third (player.body::body-reports body))))
    (is (null (player::driver-report holding)))))

(test reach-bad-frames
  "(e): a bad arm, a missing or malformed target, a bad duration, and a
skeleton without arms are motor errors."
  (dolist (frame '((:reach :arm :middle :target (:point 0 1 0))
                   (:reach :arm :right)
                   (:reach :target (:pt 0 1 0))
                   (:reach :target (:point 0 1))
                   (:reach :target (:point 0 1 0) :duration 0)
                   (:reach :target (:point 0 1 0) :hold maybe)))
    (signals player::motor-error (player::parse-motor-frame frame)))
  (dolist (skeleton (list (player.body::parse-skeleton
                           '(skeleton armless (:joint root :parent nil :center (0 0 0) :dofs ((:x -10 10)))))
                          (player.body::parse-skeleton
                           '(skeleton handless
                             (:joint root :parent nil :center (0 0 0) :dofs ((:x -10 10)))
                             (:joint sh :parent root :center (0 1 0) :dofs ((:x -90 90)))
                             (:joint el :parent sh :center (0 0.7 0) :dofs ((:x -90 0)))
                             (:joint wr :parent el :center (0 0.4 0))
                             (:role :right-arm (sh el wr))
                             (:role :right-hand sh)))))
    (signals player::motor-error
      (player::make-driver (player::parse-motor-frame '(:reach :target (:point 0 1 0))) (reach-body skeleton) 0))))
