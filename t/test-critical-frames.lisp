;;;; test-critical-frames.lisp -- critical times force a frame (issue 29,
;;;; item 2): the hammer's strike at 0.55 s has a frame of its own at every
;;;; frame rate, in the simulation, its frames file and its BVH, the nearest
;;;; grid frame moved onto it.

(in-package #:player-tests)

(def-suite* critical-frames :in player-tests)

(defun hammer-simulation (fps)
  "The hammer example (examples/hammer/) struck once, sampled at FPS."
  (let ((spec (first (load-spec (checkout-file "examples/hammer/hammer.lisp")))))
    (simulate spec :events '(ev-strike) :fps fps :silent t)))

(test critical-frame-times-move-the-nearest-frame
  "Each critical time between two grid frames moves the nearer onto it; one
on the grid pins that frame; the first and last frames stay; three in one
interval add a frame for the third; the count is the grid's otherwise."
  (let ((times (player.performance::critical-frame-times 1 4 '(0.55d0 0.5d0 0.2d0))))
    ;; 0.5 is on the grid; 0.55 is nearest 0.5, taken, so 0.75 moves; 0.2 moves 0.25.
    (is (equalp #(0d0 0.2d0 0.5d0 0.55d0 1d0) times) "~S" times))
  (let ((times (player.performance::critical-frame-times 1 4 '(0.45d0 0.5d0))))
    ;; 0.5 keeps its frame though 0.45 is nearer it than to 0.25, which moves.
    (is (equalp #(0d0 0.45d0 0.5d0 0.75d0 1d0) times) "~S" times))
  (let ((times (player.performance::critical-frame-times 1 4 '(0.55d0 0.6d0 0.65d0))))
    (is (equalp #(0d0 0.25d0 0.55d0 0.6d0 0.65d0 1d0) times) "~S" times))
  (let ((times (player.performance::critical-frame-times 1 10 '(0.01d0 0.99d0 1.5d0))))
    (is (= 0d0 (aref times 0)) "the first frame stays at 0")
    (is (= 1d0 (aref times 10)) "the last frame stays at the end")
    (is (= 0.01d0 (aref times 1)))
    (is (= 0.99d0 (aref times 9))))
  (let ((times (player.performance::critical-frame-times 2 30 '())))
    (is (= 61 (length times)))
    (is (every (lambda (time i) (= time (/ i 30d0))) times (alexandria:iota 61)))))

(test hammer-strike-frame-at-every-rate
  "At 4, 10, 24 and 30 fps the simulation has a frame exactly at the strike,
0.55 s; its frames file says (:frame N :time 0.55 ...); the BVH holds as many
frames as the frames file, at 1/FPS."
  (dolist (fps '(4 10 24 30))
    (let* ((simulation (hammer-simulation fps))
           (times (simulation-frame-times simulation))
           (grid (1+ (ceiling (* (player.performance::simulation-end simulation) fps)))))
      (is (member 0.55d0 (simulation-critical-times simulation)) "the strike is a critical time")
      (is (find 0.55d0 times) "~D fps: no frame at 0.55 s in ~S" fps times)
      (is (= grid (length times)) "~D fps: a frame moved, none added" fps)
      (is (every #'< times (subseq times 1)) "~D fps: frame times increase" fps)
      (let ((frames (temp-path (format nil "hammer-~D.frames" fps)))
            (bvh (temp-path (format nil "hammer-~D.bvh" fps))))
        (write-simulation simulation :frames frames :bvh bvh)
        (let* ((forms (read-lines-as-forms frames))
               (strike (find 0.55 forms :key (lambda (form) (getf form :time)) :test #'=)))
          (is (not (null strike)) "~D fps: no (:frame N :time 0.55 ...) line" fps)
          (is (= grid (length forms)))
          (is (= grid (length (getf (read-bvh (alexandria:read-file-into-string bvh)) :frames)))))))))

(test simulate-command-shows-the-strike
  "`simulate --frames` at 4 fps writes the strike frame."
  (let ((frames (temp-path "hammer-cli.frames")))
    (multiple-value-bind (out err code)
        (player-command "simulate" (namestring (checkout-file "examples/hammer/hammer.lisp")) "--events" "ev-strike"
                        "--fps" "4" "--frames" frames)
      (declare (ignore out))
      (is (= 0 code) "~A" err)
      (is (search ":time 0.55 " (alexandria:read-file-into-string frames))))))

(test viewer-frame-lands-on-the-strike
  "The viewer draws as the clock goes; a frame that would step over the
strike is drawn at 0.55 s instead, and the next one catches up."
  (let* ((simulation (hammer-simulation 30))
         (viewer (player.render::%make-viewer
                  :performance (player.performance:simulation-performance simulation))))
    (flet ((tick (clock)
             (player.render::viewer-tick viewer clock)
             (player.render::viewer-now viewer)))
      (is (= 0.5d0 (tick 0.5d0)))
      (is (= 0.55d0 (tick 0.6d0)) "the frame after 0.5 s is the strike's")
      (is (= 0.62d0 (tick 0.62d0)) "then the clock's again")
      (is (= 0.7d0 (tick 0.7d0))))))

(test scene-simulation-shows-every-members-critical-times
  "A scene's frames show the critical times of all its members."
  (let* ((simulation (hammer-simulation 10))
         (scene (player.cast::%make-scene-simulation
                 :members (list (cons 'one simulation)) :fps 10
                 :end (player.performance::simulation-end simulation))))
    (is (find 0.55d0 (simulation-frame-times scene)))))
