;;;; package.lisp -- player.export: a performance written as a file other
;;;; tools read.  A played simulation is sampled frame by frame, each body
;;;; becomes a MODEL (joints, skinned meshes) carrying the performance as one
;;;; animation, and the model layer's WRITE-GLTF writes it as .glb or .gltf.

(defpackage #:player.export
  (:use #:cl #:player.base #:player.spec #:player.planner #:player.ir #:player.inspect #:player.control #:player.speech #:player.body #:player.ode #:player.physics #:player.performance #:player.render #:player.model #:player.rig)
  (:documentation "A performance exported as glTF: baked frames, bodies as models, the file.")
  (:export
   #:export-performance #:performance-model #:character-model
   #:bake-simulation #:baked-body #:baked-body-p #:baked-body-name #:baked-body-skeleton
   #:baked-body-rotations #:baked-body-root-translations #:baked-body-root-rotations #:baked-body-morph-weights
   #:baked-frame-count
   #:baked-prop #:baked-prop-p #:baked-prop-object #:baked-prop-translations #:baked-prop-rotations
   #:baked-prop-scales))
