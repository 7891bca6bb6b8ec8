;;;; wuson.lisp -- a character nobody here made: Wuson, from Assimp's test
;;;; models (Debian's assimp-testmodels), driven by a Player spec.  Its script
;;;; library (wuson-scripts.lisp) brings the model in with (model "FILE" ...):
;;;; the file's Wuson_Walk and Wuson_Run animations are its walk and run, and
;;;; it turns its head to the camera through the :head role.  Try:
;;;;   bin/player simulate examples/wuson/wuson.lisp --events ev-walk,ev-run,ev-stop
;;;;   make demo-model

(in-package :player-user)

(defspec wuson
  "Wuson walks, runs, stops and looks at whoever is watching."
  (:scripts "wuson-scripts.lisp")
  (state-variable gait string rest (rest walk run))
  (state-variable watching boolean false)
  (op start-walking :precond gait.rest :add gait.walk :duration 0.5)
  (op speed-up :precond gait.walk :add gait.run :duration 0.4)
  (op slow-down :precond gait.run :add gait.walk :duration 0.4)
  (op halt :precond (not gait.rest) :add gait.rest :duration 0.6)
  (op look-up :precond (not watching) :add watching :duration 0.8)
  (op look-away :precond watching :sub watching :duration 0.8)
  (autoscript gait walk (walk-loop))
  (autoscript gait run (run-loop))
  (event ev-walk :state gait.walk)
  (event ev-run :state gait.run)
  (event ev-stop (:when-busy :preempt) :state gait.rest)
  (event ev-look :state watching)
  (event ev-look-away :state (not watching)))
