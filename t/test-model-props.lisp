;;;; test-model-props.lisp -- a model with no joints as a prop (issue 26):
;;;; (defobject NAME :kind :prop :model "FILE") draws Khronos's textured box,
;;;; its embedded texture's colours on screen; a missing prop model is an
;;;; error at its line that `check` finds; a joint-less model named as the
;;;; character says to make it a prop; the export holds the prop's mesh.

(in-package #:player-tests)

(def-suite* model-props :in player-tests)

(defparameter *textured-box-glb* "/usr/share/assimp/models/glTF2/BoxTextured-glTF-Binary/BoxTextured.glb"
  "A model with no joints whose PNG texture (the Cesium logo: grey, blue, green) is embedded.")

(defun write-prop-files (directory library)
  "Write LIBRARY (a string) as lib.lisp and a small spec using it on a
humanoid as spec.lisp in DIRECTORY; return the spec's path."
  (write-library directory library)
  (let ((spec (merge-pathnames "spec.lisp" directory)))
    (with-open-file (out spec :direction :output :if-exists :supersede)
      (write-string "(in-package :player-user)
(defspec prop-stage
  \"A humanoid and the props its library declares.\"
  (:scripts \"lib.lisp\")
  (:body humanoid)
  (state-variable up boolean false)
  (op rise :add up :duration 0.5)
  (event ev-rise :op rise))
" out))
    spec))

(defun prop-library (&key (model *textured-box-glb*) (extra ""))
  "A script library declaring the textured box as a prop named box, 0.4 m
tall, beside the humanoid's shoulders, a camera looking at it, and EXTRA."
  (format nil "(defobject box :kind :prop :model ~S :height 0.4 :position (0.5 1.1 0.3) :rotation (:euler 20 30 0))
(defobject camera :kind :camera :position (0.5 1.3 1.6) :rotation (:euler -8 0 0))
(defscript rise () (:at 0 :animate (box position) (:keys ((0 :vec3 0.5 1.1 0.3) (0.5 :vec3 0.5 1.2 0.3)))))
~A" model extra))

(defun prop-stage-scene (directory library)
  "The scene at time 0 of the spec in DIRECTORY playing LIBRARY."
  (let* ((spec (write-prop-files directory library))
         (simulation (player:simulate (first (player:load-spec spec)) :events '(ev-rise) :silent t)))
    (player.performance::simulation-scene-at simulation 0d0)))

(defun green-pixel-count (pixels)
  "How many RGBA PIXELS are clearly green, as the Cesium logo's leaves are."
  (loop for i from 0 below (length pixels) by 4
        count (let ((r (aref pixels i)) (g (aref pixels (+ i 1))) (b (aref pixels (+ i 2))))
                (and (> g (+ r 40)) (> g (+ b 40))))))

(test model-prop-draws-its-embedded-texture
  "The textured box declared as a prop is drawn, its embedded texture's
green on screen; the same box under a plain grey texture shows none (so
the green comes from the embedded PNG, and not drawing the box fails too)."
  (with-skinned-render-prerequisites
    (with-stb
      (with-rig-directory (dir)
        (let ((embedded (green-pixel-count (render-pixels (prop-stage-scene dir (prop-library)) 160 120 :floor nil)))
              (grey (merge-pathnames "grey.png" dir)))
          (player.render::write-png grey 2 2 (make-array 16 :element-type '(unsigned-byte 8) :initial-element 128))
          (let ((plain (green-pixel-count
                        (render-pixels (prop-stage-scene dir (substitute-string (prop-library) ":height 0.4"
                                                                                ":height 0.4 :texture \"grey.png\""))
                                       160 120 :floor nil))))
            (is (> embedded 30) "only ~D green pixels: the box's embedded texture is not drawn" embedded)
            (is (< plain 5) "~D green pixels with a grey texture" plain)))))))

(defun substitute-string (text old new)
  "TEXT with its first OLD replaced by NEW."
  (let ((at (search old text)))
    (concatenate 'string (subseq text 0 at) new (subseq text (+ at (length old))))))

(test model-prop-moves-with-its-object
  "A model prop is a scene object of kind :prop at its declared place, and
an :animate of its position moves it."
  (with-assimp-models
    (with-rig-directory (dir)
      (let* ((spec (write-prop-files dir (prop-library)))
             (simulation (player:simulate (first (player:load-spec spec)) :events '(ev-rise) :silent t))
             (box (player:find-object (player.performance::simulation-scene-at simulation 0.45d0) 'box)))
        (is (typep box 'player:model-prop))
        (is (eq :prop (player:object-kind box)))
        (is (< 1.15 (player.body::vec3-y (player:property-value box 'position)) 1.2)
            "the animated prop is at ~A" (player:property-value box 'position))))))

(test missing-prop-model-is-an-error-at-its-line
  "`bin/player check` reports a prop model that does not exist at the
defobject's line, naming the file, before anything renders."
  (with-assimp-models
    (with-rig-directory (dir)
      (let ((spec (write-prop-files dir (format nil "~%~%(defobject cup :kind :prop :model \"cup.glb\")~%"))))
        (multiple-value-bind (out err code) (player-command "check" (namestring spec))
          (is (= 1 code) "exit ~D: ~A" code err)
          (is (search "error: lib.lisp:3: object cup: cannot import the model" out) "~A" out)
          (is (search "cup.glb: the model file does not exist" out) "~A" out))))))

(test joint-less-character-model-says-use-a-prop
  "A library whose (model \"FILE\") names a model with no joints is one
error saying to draw it as a prop with defobject :model."
  (with-assimp-models
    (with-rig-directory (dir)
      (let ((text (library-error-text dir (format nil "(model ~S)" *textured-box-glb*))))
        (is (search "has no joints" text) "~A" text)
        (is (search "(defobject NAME :kind :prop :model" text) "~A" text)))))

(test model-prop-options-are-checked
  ":model on a camera, or :height without :model, is an error at the form."
  (with-rig-directory (dir)
    (is (search ":model draws a prop"
                (library-error-text dir (format nil "(defobject cam :kind :camera :model ~S)" *textured-box-glb*))))
    (is (search "give :model" (library-error-text dir "(defobject cup :kind :prop :height 2)")))))

(test model-prop-exported-with-its-mesh
  "The glTF export writes a model prop as a node with its model's mesh: read
back, a mesh of the prop's holds the box's 24 vertices, and the embedded
texture is written too."
  (with-assimp-models
    (with-stb
      (with-rig-directory (dir)
        (let* ((spec (write-prop-files dir (prop-library)))
               (simulation (player:simulate (first (player:load-spec spec)) :events '(ev-rise) :silent t))
               (out (namestring (merge-pathnames "out.glb" dir))))
          (player.export::export-performance simulation out)
          (let* ((model (player:import-model out))
                 (mesh (find-if (lambda (m) (search "prop/box" (player:model-mesh-name m))) (player:model-meshes model))))
            (is (not (null mesh)) "no prop mesh among ~{~S~^ ~}" (mapcar #'player:model-mesh-name (player:model-meshes model)))
            (when mesh
              (is (= 24 (player:model-mesh-vertex-count mesh)))
              (is (typep (cdr (assoc (player:model-mesh-texture mesh) (player:model-texture-images model) :test #'equal))
                         'player:image)))))))))
