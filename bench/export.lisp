;;;; export.lisp -- exporting a performance as glTF: Peedy played for 20 s,
;;;; sampled at 30 fps (601 frames), baked, made a model and written as .glb.
;;;; The simulation is played once beforehand; the row times the export alone.
;;;; Loaded by run.lisp.

(in-package #:player-bench)

(defparameter *export-events* '(("ev-search" . 0) ("ev-bad-speech" . 6)
                                ("ev-thanks" . 10))
  "Peedy's events of the exported performance, at their times (seconds).")

(defun bench-export ()
  "Row: the median time of one EXPORT-PERFORMANCE of a 20 s Peedy
performance at 30 fps to a .glb (target < 1 s)."
  (let ((path (format nil "/tmp/player-bench-export-~D.glb" (sb-posix:getpid))))
    (handler-case
        (let* ((spec (first (player:load-spec *peedy-file*)))
               (simulation (player:simulate spec :events *export-events* :until 20 :fps 30 :silent t))
               (seconds (seconds-per-call (lambda () (player:export-performance simulation path))
                                          :batches 5 :batch-seconds 0.01d0 :max-seconds 20)))
          (row (format nil "export of a 20 s performance at 30 fps (Peedy, ~D frames, .glb)"
                       (player:simulation-frame-count simulation))
               (format-seconds seconds) "< 1 s" (< seconds 1)))
      (player:player-error (e)
        (row "export of a performance" (format nil "not run: ~A" e) "-" "")))
    (when (probe-file path) (delete-file path))))
