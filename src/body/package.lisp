;;;; package.lisp -- player.body: Animation and bodies: vectors and quaternions, controls, scenes, skeletons, poses, arbitration, drivers, IK.

(defpackage #:player.body
  (:use #:cl #:player.base #:player.spec)
  (:import-from #:alexandria
                #:when-let #:if-let #:ensure-list #:hash-table-keys
                #:with-gensyms #:once-only #:appendf #:read-file-into-string)
  (:documentation "Animation and bodies: vectors and quaternions, controls, scenes, skeletons, poses, arbitration, drivers, IK.")
  (:export
   #:%clamp-pose #:*builtin-properties* #:*default-blend-time* #:*gaze-trunk-yaw-share*
   #:*property-types* #:*skeleton-roles* #:add-object #:add-slave #:aim-link-channels
   #:anim-control-error #:anim-error #:anim-fail #:apply-pose-angles #:arbitration-error
   #:arms-raised #:beak #:body #:body-add-driver #:body-base #:body-dof-name
   #:body-evaluate #:body-settle-channels #:body-settle-to #:body-settled-time #:body-target
   #:*settle-speed* #:settle-seconds #:*shortest-settle* #:*longest-settle* #:body-held #:body-joint-center #:body-joint-children #:body-joint-dof
   #:body-joint-dof-start #:body-joint-dofs #:body-joint-index #:body-joint-name
   #:body-joint-parent #:body-joint-position #:body-joint-radius #:body-pose
   #:body-pose-library #:body-reports #:body-seed #:body-skeleton #:body-stop-driver
   #:body-transforms #:bow #:bow-down #:channel-blend-weight #:channel-owner #:clamp-pose
   #:control #:control-kind #:control-p #:control-value #:copy-pose #:crest
   #:define-motor-function #:define-property #:describe-motor-function #:dof-axis-vector
   #:dof-index #:driver #:driver-additive-p #:driver-arg #:driver-begin #:driver-body
   #:driver-channels #:driver-background-p #:driver-idle-p #:driver-channel-sets
   #:driver-weight #:channel-sharers #:start-idle-life #:idle-life-drivers #:*idle-life-calls* #:emotion-mood #:body-mood #:mood-amplitude-scale #:mood-speed-scale
   #:driver-drive #:driver-end-time #:driver-report #:driver-setup
   #:driver-skeleton #:find-joint #:find-object #:find-pose #:finite-quat-p #:finite-vec3-p
   #:gaze-driver #:head-chain #:humanoid #:humanoid-root #:identity-transform
   #:joint-local-rotation #:joint-world-position #:keys-control-loop #:keys-control-p
   #:keys-control-times #:load-pose-library #:load-skeleton #:l_ankle #:l_elbow #:l_foot
   #:l_hip #:l_index1 #:l_middle1 #:l_midtarsal #:l_pinky1 #:l_primaries #:l_ring1
   #:l_shoulder #:l_thumb1 #:l_wrist #:make-arbitrator #:make-body #:make-driver
   #:make-keys-control #:make-motor-call #:make-pose #:make-quat #:make-transform
   #:make-vec3 #:mat4 #:motor-arg #:motor-call-args #:motor-call-frame
   #:motor-call-function #:motor-error #:motor-function-names #:object-kind #:object-name
   #:object-parent #:object-world-position #:object-world-transform #:on-channel-grant
   #:with-world-transforms-memoised
   #:on-channel-loss #:parrot #:parrot-root #:parse-control #:parse-motor-frame
   #:parse-value #:pose #:pose-library-name #:pose-library-names #:pose-within-limits-p
   #:pose-world-transforms #:property-type #:property-type-p #:property-value #:q* #:qnorm
   #:qnormalize #:qrotate #:qslerp #:qsquad #:quat #:quat-from-axis-angle #:quat-from-euler
   #:quat-w #:quat-x #:quat-y #:quat-z #:release-channels #:release-driver
   #:reparent-object #:request-channels #:resolve-pose #:resolve-target #:rotation
   #:sacroiliac #:scene #:scene-caption #:scene-object #:scene-objects
   #:shipped-pose-library #:skeleton #:skeleton-dof #:skeleton-error #:skeleton-fail
   #:skeleton-joints #:skeleton-name #:skeleton-source #:skeleton-rig #:parse-skeleton #:skeleton-dof-count
   #:skeleton-roles #:body-joint #:body-joint-p #:body-dof #:body-dof-min #:body-dof-max #:body-dof-axis
   #:skeleton-channels #:skeleton-joint-names #:driver-frame-fail #:driver-local-time #:driver-real #:driver-start #:transform-compose #:ramp #:driver-default-blend
   #:skeleton-morphs #:skeleton-channel-count #:morph-index #:channel-limits
   #:copy-vec3 #:quat-p #:skeleton-p #:skeleton-role #:skullbase
   #:slave-drivers #:target-form-p #:temporomandibular #:transform-invert #:transform-point
   #:transform-rotation #:transform-translation #:transform-vector #:transforms #:v* #:v+
   #:v- #:value-kind-of #:vcross #:vdistance #:vdot #:vec3 #:vec3-p #:vec3-x #:vec3-y
   #:vec3-z #:visible #:vl5 #:vlerp #:vnegate #:vnorm #:vnormalize #:wings-spread
   #:world-transforms #:write-bvh #:write-bvh-file
   ;; speed-limits.lisp, and what physics reads of a body's drivers
   #:skeleton-speed-limits #:note-shown-pose #:*speed-limits-enabled* #:body-active))
