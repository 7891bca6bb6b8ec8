;;;; model.lisp -- importing a model through Assimp: Testwuson.X (one mesh of
;;;; 3,205 vertices, 37 bones, 3 clips), from the file to Player's Lisp structs;
;;;; and writing one as glTF: a synthetic 20 s performance of 54 joints.
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

;;; Writing glTF: the export target (issue 26, item 8) is a 20 s performance
;;; at 30 fps on a 54-joint body written in well under a second.

(defparameter *export-joints* 54 "Joints of the synthetic body written.")
(defparameter *export-seconds* 20 "Seconds of its synthetic performance.")
(defparameter *export-fps* 30 "Keys a second of each joint's translation, rotation and scale.")

(defun doubles (count function)
  "A vector of COUNT double-floats, the Ith being (FUNCALL FUNCTION I)."
  (let ((vector (make-array count :element-type 'double-float)))
    (dotimes (i count vector)
      (setf (aref vector i) (float (funcall function i) 1d0)))))

(defun synthetic-performance ()
  "A model of *EXPORT-JOINTS* joints in a chain, no mesh, and one clip keying
every joint's translation, rotation and scale *EXPORT-FPS* times a second for
*EXPORT-SECONDS* s: what recording a performance of a body would export."
  (let* ((keys (1+ (* *export-seconds* *export-fps*)))
         (times (doubles keys (lambda (i) (/ i *export-fps*)))))
    (flet ((joint (i)
             (player:make-joint (format nil "joint~D" i) (and (plusp i) (1- i))
                                (doubles 3 (lambda (k) (if (= k 1) 0.1 0))) (doubles 4 (lambda (k) (if (zerop k) 1 0)))
                                (doubles 3 (constantly 1)) nil))
           (channel (j)
             (player:make-channel j times (doubles (* 3 keys) (lambda (i) (* 0.01 (sin (+ i j)))))
                                  times (doubles (* 4 keys) (lambda (i) (let ((angle (* 0.001 (floor i 4))))
                                                                          (ecase (mod i 4) (0 (cos angle)) (1 (sin angle)) ((2 3) 0)))))
                                  times (doubles (* 3 keys) (constantly 1)))))
      (player:make-model "synthetic" '()
                         (coerce (loop for i below *export-joints* collect (joint i)) 'simple-vector)
                         (list (player:make-model-animation "performance" (float *export-seconds* 1d0)
                                                      (loop for j below *export-joints* collect (channel j))))))))

(defun bench-gltf-write ()
  "Row: the median time of one WRITE-GLTF of the synthetic performance as a .glb (target < 1 s)."
  (let ((model (synthetic-performance))
        (file (format nil "/tmp/player-bench-export-~D.glb" (sb-posix:getpid))))
    (unwind-protect
         (handler-case
             (let ((seconds (seconds-per-call (lambda () (player:write-gltf model file))
                                              :batches 9 :batch-seconds 0.1d0 :max-seconds 10)))
               (row (format nil "export write of ~D s at ~D fps, ~D joints (write-gltf, .glb of ~:D bytes)"
                            *export-seconds* *export-fps* *export-joints*
                            (with-open-file (in file :element-type '(unsigned-byte 8)) (file-length in)))
                    (format-seconds seconds) "< 1 s" (< seconds 1)))
           (player:player-error (e)
             (row "export write (glTF)" (format nil "not run: ~A" e) "-" "")))
      (ignore-errors (delete-file file)))))

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
