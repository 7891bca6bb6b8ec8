;;;; package.lisp -- player.ir: The steps an event's directives compile to, which both back ends (Lisp closures, C++) read.

(defpackage #:player.ir
  (:use #:cl #:player.base #:player.spec #:player.planner)
  (:import-from #:alexandria
                #:when-let #:if-let #:ensure-list #:hash-table-keys
                #:with-gensyms #:once-only #:appendf #:read-file-into-string)
  (:documentation "The steps an event's directives compile to, which both back ends (Lisp closures, C++) read.")
  (:export
   #:achieve-step #:achieve-step-failure #:achieve-step-goal #:assign-step
   #:assign-step-index #:assign-step-variable #:c++-step #:c++-step-text #:code-step
   #:code-step-form #:directive-steps #:failure #:failure-goal-form #:if-step
   #:if-step-body #:if-step-condition #:increment-step #:increment-step-delta
   #:increment-step-variable #:label-step #:label-step-name #:label-step-slot
   #:make-failure #:op-step #:op-step-failure #:op-step-goal #:op-step-op #:time-step
   #:time-step-time))
