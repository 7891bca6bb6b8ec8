;;;; test-export.lisp -- `player export` and src/export/: a performance
;;;; written as glTF and read back through Assimp (import-model) must hold the
;;;; same joints, vertices and animation length, and play the same poses.

(in-package #:player-tests)

(def-suite* export :in player-tests)

(defparameter *export-events* '(ev-search ev-bad-speech)
  "The events the Peedy export tests play.")

(defun export-peedy-simulation (&key (fps 30) (events *export-events*))
  "Peedy's spec played on his body, silently, sampled at FPS."
  (simulate (first (load-spec (checkout-file "specs/peedy.lisp")))
            :events events :fps fps :silent t))

(defun call-with-export-file (type function)
  "Call FUNCTION with the path of a fresh temporary file of TYPE, deleted after."
  (let ((path (format nil "/tmp/player-export-~D-~D.~A" (sb-posix:getpid) (random 1000000) type)))
    (unwind-protect (funcall function path)
      (when (probe-file path) (delete-file path)))))

(defun exported-and-imported (simulation type)
  "SIMULATION exported as a file of TYPE and imported back: the model."
  (call-with-export-file type
    (lambda (path)
      (player.export:export-performance simulation path)
      (import-model path))))

(defun quat-at (values frame)
  "Frame FRAME's quaternion of VALUES (w x y z a frame) as a quat."
  (let ((base (* 4 frame)))
    (player.body::make-quat (aref values base) (aref values (+ base 1))
                           (aref values (+ base 2)) (aref values (+ base 3)))))

(test export-round-trip-keeps-joints-vertices-and-length
  (with-assimp-models
    (let* ((simulation (export-peedy-simulation))
           (frames (simulation-frame-count simulation))
           (skeleton (player.body::body-skeleton (player.performance::simulation-body simulation)))
           (original (player.export:performance-model simulation))
           ;; Assimp gives the scene a root node, ROOT, above the file's own;
           ;; the props' nodes, prop/NAME, follow the body's joints.
           (model (exported-and-imported simulation "glb"))
           (props (remove-if-not (lambda (name) (alexandria:starts-with-subseq "prop/" name))
                                 (map 'list #'joint-name (model-joints model))))
           (joints (remove-if (lambda (joint) (or (string= (joint-name joint) "ROOT")
                                                  (member (joint-name joint) props :test #'string=)))
                              (model-joints model))))
      (is (= (length (player.body::skeleton-joints skeleton)) (length joints)))
      (is (equal (map 'list (lambda (j) (string-downcase (symbol-name (player.body::body-joint-name j))))
                      (player.body::skeleton-joints skeleton))
                 (map 'list #'joint-name joints)))
      (is (= (model-vertex-count original) (model-vertex-count model)))
      (is (plusp (model-vertex-count model)))
      ;; Peedy's scene has props (his desk, the note): each is a node.
      (is (= (length (nth-value 1 (player.export:bake-simulation simulation))) (length props)))
      (is (plusp (length props)))
      (is (= 1 (length (model-animations model))))
      ;; Keys at I/FPS: the last frame's, (FRAMES - 1)/FPS, is where the clip ends.
      (is (< (abs (- (model-animation-duration (first (model-animations model)))
                     (/ (1- frames) 30d0)))
             1d-3))
      (is (every (lambda (channel) (= frames (length (channel-rotation-times channel))))
                 (model-animation-channels (first (model-animations model))))))))

(test exported-peedy-plays-the-same-poses
  ;; Every joint's local rotation read back from the file's keys at every
  ;; frame is the one the performance had (the root's with the placement).
  (with-assimp-models
    (let* ((simulation (export-peedy-simulation))
           (baked (first (player.export:bake-simulation simulation)))
           (skeleton (player.export:baked-body-skeleton baked))
           (model (exported-and-imported simulation "gltf"))
           (channels (model-animation-channels (first (model-animations model))))
           (worst 0d0))
      (loop for joint across (player.body::skeleton-joints skeleton)
            for keys across (player.export:baked-body-rotations baked)
            for root = (null (player.body::body-joint-parent joint))
            for index = (find-model-joint model (string-downcase (symbol-name (player.body::body-joint-name joint))))
            for channel = (find index channels :key #'channel-joint)
            do (is (not (null channel)))
               (when channel
                 (dotimes (frame (player.export:baked-frame-count baked))
                   (let ((expected (if root
                                       (quat-at (player.export:baked-body-root-rotations baked) frame)
                                       (quat-at keys frame))))
                     (setf worst (max worst (player.body::quat-angle expected (quat-at (channel-rotations channel) frame))))))))
      (is (< worst 1d-4) "the worst joint is ~,6F rad off" worst))))

(test exported-rotations-are-the-poses-the-performance-had
  ;; Independently of the file: the baked keys are JOINT-LOCAL-ROTATION of
  ;; the pose at each frame time.
  (let* ((simulation (export-peedy-simulation :fps 10))
         (baked (first (player.export:bake-simulation simulation)))
         (worst 0d0))
    (map-simulation-frames
     (lambda (index time scene)
       (declare (ignore time))
       (let ((body (find-if (lambda (o) (typep o 'player.body::body)) (player.body::scene-objects scene))))
         (loop for joint across (player.body::skeleton-joints (player.body::body-skeleton body))
               for keys across (player.export:baked-body-rotations baked)
               do (setf worst (max worst (player.body::quat-angle
                                          (player.body::joint-local-rotation joint (player.body::body-pose body))
                                          (quat-at keys index)))))))
     simulation)
    (is (< worst 1d-9))))

(test an-imported-model-exports-its-own-mesh
  ;; Testwuson.X made a Player skeleton and played: the export holds the
  ;; model's joints (its names) and its vertices.
  (with-assimp-models
    (let* ((source (import-model (assimp-model "X/Testwuson.X")))
           (skeleton (player.rig:model-skeleton source :height 1.7))
           (model (player.export:character-model skeleton)))
      (is (equal (map 'list #'joint-name (model-joints source)) (map 'list #'joint-name (model-joints model))))
      (is (= (model-vertex-count source) (model-vertex-count model)))
      (call-with-export-file "glb"
        (lambda (path)
          (write-gltf model path)
          (let ((back (import-model path)))
            (is (= (length (model-joints source)) (length (model-joints back))))
            (is (= (model-vertex-count source) (model-vertex-count back)))))))))

(test an-imported-character-exports-through-the-command
  ;; examples/wuson (Testwuson.X by the model form) played and exported: the
  ;; file holds the model's joints by their own names, its 3,205 vertices,
  ;; and a key per frame.
  (with-assimp-models
    (call-with-export-file "glb"
      (lambda (path)
        (multiple-value-bind (out err code)
            (player-command "export" (namestring (checkout-file "examples/wuson/wuson.lisp"))
                            "--events" "ev-walk@0,ev-run@1.5" "--at" "3" "--fps" "15" "--out" path)
          (is (= 0 code) "export failed: ~A" err)
          (is (search "; 46 frames at 15 fps" out))
          (let ((source (import-model (assimp-model "X/Testwuson.X")))
                (back (import-model path)))
            (is (= (model-vertex-count source) (model-vertex-count back)))
            (is (equal (map 'list #'joint-name (model-joints source))
                       (remove "ROOT" (map 'list #'joint-name (model-joints back)) :test #'string=)))
            (is (every (lambda (channel) (= 46 (length (channel-rotation-times channel))))
                       (model-animation-channels (first (model-animations back)))))))))))

(test export-refuses-a-wrong-out-type
  (multiple-value-bind (out err code)
      (player-command "export" (namestring (checkout-file "specs/peedy.lisp")) "--events" "ev-search" "--out" "/tmp/peedy.obj")
    (declare (ignore out))
    (is (= 2 code))
    (is (= 1 (length (lines err))))
    (is (search "player: error:" err)))
  (multiple-value-bind (out err code)
      (player-command "export" (namestring (checkout-file "specs/peedy.lisp")) "--events" "ev-search")
    (declare (ignore out))
    (is (= 2 code))
    (is (= 1 (length (lines err))))))

(test a-scene-exports-every-member
  ;; Two Peedys in one file: their joints named MEMBER/JOINT.
  (with-assimp-models
    (call-with-export-file "gltf"
      (lambda (path)
        (multiple-value-bind (out err code)
            (player-command "export" (namestring (checkout-file "specs/peedy.lisp")) "--cast" "peedy:2"
                            "--events" "all/ev-search" "--fps" "10" "--out" path)
          (declare (ignore out))
          (is (= 0 code) "export failed: ~A" err)
          (let ((names (map 'list #'joint-name (model-joints (import-model path)))))
            (is (member "peedy1/neck" names :test #'string=))
            (is (member "peedy2/neck" names :test #'string=))))))))

(test exported-peedy-is-a-file-assimp-reads
  (with-assimp-models
    (call-with-export-file "glb"
      (lambda (path)
        (multiple-value-bind (out err code)
            (player-command "export" (namestring (checkout-file "specs/peedy.lisp"))
                            "--events" "ev-search" "--fps" "12" "--out" path)
          (is (= 0 code) "export failed: ~A" err)
          (is (search "; wrote" out))
          (let ((info (assimp-output "info" path)))
            (is (search "Nodes" info) "assimp info said: ~A" info)))))))
