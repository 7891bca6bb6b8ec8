;;;; test-gaze.lisp -- the gaze driver: both eyes' lines of sight through the
;;;; target and meeting there (vergence), the head joining large shifts,
;;;; pursuit of a moving prop, main-sequence saccade durations, the parrot.

(in-package #:player-tests)

(def-suite* gaze :in player-tests)

;;; ---------------------------------------------------------------------------
;;; Helpers, shared with test-face-drivers.lisp

(defun driver-body-in-scene (skeleton &rest make-body-arguments)
  "A body called BOB with SKELETON, in a fresh scene."
  (apply #'player::make-body 'bob skeleton :scene (make-instance 'player::scene)
         make-body-arguments))

(defun start-driver-on (body frame &key (start 0d0) stop)
  "A driver for the motor FRAME on BODY from START (until STOP), scheduled."
  (let ((driver (player::make-driver (player::parse-motor-frame frame) body start :stop stop)))
    (player::body-add-driver body driver)
    driver))

(defun driver-output-within-limits-p (body driver time)
  "Do DRIVER (and its slaves) write only angles within BODY's limits at TIME, on
a copy of BODY's pose?"
  (let ((pose (player.body::copy-pose (player::body-pose body))))
    (dolist (d (append (player::slave-drivers driver) (list driver)))
      (player::driver-drive d (float time 1d0) pose))
    (player::pose-within-limits-p (player::body-skeleton body) pose 1d-6)))

(defun joint-frame (body role)
  "The world transform of BODY's joint filling ROLE (a keyword) or called ROLE,
at its last evaluation."
  (player.body::object-joint-transform
   body (if (keywordp role)
            (player.body::body-joint-name (player::skeleton-role (player::body-skeleton body) role))
            role)))

(defun joint-front (body role)
  "Where BODY's ROLE joint is and its +z axis, in the world (two values)."
  (let ((frame (joint-frame body role)))
    (values (player.body::transform-translation frame)
            (player.body::transform-vector frame (player::vec3 0d0 0d0 1d0)))))

(defun line-miss (origin direction point)
  "How far POINT is from the line through ORIGIN along the unit DIRECTION."
  (let ((w (player.body::v- point origin)))
    (player.body::vnorm (player.body::v- w (player.body::v* direction (player.body::vdot w direction))))))

(defun lines-meeting-point (p1 d1 p2 d2)
  "The midpoint of the closest approach of lines P1 + s D1 and P2 + t D2."
  (let* ((w (player.body::v- p1 p2))
         (a (player.body::vdot d1 d1)) (b (player.body::vdot d1 d2)) (c (player.body::vdot d2 d2))
         (d (player.body::vdot d1 w)) (e (player.body::vdot d2 w))
         (denominator (- (* a c) (* b b))))
    (if (< (abs denominator) 1d-14)
        (player.body::v* d1 1d6)             ; parallel lines meet at infinity
        (let ((s (/ (- (* b e) (* c d)) denominator))
              (u (/ (- (* a e) (* b d)) denominator)))
          (player.body::v* (player.body::v+ (player.body::v+ p1 (player.body::v* d1 s)) (player.body::v+ p2 (player.body::v* d2 u)))
                      0.5d0)))))

(defun gaze-errors (body point)
  "The two eyes' line-of-sight misses of POINT and the distance from POINT of
where the lines meet, in metres (three values)."
  (multiple-value-bind (pl dl) (joint-front body :left-eye)
    (multiple-value-bind (pr dr) (joint-front body :right-eye)
      (values (line-miss pl dl point) (line-miss pr dr point)
              (player.body::vdistance point (lines-meeting-point pl dl pr dr))))))

(defun eyes-midpoint (body)
  "The midpoint of BODY's eyes in its rest pose, as a vec3."
  (player::body-evaluate body 0)
  (player.body::vlerp (joint-front body :left-eye) (joint-front body :right-eye) 0.5d0))

(defun point-target (v)
  "The motor target (:point X Y Z) at the vec3 V."
  (list :point (player.body::vec3-x v) (player.body::vec3-y v) (player.body::vec3-z v)))

(defun gaze-and-check (skeleton offset &key (tolerance 0.01d0) (settle 1.5d0) (samples 30))
  "Gaze from a fresh SKELETON body at its eyes' midpoint plus OFFSET (a vec3);
check the limits on SAMPLES frames up to SETTLE, then the fixation.  Returns the body."
  (let* ((body (driver-body-in-scene skeleton))
         (point (player.body::v+ (eyes-midpoint body) offset))
         (driver (start-driver-on body `(:gaze :target ,(point-target point)) :start 0.1d0)))
    (loop for i from 1 to samples
          for time = (* settle (/ i samples))
          do (player::body-evaluate body time)
             (when (>= time 0.1d0)
               (is-true (driver-output-within-limits-p body driver time)
                        "~A gaze at ~A: a DOF beyond its limits at ~,3F s" skeleton offset time)))
    (multiple-value-bind (left right meet) (gaze-errors body point)
      (is (< left tolerance) "~A gaze at ~A: the left eye misses by ~,4F m" skeleton offset left)
      (is (< right tolerance) "~A gaze at ~A: the right eye misses by ~,4F m" skeleton offset right)
      (is (< meet tolerance) "~A gaze at ~A: the lines meet ~,4F m away" skeleton offset meet))
    body))

(defun dof-value (body joint dof)
  "BODY's angle of JOINT's DOF at its last evaluation."
  (aref (player::body-pose body) (player::dof-index (player::body-skeleton body) joint dof)))

(defun random-offsets (n reach seed)
  "N offsets 1 m ahead, up to REACH metres sideways and vertically, from SEED."
  (let ((state (sb-ext:seed-random-state seed)))
    (loop repeat n
          collect (player::vec3 (- (random (* 2 reach) state) reach)
                                (- (random (* 2 reach) state) reach) 1d0))))

;;; ---------------------------------------------------------------------------
;;; Tests

(test gaze-fixates-targets-within-reach
  "Both eyes' lines of sight pass through the target and meet there."
  (dolist (offset (random-offsets 12 0.35d0 7))
    (gaze-and-check 'humanoid offset)))

(test gaze-eye-angles-follow-the-axis-conventions
  "A target below and to the figure's left: positive pitch (down), positive yaw (left)."
  (let ((body (gaze-and-check 'humanoid (player::vec3 0.1d0 -0.1d0 1d0))))
    (is (plusp (dof-value body 'l_eyeball_joint 'pitch)))
    (is (plusp (dof-value body 'l_eyeball_joint 'yaw)))))

(test gaze-large-shift-moves-the-head
  "A shift of 60 degrees to either side turns the head (and a little trunk) and still fixates."
  (dolist (side '(1d0 -1d0))
    (let* ((angle (/ (* 60 pi) 180))
           (body (gaze-and-check 'humanoid (player::vec3 (* side (sin angle)) 0d0 (cos angle))
                                 :settle 2d0)))
      (is (> (* side (dof-value body 'skullbase :y)) 25) "the head turned only ~,1F degrees"
          (dof-value body 'skullbase :y))
      (is (> (* side (dof-value body 'vl5 :y)) 2) "the trunk did not join"))))

(test gaze-small-shift-leaves-the-head
  (let ((body (gaze-and-check 'humanoid (player::vec3 0.05d0 0d0 1d0))))
    (is (= 0 (dof-value body 'skullbase :y)))))

(test gaze-tracks-a-moving-prop
  "A prop moving along a line is followed within 1 cm after the first saccade,
by the eyes alone near the front and with the head from far to the side."
  (loop for (from to) in '(((-0.3 0 1.2) (0.4 -0.1 1.2)) ((-1.5 0.2 0.8) (-0.2 -0.2 1.2)))
        do (let* ((body (driver-body-in-scene 'humanoid))
                  (mid (eyes-midpoint body))
                  (from (player.body::v+ mid (apply #'player.body::make-vec3 from)))
                  (to (player.body::v+ mid (apply #'player.body::make-vec3 to)))
                  (ball (player::add-object (player.body::body-scene body)
                                            (make-instance 'player::scene-object :name 'ball :kind :prop
                                                                                 :position from))))
             (flet ((place (time)
                      (setf (player::property-value ball 'position)
                            (player.body::vlerp from to (min 1d0 (/ time 3d0))))))
               (let ((driver (start-driver-on body '(:gaze :target (:object ball)))))
                 (loop for frame from 0 to 90
                       for time = (/ frame 30d0)
                       do (place time)
                          (player::body-evaluate body time)
                          (is-true (driver-output-within-limits-p body driver time))
                          (when (> time 1d0)
                            (let ((miss (multiple-value-call #'max
                                          (gaze-errors body (player::object-world-position ball)))))
                              (is (< miss 0.01d0) "at ~,2F s the eyes miss the ball by ~,4F m"
                                  time miss)))))))))

(test gaze-without-tracking-holds-the-first-point
  (let* ((body (driver-body-in-scene 'humanoid))
         (mid (eyes-midpoint body))
         (ball (player::add-object (player.body::body-scene body)
                                   (make-instance 'player::scene-object :name 'ball :kind :prop
                                                                        :position (player.body::v+ mid (player::vec3 0d0 0d0 1d0))))))
    (start-driver-on body '(:gaze :target (:object ball) :track nil))
    (player::body-evaluate body 0.5d0)
    (setf (player::property-value ball 'position) (player.body::v+ mid (player::vec3 0.3d0 0d0 1d0)))
    (player::body-evaluate body 1d0)
    (is (< (multiple-value-call #'max (gaze-errors body (player.body::v+ mid (player::vec3 0d0 0d0 1d0))))
           0.01d0))))

(test saccade-duration-grows-with-amplitude
  "Durations follow the main sequence, 21 ms + 2.2 ms per degree, divided by :speed."
  (is (< (abs (- (player.body::saccade-duration 20) 0.065d0)) 1d-9))
  (is (< (abs (- (player.body::saccade-duration 20 2) 0.0325d0)) 1d-9))
  (let ((durations
          (loop for degrees in '(2 8 14)
                collect (let* ((body (driver-body-in-scene 'humanoid))
                               (radians (/ (* degrees pi) 180))
                               (point (player.body::v+ (eyes-midpoint body)
                                                  (player::vec3 (sin radians) 0d0 (cos radians))))
                               (driver (start-driver-on body `(:gaze :target ,(point-target point)))))
                          (player::body-evaluate body 0.01d0)
                          (player.body::gaze-saccade driver)))))
    (is (apply #'< durations) "durations ~A do not grow" durations)))

(test parrot-gaze-fixates
  "The parrot's eyes turn only 15 degrees: near targets by the eyes, far ones with the head."
  (dolist (offset (random-offsets 8 0.15d0 11))
    (gaze-and-check 'parrot offset))
  (let ((body (gaze-and-check 'parrot (player::vec3 0.8d0 0.2d0 0.6d0) :settle 2d0)))
    (is (> (dof-value body 'head :y) 20))
    (is (> (dof-value body 'neck :y) 5) "the neck did not share the turn")))

(test gaze-bad-frames
  (signals player::motor-error (player::parse-motor-frame '(:gaze)))
  (signals player::motor-error (player::parse-motor-frame '(:gaze :target (:point 0 1) :speed 1)))
  (signals player::motor-error (player::parse-motor-frame '(:gaze :target (:point 0 1 2) :speed 0)))
  (let ((eyeless (player::make-body
                  'stick (player.body::parse-skeleton
                          '(skeleton stick (:joint root :parent nil :center (0 0 0) :dofs ((:y -90 90))))))))
    (signals player::motor-error
      (player::make-driver (player::parse-motor-frame '(:gaze :target (:point 0 1 2))) eyeless 0))))
