;;;; test-layered-channels.lisp -- gestures that add up instead of cancelling
;;;; (issue 29): the Rea case (a nod during a held head turn), equal priorities
;;;; that blend, :usurp, additive beats, sets of channels lost together.

(in-package #:player-tests)

(def-suite* layered-channels :in player-tests)

(defun humanoid-index (joint dof)
  "The pose index of the humanoid's JOINT's DOF."
  (player:dof-index (player::load-skeleton 'humanoid) joint dof))

(defun rea-performance (&key nod)
  "A humanoid performing one script: a head turn held 3 s, and with NOD, a nod
of amplitude 15 at 1 s, both at their default priorities."
  (let* ((library (player.performance::parse-script-library-forms
                   `((defscript rea (:duration 3)
                       (:at 0 :motor (:head :action :turn-to :target (:point 1.5 1.6 1.0)))
                       ,@(and nod '((:at 1 :motor (:head :action :nod :amplitude 15))))))))
         (performance (player:make-performance library '((bob humanoid)))))
    (player:perform-script performance 'rea 0)
    performance))

(defun performance-angle (performance time joint dof)
  "The first character's JOINT DOF angle in PERFORMANCE at TIME."
  (player:performance-frame performance time)
  (aref (player:body-pose (player:performance-body performance)) (humanoid-index joint dof)))

(test rea-a-nod-layers-on-a-held-turn
  (let ((nodding (rea-performance :nod t))
        (turning (rea-performance)))
    (loop for time from 0.1d0 to 2.9d0 by 0.05d0
          for pitch = (- (performance-angle nodding time 'skullbase :x)
                         (performance-angle turning time 'skullbase :x))
          for yaw = (- (performance-angle nodding time 'skullbase :y)
                       (performance-angle turning time 'skullbase :y))
          do (is (< (abs yaw) 1d-9) "the head stays turned during the nod (yaw off by ~,3F at ~,2F s)" yaw time)
             (is (<= -1d-9 pitch 15.000001d0) "the nod pitches down by at most its amplitude (~,3F at ~,2F s)" pitch time)
             (unless (< 1d0 time 1.6d0)
               (is (< (abs pitch) 1d-9) "no nod outside its 0.6 s (~,3F at ~,2F s)" pitch time)))
    ;; Two nods (count 2) over 0.6 s: the head is lowest a quarter and three quarters in.
    (dolist (peak '(1.15d0 1.45d0))
      (is (< (abs (- 15 (- (performance-angle (rea-performance :nod t) peak 'skullbase :x)
                           (performance-angle turning peak 'skullbase :x))))
             1d-6)
          "at ~,2F s the head pitches by the nod's full 15 degrees" peak))
    (is (> (abs (performance-angle turning 2 'skullbase :y)) 30) "the turn really turns the head")))

(defun body-with-calls (&rest calls)
  "A humanoid body in a scene with a ball, each of CALLS, (START FRAME), added."
  (let* ((scene (make-instance 'player:scene))
         (body (player:make-body 'bob 'humanoid :scene scene)))
    (player:add-object scene (make-instance 'player:scene-object :name 'ball :kind :prop
                                                                 :position (player.body::make-vec3 0.3 1.2 0.5)))
    (values body
            (loop for (start frame) in calls
                  collect (player:body-add-driver body (player:make-driver (player:parse-motor-frame frame)
                                                                           body start))))))

(defun angle-at (body time joint dof)
  "BODY's JOINT DOF angle at TIME."
  (aref (player:body-evaluate body time) (humanoid-index joint dof)))

(test equal-priorities-blend-by-weight
  (flet ((elbow (&rest second)
           (angle-at (body-with-calls '(0 (:direct :set ((l_elbow :x -90)) :duration 0))
                                      `(0.5 (:direct :set ((l_elbow :x -30)) :duration 0 ,@second)))
                     2 'l_elbow :x)))
    (is (< (abs (- -60 (elbow))) 1d-9) "two equal calls meet halfway, not the first alone")
    (is (< (abs (- -75 (elbow :weight 1/3))) 1d-9) "weights 1 and 1/3: -90 counts three times as much")
    (is (< (abs (- -30 (elbow :usurp t))) 1d-9) ":usurp takes the channel from an equal")
    (is (< (abs (- -30 (elbow :priority 11))) 1d-9) "a higher priority still wins outright")))

(test joining-a-blend-crossfades
  (let ((body (body-with-calls '(0 (:direct :set ((l_elbow :x -90)) :duration 0))
                               '(1 (:keyframe :keys ((0 ((l_elbow :x -30)))) :hold t)))))
    (is (< (abs (- -90 (angle-at body 1 'l_elbow :x))) 1d-9) "no jump when the second call joins")
    (is (< -90 (angle-at body 1.1 'l_elbow :x) -60) "it fades in over the blend time")
    (is (< (abs (- -60 (angle-at body 1.5 'l_elbow :x))) 1d-9))))

(test beats-add-onto-a-held-arm
  (let* ((pose '(:direct :set ((r_elbow :x -60) (r_shoulder :x -30)) :duration 0 :priority 30))
         (beating (body-with-calls `(0 ,pose) '(0.2 (:beat :arm :right :times (0.5)))))
         (holding (body-with-calls `(0 ,pose))))
    (angle-at beating 0.3 'r_elbow :x)
    (angle-at holding 0.3 'r_elbow :x)
    (let ((moved (loop for (joint dof) in '((r_elbow :x) (r_elbow :y) (r_wrist :x) (r_wrist :z))
                       sum (abs (- (angle-at beating 0.7 joint dof) (angle-at holding 0.7 joint dof))))))
      (is (> moved 5) "the beat shows on an arm held at a higher priority (moved ~,2F degrees)" moved))
    (is (< (abs (- (angle-at beating 1.5 'r_elbow :x) (angle-at holding 1.5 'r_elbow :x))) 1d-9)
        "and leaves it where it was held")))

(defparameter *reach-call* '(:reach :arm :left :target (:joint :self vl5 :offset (0.2 0.2 0.4)) :duration 1)
  "A reach of the left arm taking a second.")

(test a-set-is-lost-together
  (dolist (policy '(:hand-over :end))
    (multiple-value-bind (body drivers)
        (body-with-calls `(0 (,@*reach-call* :on-channel-loss ,policy))
                         '(0.4 (:direct :set ((l_elbow :x -100)) :duration 0.2 :priority 50)))
      (let ((shoulder (humanoid-index 'l_shoulder :x)))
        (player:body-evaluate body 0.4)
        (let ((at-loss (aref (player:body-evaluate body 0.45) shoulder)))
          (is (< (abs (- at-loss (aref (player:body-evaluate body 1.5) shoulder))) 1d-9)
              "~A: the shoulder stops with the elbow it reached with" policy))
        (is (null (player:channel-owner (player.body::body-arbitrator body) shoulder))
            "~A: the reach holds no part of the arm" policy)
        (is (not (member (first drivers) (player.body::body-active body)))
            "~A: the reach, its one set given up, ends" policy)))))

(test a-set-is-taken-together
  (let* ((body (body-with-calls '(0 (:direct :set ((l_elbow :x -100)) :duration 0 :priority 50))
                                `(0.2 ,*reach-call*)))
         (shoulder (humanoid-index 'l_shoulder :x))
         (before (angle-at body 0.2 'l_shoulder :x)))
    (is (< (abs (- before (angle-at body 1.5 'l_shoulder :x))) 1d-9)
        "a reach that cannot have the elbow does not move the shoulder")
    (is (null (player:channel-owner (player.body::body-arbitrator body) shoulder)))))

(test a-lower-priority-does-not-break-a-set
  (let ((reaching (body-with-calls `(0 ,*reach-call*)))
        (disturbed (body-with-calls `(0 ,*reach-call*)
                                    '(0.4 (:direct :set ((l_elbow :x -100)) :duration 0.2 :priority 5)))))
    (is (< (abs (- (angle-at reaching 1.5 'l_shoulder :x) (angle-at disturbed 1.5 'l_shoulder :x))) 1d-9))
    (is (< (abs (- (angle-at reaching 1.5 'l_elbow :x) (angle-at disturbed 1.5 'l_elbow :x))) 1d-9))))

(test hand-over-keeps-the-other-limbs
  (let ((keys '(:keyframe :keys ((0 :start) (2 ((l_shoulder :x -60) (l_elbow :x -60)
                                                (r_shoulder :x -60) (r_elbow :x -60))))
                :hold t)))
    (dolist (policy '(:hand-over :end))
      (let ((body (body-with-calls `(0 (,@keys :on-channel-loss ,policy))
                                   '(0.5 (:direct :set ((l_elbow :x -100)) :duration 0.2 :priority 50)))))
        (let ((left (angle-at body 0.6 'l_shoulder :x))
              (right (angle-at body 0.6 'r_shoulder :x)))
          (is (< (abs (- left (angle-at body 1.5 'l_shoulder :x))) 1d-9)
              "~A: the left shoulder stops with its elbow" policy)
          (if (eq policy :end)
              (is (< (abs (- right (angle-at body 1.5 'r_shoulder :x))) 1d-9) ":end stops the right arm too")
              (is (< (angle-at body 1.5 'r_shoulder :x) (- right 10)) ":hand-over lets the right arm go on")))))))
