;;;; test-model-fuzz.lisp -- the model fuzzer (fuzz-models.lisp) in `make test`:
;;;; its cases are deterministic, its JSON and .glb edits keep what they do not
;;;; change, and a short sample of mutated .gltf, .glb and .x files through
;;;; bin/player model each ends in exit 0 or one "player: error:" line naming
;;;; the file.  `make fuzz` runs hundreds (FUZZ_MODEL_CASES).

(in-package #:player-tests)

(def-suite* model-fuzz :in player-tests)

(defparameter *model-fuzz-test-seed* 11
  "The seed of the sample of model cases `make test` runs.")

(defparameter *model-fuzz-test-cases* 20
  "How many model cases `make test` runs: a sample, each a process of bin/player.")

(defmacro with-fuzz-seeds (&body body)
  "Run BODY when Debian's test models are installed; else skip with a note."
  `(if (probe-file *fzm-models-directory*)
       (progn ,@body)
       (skip "Assimp's test models are not installed (Debian assimp-testmodels): models not fuzzed")))

(test model-fuzz-cases-are-deterministic
  (with-fuzz-seeds
    (loop for index below 40
          for a = (fzm-generate 3 index)
          for b = (fzm-generate 3 index)
          do (is (equalp (fzmc-octets a) (fzmc-octets b)) "case ~D: bytes differ" index)
             (is (equal (fzmc-notes a) (fzmc-notes b)))
             (is (equalp (fzmc-extras a) (fzmc-extras b))))
    (is (not (equalp (fzmc-octets (fzm-generate 3 0)) (fzmc-octets (fzm-generate 4 0)))))))

(test model-fuzz-reaches-every-format-and-kind
  (with-fuzz-seeds
    (let ((formats '()) (kinds '()))
      (loop for index below 400
            for case = (fzm-generate 1 index)
            do (pushnew (fzmc-format case) formats)
               (dolist (kind (fzmc-kinds case)) (pushnew kind kinds)))
      (is (subsetp '(:gltf :glb :x-text :x-binary) formats) "formats met: ~S" formats)
      (dolist (kind (append (mapcar #'cdr *fzm-gltf-kinds*) (mapcar #'cdr *fzm-x-kinds*)
                            (mapcar #'cdr *fzm-byte-kinds*) '(:buffer-words :texture)))
        (is (member kind kinds) "no case of kind ~S in 400" kind)))))

(test model-fuzz-json-round-trips
  "Every glTF seed's JSON, written back, reads as the same value, and a .glb
packed again from its own chunks imports as the original does."
  (with-fuzz-seeds
    (dolist (name (fzm-seeds))
      (when (eq (fzm-format name) :gltf)
        (let ((json (ignore-errors (fzm-json-parse (alexandria:read-file-into-string
                                                    (merge-pathnames name *fzm-models-directory*))))))
          (when json
            (is (equal json (fzm-json-parse (fzm-json-text json))) "~A" name)))))
    (let* ((name "glTF2/BoxTextured-glTF-Binary/BoxTextured.glb")
           (octets (fzm-seed-octets name))
           (file (format nil "/tmp/player-test-~D-repacked.glb" (sb-posix:getpid))))
      (multiple-value-bind (json binary) (fzm-glb-chunks octets)
        (with-open-file (out file :direction :output :if-exists :supersede :element-type '(unsigned-byte 8))
          (write-sequence (fzm-glb-pack (fzm-json-text (fzm-json-parse json)) binary) out)))
      (unwind-protect
           (is (= (player.model:model-triangle-count (player.model:import-model (assimp-model name)))
                  (player.model:model-triangle-count (player.model:import-model file))))
        (delete-file file)))))

(test mutated-models-through-bin-player
  "A sample of mutated models through bin/player model: each exits 0, or 1
with one \"player: error:\" line naming the file; never a signal, a memory
fault, a backtrace, a Lisp object printed or a hang."
  (with-fuzz-seeds
    (ensure-player-core)
    (let ((results (fuzz-models :seed *model-fuzz-test-seed* :cases *model-fuzz-test-cases* :timeout 20)))
      (is (= *model-fuzz-test-cases* (length results)))
      (dolist (result results)
        (is (null (fzmr-problems result))
            "seed ~D case ~D (~A, ~{~A~^; ~}): ~{~A~^, ~}; exit ~A; stderr: ~A"
            (fzmr-seed result) (fzmr-index result) (fzmr-base result) (fzmr-notes result)
            (fzmr-problems result) (fzmr-exit result) (fzmr-stderr result))))))
