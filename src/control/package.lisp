;;;; package.lisp -- player.control: Running a machine: the controller, the presenter and recorder protocol, the Lisp closures, the timed controller.

(defpackage #:player.control
  (:use #:cl #:player.base #:player.spec #:player.planner #:player.ir)
  (:import-from #:alexandria
                #:when-let #:if-let #:ensure-list #:hash-table-keys
                #:with-gensyms #:once-only #:appendf #:read-file-into-string)
  (:documentation "Running a machine: the controller, the presenter and recorder protocol, the Lisp closures, the timed controller.")
  (:export
   #:*controller* #:*initial-state-phrase* #:advance #:clear-trace #:code-diagnostics #:compile-spec #:finish-trace
   #:compiled-machine #:controller #:controller-bits #:controller-busy-p #:controller-clock
   #:controller-machine #:controller-p #:controller-presenter #:controller-state
   #:controller-time #:controller-microseconds #:controller-timeline #:critical-time #:deferred-sends-error
   #:event-names #:event-target
   #:find-compiled-event #:finish-events #:follow-spec #:initial-state-p #:make-controller
   #:make-null-presenter #:make-trace-presenter #:null-presenter #:op-channel-set
   #:planned-op-duration #:play-events #:play-script #:present-cut #:present-event
   #:present-failure #:present-initial-state #:present-state-change #:present-macro-end #:present-macro-start
   #:present-op #:present-state #:presenter #:presenter-result-error
   #:presenter-result-error-function #:presenter-result-error-op
   #:presenter-result-error-presenter #:presenter-result-error-value #:recompile #:redefine-controller
   #:redefinition-warning #:redefinition-warning-error #:run-director #:send-event
   #:spec-of #:start-autoscript #:state-value #:stop-autoscript #:target-send-event
   #:timeline-error #:trace-dropped #:trace-line-p #:trace-line-string #:trace-line-vector
   #:trace-lines #:trace-presenter #:trace-presenter-p #:unfollow-spec #:watch
   #:write-trace-line
   #:trace-open-macros))
