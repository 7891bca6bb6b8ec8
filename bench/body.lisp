;;;; body.lisp -- pose evaluation: frames per second of one body with every
;;;; driver active at once, and how the cost grows with the number of
;;;; characters in a scene.  Loaded by run.lisp.

(in-package #:player-bench)

(defparameter *frame-step* (/ 1d0 60)
  "Seconds between evaluated frames.")

(defun all-driver-frames (skeleton-name)
  "Motor frames that keep every kind of driver busy on SKELETON-NAME for a long
time: keyframes, direct, gaze tracking a moving prop (with its head slave),
blink, head turn, facing, eyebrows (the parrot's crest), reach, beats, lips, idle."
  (let ((beats (loop for i from 1 to 2000 collect (* i 0.7)))
        (visemes (loop for i from 0 below 4000
                       collect (list (* i 0.15) (nth (mod i 4) '(:aa :mm :oh :ee))))))
    `((:keyframe :keys ((0 :start) (1 ((l_hip :x 10))) (2 ((l_hip :x 0))))
                 :loop t :priority 5)
      (:direct :set ,(if (eq skeleton-name 'parrot) '((:tail :x 10)) '((:left-fingers curl 40)))
               :priority 5)
      (:gaze :target (:object ball))
      (:blink :mean-interval 2.0)
      (:head :action :turn-to :target (:object ball) :priority 15)
      (:facing :target (:point 0 0 3))
      (:eyebrows :raise 0.5 :hold nil)
      ;; A reachable target: the wing to the ear for the parrot, a point in
      ;; front of the chest for the humanoid (an unreachable one searches).
      (:reach :arm :left :target ,(if (eq skeleton-name 'parrot)
                                      '(:joint :self :head :offset (0.05 0 0))
                                      '(:joint :self vl5 :offset (0.2 0.1 0.35))))
      (:beat :arm :right :times ,beats)
      (:lips :visemes ,visemes)
      (:idle :amplitude 2 :joints (:spine)))))

(defun bench-scene (skeleton-name count)
  "A scene with a moving ball and COUNT bodies of SKELETON-NAME, each with every driver."
  (let* ((scene (make-instance 'player:scene))
         (ball (player:add-object scene (make-instance 'player:scene-object
                                                       :name 'ball :kind :prop
                                                       :position (player.body::make-vec3 0.3 1.2 1.0))))
         (skeleton (player:load-skeleton skeleton-name))
         (bodies (loop for i below count
                       collect (player:make-body (intern (format nil "BODY-~D" i) '#:player-bench)
                                                 skeleton :scene scene
                                                 :position (player.body::make-vec3 (* 0.8 i) 0 0)))))
    (dolist (body bodies)
      (dolist (frame (all-driver-frames skeleton-name))
        (when (or (not (eq (first frame) :eyebrows))
                  (player::skeleton-role skeleton :left-brow)
                  (player::skeleton-role skeleton :crest))
          (player:body-add-driver body (player:make-driver (player:parse-motor-frame frame) body 0d0)))))
    (values scene bodies ball)))

(defun frame-evaluator (skeleton-name count)
  "A thunk that evaluates the next frame of a BENCH-SCENE (the ball moves)."
  (multiple-value-bind (scene bodies ball) (bench-scene skeleton-name count)
    (declare (ignore scene))
    (let* ((time 0d0)
           (thunk (lambda ()
                    (incf time *frame-step*)
                    (setf (player:property-value ball 'position)
                          (player.body::make-vec3 (* 0.4 (sin time)) 1.2 1.0))
                    (dolist (body bodies)
                      (player:body-evaluate body time)))))
      ;; Ten simulated seconds past the starts (the first saccades, turns and
      ;; reaches), so the timing is the steady state.
      (dotimes (i (round 10 *frame-step*)) (funcall thunk))
      thunk)))

(defun idle-life-evaluator ()
  "A thunk that evaluates the next frame of a humanoid at rest with its idle
life (blinks, breathing, saccades, weight shifts, relaxed hands), as every
performance's characters have by default."
  (let* ((scene (make-instance 'player:scene))
         (body (player:make-body 'idle-bench 'humanoid :scene scene))
         (time 0d0))
    (player:start-idle-life body 0)
    (let ((thunk (lambda () (player:body-evaluate body (incf time *frame-step*)))))
      ;; Ten simulated seconds in, past the first blinks, saccades and shifts.
      (dotimes (i (round 10 *frame-step*)) (funcall thunk))
      thunk)))

(defun bench-pose-evaluation ()
  "Rows: frames per second for one body of each skeleton, and the cost per
character as one scene grows from 1 to 100 characters."
  (let* ((seconds (seconds-per-call (idle-life-evaluator)))
         (fps (/ 1 seconds)))
    ;; Issue 29's row, with physics and collision on, is bench/physics.lisp's;
    ;; this one shows what the physics adds to it.
    (row "pose evaluation with idle life, one humanoid, no props (no physics)"
         (format nil "~A frames/s (~,1F us/frame)" (format-count fps) (* 1d6 seconds))
         "-" ""))
  (dolist (skeleton '(humanoid parrot))
    (let* ((seconds (seconds-per-call (frame-evaluator skeleton 1)))
           (fps (/ 1 seconds)))
      (row (format nil "pose evaluation, one ~(~A~), all 11 drivers" skeleton)
           (format nil "~A frames/s (~,1F us/frame)" (format-count fps) (* 1d6 seconds))
           (if (eq skeleton 'humanoid) ">= 20,000 frames/s" "-")
           (if (eq skeleton 'humanoid) (if (>= fps 20000) "ok" "MISS") ""))))
  (let ((per-character
          (loop for count in '(1 10 50 100)
                collect (cons count (/ (seconds-per-call (frame-evaluator 'humanoid count)
                                                         :batches 5)
                                       count)))))
    (row "humanoids per scene: us/frame per character at 1 / 10 / 50 / 100"
         (format nil "~{~,1F~^ / ~}" (mapcar (lambda (entry) (* 1d6 (cdr entry))) per-character))
         "linear (flat per character)"
         (let ((ratio (/ (cdr (car (last per-character))) (cdr (first per-character)))))
           (if (< ratio 1.5) "ok" (format nil "MISS (x~,1F)" ratio))))))
