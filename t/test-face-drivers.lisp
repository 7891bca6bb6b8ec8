;;;; test-face-drivers.lisp -- the blink, head, facing and eyebrows drivers.
;;;; Uses the helpers of test-gaze.lisp, which loads first.

(in-package #:player-tests)

(def-suite* face-drivers :in player-tests)

(defun run-frames (body driver times &optional (check (constantly nil)))
  "Evaluate BODY at each of TIMES (increasing), checking DRIVER's output stays
within limits and calling CHECK with each time after evaluating."
  (dolist (time times)
    (player::body-evaluate body time)
    (when (>= time (player.body::driver-start driver))
      (is-true (driver-output-within-limits-p body driver time)
               "~A: a DOF beyond its limits at ~,3F s" (player.body::motor-call-frame (player.body::driver-call driver)) time))
    (funcall check time)))

(defun frame-times (from to &optional (step 1/30))
  "The times FROM to TO by STEP, as double-floats."
  (loop for time from from to to by step collect (float time 1d0)))

(defun front-angle (body role point &key horizontal)
  "Degrees between ROLE's +z and the direction from ROLE's joint to POINT; with
HORIZONTAL, both projected on the ground plane."
  (multiple-value-bind (origin front) (joint-front body role)
    (let ((to (player.body::v- point origin)))
      (when horizontal
        (setf (player.body::vec3-y to) 0d0 (player.body::vec3-y front) 0d0))
      (player.body::angle-between front to))))

;;; ---------------------------------------------------------------------------
;;; Blink

(test blink-intervals-are-exponential-and-seeded
  (dolist (mean '(4.0 1.5))
    (let* ((intervals (player.body::blink-intervals 10000 :seed 3 :mean-interval mean))
           (average (/ (reduce #'+ intervals) 10000)))
      (is (< (abs (- average mean)) (* 0.05 mean)) "mean ~,3F, wanted ~A" average mean)
      (is (every #'plusp intervals))
      ;; Exponential: about 1 - 1/e of the intervals are below the mean.
      (is (< 0.6 (/ (count-if (lambda (x) (< x mean)) intervals) 10000) 0.66))))
  (is (equal (player.body::blink-intervals 50 :seed 9) (player.body::blink-intervals 50 :seed 9)))
  (is (not (equal (player.body::blink-intervals 50 :seed 9) (player.body::blink-intervals 50 :seed 10)))))

(defun lid-angles (body)
  "BODY's two upper-lid close angles."
  (list (dof-value body 'l_eyelid_joint 'close) (dof-value body 'r_eyelid_joint 'close)))

(test blink-shuts-the-lids-mid-blink-and-opens-between
  (let* ((body (driver-body-in-scene 'humanoid))
         (driver (start-driver-on body '(:blink :mean-interval 1.0 :seed 5 :blend 0)))
         (blinks (progn (player::body-evaluate body 0) (player.body::blink-times driver 20d0)))
         (duration 0.15d0)
         (shut (loop for b in blinks collect (+ b (/ duration 2))))
         (open (loop for (a b) on blinks
                     when (and b (> (- b a) (* 2 duration))) collect (/ (+ a duration b) 2))))
    (is (> (length blinks) 10))
    (run-frames body driver (sort (remove-duplicates (append shut open (frame-times 0 20 1/10))) #'<)
                (lambda (time)
                  (cond ((member time shut)
                         (is (every (lambda (a) (< (abs (- a 60)) 1)) (lid-angles body))
                             "lids ~A at the middle of a blink at ~,3F" (lid-angles body) time))
                        ((member time open)
                         (is (every (lambda (a) (< (abs a) 1d-9)) (lid-angles body))
                             "lids ~A between blinks at ~,3F" (lid-angles body) time)))))))

(test blink-on-gaze-shift
  (dolist (on '(t nil))
    (let* ((body (driver-body-in-scene 'humanoid))
           (blink (start-driver-on body `(:blink :mean-interval 1000 :on-gaze-shift ,on :blend 0))))
      (start-driver-on body '(:gaze :target (:point 1 1.7 1)) :start 1d0)
      (run-frames body blink (list 0.5d0 1d0 1.075d0 1.5d0)
                  (lambda (time)
                    (let ((lids (lid-angles body)))
                      (if (and on (= time 1.075d0))
                          (is (every (lambda (a) (< (abs (- a 60)) 1)) lids) "no blink on the gaze shift: ~A" lids)
                          (is (every (lambda (a) (< (abs a) 1d-9)) lids) "lids ~A at ~A" lids time)))))))
  (signals player::motor-error
    (player::make-driver (player::parse-motor-frame '(:blink :seed 1.5)) (driver-body-in-scene 'humanoid) 0)))

;;; ---------------------------------------------------------------------------
;;; Head

(test head-nod-and-shake-end-by-themselves
  (loop for (action moving still) in '((:nod :x :y) (:shake :y :x))
        do (let* ((body (driver-body-in-scene 'humanoid))
                  (driver (start-driver-on body `(:head :action ,action :count 2 :amplitude 15
                                                        :duration 0.6 :blend 0)
                                           :start 0.5d0))
                  (peak 0d0))
             (run-frames body driver (frame-times 0 1.5 1/100)
                         (lambda (time)
                           (declare (ignore time))
                           (setf peak (max peak (abs (dof-value body 'skullbase moving))))
                           (is (= 0 (dof-value body 'skullbase still)))))
             (is (< 14 peak 15.001) "~A peak ~,2F" action peak)
             (is (= 1.1d0 (player::driver-end-time driver)))
             (is (not (member driver (player.body::body-active body))) "~A did not end" action)
             (is (< (abs (dof-value body 'skullbase moving)) 1d-9) "~A did not return" action))))

(test parrot-nod-shares-neck-and-head
  (let* ((body (driver-body-in-scene 'parrot))
         (driver (start-driver-on body '(:head :action :nod :count 1 :amplitude 30 :duration 1 :blend 0))))
    (run-frames body driver '(0.5d0))
    (is (< (abs (- 30 (+ (dof-value body 'neck :x) (dof-value body 'head :x)))) 1d-6))
    (is (plusp (dof-value body 'neck :x)))))

(test head-turn-to-faces-the-target
  (loop for (skeleton point) in '((humanoid (0.5 1.8 1.0)) (humanoid (-0.6 1.4 0.8))
                                  (parrot (0.3 0.3 0.3)) (parrot (-0.4 0.1 0.2)))
        do (let* ((body (driver-body-in-scene skeleton))
                  (driver (start-driver-on body `(:head :action :turn-to :target (:point ,@point)))))
             (run-frames body driver (frame-times 0 1.5 1/20))
             (is (< (front-angle body :head (apply #'player.body::make-vec3 point)) 1)
                 "~A's head is ~,2F degrees off ~A" skeleton
                 (front-angle body :head (apply #'player.body::make-vec3 point)) point)
             (is (member driver (player.body::body-active body)) "turn-to should hold until stopped"))))

(test head-turn-away-turns-to-the-other-side
  (let* ((body (driver-body-in-scene 'humanoid))
         (driver (start-driver-on body '(:head :action :turn-away :target (:point 1 1.6 1) :amplitude 30))))
    (run-frames body driver (frame-times 0 1 1/20))
    (is (< (abs (+ 30 (dof-value body 'skullbase :y))) 1d-6))))

(test head-bad-frames
  (signals player::motor-error (player::parse-motor-frame '(:head :action :wobble)))
  (signals player::motor-error
    (player::make-driver (player::parse-motor-frame '(:head :count 1.5))
                         (driver-body-in-scene 'humanoid) 0))
  (signals player::motor-error
    (player::make-driver (player::parse-motor-frame '(:head :action :turn-to))
                         (driver-body-in-scene 'humanoid) 0)))

;;; ---------------------------------------------------------------------------
;;; Facing

(test facing-turns-the-body-to-the-target
  (loop for (point position yaw) in '(((2 0 1) (0 0 0) 0) ((-1 0 -2) (0 0 0) 0)
                                      ((0 1 -3) (1 0 0) 90) ((-2 0 2) (0.5 0 -1) -135))
        do (let* ((rotation (player.body::quat-from-axis-angle (player::vec3 0d0 1d0 0d0) (/ (* yaw pi) 180)))
                  (body (driver-body-in-scene 'humanoid :position (apply #'player.body::make-vec3 position)
                                                        :rotation rotation))
                  (target (apply #'player.body::make-vec3 point))
                  (driver (start-driver-on body `(:facing :target (:point ,@point) :duration 1))))
             (run-frames body driver (frame-times 0 1.5 1/10))
             (let* ((root (player.body::body-joint-name (player.body::skeleton-root (player::body-skeleton body))))
                    (off (front-angle body root target :horizontal t)))
               (is (< off 1) "facing ~A from ~A: ~,2F degrees off" point position off))
             (is (not (member driver (player.body::body-active body))) "facing should end"))))

(test facing-needs-a-known-mode
  ;; Without a :target the body faces the front it was placed with (issue 29).
  (signals player::motor-error (player::parse-motor-frame '(:facing :mode :sideways))))

;;; ---------------------------------------------------------------------------
;;; Eyebrows

(test eyebrows-raise-hold-and-return
  (let* ((body (driver-body-in-scene 'humanoid))
         (driver (start-driver-on body '(:eyebrows :raise 1.0 :duration 0.3 :hold 1.0 :blend 0))))
    (run-frames body driver (frame-times 0 2 1/20)
                (lambda (time)
                  (let ((left (dof-value body 'l_eyebrow_joint 'raise))
                        (right (dof-value body 'r_eyebrow_joint 'raise)))
                    (cond ((<= 0.3d0 time 1.3d0) (is (= 20 left right) "brows ~A ~A at ~A" left right time))
                          ((>= time 1.6d0) (is (= 0 left right)))))))
    (is (not (member driver (player.body::body-active body))))))

(test eyebrows-lower-one-side
  (let* ((body (driver-body-in-scene 'humanoid))
         (driver (start-driver-on body '(:eyebrows :raise -0.5 :side :left :hold nil :blend 0))))
    (run-frames body driver (frame-times 0 3 1/10))
    (is (= -5 (dof-value body 'l_eyebrow_joint 'raise)))
    (is (= 0 (dof-value body 'r_eyebrow_joint 'raise)))
    (is (member driver (player.body::body-active body)) ":hold nil holds until stopped")))

(test parrot-raises-its-crest
  (let* ((body (driver-body-in-scene 'parrot))
         (driver (start-driver-on body '(:eyebrows :raise 0.5 :blend 0))))
    (run-frames body driver (frame-times 0 0.8 1/10))
    (is (= 30 (dof-value body 'crest 'raise)))))

(test eyebrows-bad-frames
  (signals player::motor-error
    (player::make-driver (player::parse-motor-frame '(:eyebrows :raise 2.0)) (driver-body-in-scene 'humanoid) 0))
  (signals player::motor-error (player::parse-motor-frame '(:eyebrows :side :middle)))
  (let ((browless (player::make-body
                   'stick (player.body::parse-skeleton
                           '(skeleton stick (:joint root :parent nil :center (0 0 0) :dofs ((:y -90 90))))))))
    (signals player::motor-error
      (player::make-driver (player::parse-motor-frame '(:eyebrows)) browless 0))))

;;; ---------------------------------------------------------------------------
;;; Purity

(test drivers-are-pure-in-time
  "Driving again at an earlier time, after later ones, gives the same angles."
  (let* ((body (driver-body-in-scene 'humanoid))
         (drivers (list (start-driver-on body '(:blink :mean-interval 0.5 :seed 2))
                        (start-driver-on body '(:head :action :shake :duration 2))
                        (start-driver-on body '(:gaze :target (:point 1.2 1.5 0.6)) :start 0.5d0)))
         (times (frame-times 0.6 1.8 1/10))
         (first-pass '()))
    (flet ((drive-all (time)
             (let ((pose (player.body::copy-pose (player::body-pose body))))
               (dolist (d drivers pose)
                 (dolist (s (append (player::slave-drivers d) (list d)))
                   (player::driver-drive s time pose))))))
      (dolist (time times)
        (player::body-evaluate body time)
        (push (cons time (drive-all time)) first-pass))
      (loop for (time . pose) in first-pass
            do (is (equalp pose (drive-all time)) "the angles at ~,2F s changed" time)))))
