;;;; player.asd -- the system definition; read in order, it is the pipeline:
;;;; spec language -> canonical expressions -> planner -> code generators -> runtime -> CLI.

(defsystem "player"
  :description "Planning-based animation controllers: declare operators with
preconditions and effects, precompile plans from every state to every goal, and
run the resulting state machine as Lisp closures."
  :version "0.1.0"
  :license "MIT"
  :depends-on ("alexandria" "sb-md5" "cffi" "salza2")
  :serial t
  :components
  ((:module "src"
    :serial t
    :components
    ((:file "package")
     (:module "spec"
      :serial t
      :components ((:file "conditions")
                   (:file "printing")
                   (:file "model")
                   (:file "syntax")
                   (:file "expressions")
                   (:file "canonical")
                   (:file "classes")
                   (:file "parse")
                   (:file "directives")
                   (:file "validate")
                   (:file "registry")))
     (:module "planner"
      :serial t
      :components ((:file "encoding")
                   (:file "regression")
                   (:file "goals")
                   (:file "machine")
                   (:file "diagnostics")))
     (:module "runtime-protocol"
      :pathname "runtime"
      :serial t
      :components ((:file "presenter")
                   (:file "controller-state")))
     (:module "codegen"
      :serial t
      :components ((:file "ir")
                   (:file "lisp-closures")))
     (:module "runtime"
      :serial t
      :components ((:file "controller")))
     (:module "anim"
      :pathname "runtime/anim"
      :serial t
      :components ((:file "vectors")
                   (:file "quaternions")
                   (:file "transforms")
                   (:file "controls")
                   (:file "keyframes")
                   (:file "noise")
                   (:file "control-forms")
                   (:file "scene")))
     (:module "body"
      :pathname "runtime/body"
      :serial t
      :components ((:file "skeleton")
                   (:file "arbitration")
                   (:file "pose")
                   (:file "bvh")
                   (:file "motor-functions")
                   (:file "driver")
                   (:file "body")
                   (:file "pose-library")
                   (:file "ik")
                   (:file "ik-search")))
     (:module "drivers"
      :pathname "runtime/body/drivers"
      :serial t
      :components ((:file "direct")
                   (:file "keyframe")
                   (:file "lips")
                   (:file "beat")
                   (:file "idle")
                   (:file "head")
                   (:file "gaze")
                   (:file "blink")
                   (:file "facing")
                   (:file "eyebrows")
                   (:file "reach")))
     (:module "scripts"
      :pathname "runtime/anim"
      :serial t
      :components ((:file "scripts")
                   (:file "directors")
                   (:file "script-library")))
     (:module "performance"
      :pathname "runtime"
      :serial t
      :components ((:file "performance")
                   (:file "body-presenter")
                   (:file "simulation")))
     (:module "render"
      :pathname "runtime/render"
      :serial t
      :components ((:file "mesh")
                   (:file "appearance")
                   (:file "body-mesh")
                   (:file "scene-mesh")
                   (:file "libraries")
                   (:file "gl")
                   (:file "osmesa")
                   (:file "framebuffer")
                   (:file "png")
                   (:file "camera")
                   (:file "antialias")
                   (:file "shaders")
                   (:file "renderer")
                   (:file "render-command")
                   (:file "glfw")
                   (:file "viewer")))
     (:module "codegen-c++"
      :pathname "codegen"
      :serial t
      :components ((:file "cpp-names")
                   (:file "cpp")
                   (:file "cpp-steps")
                   (:file "cpp-source")
                   (:file "cpp-build")))
     (:file "cli"))))
  :in-order-to ((test-op (test-op "player/tests"))))

(defsystem "player/tests"
  :description "FiveAM suite for Player; run with (asdf:test-system :player)."
  :depends-on ("player" "fiveam")
  :serial t
  :components
  ((:module "t"
    :serial t
    :components ((:file "package")
                 (:file "random-specs")
                 (:file "reference-bfs")
                 (:file "random-events")
                 (:file "test-language")
                 (:file "test-errors")
                 (:file "test-planner")
                 (:file "test-controller")
                 (:file "test-peedy")
                 (:file "test-peedy-body")
                 (:file "test-properties")
                 (:file "test-c++")
                 (:file "test-cli")
                 (:file "test-anim")
                 (:file "test-body")
                 (:file "test-bvh")
                 (:file "test-scene")
                 (:file "test-pose-drivers")
                 (:file "test-gaze")
                 (:file "test-face-drivers")
                 (:file "test-scripts")
                 (:file "test-performance")
                 (:file "test-simulate")
                 (:file "test-render-base")
                 (:file "test-mesh")
                 (:file "test-reach")
                 (:file "test-render")
                 (:file "test-viewer"))))
  :perform (test-op (o c) (symbol-call :player-tests '#:run-tests-and-report)))
