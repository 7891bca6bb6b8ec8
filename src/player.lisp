;;;; player.lisp -- the facade: PLAYER, the one package users, spec files and the
;;;; docs see, and PLAYER-USER, where spec files are read.  Each name is defined
;;;; in its layer's package (src/*/package.lisp; the map is
;;;; doc/internals/architecture.md) and only re-exported here.

(defpackage #:player
  (:use #:cl)
  (:import-from #:player.base
   #:argument-error #:argument-error-argument #:argument-error-expected
   #:argument-error-function #:argument-error-value #:class-cycle-error #:domain-error
   #:duplicate-definition #:effect-error #:goal-error #:label-error #:player-error
   #:reachable-space-too-large #:spec-error #:spec-error-form #:spec-error-position
   #:spec-error-spec #:spec-reader-error #:spec-syntax-error #:state-outside-planned-set
   #:state-space-too-large #:state-transfer-error #:type-error-in-spec #:unknown-event
   #:unknown-event-name #:unknown-name-error #:untrusted-code-error #:code-error
   #:io-error #:io-error-file #:io-error-reason)
  (:import-from #:player.spec
   #:*default-max-depth* #:*when-busy-policies* #:define-spec #:defspec #:find-spec
   #:list-specs #:load-spec #:op-director #:op-duration #:op-kind #:op-name #:op-script
   #:remove-spec #:spec #:spec-documentation #:spec-max-depth #:spec-name #:spec-options
   #:spec-source-file)
  (:import-from #:player.planner
   #:*plan-rows-built* #:check-spec #:diagnostic #:diagnostic-details #:diagnostic-kind
   #:diagnostic-message #:machine #:machine-goals #:machine-rows-built #:machine-spec
   #:machine-state-count #:plan-spec #:plans
   #:*planning-budget* #:planning-budget-exceeded #:machine-planning-work)
  (:import-from #:player.inspect
   #:*dot-program* #:build-state-graph #:explain-plan #:explained-goal
   #:explained-goal-holds #:explained-goal-p #:explained-op #:explained-op-literals
   #:explained-op-name #:explained-op-p #:explained-op-reason #:explained-op-target
   #:explained-unreachable #:explained-unreachable-p #:explanation-step #:graphviz-error
   #:print-explanation #:state-graph-error #:write-state-graph #:write-state-graph-file)
  (:import-from #:player.compose
   #:cradle-ode-script-forms
   #:binding #:complete-graph #:cradle-node #:cradle-spheres #:cradle-stage #:cradle-stages
   #:define-graph #:edge-predicate #:find-graph #:graph #:graph->spec #:graph->spec-forms
   #:graph-edge-count #:graph-edges #:graph-empty-p #:graph-equal #:graph-error
   #:graph-error-value #:graph-expression #:graph-expression-error #:graph-has-edge-p
   #:graph-has-node-p #:graph-intersection #:graph-map #:graph-merge #:graph-node-count
   #:graph-nodes #:graph-p #:graph-product #:graph-reachable #:graph-successors #:graph-sum
   #:graph-traces #:make-graph #:map-graph-traces #:match-pattern #:newton-cradle #:node<
   #:pattern #:pred-and #:pred-edge #:pred-implies #:pred-nodes #:random-trace
   #:register-graph #:restrict #:seq-all #:seq-count #:seq-exists #:seq-restrict #:seq-rev
   #:seq-suffixes #:spec->graph #:sphere-state-p #:subgraph-p #:tree-flatten #:tree-left
   #:tree-merge #:tree-p #:tree-product #:tree-right
   #:*lazy-node-limit* #:graph-with-durations #:graph-timed-p #:graph-edge-duration #:cradle-refinement #:timed-cradle #:lazy-product #:lazy-sum #:friction-cradle #:friction-amplitude #:guarded-graph #:guarded-cradle #:cradle-well-behaved-p #:cradle-free-swing #:cradle-start #:cradle-run #:cradle-figure #:lazy-cradle #:lazy-graph #:lazy-graph-p #:make-lazy-graph #:lazy-successors #:lazy-restrict #:lazy-reachable #:cradle-paper #:physical-successor)
  (:import-from #:player.logic
   #:*verify-state-limit* #:behaviour #:behaviour-p #:behaviour-state-count #:behaviour-state-name
   #:behaviour-dead-ends #:behaviour-initial-states #:counterexample #:counterexample-p
   #:counterexample-states #:counterexample-loop #:counterexample-names #:formula-error
   #:make-behaviour #:spec-behaviour #:graph-behaviour #:verify #:formula-holds-states
   #:write-counterexample-dot #:print-counterexample
   #:diff-graphs #:graph-diff #:graph-diff-p #:graph-diff-dead-ends #:graph-diff-removed
   #:graph-diff-added #:graph-diff-removed-states #:graph-diff-added-states #:graph-diff-consistent-p #:graph-spec-p #:graph-spec-diagnostics)
  (:import-from #:player.control
   #:deferred-sends-error #:presenter-result-error #:presenter-result-error-function
   #:presenter-result-error-op #:presenter-result-error-presenter
   #:presenter-result-error-value
   #:*controller* #:advance #:clear-trace #:compile-spec #:finish-trace #:compiled-machine #:controller
   #:controller-busy-p #:controller-clock #:controller-machine #:controller-presenter
   #:controller-state #:controller-time #:controller-microseconds #:event-names #:finish-events #:follow-spec
   #:make-controller #:make-null-presenter #:make-trace-presenter #:null-presenter
   #:play-events #:play-script #:present-event #:present-failure #:present-macro-end
   #:present-macro-start #:present-op #:present-state #:presenter #:recompile
   #:redefine-controller #:redefinition-warning #:redefinition-warning-error #:run-director
   #:send-event #:start-autoscript #:state-value #:stop-autoscript #:timeline-error
   #:trace-line-string #:trace-lines #:trace-presenter #:unfollow-spec #:write-trace-line)
  (:import-from #:player.cpp
   #:*c++-compiler* #:*c++-flags* #:emit-c++ #:run-c++-trace)
  (:import-from #:player.speech
   #:*default-speech-rate* #:*default-voice* #:make-clip #:make-sound #:mix-clips
   #:phoneme-viseme #:read-wav #:recognize-sound #:recognize-wav #:sound #:sound-duration
   #:*rejection-margin* #:*longest-phone* #:*most-unexplained-speech* #:*longest-request* #:read-request-wav
   #:*capture-device* #:open-capture #:close-capture #:listen-for-requests
   #:sound-rate #:sound-samples #:speech-error #:speech-unavailable #:synthesize-speech
   #:utterance #:utterance-duration #:utterance-phonemes #:utterance-sound #:utterance-text
   #:utterance-visemes #:utterance-word-time #:utterance-words #:write-wav #:track-tune)
  (:import-from #:player.model
   #:guess-roles #:roles-enabling-drivers #:role-error #:role-error-role #:role-error-joint
   #:import-model #:model-error #:model-error-file #:model-library-missing
   #:read-image #:image #:image-p #:image-width #:image-height #:image-channels #:image-pixels
   #:image-error #:image-error-file #:image-error-reason #:image-library-missing
   #:*image-pixel-limit* #:model-texture-images #:mesh-texture-image #:model-embedded-textures
   #:*model-post-processing* #:*model-vertex-limit* #:*model-triangle-limit*
   #:*model-joint-limit* #:*model-key-limit* #:*model-node-limit*
   #:model #:model-file #:model-meshes #:model-joints #:model-animations
   #:model-vertex-count #:model-triangle-count #:model-bone-count #:model-textures
   #:model-morph-targets #:find-model-joint
   #:model-mesh #:model-mesh-name #:model-mesh-positions #:model-mesh-normals #:model-mesh-uvs #:model-mesh-colours
   #:model-mesh-triangles #:model-mesh-joints #:model-mesh-weights #:model-mesh-bones #:model-mesh-texture
   #:model-mesh-morph-targets #:model-mesh-holder #:model-mesh-transform #:model-mesh-vertex-count #:model-mesh-triangle-count
   #:model-joint #:joint-name #:joint-parent #:joint-translation #:joint-rotation #:joint-scale
   #:joint-inverse-bind #:model-animation #:model-animation-name #:model-animation-duration #:model-animation-channels
   #:model-channel #:channel-joint #:channel-position-times #:channel-positions
   #:channel-rotation-times #:channel-rotations #:channel-scale-times #:channel-scales
   #:make-model #:make-model-mesh #:make-joint #:make-model-animation #:make-channel
   #:write-gltf #:model-write-error
   #:make-morph-target #:morph-target #:morph-target-name #:morph-target-deltas #:model-mesh-morphs
   #:model-animation-morph-channels #:morph-channel #:morph-channel-node #:morph-channel-meshes
   #:morph-channel-times #:morph-channel-weights #:morph-channel-target-count #:make-morph-channel)
  (:import-from #:player.rig
   #:model-skeleton #:make-prop-model #:prop-model #:model-prop #:model-prop-model #:retarget-clip #:rig #:rig-error #:rig-model #:rig-clips #:rig-bounds #:rig-skins #:rig-placement #:find-clip #:rig-clip-names
   #:motion-clip #:clip-name #:clip-duration #:clip-angles #:quat-to-xyz-degrees
   #:mesh-skin #:skin-vertices #:skin-palette-matrices)
  (:import-from #:player.body
   #:*default-blend-time* #:add-object #:add-slave #:anim-control-error #:anim-error
   #:arbitration-error #:body #:body-add-driver #:body-evaluate #:body-joint-position
   #:body-pose #:body-skeleton #:body-stop-driver #:body-transforms #:channel-blend-weight
   #:channel-owner #:clamp-pose #:control-value #:define-motor-function #:define-property
   #:describe-motor-function #:dof-index #:driver #:driver-additive-p #:driver-arg
   #:driver-background-p #:driver-idle-p #:driver-channel-sets #:driver-weight #:channel-sharers #:start-idle-life #:idle-life-drivers #:*idle-life-calls*
   #:emotion-mood #:body-mood
   #:driver-begin #:driver-drive #:driver-end-time #:driver-report #:driver-setup
   #:find-joint #:find-object #:joint-world-position #:load-skeleton #:make-arbitrator
   #:make-body #:make-driver #:make-keys-control #:make-pose #:motor-error
   #:motor-function-names #:object-kind #:object-name #:object-parent
   #:object-world-position #:object-world-transform #:on-channel-grant #:on-channel-loss
   #:parse-control #:parse-motor-frame #:pose #:pose-within-limits-p #:pose-world-transforms
   #:property-value #:qslerp #:qsquad #:quat #:release-channels #:release-driver
   #:reparent-object #:request-channels #:resolve-target #:scene #:scene-object
   #:scene-objects #:skeleton-error #:skeleton-joints #:skeleton-role #:slave-drivers #:vec3
   #:world-transforms #:write-bvh #:write-bvh-file)
  (:import-from #:player.ode
   #:ode-error #:ode-unavailable #:ode-available-p)
  (:import-from #:player.physics
   #:*physics-step* #:prop-shape #:prop-dynamic-p #:scene-physics #:advance-scene-physics
   #:physics-prop-resting-p #:*collisions* #:*stop-at-contact* #:scene-collisions)
  (:import-from #:player.body #:*speed-limits-enabled* #:skeleton-speed-limits)
  (:import-from #:player.performance
   #:body-presenter #:controller-simulation #:director-schedule #:find-director
   #:find-script #:load-script-library #:make-body-presenter #:make-performance
   #:map-simulation-frames #:perform-director #:perform-script #:performance-audio
   #:performance-body #:performance-clips #:performance-frame #:performance-play-sound
   #:performance-sent-events #:performance-signal #:performance-play-music #:performance-stop-music #:performance-set-tempo #:performance-tempo #:performance-say #:performance-scene #:presenter-performance #:reload-script-library
   #:performance-set-mood
   #:reload-character-skeleton
   #:script-critical-time #:script-duration #:script-error #:simulate
   #:simulation-frame-count #:simulation-scene-at #:stop-script-run #:write-simulation
   #:simulation-frame-times #:simulation-critical-times)
  (:import-from #:player.render
   #:bind-msaa-target #:call-in-view #:compile-shader-program #:delete-msaa-target
   #:gl-version-string #:glfw-proc-address #:load-gl-functions #:make-msaa-target
   #:osmesa-proc-address #:png-octets #:read-frame-pixels #:reload-view-scripts
   #:render-error #:render-simulation #:resolve-msaa-target #:start-swank #:stop-swank
   #:stop-view #:view #:view-running-p #:view-spec #:viewer-session #:with-gl-traps-masked
   #:with-offscreen-context #:write-png)
  (:import-from #:player.cast
   #:cast #:cast-documentation #:cast-events #:cast-member #:cast-member-initial
   #:cast-member-name #:cast-member-position #:cast-member-spec #:cast-members #:cast-name
   #:cast-p #:define-cast #:defscene #:duplicate-member-error #:ensemble #:ensemble-cast
   #:ensemble-controller #:ensemble-p #:ensemble-trace-lines #:find-cast #:list-casts
   #:load-scene-file #:make-ensemble #:missing-member-spec-error #:play-scene-events
   #:remove-cast #:replicate-cast #:scene-error #:scene-simulation #:scene-simulation-member
   #:scene-simulation-p #:send-scene-event #:simulate-scene #:unknown-member-error
   #:write-ensemble-trace #:write-scene-simulation)
  (:import-from #:player.export
   #:export-performance #:performance-model #:character-model #:bake-simulation)
  (:import-from #:player.dialogue
   #:*say-function* #:begin-conversation #:call-with-speaker #:choose-template
   #:context-value #:conversation #:conversation-controller #:conversation-dialogue
   #:conversation-hear #:conversation-input #:conversation-memory
   #:conversation-player-events #:conversation-state #:defdialogue #:define-dialogue
   #:define-dialogue-action #:dialogue #:dialogue-error #:dialogue-initial-state
   #:dialogue-jsgf #:dialogue-name #:dialogue-not-understood #:dialogue-p
   #:dialogue-player-initial #:dialogue-player-spec #:dialogue-presenter
   #:dialogue-state-names #:episodic-memory #:expand-template #:find-dialogue #:gesture-marks #:*music-function* #:speaker-play-music #:track-sound
   #:load-dialogue #:load-memory #:make-conversation #:make-memory #:make-speaker
   #:make-text-presenter #:match-utterance #:explain-utterance #:memory-conversations #:memory-log #:memory-mood
   #:memory-user #:present-input #:present-transition #:present-utterance #:save-memory
   #:speaker #:speaker-end #:speaker-lines #:speaker-listen #:speaker-say
   #:speaker-say-function #:speaker-wait #:text-presenter #:text-words #:turn-event
   #:turn-events #:turn-from #:turn-slots #:turn-text #:turn-to #:turn-understood
   #:turn-utterances #:with-speaker)
  (:import-from #:player.traces
   #:*default-frame-tolerance* #:read-recording #:record-scenario #:recording
   #:recording-difference-kind #:recording-difference-message #:recording-error
   #:recording-frames #:recording-lines #:recording-mismatch #:recording-p #:verification
   #:verification-difference #:verification-message #:verification-ok-p #:verify-recording
   #:write-recording)
  (:import-from #:player.cli
   #:main #:usage-error)
  (:export
   ;; Files (a failed read or write names the file and the reason)
   #:io-error #:io-error-file #:io-error-reason
   ;; The language
   #:defspec #:define-spec #:find-spec #:load-spec #:list-specs #:remove-spec
   #:spec #:spec-name #:spec-documentation #:spec-max-depth #:spec-options
   #:spec-source-file
   ;; Compilation
   #:compile-spec #:plan-spec #:compiled-machine #:machine #:machine-spec #:machine-goals #:plans
   #:machine-state-count #:check-spec #:diagnostic #:diagnostic-kind
   #:diagnostic-message #:diagnostic-details
   #:*default-max-depth*
   #:explain-plan #:print-explanation #:explanation-step #:explained-op #:explained-op-p #:explained-op-name #:explained-op-reason #:explained-op-target #:explained-op-literals #:explained-goal #:explained-goal-p #:explained-goal-holds #:explained-unreachable #:explained-unreachable-p
   #:write-state-graph #:write-state-graph-file #:build-state-graph #:state-graph-error #:graphviz-error #:*dot-program*
   ;; C++ backend
   #:emit-c++ #:run-c++-trace #:*c++-flags* #:*c++-compiler*
   ;; Animation engine and body model
   #:vec3 #:quat #:qslerp #:qsquad #:world-transforms
   #:control-value #:parse-control #:make-keys-control #:anim-error #:anim-control-error
   #:load-skeleton #:skeleton-error #:find-joint #:skeleton-joints #:skeleton-role
   #:make-arbitrator #:request-channels #:release-channels #:release-driver #:channel-owner
   #:channel-blend-weight #:on-channel-loss #:on-channel-grant #:add-slave #:arbitration-error
   ;; Scenes
   #:scene #:scene-object #:add-object #:find-object #:scene-objects #:object-name #:object-kind
   #:object-parent #:reparent-object #:define-property #:property-value
   #:object-world-transform #:object-world-position
   ;; Poses and bodies
   #:pose #:make-pose #:dof-index #:clamp-pose #:pose-within-limits-p #:pose-world-transforms
   #:joint-world-position #:body #:make-body #:body-skeleton #:body-pose #:body-evaluate
   #:body-add-driver #:body-stop-driver #:body-joint-position #:body-transforms
   #:*default-blend-time*
   ;; Motor functions and drivers
   #:define-motor-function #:parse-motor-frame #:motor-error #:describe-motor-function
   #:motor-function-names #:make-driver #:driver #:driver-setup #:driver-begin #:driver-drive
   #:driver-end-time #:driver-additive-p #:slave-drivers #:driver-report #:driver-arg
   #:driver-background-p #:driver-idle-p #:driver-channel-sets #:driver-weight #:channel-sharers #:start-idle-life #:idle-life-drivers #:*idle-life-calls*
   #:emotion-mood #:body-mood
   #:resolve-target
   ;; Scripts, directors, performances
   #:load-script-library #:script-error #:find-script #:find-director #:script-duration
   #:script-critical-time #:director-schedule
   #:make-performance #:perform-script #:perform-director #:stop-script-run
   #:performance-signal #:performance-sent-events
   #:performance-play-music #:performance-stop-music #:performance-set-tempo #:performance-tempo #:track-tune
   #:performance-frame #:performance-body #:performance-scene
   #:body-presenter #:make-body-presenter #:play-script #:presenter-performance
   #:simulate #:controller-simulation #:write-simulation #:map-simulation-frames #:simulation-frame-count
   #:simulation-frame-times #:simulation-critical-times
   #:write-bvh #:write-bvh-file
   ;; Speech: synthesis, sounds, the audio track, recognition
   #:synthesize-speech #:utterance #:utterance-text #:utterance-sound #:utterance-phonemes
   #:utterance-duration #:utterance-visemes #:phoneme-viseme #:*default-voice* #:*default-speech-rate*
   #:utterance-words #:utterance-word-time
   #:sound #:make-sound #:sound-samples #:sound-rate #:sound-duration #:read-wav #:write-wav
   #:performance-say #:performance-set-mood #:performance-play-sound #:performance-clips #:performance-audio #:mix-clips #:make-clip
   #:recognize-wav #:recognize-sound #:speech-error #:speech-unavailable
   #:*rejection-margin* #:*longest-phone* #:*most-unexplained-speech* #:*longest-request* #:read-request-wav
   #:*capture-device* #:open-capture #:close-capture #:listen-for-requests
   ;; Models imported through Assimp (doc/models.md)
   #:guess-roles #:roles-enabling-drivers #:role-error #:role-error-role #:role-error-joint
   #:import-model #:model-error #:model-error-file #:model-library-missing
   #:read-image #:image #:image-p #:image-width #:image-height #:image-channels #:image-pixels
   #:image-error #:image-error-file #:image-error-reason #:image-library-missing
   #:*image-pixel-limit* #:model-texture-images #:mesh-texture-image #:model-embedded-textures
   #:*model-post-processing* #:*model-vertex-limit* #:*model-triangle-limit*
   #:*model-joint-limit* #:*model-key-limit* #:*model-node-limit*
   #:model #:model-file #:model-meshes #:model-joints #:model-animations
   #:model-vertex-count #:model-triangle-count #:model-bone-count #:model-textures
   #:model-morph-targets #:find-model-joint
   #:model-mesh #:model-mesh-name #:model-mesh-positions #:model-mesh-normals #:model-mesh-uvs #:model-mesh-colours
   #:model-mesh-triangles #:model-mesh-joints #:model-mesh-weights #:model-mesh-bones #:model-mesh-texture
   #:model-mesh-morph-targets #:model-mesh-holder #:model-mesh-transform #:model-mesh-vertex-count #:model-mesh-triangle-count
   #:model-joint #:joint-name #:joint-parent #:joint-translation #:joint-rotation #:joint-scale
   #:joint-inverse-bind #:model-animation #:model-animation-name #:model-animation-duration #:model-animation-channels
   #:model-channel #:channel-joint #:channel-position-times #:channel-positions
   #:channel-rotation-times #:channel-rotations #:channel-scale-times #:channel-scales
   #:make-model #:make-model-mesh #:make-joint #:make-model-animation #:make-channel
   #:write-gltf #:model-write-error
   #:make-morph-target #:morph-target #:morph-target-name #:morph-target-deltas #:model-mesh-morphs
   #:model-animation-morph-channels #:morph-channel #:morph-channel-node #:morph-channel-meshes
   #:morph-channel-times #:morph-channel-weights #:morph-channel-target-count #:make-morph-channel
   ;; Characters from models (doc/models.md)
   #:model-skeleton #:make-prop-model #:prop-model #:model-prop #:model-prop-model #:retarget-clip #:rig #:rig-error #:rig-model #:rig-clips #:rig-bounds #:rig-skins #:rig-placement #:find-clip #:rig-clip-names
   #:motion-clip #:clip-name #:clip-duration #:clip-angles #:quat-to-xyz-degrees
   #:mesh-skin #:skin-vertices #:skin-palette-matrices
   ;; Rendering
   #:render-simulation #:view-spec #:render-error #:with-offscreen-context #:read-frame-pixels #:gl-version-string
   #:compile-shader-program #:write-png #:png-octets
   #:make-msaa-target #:bind-msaa-target #:resolve-msaa-target #:delete-msaa-target
   #:load-gl-functions #:with-gl-traps-masked #:osmesa-proc-address #:glfw-proc-address
   ;; Controllers
   #:make-controller #:controller #:send-event #:state-value #:controller-state
   #:controller-clock #:controller-machine #:controller-presenter #:recompile
   #:redefine-controller #:follow-spec #:unfollow-spec #:redefinition-warning
   #:redefinition-warning-error #:*plan-rows-built* #:machine-rows-built
   #:view #:stop-view #:call-in-view #:viewer-session #:view-running-p #:reload-script-library #:reload-view-scripts
   #:reload-character-skeleton
   #:start-swank #:stop-swank
   #:advance #:finish-events #:play-events #:controller-busy-p #:controller-time #:controller-microseconds #:timeline-error
   #:presenter-result-error #:presenter-result-error-presenter #:presenter-result-error-function
   #:presenter-result-error-op #:presenter-result-error-value #:deferred-sends-error
   #:*when-busy-policies*
   #:event-names #:*controller*
   ;; Presenter protocol
   #:presenter #:present-op #:start-autoscript #:stop-autoscript #:run-director
   #:present-macro-start #:present-macro-end #:present-event
   #:present-failure #:present-state
   #:null-presenter #:make-null-presenter
   #:trace-presenter #:make-trace-presenter #:trace-lines #:clear-trace
   #:write-trace-line #:trace-line-string
   ;; Op objects, as presenters see them
   #:op-name #:op-script #:op-director #:op-duration #:op-kind
   ;; Conditions
   #:player-error #:spec-error #:spec-error-form #:spec-error-spec
   #:spec-error-position #:spec-syntax-error #:unknown-name-error
   #:domain-error #:type-error-in-spec #:duplicate-definition
   #:class-cycle-error #:label-error #:effect-error #:goal-error
   #:spec-reader-error #:untrusted-code-error #:code-error #:unknown-event #:unknown-event-name
   #:state-space-too-large #:state-transfer-error
   #:reachable-space-too-large #:state-outside-planned-set
   #:planning-budget-exceeded #:*planning-budget* #:machine-planning-work
   ;; Command line
   #:main #:usage-error
   ;; Argument checking of the Lisp API (issue 11): every exported function
   ;; signals ARGUMENT-ERROR for a bad argument
   #:argument-error #:argument-error-function #:argument-error-argument
   #:argument-error-value #:argument-error-expected
   ;; Composing behaviours (src/compose/)
   #:graph #:graph-p #:make-graph #:complete-graph #:graph-nodes #:graph-edges
   #:graph-node-count #:graph-edge-count #:graph-empty-p #:graph-has-node-p #:graph-has-edge-p
   #:graph-successors #:graph-equal #:subgraph-p #:node< #:graph-error #:graph-error-value
   #:graph-sum #:graph-intersection #:graph-reachable
   #:pattern #:match-pattern #:binding #:edge-predicate #:pred-implies #:pred-edge #:pred-nodes
   #:pred-and #:restrict
   #:graph-product #:graph-map
   #:tree-p #:tree-left #:tree-right #:tree-merge #:tree-product #:tree-flatten
   #:seq-rev #:seq-restrict #:seq-count #:seq-suffixes #:seq-all #:seq-exists
   #:graph-merge #:graph-traces #:map-graph-traces #:random-trace
   #:newton-cradle #:cradle-stages #:cradle-stage #:cradle-node #:cradle-spheres #:sphere-state-p
   #:graph->spec #:graph->spec-forms #:spec->graph
   #:register-graph #:define-graph #:find-graph #:graph-expression #:graph-expression-error
   #:*lazy-node-limit* #:graph-with-durations #:graph-timed-p #:graph-edge-duration #:cradle-refinement #:timed-cradle #:lazy-product #:lazy-sum #:friction-cradle #:friction-amplitude #:guarded-graph #:guarded-cradle #:cradle-well-behaved-p #:cradle-free-swing #:cradle-start #:cradle-run #:cradle-figure #:lazy-cradle #:lazy-graph #:lazy-graph-p #:make-lazy-graph #:lazy-successors #:lazy-restrict #:lazy-reachable #:cradle-paper #:physical-successor
   ;; A logic for behaviours (src/logic/)
   #:*verify-state-limit* #:behaviour #:behaviour-p #:behaviour-state-count #:behaviour-state-name
   #:behaviour-dead-ends #:behaviour-initial-states #:counterexample #:counterexample-p
   #:counterexample-states #:counterexample-loop #:counterexample-names #:formula-error
   #:make-behaviour #:spec-behaviour #:graph-behaviour #:verify #:formula-holds-states
   #:write-counterexample-dot #:print-counterexample
   #:diff-graphs #:graph-diff #:graph-diff-p #:graph-diff-dead-ends #:graph-diff-removed
   #:graph-diff-added #:graph-diff-removed-states #:graph-diff-added-states #:graph-diff-consistent-p #:graph-spec-p #:graph-spec-diagnostics
   ;; Several characters in one scene (src/cast/)
   #:defscene #:define-cast #:find-cast #:list-casts #:remove-cast #:load-scene-file #:replicate-cast
   #:cast #:cast-p #:cast-name #:cast-documentation #:cast-members #:cast-events
   #:cast-member #:cast-member-name #:cast-member-spec #:cast-member-position #:cast-member-initial
   #:scene-error #:missing-member-spec-error #:duplicate-member-error #:unknown-member-error
   #:make-ensemble #:ensemble #:ensemble-p #:ensemble-cast #:ensemble-controller
   #:send-scene-event #:play-scene-events #:ensemble-trace-lines #:write-ensemble-trace
   ;; Export
   #:export-performance #:performance-model #:character-model #:bake-simulation
   #:simulate-scene #:scene-simulation #:scene-simulation-p #:scene-simulation-member
   #:write-scene-simulation #:simulation-scene-at
   #:record-scenario #:write-recording #:read-recording #:verify-recording #:recording #:recording-p #:recording-lines #:recording-frames #:recording-error #:recording-mismatch #:verification #:verification-ok-p #:verification-difference #:verification-message #:recording-difference-kind #:recording-difference-message #:*default-frame-tolerance*
   ;; The dialogue manager (src/dialogue/)
   #:defdialogue #:define-dialogue #:load-dialogue #:find-dialogue #:dialogue #:dialogue-p #:dialogue-name
   #:dialogue-state-names #:dialogue-initial-state #:dialogue-not-understood #:dialogue-player-spec #:dialogue-player-initial
   #:dialogue-error #:dialogue-jsgf #:match-utterance #:explain-utterance #:text-words
   #:make-conversation #:conversation #:conversation-state #:conversation-hear #:conversation-input
   #:conversation-memory #:conversation-player-events #:conversation-controller #:conversation-dialogue
   #:context-value
   #:turn-text #:turn-understood #:turn-event #:turn-slots #:turn-from #:turn-to #:turn-events #:turn-utterances
   #:dialogue-presenter #:present-input #:present-transition #:present-utterance #:*say-function*
   #:text-presenter #:make-text-presenter
   #:speaker #:make-speaker #:speaker-say #:speaker-listen #:speaker-wait #:speaker-end #:speaker-lines
   #:speaker-say-function #:with-speaker #:call-with-speaker
   #:define-dialogue-action #:choose-template #:expand-template #:gesture-marks
   #:*music-function* #:speaker-play-music #:track-sound
   #:episodic-memory #:make-memory #:load-memory #:save-memory #:begin-conversation
   #:memory-user #:memory-mood #:memory-conversations #:memory-log
   ;; Physics through ODE (src/ode/, src/physics/)
   #:ode-error #:ode-unavailable #:ode-available-p
   #:*physics-step* #:prop-shape #:prop-dynamic-p #:scene-physics #:advance-scene-physics
   #:physics-prop-resting-p #:cradle-ode-script-forms #:*collisions* #:*stop-at-contact* #:scene-collisions
   #:*speed-limits-enabled* #:skeleton-speed-limits))

(defpackage #:player-user
  (:use #:cl #:player)
  (:documentation "The package spec files are read in: CL plus the PLAYER API."))
