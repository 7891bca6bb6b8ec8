;;;; test-model.lisp -- importing models through Assimp (src/model/), checked
;;;; against Assimp's own command, `assimp info` and `assimp dump`, as the
;;;; independent reference; bad files; and `bin/player model`.
;;;; Debian's test models (assimp-testmodels) must be installed; without them
;;;; the tests skip with a note.

(in-package #:player-tests)

(def-suite* model :in player-tests)

(defparameter *assimp-models* #p"/usr/share/assimp/models/"
  "Where Debian's assimp-testmodels puts Assimp's test models.")

(defparameter *reference-models*
  '("glTF2/simple_skin/simple_skin.gltf" "X/Testwuson.X" "BVH/01_01.bvh" "X/BCN_Epileptic.X")
  "The test models whose import is compared with Assimp's own command; the
fast tier takes the first and the last (a glTF and a skinned .x).")

(defun assimp-model (name)
  "The path of Assimp's test model NAME, as a string."
  (namestring (merge-pathnames name *assimp-models*)))

(defmacro with-assimp-models (&body body)
  "Run BODY when Debian's test models and the assimp command are there; else skip with a note."
  `(if (and (probe-file *assimp-models*) (probe-file "/usr/bin/assimp"))
       (progn ,@body)
       (skip "Assimp's test models or its command are not installed (Debian assimp-testmodels, assimp-utils): model import not tested")))

(defun assimp-output (&rest arguments)
  "What the assimp command prints when run with ARGUMENTS."
  (with-output-to-string (out)
    (sb-ext:run-program "/usr/bin/assimp" arguments :output out :error nil :search nil)))

(defun assimp-info-counts (file &key raw)
  "The counts `assimp info FILE` (with -r when RAW) prints, as a plist:
:meshes :vertices :faces :bones :animations :channels."
  (let ((text (apply #'assimp-output "info" file (and raw '("-r")))))
    ;; Each count follows its label after some spaces.
    (flet ((field (label)
             (let ((start (search label text)))
               (when start
                 (let ((digit (position-if #'digit-char-p text :start (+ start (length label)))))
                   (parse-integer text :start digit :junk-allowed t))))))
        (list :meshes (field (format nil "~%Meshes:")) :vertices (field "Vertices:")
              :faces (field "Faces:") :bones (field "Bones:")
              :animations (field (format nil "~%Animations:")) :channels (field "Animation Channels:")))))

(defun attribute (line name)
  "The value of the XML attribute NAME in LINE, or NIL."
  (let* ((key (format nil "~A=\"" name))
         (start (search key line)))
    (when start
      (let ((from (+ start (length key))))
        (subseq line from (position #\" line :start from))))))

(defun assimp-dump-animations (file)
  "The animations `assimp dump FILE` writes, as (NAME SECONDS CHANNELS) lists:
seconds are its duration over its ticks per second (25 when it gives 0)."
  (let ((dump (format nil "/tmp/player-test-model-~D.assxml" (sb-posix:getpid)))
        (animations '()))
    (unwind-protect
         (progn
           (assimp-output "dump" file dump)
           (with-open-file (in dump :external-format '(:utf-8 :replacement #\?))
             (loop for line = (read-line in nil) while line
                   do (cond ((search "<Animation " line)
                             (let ((ticks (let ((*read-default-float-format* 'double-float))
                                            (read-from-string (attribute line "duration"))))
                                   (rate (let ((*read-default-float-format* 'double-float))
                                           (read-from-string (attribute line "tick_cnt")))))
                               (push (list (attribute line "name")
                                           (/ ticks (if (zerop rate) 25d0 rate))
                                           0)
                                     animations)))
                            ((and animations (search "<NodeAnimList " line))
                             (setf (third (first animations))
                                   (parse-integer (attribute line "num"))))))))
      (ignore-errors (delete-file dump)))
    (nreverse animations)))

(defun channel-count (model)
  "How many channels MODEL's animations have together."
  (reduce #'+ (player.model:model-animations model)
          :key (lambda (a) (length (player.model:model-animation-channels a)))))

(test model-counts-agree-with-assimp-info
  (with-assimp-models
    (dolist (name (sweep-sample *reference-models* 2))
      (let* ((file (assimp-model name))
             (model (player.model:import-model file))
             (info (assimp-info-counts file)))
        (is (eql (getf info :meshes) (length (player.model:model-meshes model))) "~A: meshes" name)
        (is (eql (getf info :faces) (player.model:model-triangle-count model)) "~A: triangles" name)
        (is (eql (getf info :bones) (player.model:model-bone-count model)) "~A: bones" name)
        (is (eql (getf info :animations) (length (player.model:model-animations model))) "~A: animations" name)
        (is (eql (getf info :channels) (channel-count model)) "~A: channels" name)))))

(test raw-model-vertices-agree-with-assimp-info-r
  ;; Joining identical vertices changes the count, and `assimp info` joins
  ;; them after its own steps; a raw import on both sides compares them.
  (with-assimp-models
    (dolist (name (sweep-sample *reference-models* 2))
      (let* ((file (assimp-model name))
             (model (player.model:import-model file :post-processing '()))
             (joined (player.model:import-model file))
             (info (assimp-info-counts file :raw t)))
        (is (eql (getf info :vertices) (player.model:model-vertex-count model)) "~A: raw vertices" name)
        (is (eql (getf info :faces) (player.model:model-triangle-count model)) "~A: raw faces" name)
        (is (<= (player.model:model-vertex-count joined) (player.model:model-vertex-count model))
            "~A: joining vertices never adds any" name)))))

(test model-animations-agree-with-assimp-dump
  (with-assimp-models
    (dolist (name (sweep-sample *reference-models* 2))
      (let ((model (player.model:import-model (assimp-model name)))
            (reference (assimp-dump-animations (assimp-model name))))
        (is (= (length reference) (length (player.model:model-animations model))) "~A: clips" name)
        (loop for (clip-name seconds channels) in reference
              for animation in (player.model:model-animations model)
              do (is (string= clip-name (player.model:model-animation-name animation)) "~A: clip name" name)
                 (is (< (abs (- seconds (player.model:model-animation-duration animation))) 1d-4)
                     "~A: ~A lasts ~A s, Assimp says ~A" name clip-name
                     (player.model:model-animation-duration animation) seconds)
                 (is (= channels (length (player.model:model-animation-channels animation)))
                     "~A: ~A's channels" name clip-name))))))

(test testwuson-has-its-skeleton-and-clips
  (with-assimp-models
    (let ((model (player.model:import-model (assimp-model "X/Testwuson.X"))))
      (is (= 37 (count-if #'player.model:joint-inverse-bind (player.model:model-joints model))))
      (is (equal '("Wuson_Run" "Wuson_Walk" "Wuson_Bind")
                 (mapcar #'player.model:model-animation-name (player.model:model-animations model))))
      ;; Parents come before their children, and exactly one joint is the root.
      (is (= 1 (count nil (player.model:model-joints model) :key #'player.model:joint-parent)))
      (is (every (lambda (joint i) (or (null (player.model:joint-parent joint))
                                       (< (player.model:joint-parent joint) i)))
                 (player.model:model-joints model)
                 (alexandria:iota (length (player.model:model-joints model))))))))

(test skin-weights-sum-to-one
  (with-assimp-models
    (dolist (name (sweep-sample *reference-models* 2))
      (let ((model (player.model:import-model (assimp-model name))))
        (dolist (mesh (player.model:model-meshes model))
          (let ((weights (player.model:model-mesh-weights mesh))
                (joints (player.model:model-mesh-joints mesh)))
            (when weights
              (is (= (* 4 (player.model:model-mesh-vertex-count mesh)) (length weights)))
              (is (every (lambda (j) (< j (length (player.model:model-joints model)))) joints)
                  "~A: a joint index out of range" name)
              (is (loop for base from 0 below (length weights) by 4
                        always (< (abs (- 1d0 (+ (aref weights base) (aref weights (+ base 1))
                                                 (aref weights (+ base 2)) (aref weights (+ base 3)))))
                                  1d-6))
                  "~A: mesh ~A has a vertex whose weights do not sum to 1" name
                  (player.model:model-mesh-name mesh)))))))))

(test key-times-lie-within-their-animation
  (with-assimp-models
    (dolist (name (sweep-sample *reference-models* 2))
      (dolist (animation (player.model:model-animations (player.model:import-model (assimp-model name))))
        (let ((duration (player.model:model-animation-duration animation)))
          (is (every (lambda (channel)
                       (every (lambda (times) (every (lambda (time) (<= 0d0 time duration)) times))
                              (list (player.model:channel-position-times channel)
                                    (player.model:channel-rotation-times channel)
                                    (player.model:channel-scale-times channel))))
                     (player.model:model-animation-channels animation))
              "~A: ~A has a key outside 0 to ~A s" name (player.model:model-animation-name animation) duration))))))

;;;# Bad input: one MODEL-ERROR naming the file, never a crash

(defun model-error-of (file &rest arguments)
  "The MODEL-ERROR importing FILE (with ARGUMENTS) signals, or NIL when it signals none."
  (handler-case (progn (apply #'player.model:import-model file arguments) nil)
    (player.model:model-error (e) e)))

(defun temporary-model-file (name writer)
  "A file /tmp/player-test-NAME-PID, written by calling WRITER with an octet output stream."
  (let ((path (format nil "/tmp/player-test-~D-~A" (sb-posix:getpid) name)))
    (with-open-file (out path :direction :output :if-exists :supersede :element-type '(unsigned-byte 8))
      (funcall writer out))
    path))

(defun names-file-p (condition file)
  "Does CONDITION's report name FILE?"
  (search (file-namestring file) (princ-to-string condition)))

(test missing-model-is-a-model-error
  (let ((e (model-error-of "/nonexistent/wuson.x")))
    (is (typep e 'player:player-error))
    (is (names-file-p e "/nonexistent/wuson.x"))))

(test text-file-is-a-model-error
  (let* ((file (temporary-model-file "notes.txt"
                                     (lambda (out) (write-sequence (sb-ext:string-to-octets
                                                                    (format nil "these are notes, not a model~%"))
                                                                   out))))
         (e (unwind-protect (model-error-of file) (delete-file file))))
    (is (typep e 'player.model:model-error))
    (is (and e (names-file-p e file)))))

(test truncated-model-is-a-model-error
  (with-assimp-models
    (let* ((octets (alexandria:read-file-into-byte-vector (assimp-model "X/Testwuson.X")))
           (file (temporary-model-file "half.x"
                                       (lambda (out) (write-sequence octets out :end (floor (length octets) 2)))))
           (e (unwind-protect (model-error-of file) (delete-file file))))
      (is (typep e 'player.model:model-error))
      (is (and e (names-file-p e file))))))

(test model-limits-are-errors
  (with-assimp-models
    (let ((file (assimp-model "X/Testwuson.X")))
      (let ((e (model-error-of file :joint-limit 10)))
        (is (and e (search "joints, more than the limit of 10" (princ-to-string e)))))
      (let ((e (model-error-of file :vertex-limit 100)))
        (is (and e (search "vertices, more than the limit of 100" (princ-to-string e)))))
      (let ((e (model-error-of file :texture "/nonexistent/skin.png")))
        (is (and e (names-file-p e "/nonexistent/skin.png")))))))

;;;# bin/player model

(test model-command-summarises-testwuson
  (with-assimp-models
    (multiple-value-bind (out err code) (player-command "model" (assimp-model "X/Testwuson.X"))
      (is (= 0 code))
      (is (string= "" err))
      (is (search "1 mesh, 3205 vertices, 3732 triangles" out))
      (is (search "joints (37 bones):" out))
      (dolist (clip '("\"Wuson_Run\": 0.966667 s" "\"Wuson_Walk\": 3.6 s" "\"Wuson_Bind\": 0 s"))
        (is (search clip out) "no ~A in ~A" clip out))
      (is (search (format nil "~%            Pelvis (bone)~%") out)))))

(test model-command-prints-guessed-roles-and-their-drivers
  "The roles are guessed among the skeleton's joints, not the nodes that only
hold a mesh, and each driver they leave out names the role it lacks."
  (with-assimp-models
    ;; CMU motion capture: the hips carry no skin weights in Assimp's import, yet are the hips.
    (let ((out (player-command "model" (assimp-model "BVH/01_01.bvh"))))
      (dolist (line '("  :hips: Hips" "  :left-arm: LeftArm LeftForeArm LeftHand"
                      "  :right-leg: RightUpLeg RightLeg RightFoot RightToeBase"
                      "drivers: gaze, head, facing, reach" "  no visemes: needs :jaw or :mouth-morphs"))
        (is (member line (lines out) :test #'string=) "no line ~S in~%~A" line out)))
    ;; BCN: a jaw and lids, but only a mesh node is called Head.
    (let ((out (player-command "model" (assimp-model "X/BCN_Epileptic.X"))))
      (dolist (line '("  :jaw: B_Jaw" "drivers: gaze, facing, reach, visemes, blink" "  no head: needs :head"))
        (is (member line (lines out) :test #'string=) "no line ~S in~%~A" line out))
      (is (notany (lambda (line) (search ": Head" line)) (lines out)) "the mesh node Head taken for a role"))))

(test model-command-bad-file-is-one-error-line
  (multiple-value-bind (out err code) (player-command "model" "/nonexistent/wuson.x")
    (is (= 1 code))
    (is (string= "" out))
    (is (= 1 (length (lines err))))
    (is (search "player: error: cannot import the model /nonexistent/wuson.x" err))))

;;;# Textures, morph targets, and Assimp's own broken models

(test textures-resolve-against-the-model-folder
  (with-assimp-models
    (let ((model (player.model:import-model (assimp-model "glTF2/BoxTextured-glTF/BoxTextured.gltf"))))
      (is (equal (list (assimp-model "glTF2/BoxTextured-glTF/CesiumLogoFlat.png"))
                 (player.model:model-textures model))))
    ;; A texture inside the file is named as Assimp names it.
    (is (equal '("*0") (player.model:model-textures
                        (player.model:import-model (assimp-model "glTF2/BoxTextured-glTF-Embedded/BoxTextured.gltf")))))
    ;; --texture (:texture) replaces every mesh's texture.
    (is (equal (list (assimp-model "glTF2/BoxTextured-glTF/CesiumLogoFlat.png"))
               (player.model:model-textures
                (player.model:import-model (assimp-model "X/Testwuson.X")
                                           :texture (assimp-model "glTF2/BoxTextured-glTF/CesiumLogoFlat.png")))))))

(test morph-targets-are-named
  (with-assimp-models
    (is (= 2 (length (player.model:model-morph-targets
                      (player.model:import-model
                       (assimp-model "glTF2/glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf"))))))))

(test broken-test-models-are-model-errors
  ;; Assimp's own hostile models: infinities in the positions, a node that is
  ;; its own child, a buffer file that is missing.
  (with-assimp-models
    (dolist (name '("glTF2/BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb"
                    "glTF2/RecursiveNodes/RecursiveNodes.gltf"
                    "glTF2/MissingBin/BoxTextured.gltf"))
      (let ((e (model-error-of (assimp-model name))))
        (is (typep e 'player.model:model-error) "~A imported without an error" name)
        (is (and e (names-file-p e (assimp-model name))))))))

(test model-command-refuses-a-text-file
  (let ((file (temporary-model-file "notes.txt"
                                    (lambda (out) (write-sequence (sb-ext:string-to-octets "not a model") out)))))
    (unwind-protect
         (multiple-value-bind (out err code) (player-command "model" file)
           (is (= 1 code))
           (is (string= "" out))
           (is (equal (list (format nil "player: error: cannot import the model ~A: Assimp cannot read it: ~
No suitable reader found for the file format of file \"~A\"" file file))
                      (lines err))))
      (delete-file file))))
