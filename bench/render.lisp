;;;; render.lisp -- the renderer's speed: offscreen frames per second (drawn
;;;; and read back) for each skeleton at three sizes, and PNG frames written
;;;; per second as `bin/player render` writes them.  Loaded by run.lisp.

(in-package #:player-bench)

(defparameter *render-sizes* '((320 240) (640 480) (1280 720))
  "Frame sizes the renderer is timed at.")

(defun render-bench-scene (skeleton-name)
  "A scene with one body of SKELETON-NAME in a pose with bent limbs and an open mouth."
  (let* ((scene (make-instance 'player:scene))
         (body (player:make-body 'figure skeleton-name :scene scene))
         (skeleton (player::body-skeleton body))
         (pose (player::body-pose body)))
    (loop for (joint dof degrees) in (if (eq skeleton-name 'parrot)
                                         '((head y 20) (beak open 15) (l_shoulder z 30) (tail spread 20))
                                         '((l_shoulder z 50) (r_elbow x 40) (temporomandibular open 12)))
          do (setf (aref pose (player::dof-index skeleton joint dof)) (float degrees 1d0)))
    (player::pose-world-transforms skeleton pose :result (player::body-transforms body))
    scene))

(defun frames-per-second (thunk)
  "How many times a second THUNK runs, by SECONDS-PER-CALL's median."
  (/ 1 (seconds-per-call thunk :batches 7 :batch-seconds 0.2d0 :max-seconds 6)))

(defun render-rate (skeleton-name width height &key (antialias :fxaa))
  "Offscreen frames per second for SKELETON-NAME at WIDTH x HEIGHT: each frame
posed, drawn, antialiased and read back."
  (let ((scene (render-bench-scene skeleton-name)))
    (player::with-offscreen-context ((context) width height)
      (let ((renderer (player.render::make-renderer width height :antialias antialias)))
        (prog1 (frames-per-second (lambda ()
                                    (player.render::render-scene renderer scene)
                                    (player.render::renderer-pixels renderer)))
          (player.render::delete-renderer renderer))))))

(defun png-rate (skeleton-name width height)
  "PNG frames written per second at WIDTH x HEIGHT: drawn, read back, encoded
and written to a file, as the render command does."
  (let ((scene (render-bench-scene skeleton-name))
        (path (format nil "/tmp/player-bench-~D.png" (sb-posix:getpid))))
    (unwind-protect
         (player::with-offscreen-context ((context) width height)
           (let ((renderer (player.render::make-renderer width height)))
             (prog1 (frames-per-second (lambda ()
                                         (player.render::render-scene renderer scene)
                                         (player::write-png path width height
                                                            (player.render::renderer-pixels renderer))))
               (player.render::delete-renderer renderer))))
      (ignore-errors (delete-file path)))))

(defparameter *skinned-bench-model* "/usr/share/assimp/models/X/Testwuson.X"
  "The imported model the skinned render is timed with (Debian assimp-testmodels).")

(defun skinned-render-rate (width height &key (gpu t))
  "Offscreen frames per second for Testwuson walking (its clip \"wuson-walk\"
looping) at WIDTH x HEIGHT: each frame evaluated a 30th of a second later,
skinned (on the GPU, or the CPU unless GPU), drawn, antialiased and read back."
  (let* ((skeleton (player.rig:model-skeleton (player.model:import-model *skinned-bench-model*) :height 1.0))
         (scene (make-instance 'player:scene))
         (body (player:make-body 'wuson skeleton :scene scene))
         (time 0d0)
         (player.render::*gpu-skinning* gpu))
    (player.body::body-add-driver
     body (player.body::make-driver (player.body::parse-motor-frame '(:clip :name "wuson-walk" :loop t)) body 0d0))
    (player::with-offscreen-context ((context) width height)
      (let ((renderer (player.render::make-renderer width height)))
        (prog1 (frames-per-second (lambda ()
                                    (player.body::body-evaluate body (incf time (/ 1d0 30)))
                                    (player.render::render-scene renderer scene)
                                    (player.render::renderer-pixels renderer)))
          (player.render::delete-renderer renderer))))))

(defun bench-skinned-render ()
  "Rows: Testwuson walking at 640x480, skinned on the GPU (target 100 frames/s)
and, for comparison, on the CPU (the fallback)."
  (if (probe-file *skinned-bench-model*)
      (loop for gpu in '(t nil)
            for fps = (skinned-render-rate 640 480 :gpu gpu)
            do (row (format nil "skinned render, Testwuson (3.2k vertices, 37 joints), 640x480~:[, CPU skinning~;~]" gpu)
                    (format nil "~,1F frames/s (~,2F ms)" fps (/ 1000 fps))
                    (if gpu ">= 100 frames/s" "-")
                    (if gpu (>= fps 100) "")))
      (row "skinned render" "not run: Testwuson (Debian assimp-testmodels) is not installed" "-" "")))

(defun bench-render ()
  "Rows: offscreen frames per second for the parrot and the humanoid at each of
*RENDER-SIZES* (target: 100 at 640x480), the same with 4x multisampling
instead of FXAA at 640x480, and PNG frames written per second (target 20)."
  (handler-case
      (progn
        (dolist (skeleton '(parrot humanoid))
          (dolist (size *render-sizes*)
            (destructuring-bind (width height) size
              (let ((fps (render-rate skeleton width height))
                    (targeted (= width 640)))
                (row (format nil "render ~(~A~) ~Dx~D, FXAA, offscreen + read back" skeleton width height)
                     (format nil "~,1F frames/s (~,2F ms)" fps (/ 1000 fps))
                     (if targeted ">= 100 frames/s" "-")
                     (if targeted (>= fps 100) ""))))))
        (dolist (skeleton '(parrot humanoid))
          (let ((fps (render-rate skeleton 640 480 :antialias :msaa)))
            (row (format nil "render ~(~A~) 640x480, 4x MSAA instead" skeleton)
                 (format nil "~,1F frames/s (~,2F ms)" fps (/ 1000 fps)) "-" "")))
        (dolist (skeleton '(parrot humanoid))
          (let ((fps (png-rate skeleton 640 480)))
            (row (format nil "PNG frames written, ~(~A~) 640x480" skeleton)
                 (format nil "~,1F frames/s (~,1F ms)" fps (/ 1000 fps))
                 ">= 20 frames/s" (>= fps 20))))
        (bench-skinned-render))
    (player::render-error (e)
      (row "renderer" (format nil "not run: ~A" e) "-" ""))))
