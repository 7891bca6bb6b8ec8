;;;; package.lisp -- player.render: Pictures: meshes, OpenGL through OSMesa and GLFW, PNG, the viewer and live authoring.

(defpackage #:player.render
  (:use #:cl #:player.base #:player.spec #:player.planner #:player.ir #:player.inspect #:player.control #:player.speech #:player.body #:player.ode #:player.physics #:player.performance #:player.model #:player.rig)
  (:import-from #:alexandria
                #:when-let #:if-let #:ensure-list #:hash-table-keys
                #:with-gensyms #:once-only #:appendf #:read-file-into-string)
  (:documentation "Pictures: meshes, OpenGL through OSMesa and GLFW, PNG, the viewer and live authoring.")
  (:export
   #:*max-image-side* #:*view-control-keys* #:*view-event-keys* #:advance-viewer
   #:bind-msaa-target #:call-in-view #:compile-shader-program #:delete-msaa-target
   #:find-ffmpeg #:gl-version-string #:glfw-proc-address #:load-gl-functions
   #:make-msaa-target #:osmesa-proc-address #:png-octets #:print-due-trace
   #:read-frame-pixels #:read-size #:reload-view-scripts #:render-error
   #:render-policy-sheet #:render-simulation #:resolve-msaa-target #:scripted-keys-problem
   #:show-viewer #:start-swank #:stop-swank #:stop-view #:trace-line-time #:view
   #:+glfw-key-enter+ #:+glfw-press+ #:+glfw-release+
   #:view-event-keys #:view-running-p #:view-send-event #:view-spec #:view-title #:viewer
   #:viewer-clips #:viewer-controller #:viewer-name #:viewer-now #:viewer-paused-at
   #:viewer-performance #:viewer-scene #:viewer-session #:with-gl-traps-masked
   #:with-offscreen-context #:write-png
   #:event-key-map #:camera-taking-in #:body-rest-extent #:camera-fov #:trace-line-due-p #:request-viewer-stop #:viewer-stop-request #:clear-viewer-stop-request
   #:make-body-mesh #:body-mesh-positions #:body-mesh-normals #:body-mesh-colours #:body-mesh-indices
   #:body-mesh-joints #:body-mesh-starts #:body-mesh-ends #:object-prop-mesh #:prop-body-mesh))
