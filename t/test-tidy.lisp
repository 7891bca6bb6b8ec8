;;;; test-tidy.lisp -- leftovers tidied: an undecodable `bin/player model
;;;; --texture` file is one error, and a character that root motion carried
;;;; rests where it arrived.

(in-package #:player-tests)

(def-suite* tidy :in player-tests)

;;; ---------------------------------------------------------------------------
;;; `player model --texture` with a file that is not a picture

(test model-command-refuses-an-undecodable-texture
  "A --texture file stb_image cannot decode is one `player: error:` line on
stderr naming the file and the reason, exit 1, and no summary."
  (with-stb
    (with-assimp-models
      (let ((gltf (assimp-model "glTF/BoxTextured-glTF/BoxTextured.gltf")))
        (with-image-file (path "png")
          (with-open-file (out path :direction :output :if-exists :supersede)
            (write-line "not a picture" out))
          (multiple-value-bind (out err code) (player-command "model" gltf "--texture" (namestring path))
            (let ((lines (remove "" (uiop:split-string err :separator '(#\Newline)) :test #'string=)))
              (is (= 1 code) "exit ~D: ~A" code err)
              (is (= 1 (length lines)) "~S" lines)
              (is (eql 0 (search "player: error: " (first lines))) "~A" err)
              (is (search (file-namestring path) err) "the texture file is not named: ~A" err)
              (is (search "stb_image cannot decode it" err) "no reason given: ~A" err)
              (is (not (search "textures:" out)) "a summary was printed: ~A" out))))))))

;;; ---------------------------------------------------------------------------
;;; Root motion moves the character's resting place

(defun walk-then-stop-spec (directory library)
  "Write LIBRARY as lib.lisp and a spec in DIRECTORY whose ev-walk goes to a
walking gait (its autoscript WALK-LOOP) and ev-stop, preempting, back to rest;
return the spec."
  (write-library directory library)
  (let ((path (merge-pathnames "spec.lisp" directory)))
    (with-open-file (out path :direction :output :if-exists :supersede)
      (write-string "(in-package :player-user)
(defspec stroller \"Walks, then stops.\" (:scripts \"lib.lisp\")
  (state-variable gait string rest (rest walk))
  (op start-walking :precond gait.rest :add gait.walk :duration 0.2)
  (op halt :precond gait.walk :add gait.rest :duration 0.3)
  (autoscript gait walk (walk-loop))
  (event ev-walk :state gait.walk)
  (event ev-stop (:when-busy :preempt) :state gait.rest))
" out))
    (first (player:load-spec path))))

(defun body-position-in (simulation time)
  "Where SIMULATION's body stands at TIME seconds (a vec3)."
  (let ((scene (player.performance::simulation-scene-at simulation (float time 1d0))))
    (player:property-value (find-if (lambda (o) (typep o 'player:body)) (player:scene-objects scene))
                           'player.body::position)))

(test settling-keeps-where-root-motion-took-the-character
  "CMU's walk (01_01.bvh, whose hips cross the room) looped with :root :move
while walking, then a stop: the last frame, the body settled, stands where
the walk ended (within 1 cm), not back where it was placed; the pose's
settling does not undo the travel.  (Testwuson's walk keeps its root still,
so Wuson could not show it.)"
  (with-assimp-models
    (with-rig-directory (dir)
      (let* ((spec (walk-then-stop-spec dir (format nil "(model ~S)
(defscript walk-loop (:loop t :duration 2) (:at 0 :clip motion :root :move :loop t :fade 0))
(defscript halt (:duration 0.3) (:at 0 :clip motion :fade 0.3 :for 0.3))"
                                                     (assimp-model "BVH/01_01.bvh"))))
             (simulation (player:simulate spec :events '((ev-walk . 0) (ev-stop . 1.5)) :silent t))
             ;; The loop goes on through the halt: the state leaves gait.walk,
             ;; stopping it, when the halt is done, 0.3 s after ev-stop.
             (stopped (body-position-in simulation 1.8))
             (end (player.performance::simulation-end simulation))
             (last (body-position-in simulation end)))
        (is (> (player.body:vdistance stopped (player.body::vec3)) 1) "the walk went only to ~A: no test" stopped)
        (is (> end 1.8) "the simulation ends at ~A, before the halt" end)
        (is (< (player.body:vdistance last stopped) 0.01)
            "the last frame (~,2F s) stands at ~A, the walk ended at ~A" end last stopped)))))

;;; ---------------------------------------------------------------------------
;;; Morph targets and their weights through glTF and back

(defun morph-summary (model)
  "MODEL's morph targets and weight keys, for comparing: per mesh, its
targets as (NAME DELTAS); per animation, its morph channels as (MESHES TIMES
WEIGHTS TARGET-COUNT)."
  (list (mapcar (lambda (mesh)
                  (mapcar (lambda (target) (list (player.model::morph-target-name target)
                                                 (player.model::morph-target-deltas target)))
                          (player.model::model-mesh-morphs mesh)))
                (player:model-meshes model))
        (mapcar (lambda (animation)
                  (mapcar (lambda (channel)
                            (list (player.model::morph-channel-meshes channel)
                                  (player.model::morph-channel-times channel)
                                  (player.model::morph-channel-weights channel)
                                  (player.model::morph-channel-target-count channel)))
                          (player.model::model-animation-morph-channels animation)))
                (player:model-animations model))))

(defun nearly-equal-tree-p (a b tolerance)
  "Are A and B the same tree of lists, vectors, strings and numbers, numbers
within TOLERANCE?"
  (cond ((and (numberp a) (numberp b)) (<= (abs (- a b)) tolerance))
        ((and (stringp a) (stringp b)) (string= a b))
        ((and (vectorp a) (vectorp b))
         (and (= (length a) (length b)) (every (lambda (x y) (nearly-equal-tree-p x y tolerance)) a b)))
        ((and (listp a) (listp b))
         (and (= (length a) (length b)) (every (lambda (x y) (nearly-equal-tree-p x y tolerance)) a b)))
        (t (equal a b))))

(test gltf-writes-morph-targets-and-their-weights
  "AnimatedMorphCube (two morph targets, their weights keyed 127 times)
written as .glb and as .gltf and imported back through Assimp: the same
targets, deltas and weight keys (within float rounding)."
  (with-assimp-models
    (let* ((model (player:import-model
                   (assimp-model "glTF2/glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf")))
           (before (morph-summary model)))
      (is (= 2 (length (first (first before)))) "no morph targets to test: ~S" before)
      (is (some (lambda (channels) (plusp (length channels))) (second before)) "no weight keys to test")
      (dolist (type '("glb" "gltf"))
        (uiop:with-temporary-file (:pathname path :type type :keep nil)
          (player.model:write-gltf model path)
          (let ((after (morph-summary (player:import-model path))))
            (is (nearly-equal-tree-p before after 1d-6) "~A: before ~S~%after ~S" type before after)))))))

(defun largest-delta-share (mesh)
  "For each morph target of MESH, its largest delta component over the
largest extent of MESH's positions along an axis: what a uniform scale and
a turn by right angles (Player's space from the file's) leave unchanged."
  (let* ((positions (player:model-mesh-positions mesh))
         (extent (loop for axis below 3
                       maximize (loop for i from axis below (length positions) by 3
                                      maximize (aref positions i) into high
                                      minimize (aref positions i) into low
                                      finally (return (- high low))))))
    (mapcar (lambda (target) (/ (reduce #'max (player:morph-target-deltas target) :key #'abs) extent))
            (player:model-mesh-morphs mesh))))

(test export-writes-the-bodys-morph-targets-and-weights
  "AnimatedMorphCube as a character playing its clip, exported as .glb and
imported back through Assimp: its two morph targets, their deltas the file's
to scale, and their weights keyed at every frame as the body's pose held them."
  (with-assimp-models
    (with-rig-directory (dir)
      (let* ((model (player:import-model (assimp-model *morph-cube*)))
             (clip (player.rig:clip-name-from-animation
                    (player:model-animation-name (first (player:model-animations model)))))
             (spec (write-walker-files dir (format nil "(model ~S)
(defscript walk (:duration 3) (:at 0 :clip ~(~A~) :fade 0 :for 3))" (assimp-model *morph-cube*) clip)))
             (simulation (player:simulate spec :events '(ev-walk) :silent t))
             (baked (first (player:bake-simulation simulation)))
             (path (player:export-performance simulation (merge-pathnames "out.glb" dir)))
             (back (player:import-model path))
             (mesh (first (player:model-meshes back)))
             (channel (first (player:model-animation-morph-channels (first (player:model-animations back))))))
        (is (equal (player:model-morph-targets model) (player:model-morph-targets back)))
        (is (every (lambda (a b) (< (abs (- a b)) 1d-4))
                   (largest-delta-share (first (player:model-meshes model))) (largest-delta-share mesh))
            "the deltas' shares ~S, the file's ~S"
            (largest-delta-share mesh) (largest-delta-share (first (player:model-meshes model))))
        (is (not (null channel)) "no weight keys came back")
        (when channel
          (let ((expected (player.export:baked-body-morph-weights baked))
                (weights (player:morph-channel-weights channel)))
            (is (= (player.export:baked-frame-count baked) (length (player:morph-channel-times channel))))
            (is (> (reduce #'max expected) 0.5) "the weights hardly move: no test")
            (is (= (length expected) (length weights)))
            (is (every (lambda (a b) (< (abs (- a b)) 1d-6)) expected weights)
                "the weights keyed differ from the body's")))))))
