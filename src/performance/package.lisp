;;;; package.lisp -- player.performance: Scripts played on a body: script libraries, directors, the performance, the body presenter, simulation.

(defpackage #:player.performance
  (:use #:cl #:player.base #:player.spec #:player.planner #:player.ir #:player.control #:player.speech #:player.body #:player.ode #:player.physics #:player.model #:player.rig)
  (:import-from #:alexandria
                #:when-let #:if-let #:ensure-list #:hash-table-keys
                #:with-gensyms #:once-only #:appendf #:read-file-into-string)
  (:documentation "Scripts played on a body: script libraries, directors, the performance, the body presenter, simulation.")
  (:export
   #:%make-simulation #:*audio-file-name* #:*max-fps* #:body-presenter
   #:check-body-presenter-arguments #:check-fps #:checked-script-library
   #:controller-simulation #:diagnostic-error-p #:director-schedule #:find-director
   #:find-script #:frame-form #:load-script-library #:make-body-presenter
   #:make-performance #:map-simulation-frames #:perform-director #:perform-script
   #:performance #:performance-audio #:performance-body #:performance-clips
   #:performance-frame #:performance-library #:performance-p #:performance-play-sound
   #:performance-say #:performance-scene #:performance-sent-events #:performance-signal #:performance-play-music #:performance-stop-music #:performance-set-tempo #:performance-tempo #:presenter-library #:presenter-performance #:library-carried-objects
   #:performance-set-mood
   #:reload-script-library #:replay-clips #:script #:script-critical-time
   #:reload-character-skeleton #:script-library-poses
   #:script-diagnostics #:script-duration #:script-error #:script-library-source #:simulate
   #:simulation #:simulation-clips #:simulation-controller #:simulation-end #:simulation-fps
   #:simulation-frame-count #:simulation-p #:simulation-performance #:simulation-reports
   #:simulation-frame-times #:simulation-critical-times #:performance-critical-times
   #:performance-critical-time-between
   #:simulation-scene-at #:stop-script-run #:write-simulation #:write-simulation-audio))
