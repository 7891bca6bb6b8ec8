;;;; model.lisp -- importing a model through Assimp: Testwuson.X (one mesh of
;;;; 3,205 vertices, 37 bones, 3 clips), from the file to Player's Lisp structs.
;;;; Loaded by run.lisp.

(in-package #:player-bench)

(defparameter *bench-model* "/usr/share/assimp/models/X/Testwuson.X"
  "The model imported: Debian's assimp-testmodels.")

(defun bench-model-import ()
  "Row: the median time of one import of *BENCH-MODEL* (target < 0.2 s)."
  (if (probe-file *bench-model*)
      (handler-case
          (let ((seconds (seconds-per-call (lambda () (player:import-model *bench-model*))
                                           :batches 9 :batch-seconds 0.1d0 :max-seconds 10)))
            (row "model import through Assimp (Testwuson.X, 3,205 vertices, 37 bones, 3 clips)"
                 (format-seconds seconds) "< 0.2 s" (< seconds 0.2)))
        (player:player-error (e)
          (row "model import" (format nil "not run: ~A" e) "-" "")))
      (row "model import" "not run: no Testwuson.X (Debian assimp-testmodels)" "-" "")))

(defparameter *bench-clip-model* "/usr/share/assimp/models/X/BCN_Epileptic.X"
  "The model whose clip is sampled: 58 joints, one clip of 3.3 s moving 54 of them.")

(defun bench-clip-pose ()
  "Row: frames a second of pose evaluation of *BENCH-CLIP-MODEL*'s clip through
CLIP-ANGLES (a slerp and an x/y/z decomposition per joint; target >= 50,000)."
  (if (probe-file *bench-clip-model*)
      (handler-case
          (let* ((skeleton (player:model-skeleton (player:import-model *bench-clip-model*)))
                 (clip (first (alexandria:hash-table-values
                               (player.rig:rig-clips (player.body:skeleton-rig skeleton)))))
                 (out (make-array (* 3 (length (player.rig:clip-tracks clip))) :element-type 'double-float))
                 (time 0d0)
                 (seconds (seconds-per-call (lambda ()
                                              ;; A new time each frame, stepping through the clip at 60 fps.
                                              (setf time (mod (+ time (/ 1d0 60)) (player:clip-duration clip)))
                                              (player:clip-angles clip time out))
                                            :batches 9 :batch-seconds 0.05d0 :max-seconds 10))
                 (rate (/ 1d0 seconds)))
            (row (format nil "pose evaluation of a ~D-joint clip (BCN_Epileptic.X, clip-angles)"
                         (length (player.rig:clip-tracks clip)))
                 (format nil "~:D frames/s" (round rate)) ">= 50,000 frames/s" (>= rate 50000)))
        (player:player-error (e)
          (row "pose evaluation of a clip" (format nil "not run: ~A" e) "-" "")))
      (row "pose evaluation of a clip" "not run: no BCN_Epileptic.X (Debian assimp-testmodels)" "-" "")))
