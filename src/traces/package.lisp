;;;; package.lisp -- player.traces: Recorded traces as regression tests: record a scenario, verify a replay.

(defpackage #:player.traces
  (:use #:cl #:player.base #:player.spec #:player.planner #:player.ir #:player.control #:player.speech #:player.body #:player.ode #:player.physics #:player.performance #:player.model #:player.rig)
  (:import-from #:alexandria
                #:when-let #:if-let #:ensure-list #:hash-table-keys
                #:with-gensyms #:once-only #:appendf #:read-file-into-string)
  (:documentation "Recorded traces as regression tests: record a scenario, verify a replay.")
  (:export
   #:*default-frame-tolerance* #:read-recording #:record-scenario #:recording
   #:recording-difference-kind #:recording-difference-message #:recording-error
   #:recording-frames #:recording-lines #:recording-mismatch #:recording-p #:verification
   #:verification-difference #:verification-message #:verification-ok-p #:verify-recording
   #:write-recording))
