;;;; player.asd -- the system definition; read in order, it is the pipeline:
;;;; spec language -> planner -> code generators (Lisp closures, C++) ->
;;;; runtime (controller -> anim -> body -> scripts -> performance -> render) -> CLI.
;;;; Every module is one folder.

(defsystem "player"
  :description "Planning-based animation controllers: declare operators with
preconditions and effects, precompile plans from every state to every goal, and
run the resulting state machine as Lisp closures or embedded C++."
  :version "0.1.0"
  :license "MIT"
  :depends-on ("alexandria" "sb-md5" "cffi" "salza2" "bordeaux-threads")
  :serial t
  :components
  ((:module "src"
    :serial t
    :components
    ((:file "package")
     (:file "utilities")
     (:module "spec"
      :serial t
      :components ((:file "conditions")
                   (:file "printing")
                   (:file "structure")
                   (:file "arguments")
                   (:file "model")
                   (:file "syntax")
                   (:file "expressions")
                   (:file "canonical")
                   (:file "classes")
                   (:file "variables")
                   (:file "state-space")
                   (:file "spec-options")
                   (:file "parse")
                   (:file "directives")
                   (:file "interruption")
                   (:file "timers")
                   (:file "validate")
                   (:file "initial-values")
                   (:file "code-sites")
                   (:file "registry")
                   (:file "data-files")
                   (:file "spec-files")))
     (:module "planner"
      :serial t
      :components ((:file "encoding")
                   (:file "solved-states")
                   ;; Past the full space: plans for the reachable states only.
                   (:file "reachable")
                   (:file "regression")
                   (:file "uniform-cost")
                   (:file "goal-identity")
                   (:file "goals")
                   (:file "macro-exactness")
                   (:file "plan-memo")
                   (:file "machine")
                   (:file "diagnostics")))
     ;; Looking at a planned machine: its state graph as Graphviz, explanations.
     (:module "inspect"
      :serial t
      :components ((:file "state-graph")
                   (:file "dot")
                   (:file "explanation-steps")
                   (:file "unreachable-goals")
                   (:file "explain")))
     (:module "compose"
      :serial t
      :components ((:file "conditions")
                   (:file "nodes")
                   (:file "graphs")
                   (:file "patterns")
                   (:file "restriction")
                   (:file "products")
                   (:file "trees")
                   (:file "merge")
                   (:file "traces")
                   (:file "cradle")
                   (:file "graph-spec")
                   (:file "cradle-spec")
                   (:file "cradle-scripts")
                   (:file "spec-graph")
                   (:file "graph-expressions")
                   (:file "graph-option")))
     (:module "codegen"
      :serial t
      :components ((:file "ir")
                   ;; Lisp: closures running on a controller struct.
                   (:file "controller-state")
                   (:file "lisp-closures")
                   (:file "lisp-steps")
                   ;; C++: a standalone controller to embed.
                   (:file "cpp-names")
                   ;; The one-hot state in 64-bit words: one for most specs, more for wide ones.
                   (:file "cpp-words")
                   (:file "cpp")
                   (:file "cpp-steps")
                   (:file "cpp-timeline")
                   (:file "cpp-timeline-agenda")
                   (:file "cpp-timeline-dispatch")
                   (:file "cpp-timeline-clock")
                   (:file "cpp-timeline-machine")
                   (:file "cpp-source")
                   (:file "cpp-drivers")
                   (:file "cpp-build")
                   (:file "cpp-batch")))
     ;; Speech: sound files, espeak-ng synthesis with its phoneme timeline as
     ;; visemes, pocketsphinx recognition; libraries loaded on first use.
     (:module "speech"
      :serial t
      :components ((:file "libraries")
                   (:file "wav")
                   (:file "espeak")
                   (:file "synthesis")
                   (:file "visemes")
                   (:file "mix")
                   (:file "pocketsphinx")
                   (:file "pronunciation")
                   (:file "recognition")
                   (:file "playback")))
     (:module "runtime"
      :serial t
      :components
      ((:module "controller"
        :serial t
        :components ((:file "presenter")
                     (:file "presenter-silence")
                     (:file "controller")
                     ;; States the reachable regime has no plans from.
                     (:file "unplanned-states")
                     ;; Live authoring: a running controller switched to its redefined spec.
                     (:file "redefinition")
                     (:file "following")))
       ;; The timed controller: events meeting while the character moves.
       (:module "timeline"
        :serial t
        :components ((:file "agenda")
                     (:file "runs")
                     (:file "item-pool")
                     (:file "feeding")
                     (:file "footprints")
                     (:file "recorder")
                     (:file "timeline")
                     ;; Plans taped the first time, replayed after.
                     (:file "tapes")
                     (:file "advance")
                     (:file "arrivals")
                     (:file "cuts")
                     (:file "timers")
                     (:file "api")))
       (:module "anim"
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
        :serial t
        :components ((:file "skeleton")
                     (:file "arbitration")
                     (:file "pose")
                     (:file "pose-library")
                     (:file "bvh")
                     (:file "motor-functions")
                     (:file "driver")
                     (:file "body")
                     (:file "ik")
                     (:file "ik-search")
                     (:module "drivers"
                      :serial t
                      :components ((:file "direct")
                                   (:file "keyframe")
                                   (:file "lips")
                                   (:file "beat")
                                   (:file "idle")
                                   (:file "aim")
                                   (:file "head")
                                   (:file "gaze")
                                   (:file "blink")
                                   (:file "facing")
                                   (:file "eyebrows")
                                   (:file "reach")))))
       (:module "scripts"
        :serial t
        :components ((:file "scripts")
                     (:file "audio-items")
                     (:file "directors")
                     (:file "script-library")
                     (:file "pose-when")))
       (:module "performance"
        :serial t
        :components ((:file "performance")
                     (:file "captions")
                     (:file "starting-pose")
                     (:file "placeholders")
                     (:file "speech")
                     (:file "body-presenter")
                     (:file "op-channels")
                     (:file "script-check")
                     (:file "simulation")
                     (:file "library-reload")))
       ;; Live authoring's plumbing: work posted between threads, watched files.
       (:module "live"
        :serial t
        :components ((:file "inbox")
                     (:file "watch")
                     (:file "reports")
                     (:file "swank")))
       (:module "render"
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
                     (:file "caption-font")
                     (:file "captions")
                     (:file "renderer")
                     (:file "render-simulation")
                     (:file "glfw")
                     (:file "viewer")
                     (:file "live-viewer")
                     (:file "view-session")))))
     ;; Several characters in one scene: DEFSCENE, event addresses, one
     ;; controller per member over a shared machine, a scene simulated and drawn.
     (:module "cast"
      :serial t
      :components ((:file "conditions")
                   (:file "defscene")
                   (:file "addresses")
                   (:file "scene-files")
                   (:file "ensemble")
                   (:file "scene-simulation")
                   (:file "scene-viewer")))
     ;; Persona's dialogue manager: a sentence -> an input event -> a transition
     ;; -> Player events and spoken templates, with context and episodic memory.
     (:module "dialogue"
      :serial t
      :components ((:file "names")
                   (:file "conditions")
                   (:file "model")
                   (:file "catalogue")
                   (:file "memory")
                   (:file "conversation")
                   (:file "expressions")
                   (:file "templates")
                   (:file "actions")
                   (:file "catalogue-actions")
                   (:file "matcher")
                   (:file "jsgf")
                   (:file "parse")
                   (:file "files")
                   (:file "turns")
                   ;; The loop closed: replies spoken on the performance, beak in sync.
                   (:file "speaking")))
     ;; Recorded traces as regression tests: record a scenario, verify a replay.
     (:module "regression"
      :serial t
      :components ((:file "conditions")
                   (:file "recording")
                   (:file "scenario")
                   (:file "files")
                   (:file "differences")
                   (:file "api")))
     (:module "cli"
      :serial t
      :components ((:file "options")
                   (:file "commands")
                   (:file "help")
                   (:file "main")
                   (:file "cast")
                   (:file "run")
                   (:file "plans")
                   (:file "dot")
                   (:file "check")
                   (:file "explain")
                   (:file "emit-c++")
                   (:file "simulate")
                   (:file "render")
                   (:file "view")
                   (:file "record")
                   (:file "verify")
                   (:file "chat")
                   (:file "speak"))))))
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
                 (:file "test-macro-exactness")
                 (:file "test-goal-identity")
                 (:file "test-explain")
                 (:file "reference-ucs")
                 (:file "test-planner-scale")
                 (:file "test-dot")
                 (:file "test-controller")
                 (:file "test-peedy")
                 (:file "test-peedy-body")
                 (:file "test-properties")
                 (:file "timeline-streams")
                 (:file "timeline-model")
                 (:file "timeline-model-runs")
                 (:file "timeline-model-arrivals")
                 (:file "timeline-model-replay")
                 (:file "test-timeline-model")
                 (:file "test-c++")
                 (:file "test-dispatch")
                 (:file "test-c++-hostile")
                 (:file "test-cli")
                 ;; the reachable regime (issue 13), its CLI too
                 (:file "strips-families")
                 (:file "reference-reachable")
                 (:file "test-reachable")
                 (:file "test-timeline")
                 (:file "test-c++-timeline")
                 ;; after test-c++-timeline: it plays that file's random specs too
                 (:file "test-item-pool")
                 ;; after test-c++-timeline too
                 (:file "test-plan-tapes")
                 (:file "test-c++-wide")
                 (:file "test-hostile-input")
                 (:file "test-repl")
                 (:file "test-anim")
                 (:file "test-body")
                 (:file "test-bvh")
                 (:file "test-scene")
                 (:file "test-pose-drivers")
                 (:file "test-gaze")
                 (:file "test-face-drivers")
                 (:file "test-scripts")
                 (:file "test-performance")
                 (:file "test-op-channels")
                 (:file "test-script-check")
                 (:file "test-simulate")
                 (:file "test-record")
                 (:file "test-render-base")
                 (:file "test-mesh")
                 (:file "test-reach")
                 (:file "test-render")
                 (:file "test-viewer")
                 (:file "test-authoring")
                 (:file "test-sub-form-lines")
                 (:file "test-speech")
                 (:file "test-speech-recognition")
                 (:file "test-readme")
                 (:file "fuzz")
                 (:file "fuzz-form-mutations")
                 (:file "fuzz-text-mutations")
                 (:file "fuzz-harness")
                 (:file "fuzz-children")
                 (:file "fuzz-minimize")
                 (:file "test-fuzz")
                 (:file "test-api-arguments")
                 (:file "test-compose")
                 (:file "test-compose-specs")
                 (:file "test-cradle-render")
                 (:file "test-scenes")
                 (:file "test-live")
                 (:file "test-live-viewer")
                 (:file "test-dialogue")
                 (:file "test-dialogue-errors")
                 (:file "test-dialogue-cli")
                 (:file "test-persona-loop"))))
  :perform (test-op (o c) (symbol-call :player-tests '#:run-tests-and-report)))
