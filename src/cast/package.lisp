;;;; package.lisp -- player.cast: Several characters in one scene: DEFSCENE, event addresses, ensembles, scenes simulated and drawn.

(defpackage #:player.cast
  (:use #:cl #:player.base #:player.spec #:player.planner #:player.ir #:player.inspect #:player.control #:player.speech #:player.body #:player.ode #:player.physics #:player.performance #:player.render #:player.model #:player.rig)
  (:import-from #:alexandria
                #:when-let #:if-let #:ensure-list #:hash-table-keys
                #:with-gensyms #:once-only #:appendf #:read-file-into-string)
  (:documentation "Several characters in one scene: DEFSCENE, event addresses, ensembles, scenes simulated and drawn.")
  (:export
   #:cast #:cast-documentation #:cast-events #:cast-member #:cast-member-initial
   #:cast-member-name #:cast-member-position #:cast-member-spec #:cast-members #:cast-name
   #:cast-p #:define-cast #:defscene #:defscene-form-p #:duplicate-member-error #:ensemble
   #:ensemble-cast #:ensemble-controller #:ensemble-p #:ensemble-trace-lines #:find-cast
   #:list-casts #:load-scene-file #:make-ensemble #:missing-member-spec-error
   #:play-scene-events #:remove-cast #:replicate-cast #:scene-error #:scene-event-keys
   #:scene-simulation #:scene-simulation-ensemble #:scene-simulation-member
   #:scene-simulation-p #:scene-timed-members #:send-scene-event #:simulate-scene
   #:unknown-member-error #:view-scene #:write-ensemble-states #:write-ensemble-trace
   #:write-scene-simulation))
