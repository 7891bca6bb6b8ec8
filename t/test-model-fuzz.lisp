;;;; test-model-fuzz.lisp -- the model fuzzer (fuzz-models.lisp) in `make test`:
;;;; its cases are deterministic, its JSON and .glb edits keep what they do not
;;;; change, and a short sample of mutated .gltf, .glb and .x files through
;;;; bin/player model, check and render each ends in exit 0 or one
;;;; "player: error:" line naming the file.  `make fuzz` runs hundreds (FUZZ_MODEL_CASES).

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
  "A sample of mutated models through every target (bin/player model, and
check and render of a library naming the model, as the character and as a
prop): each exits 0, or 1 with one \"player: error:\" line naming the file;
never a signal, a memory fault, a backtrace, a Lisp object printed or a hang."
  (with-fuzz-seeds
    (ensure-player-core)
    (let ((results (fuzz-models :seed *model-fuzz-test-seed* :cases *model-fuzz-test-cases* :timeout 20)))
      (is (= (* (length *fzm-targets*) *model-fuzz-test-cases*) (length results)))
      (dolist (target *fzm-targets*)
        (is (find (fzmt-name target) results :key #'fzmr-target :test #'string=)
            "target ~A ran on no case" (fzmt-name target)))
      (dolist (result results)
        (is (null (fzmr-problems result))
            "~A: seed ~D case ~D (~A, ~{~A~^; ~}): ~{~A~^, ~}; exit ~A; stderr: ~A"
            (fzmr-target result) (fzmr-seed result) (fzmr-index result) (fzmr-base result) (fzmr-notes result)
            (fzmr-problems result) (fzmr-exit result) (fzmr-stderr result))))))

;;;# Bad input the fuzzer found or the issue lists: one MODEL-ERROR naming the file

(defun model-case-run (seed index)
  "Run bin/player model on model case INDEX of SEED, written with a copy of
its base's folder into a fresh folder; (VALUES STDOUT STDERR EXIT-CODE FILE)."
  (ensure-player-core)
  (let ((folder (fz-make-directory "player-fuzz-model-test")))
    (unwind-protect
         (progn
           (fuzz-model-case seed index folder)
           (let* ((case (fzm-generate seed index))
                  (file (namestring (merge-pathnames (fzmc-file-name case) folder))))
             (multiple-value-bind (out err code) (player-command "model" file)
               (values out err code file))))
      (fz-delete-tree folder))))

(defun one-error-line-naming-p (err code file)
  "Did a run end with exit 1 and one \"player: error:\" line naming FILE?"
  (and (eql 1 code)
       (= 1 (length (lines err)))
       (eql 0 (search "player: error: " err))
       (search (file-namestring file) err)))

(test a-failed-assimp-assertion-is-one-model-error
  "A glTF 1.0 accessor whose count overruns its buffer view fails an
ai_assert inside Assimp, which would abort() the process: it is one
MODEL-ERROR naming the file and the assertion, in this process and on the
command line (seed 1 case 60 of the model fuzzer)."
  (with-fuzz-seeds
    (let ((folder (fz-make-directory "player-fuzz-model-test")))
      (unwind-protect
           (progn
             (fuzz-model-case 1 60 folder)
             (let* ((file (namestring (merge-pathnames "fuzz-case.gltf" folder)))
                    (e (model-error-of file)))
               (is (typep e 'player.model:model-error))
               (is (and e (names-file-p e file)))
               (is (and e (search "Assimp's own check failed reading it: count * stride <= bufferView->byteLength"
                                  (princ-to-string e))))))
        (fz-delete-tree folder)))
    (multiple-value-bind (out err code file) (model-case-run 1 60)
      (declare (ignore out))
      (is (one-error-line-naming-p err code file) "exit ~A: ~A" code err))))

(test a-memory-fault-in-assimp-is-one-error-line
  "A .x count set to 2^31-1 makes Assimp read past its arrays (a memory
fault): bin/player says so in one line naming the file, SBCL's corruption
warning kept off stderr (seed 1 case 299 of the model fuzzer)."
  (with-fuzz-seeds
    (multiple-value-bind (out err code file) (model-case-run 1 299)
      (declare (ignore out))
      (is (one-error-line-naming-p err code file) "exit ~A: ~A" code err))))

(defun model-with-key (value)
  "A copy of Testwuson.X whose first rotation key's w is VALUE (text); its path."
  (let* ((text (alexandria:read-file-into-string (assimp-model "X/Testwuson.X") :external-format :latin-1))
         (key "0;4;0.707107,-0.707107,0.000000,0.000000;;;")
         (at (search key text))
         (path (format nil "/tmp/player-test-~D-key-~A.x" (sb-posix:getpid) value)))
    (alexandria:write-string-into-file (concatenate 'string (subseq text 0 at) "0;4;" value
                                                    (subseq text (+ at (length "0;4;0.707107"))))
                                       path :external-format :latin-1 :if-exists :supersede)
    path))

(test nan-or-infinite-keys-are-model-errors
  (with-fuzz-seeds
    (dolist (value '("nan" "1e39"))
      (let ((file (model-with-key value)))
        (unwind-protect
             (progn
               (let ((e (model-error-of file)))
                 (is (and e (names-file-p e file) (search "not finite" (princ-to-string e))) "~A: ~A" value e))
               (multiple-value-bind (out err code) (player-command "model" file)
                 (declare (ignore out))
                 (is (one-error-line-naming-p err code file) "~A: exit ~A: ~A" value code err)))
          (delete-file file))))))

(test every-model-limit-is-a-model-error
  "Each limit of conditions.lisp, bound lower, refuses Testwuson.X with one MODEL-ERROR naming it."
  (with-fuzz-seeds
    (let ((file (assimp-model "X/Testwuson.X")))
      (flet ((refused (text) (let ((e (model-error-of file)))
                               (is (and e (names-file-p e file) (search text (princ-to-string e))) "~A: ~A" text e))))
        (let ((player.model:*model-triangle-limit* 100)) (refused "triangles, more than the limit of 100"))
        (let ((player.model:*model-key-limit* 50)) (refused "more than 50 keys"))
        (let ((player.model:*model-node-limit* 5)) (refused "more than 5 nodes"))
        (let ((player.model:*model-joint-limit* 36)) (refused "joints, more than the limit of 36"))
        (let ((player.model:*model-vertex-limit* 3204)) (refused "vertices, more than the limit of 3,204"))))))

(test bad-models-on-the-command-line-are-one-error-line
  "A truncated model, a file that is not a model, and a missing texture given
with --texture: exit 1 and one line naming the file."
  (with-fuzz-seeds
    (let* ((octets (alexandria:read-file-into-byte-vector (assimp-model "glTF2/BoxTextured-glTF-Binary/BoxTextured.glb")))
           (file (temporary-model-file "cut.glb" (lambda (out) (write-sequence octets out :end 700)))))
      (unwind-protect
           (multiple-value-bind (out err code) (player-command "model" file)
             (is (string= "" out))
             (is (one-error-line-naming-p err code file) "exit ~A: ~A" code err))
        (delete-file file)))
    (multiple-value-bind (out err code)
        (player-command "model" (assimp-model "X/Testwuson.X") "--texture" "/nonexistent/skin.png")
      (declare (ignore out))
      (is (one-error-line-naming-p err code "/nonexistent/skin.png") "exit ~A: ~A" code err))))
