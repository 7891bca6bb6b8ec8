;;;; physics.lisp -- physics through ODE (issue 29, item 6): frames per second
;;;; of issue 29's two rows -- a humanoid with its idle life, physics and
;;;; collision on (standing at a table whose note, a dynamic prop, is tossed
;;;; and lands again and again), and Peedy with physics -- and of a humanoid
;;;; with every driver as well.  Loaded by run.lisp.

(in-package #:player-bench)

(defparameter *peedy-scripts-file* (merge-pathnames "../specs/peedy-scripts.lisp" *bench-directory*))

(defun peedy-physics-evaluator ()
  "A thunk evaluating the next frame (1/60 s on) of Peedy tapping his foot
\(a looping script) while his note, a dynamic prop, is tossed up every second
and falls back onto the table."
  (let* ((library (player:load-script-library *peedy-scripts-file*))
         (performance (player:make-performance library '((peedy parrot))))
         (time 0d0) (frame 0))
    (player:perform-script performance 'tap-foot 0)
    (flet ((next ()
             (incf time *frame-step*)
             (let ((scene (player:performance-frame performance time)))
               (when (zerop (mod (incf frame) 60))
                 (setf (player:property-value (player:find-object scene 'note) 'velocity)
                       (player.body::make-vec3 0.1 1.5 0))))))
      (dotimes (i 120) (next))
      #'next)))

(defparameter *table-scene-forms*
  '((defobject table :kind :prop :position (0 0.72 0.5)
     :properties ((size :vector (1.2 0.04 0.6)))
     :documentation "A counter-high table just in front of the humanoid's hands.")
    (defobject note :kind :prop :position (0.1 0.745 0.4) :dynamic t
     :properties ((size :vector (0.06 0.002 0.08)))
     :documentation "A note lying on the table: a dynamic prop."))
  "The set of the idle humanoid's row, as a script library's forms.")

(defun humanoid-idle-physics-evaluator ()
  "A thunk evaluating the next frame (1/60 s on) of a performance whose humanoid
stands at a table with only its idle life (blinks, breathing, saccades,
weight shifts, relaxed hands), collision shapes on (its hands are tested
against the table and its trunk every frame), while the note on the table, a
dynamic prop, is tossed up every second, to alternate sides, and lands again."
  (let* ((library (player.performance::parse-script-library-forms *table-scene-forms*))
         (performance (player:make-performance library '((bob humanoid))))
         (time 0d0) (frame 0))
    (flet ((next ()
             (incf time *frame-step*)
             (let ((scene (player:performance-frame performance time)))
               (when (zerop (mod (incf frame) 60))
                 (setf (player:property-value (player:find-object scene 'note) 'velocity)
                       (player.body::make-vec3 (if (evenp (floor frame 60)) 0.1 -0.1) 1.5 0))))))
      ;; Ten simulated seconds in: past the first blinks, saccades and shifts.
      (dotimes (i 600) (next))
      (let ((physics (player:scene-physics (player:performance-scene performance))))
        (unless (and physics (player.physics::scene-physics-colliders physics))
          (note "the idle humanoid's row ran without collision shapes (is libode8 installed?)")))
      #'next)))

(defun humanoid-physics-evaluator ()
  "A thunk evaluating the next frame of a humanoid with every driver (bench/body.lisp),
its speed limits and collisions on, in a scene whose dynamic note is tossed every second."
  (multiple-value-bind (scene bodies ball) (bench-scene 'humanoid 1)
    (let ((note (player:add-object scene (make-instance 'player:scene-object
                                                        :name 'note :kind :prop
                                                        :position (player.body::make-vec3 0.3 0.5 0.3))))
          (time 0d0) (frame 0))
      (player:define-property note 'dynamic :boolean t)
      (player:define-property note 'velocity :vector (player.body::make-vec3 0 0 0))
      (flet ((next ()
               (incf time *frame-step*)
               (setf (player:property-value ball 'position)
                     (player.body::make-vec3 (* 0.4 (sin time)) 1.2 1.0))
               (when (zerop (mod (incf frame) 60))
                 (setf (player:property-value note 'velocity) (player.body::make-vec3 0 2 0)))
               (dolist (body bodies)
                 (player:body-evaluate body time))
               (player:advance-scene-physics scene time)))
        (dotimes (i 600) (next))
        #'next))))

(defun bench-physics ()
  "Rows: issue 29's two (the idle humanoid with physics and collision on, Peedy
with physics), and a humanoid with every driver and physics, in frames per second."
  (let* ((seconds (seconds-per-call (humanoid-idle-physics-evaluator)))
         (fps (/ 1 seconds)))
    (row "pose evaluation with idle life, physics and collision on, humanoid (at a table, note tossed)"
         (format nil "~A frames/s (~,1F us/frame)" (format-count fps) (* 1d6 seconds))
         ">= 20,000 frames/s" (if (>= fps 20000) "ok" "MISS")))
  (let* ((seconds (seconds-per-call (peedy-physics-evaluator)))
         (fps (/ 1 seconds)))
    (row "Peedy with physics (note tossed and landing, 60 fps)"
         (format nil "~A frames/s (~,1F us/frame)" (format-count fps) (* 1d6 seconds))
         ">= 5,000 frames/s" (if (>= fps 5000) "ok" "MISS")))
  (let* ((seconds (seconds-per-call (humanoid-physics-evaluator)))
         (fps (/ 1 seconds)))
    (row "pose evaluation, humanoid, all 11 drivers, speed limits, collisions, a dynamic prop"
         (format nil "~A frames/s (~,1F us/frame)" (format-count fps) (* 1d6 seconds))
         ">= 20,000 frames/s" (if (>= fps 20000) "ok" "MISS"))))
