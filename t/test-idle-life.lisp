;;;; test-idle-life.lisp -- a body at rest is never still (issue 29, item 4):
;;;; idle blinks at their declared mean interval, breathing, saccades, weight
;;;; shifts and relaxed hands by default, every one overridden by any op, all
;;;; seeded; (idle nil) keeps a library's characters still.

(in-package #:player-tests)

(def-suite* idle-life :in player-tests)

(defun idle-body (skeleton seed)
  "A body of SKELETON in a scene, with its idle life from 0 seeded by SEED."
  (let* ((scene (make-instance 'player:scene))
         (body (player:make-body 'bob skeleton :scene scene)))
    (player:start-idle-life body 0 :seed seed)
    body))

(defun closing-times (body seconds &key (step 1/40))
  "The times in [0, SECONDS] when BODY's left upper lid passes half shut, closing."
  (let* ((skeleton (player:body-skeleton body))
         (lid (player.body::lid-close-channel
               (player:make-driver (player:parse-motor-frame '(:blink)) body 0)
               (player.body::skeleton-role skeleton :left-upper-lid)))
         (shut nil))
    (loop for i from 0 to (round seconds step)
          for time = (* i (float step 1d0))
          for now = (> (aref (player:body-evaluate body time) lid) 30)
          when (and now (not shut)) collect time
          do (setf shut now))))

(test idle-blinks-keep-their-mean-interval
  (let ((declared (getf (rest (assoc :blink player:*idle-life-calls*)) :mean-interval)))
    (dolist (seed '(0 1 2))
      (let* ((times (closing-times (idle-body 'humanoid seed) 60))
             (mean (/ (- (car (last times)) (first times)) (1- (length times)))))
        (is (<= (* 0.8 declared) mean (* 1.2 declared))
            "seed ~D: ~D idle blinks in 60 s, a mean interval of ~,2F s, declared ~A s"
            seed (length times) mean declared)))))

(defun rest-library-performance (&rest forms)
  "A humanoid performing a library of FORMS (none started)."
  (player:make-performance (player.performance::parse-script-library-forms forms) '((bob humanoid))))

(defun pose-at (performance time)
  "A copy of PERFORMANCE's first character's pose at TIME."
  (player:performance-frame performance time)
  (copy-seq (player:body-pose (player:performance-body performance))))

(test a-character-at-rest-is-never-still
  (let* ((alive (rest-library-performance))
         (still (rest-library-performance '(idle nil)))
         (skeleton (player::load-skeleton 'humanoid))
         (rest (player:make-pose skeleton)))
    (flet ((moved (pose joint dof)
             (abs (- (aref pose (player:dof-index skeleton joint dof))
                     (aref rest (player:dof-index skeleton joint dof))))))
      (let ((poses (loop for time from 0.5d0 to 12 by 0.5d0 collect (pose-at alive time))))
        (is (some (lambda (pose) (> (moved pose 'vl5 :x) 0.5)) poses) "it breathes (the chest lifts)")
        (is (some (lambda (pose) (> (moved pose 'vl5 :z) 0.5)) poses) "it shifts its weight")
        (is (some (lambda (pose) (> (moved pose 'l_eyeball_joint 'yaw) 0.5)) poses) "its eyes make saccades")
        (is (every (lambda (pose) (> (moved pose 'r_middle1 'curl) 20)) (cdr poses)) "its hands rest curled"))
      (dolist (time '(0.5d0 3d0 11d0))
        (is (equalp rest (pose-at still time)) "(idle nil): the rest pose at ~A s" time)))))

(test any-op-overrides-idle-life
  (let ((forms '((defscript hold (:duration 6)
                   (:at 0 :motor (:direct :set ((vl5 :x 10 :z -5) (l_index1 curl -20) (l_pinky1 curl -20)) :duration 0.5))
                   (:at 0 :motor (:gaze :target (:point 0.5 1.6 2)))))))
    (let ((alive (apply #'rest-library-performance forms))
          (still (apply #'rest-library-performance '(idle nil) forms))
          (skeleton (player::load-skeleton 'humanoid)))
      (player:perform-script alive 'hold 0)
      (player:perform-script still 'hold 0)
      (dolist (time '(2d0 3.3d0 5.9d0))
        (let ((a (pose-at alive time)) (b (pose-at still time)))
          (loop for (joint dof) in '((vl5 :x) (vl5 :z) (l_index1 curl) (l_pinky1 curl)
                                     (l_eyeball_joint pitch) (r_eyeball_joint yaw))
                for i = (player:dof-index skeleton joint dof)
                do (is (< (abs (- (aref a i) (aref b i))) 1d-9)
                       "~A ~A at ~A s: the op's ~,3F, not idle life's ~,3F" joint dof time (aref b i) (aref a i))))))))

(test idle-life-resumes-where-an-op-lets-go
  (let ((performance (rest-library-performance
                      '(defscript grip (:duration 1)
                        (:at 0 :motor (:direct :set ((r_middle1 curl 80)) :duration 0.3)))))
        (index (player:dof-index (player::load-skeleton 'humanoid) 'r_middle1 'curl)))
    (player:perform-script performance 'grip 2)
    (is (< (abs (- 80 (aref (pose-at performance 2.9d0) index))) 1d-6) "the grip holds the fingers")
    (let ((just-after (aref (pose-at performance 3.1d0) index))
          (later (aref (pose-at performance 6d0) index)))
      (is (< 40 just-after 80) "released, the fingers start to relax (~,2F)" just-after)
      (is (< (abs (- 25 later)) 1d-6) "and rest at the relaxed curl (~,2F)" later))))

(test idle-life-is-seeded
  (flet ((frames (seed)
           (let ((performance (player:make-performance (player.performance::parse-script-library-forms '())
                                                       '((bob humanoid)) :seed seed)))
             (loop for time from 0 to 8 by 0.25d0 collect (pose-at performance time)))))
    (is (equalp (frames 3) (frames 3)) "the same seed, the same idle life")
    (is (not (equalp (frames 3) (frames 4))) "another seed, another")))

(test peedy-has-idle-life
  (let* ((body (idle-body 'parrot 0))
         (kinds (mapcar (lambda (driver) (player.body::motor-call-function (player.body::driver-call driver)))
                        (append (player.body::body-pending body) (player.body::body-active body)))))
    (is (subsetp '(:blink :breathe :saccades :weight-shift) kinds) "~A" kinds)
    (is (not (member :hand-relaxer kinds)) "a parrot has no fingers to relax")
    (is (closing-times body 20) "his lids blink")))

(defun knee-range (&rest frames)
  "How far a parrot's left knee moves between 2 and 4.5 s with idle life, after FRAMES (ending by 1 s) shape it."
  (let ((body (idle-body 'parrot 0)))
    (dolist (frame frames)
      (player:body-add-driver body (player:make-driver (player:parse-motor-frame frame) body 0)))
    (let ((angles (loop for time from 2 to 4.5 by 0.05d0 collect (dof-at body time 'l_knee :x))))
      (- (reduce #'max angles) (reduce #'min angles)))))

(test peedy-waves-his-legs-while-sitting-awake
  (let ((sit '(:keyframe :keys ((0 ((l_knee x 45) (r_knee x 45))) (0.5 ((l_knee x 45) (r_knee x 45))))))
        (doze '(:keyframe :keys ((0 ((:left-upper-lid close 56) (:right-upper-lid close 56)))
                                 (0.5 ((:left-upper-lid close 56) (:right-upper-lid close 56)))))))
    (is (> (knee-range sit) 15) "sitting awake, the legs swing (~,2F degrees)" (knee-range sit))
    (is (< (knee-range) 1d-9) "standing, they do not")
    (is (< (knee-range sit doze) 1d-9) "dozing, they rest")))

(test two-characters-do-not-blink-as-one
  (let* ((performance (player:make-performance (player.performance::parse-script-library-forms '())
                                               (list '(ann humanoid) (list 'bob 'humanoid (player.body::make-vec3 1 0 0)))))
         (lid (player:dof-index (player::load-skeleton 'humanoid) 'l_eyelid_joint 'close))
         (shut (loop for time from 0 to 20 by 1/40
                     do (player:performance-frame performance (float time 1d0))
                     collect (mapcar (lambda (name)
                                       (> (aref (player:body-pose (player:performance-body performance name)) lid) 30))
                                     '(ann bob)))))
    (is (some #'first shut) "ann blinks")
    (is (some #'second shut) "bob blinks")
    (is (notevery (lambda (both) (eq (first both) (second both))) shut) "but not at the same moments")))
