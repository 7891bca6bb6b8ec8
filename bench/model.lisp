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
