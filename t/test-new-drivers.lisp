;;;; test-new-drivers.lisp -- the drivers issue 29 adds (item 5): a forced
;;;; blink, the HandRelaxer, facing full/half/away, reach in gesture space
;;;; with swivel and twist, keyframe repeats, retunable breathing, mood.
;;;; Each parameter moves the joints the way Pantomime describes: signs and amounts.

(in-package #:player-tests)

(def-suite* new-drivers :in player-tests)

(defun lone-body (&optional (skeleton 'humanoid))
  "A body of SKELETON in a scene of its own, with no idle life."
  (player:make-body 'bob skeleton :scene (make-instance 'player:scene)))

(defun add-call (body start frame)
  "Add the driver of FRAME to BODY from START; return it."
  (player:body-add-driver body (player:make-driver (player:parse-motor-frame frame) body start)))

(defun dof-at (body time joint dof)
  "BODY's JOINT DOF at TIME (evaluating it)."
  (aref (player:body-evaluate body time) (player:dof-index (player:body-skeleton body) joint dof)))

(defun near-p (a b &optional (tolerance 1d-6))
  "Are A and B within TOLERANCE?"
  (< (abs (- a b)) tolerance))

(test a-forced-blink-blinks-once
  (let* ((body (lone-body))
         (driver (add-call body 1 '(:blink))))
    (is (near-p 0 (dof-at body 0.9 'l_eyelid_joint 'close)))
    (is (near-p 60 (dof-at body 1.075 'l_eyelid_joint 'close)) "shut at the middle of its 0.15 s")
    (is (near-p 60 (dof-at body 1.075 'r_eyelid_joint 'close)))
    (is (near-p 0 (dof-at body 1.16 'l_eyelid_joint 'close)) "open again")
    (is (not (member driver (player.body::body-active body))) "and done")
    (let ((again (lone-body)))
      (add-call again 1 '(:blink))
      (is (= 1 (length (closing-times again 8))) "one blink, not a reflex"))))

(test the-hand-relaxer-curls-free-fingers
  (let ((body (lone-body)))
    (add-call body 0 '(:hand-relaxer :side :right :curl 30 :duration 1))
    (add-call body 0 '(:direct :set ((r_index1 curl -20)) :duration 0 :priority 10))
    (is (near-p 15 (dof-at body 0.5 'r_middle1 'curl)) "half way in half its :duration")
    (loop for (finger share) in '((r_thumb1 0.5) (r_middle1 1) (r_ring1 1.15) (r_pinky1 1.3))
          do (is (near-p (* share 30) (dof-at body 2 finger 'curl)) "~A curls ~A of :curl" finger share))
    (is (near-p -20 (dof-at body 2 'r_index1 'curl)) "a finger an op holds is not relaxed")
    (is (near-p 0 (dof-at body 2 'l_middle1 'curl)) ":side :right leaves the left hand")))

(test facing-full-half-away
  (flet ((facing (&rest arguments)
           (let ((body (lone-body)))
             (add-call body 0 `(:facing ,@arguments :duration 1))
             (dof-at body 2 'humanoid-root :y))))
    ;; The point is level with the root, on the figure's left (+x): facing it is a turn of +90 about y.
    (is (near-p 90 (facing :target '(:point 3 0.824 0.0277))))
    (is (near-p 45 (facing :target '(:point 3 0.824 0.0277) :mode :half)) "half: 45 degrees off the target")
    (is (near-p 0 (facing :target '(:point 3 0.824 0.0277) :mode :away)) "away: 90 degrees off, a shoulder to it")
    (is (near-p 45 (facing :target '(:point 3 0.824 0.0277) :amount 0.5)) ":amount 0.5 turns half way")
    (is (near-p 0 (facing)) "no target: the front it was placed with")))

(defun wrist-position (body)
  "Where BODY's right wrist is at its last evaluation."
  (player:body-joint-position body 'r_wrist))

(defun gesture-reach-body (&rest arguments)
  "A body reaching with its right arm, ARGUMENTS added to the call, evaluated at 2 s."
  (let ((body (lone-body)))
    (add-call body 0 `(:reach :arm :right ,@arguments :duration 0.5))
    (player:body-evaluate body 2)
    body))

(defun gesture-point (x y z)
  "Gesture space (X Y Z) of the humanoid at rest, in the world."
  (let ((body (lone-body)))
    (player.body::gesture-space-point
     (player:make-driver (player:parse-motor-frame '(:reach :arm :right :target (:zone :center))) body 0)
     (player:make-pose (player:body-skeleton body)) x y z)))

(test reach-into-gesture-space
  (let* ((skeleton (player::load-skeleton 'humanoid))
         (shoulders (player.body::v* (player.body::v+ (player.body::joint-rest-position (player:find-joint skeleton 'l_shoulder))
                                                      (player.body::joint-rest-position (player:find-joint skeleton 'r_shoulder)))
                                     0.5d0)))
    (is (< (player.body::vdistance (gesture-point 0 0 0) shoulders) 1d-9) "the origin is between the shoulders")
    (let ((forward (gesture-point 0 0 0.8)))
      (is (< (player.body::vdistance (player.body::v- forward shoulders)
                                     (player.body::make-vec3 0 0 (* 0.8 (+ 0.3021 0.2696))))
             0.01)
          "z is in arm lengths, forward"))
    (dolist (zone (mapcar #'first player.body::*gesture-zones*))
      (let* ((body (gesture-reach-body :target `(:zone ,zone)))
             (point (destructuring-bind (x y z) (rest (assoc zone player.body::*gesture-zones*))
                      (gesture-point (- x) y z))))
        (is (< (player.body::vdistance (wrist-position body) point) 0.01)
            "the right hand reaches the zone ~A" zone)))
    (flet ((wrist (zone) (wrist-position (gesture-reach-body :target `(:zone ,zone)))))
      (is (> (player.body::vec3-y (wrist :periphery-upper)) (player.body::vec3-y shoulders)) "upper periphery: above the shoulders")
      (is (< (player.body::vec3-x (wrist :extreme-periphery-side)) (- (player.body::vec3-x shoulders) 0.4))
          "the right arm's extreme periphery is far to its right (-x)")
      (is (< (abs (player.body::vec3-x (wrist :center-center))) 0.05) "the centre-centre is before the chest"))
    (is (< (player.body::vdistance (wrist-position (gesture-reach-body :target '(:point 0 0 0.8) :space :gesture))
                                   (gesture-point 0 0 0.8))
           0.01)
        ":space :gesture places a :point in gesture space")))

(test reach-swivel-and-twist
  (let* ((target '(:zone :center))
         (plain (gesture-reach-body :target target))
         (out (gesture-reach-body :target target :swivel 40))
         (in (gesture-reach-body :target target :swivel -40)))
    (flet ((elbow (body) (player:body-joint-position body 'r_elbow)))
      (is (< (player.body::vdistance (wrist-position out) (wrist-position plain)) 0.01) "the hand stays put")
      (is (> (player.body::vec3-y (elbow out)) (+ (player.body::vec3-y (elbow plain)) 0.02)) "a positive swivel lifts the elbow")
      (is (< (player.body::vec3-x (elbow out)) (player.body::vec3-x (elbow plain))) "outward: to the right arm's side")
      (is (> (player.body::vec3-x (elbow in)) (player.body::vec3-x (elbow plain))) "a negative swivel brings it in"))
    (dolist (twist '(30 -30))
      (is (near-p twist (dof-at (gesture-reach-body :target target :twist twist) 2 'r_elbow :y))
          "the forearm twists to ~A" twist))
    (is (near-p (dof-at plain 2 'r_elbow :y) 0) "no :twist keeps the forearm")))

(test keyframe-repeat
  (let* ((body (lone-body))
         (driver (add-call body 0 '(:keyframe :keys ((0.5 ((l_elbow :x -90))) (1 ((l_elbow :x -10)))) :repeat 3))))
    (dolist (time '(0.5 1.5 2.5))
      (is (near-p -90 (dof-at body time 'l_elbow :x)) "the keys play again at ~A s" time))
    (is (near-p -10 (dof-at body 2.99 'l_elbow :x) 0.1))
    (is (member driver (player.body::body-active body)) "still playing its third time")
    (is (near-p -10 (dof-at body 4 'l_elbow :x)) "holding the last key")
    (is (not (member driver (player.body::body-active body))) "three times, then done")
    (signals player:motor-error (player:make-driver (player:parse-motor-frame '(:keyframe :keys ((1 ((l_elbow :x -9)))) :repeat 1.5))
                                                    (lone-body) 0))))

(test breathing-rate-and-depth-retune-while-it-runs
  (let* ((body (lone-body))
         (chest (player:dof-index (player:body-skeleton body) 'vl5 :x))
         (head (player:dof-index (player:body-skeleton body) 'skullbase :x)))
    (add-call body 0 '(:breathe))
    (flet ((chest (time) (aref (player:body-evaluate body time) chest)))
      ;; 14 breaths a minute, depth 1: the chest lifts (extends: negative x) by 1 at half a breath.
      (is (near-p -1 (chest (/ 30d0 14))))
      (is (near-p 1 (aref (player:body-pose body) head)) "the head keeps level, tipping as much as the chest lifts")
      (is (near-p 0 (chest (/ 60d0 14))) "a breath takes 60/14 s")
      (setf (player:property-value body 'player.body::breathing-rate) 30)
      (chest 5)
      ;; From 5 s at 30 a minute: the next top is where the phase reaches an odd half.
      (let* ((phase (+ (* 14 5/60) 0d0))
             (top (+ 5 (* 2 (- (+ (floor (- phase 1/2)) 1.5) phase)))))
        (is (near-p -1 (chest top) 1d-6) "a faster rate, from where the breath was"))
      (setf (player:property-value body 'player.body::breathing-depth) 3)
      (is (< (abs (chest 9.5)) 3.01))
      (let ((late (loop for time from 20 to 22 by 0.01 minimize (chest time))))
        (is (near-p -3 late 0.01) "a deeper breath after the depth eased in (~,3F)" late)))))

(test mood-scales-amplitude-and-speed
  (flet ((nod (mood)
           (let ((body (lone-body)))
             (setf (player:property-value body 'player.body::mood) mood)
             (let ((driver (add-call body 0 '(:head :action :nod :count 1 :amplitude 10 :duration 1))))
               (values (loop for time from 0 to 1.2 by 0.005d0 maximize (dof-at body time 'skullbase :x))
                       (player.body::driver-finish-time driver))))))
    (multiple-value-bind (amplitude end) (nod 0)
      (is (near-p 10 amplitude 1d-3)) (is (near-p 1 end)))
    (multiple-value-bind (amplitude end) (nod 1)
      (is (near-p 13 amplitude 1d-3) "happy: 30 % bigger") (is (near-p 0.8 end) "and 25 % faster"))
    (multiple-value-bind (amplitude end) (nod -1)
      (is (near-p 7 amplitude 1d-3) "sad: smaller") (is (near-p (/ 1 0.75) end) "and slower"))
    (is (near-p 13 (nod 5) 1d-3) "within limits")
    (is (plusp (player:emotion-mood 'happy)))
    (is (minusp (player:emotion-mood "sad")))
    (is (zerop (player:emotion-mood 'puzzled)))))

(test breathing-adds-onto-a-held-chest-when-not-idle
  (flet ((chest (&rest breathe)
           (let ((body (lone-body)))
             (add-call body 0 '(:direct :set ((vl5 :x 20)) :duration 0))
             (add-call body 0 `(:breathe ,@breathe))
             (dof-at body (/ 30d0 14) 'vl5 :x))))
    (is (near-p 20 (chest)) "idle life yields to the op holding the chest")
    (is (near-p 19 (chest :idle nil)) ":idle nil breathes on top of it")
    (is (near-p 19.5 (chest :idle nil :weight 0.5)) "by its :weight")))

(test saccades-and-weight-shifts-stay-within-their-amplitudes
  (let ((body (lone-body)))
    (add-call body 0 '(:saccades :amplitude 4 :mean-interval 0.5))
    (add-call body 0 '(:weight-shift :amplitude 2 :period 1 :transition 0.2))
    (let ((yaws '()) (leans '()))
      (loop for time from 0.05d0 to 20 by 0.05d0
            do (player:body-evaluate body time)
               (let ((yaw (dof-at body time 'l_eyeball_joint 'yaw))
                     (lean (dof-at body time 'vl5 :z)))
                 (is (near-p yaw (dof-at body time 'r_eyeball_joint 'yaw)) "both eyes jump together")
                 (is (<= (abs (dof-at body time 'l_eyeball_joint 'pitch)) 2.000001) "pitch: half the amplitude")
                 (is (near-p (- lean) (dof-at body time 'skullbase :z)) "the head stays upright")
                 (push yaw yaws) (push lean leans)))
      (is (<= (reduce #'max (mapcar #'abs yaws)) 4.000001))
      (is (> (length (remove-duplicates yaws)) 20) "many saccades in 20 s at 0.5 s apart")
      (loop with shifting = (lone-body)
            initially (add-call shifting 0 '(:weight-shift :amplitude 2 :period 1 :transition 0.2))
            for k from 1 to 19
            for lean = (dof-at shifting (+ k 0.5d0) 'vl5 :z)
            do (is (<= 0.999999 (abs lean) 2.000001) "a shift leans between half and all of :amplitude (~,3F)" lean)
               (is (eq (oddp k) (plusp lean)) "alternate sides")))))

(test a-performance-mood-from-an-emotion
  (let ((performance (player:make-performance
                      (player.performance::parse-script-library-forms
                       '((idle nil)
                         (defscript nod (:duration 1) (:at 0 :motor (:head :action :nod :count 1 :amplitude 10 :duration 1)))))
                      '((bob humanoid))))
        (index (player:dof-index (player::load-skeleton 'humanoid) 'skullbase :x)))
    (flet ((deepest (from)
             (loop for time from from to (+ from 1) by 0.01d0
                   maximize (progn (player:performance-frame performance time)
                                   (aref (player:body-pose (player:performance-body performance)) index)))))
      (player:perform-script performance 'nod 0)
      (player:perform-script performance 'nod 2)
      (is (= 0.6d0 (player:performance-set-mood performance 'happy :at 1.5)))
      (is (near-p 10 (deepest 0) 1d-3) "neutral before")
      (is (near-p 11.8 (deepest 2) 0.01) "happy (0.6): 18 % bigger after")
      (is (near-p 10 (deepest 0) 1d-3) "and a replay from the start agrees"))))
