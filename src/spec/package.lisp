;;;; package.lisp -- player.spec: The spec language: the model of a spec, its parser and checks, the registry, data files.

(defpackage #:player.spec
  (:use #:cl #:player.base)
  (:import-from #:alexandria
                #:when-let #:if-let #:ensure-list #:hash-table-keys
                #:with-gensyms #:once-only #:appendf #:read-file-into-string)
  (:documentation "The spec language: the model of a spec, its parser and checks, the registry, data files.")
  (:export
   #:*data-readtable* #:*default-max-depth* #:*defined-specs* #:*spec*
   #:*spec-definition-hooks* #:*spec-designator* #:*when-busy-policies* #:autoscript-procs
   #:autoscript-value #:autoscript-value-index #:autoscript-variable #:boolean-word #:call-with-spec-context
   #:cube-empty-p #:cube-expression #:cube-subset-p #:cubes-expression #:cut-effect-delta
   #:cut-effect-fields #:define-spec #:defspec #:defspec-form-p #:event-def
   #:event-directives #:event-entry-name #:event-entry-p #:event-name #:event-policy
   #:event-runs-code-p #:event-time-variables #:expand-spec-option #:expression-cubes
   #:expression-fields #:field-expression #:find-spec #:find-variable-named #:form-places
   #:initial-assignments #:line-of #:list-element-positions #:list-specs #:load-spec
   #:macro-sub-ops #:make-op-def #:name-key #:native-namestring #:op #:op-c++ #:op-channels
   #:op-code #:op-cut-effects #:op-def #:op-def-p #:op-director #:op-duration
   #:op-effect-bits #:op-effect-mask #:op-effects #:op-form #:op-interrupt #:op-kind
   #:op-must-ask #:op-name #:op-precond #:op-precond-form #:op-script #:op-seq
   #:op-variable-fields #:parse-expression #:plannable-p #:plannable-variables
   #:proper-list-p #:read-data-file #:refuse-code #:regular-file-p #:remove-spec #:spec
   #:spec-autoscripts #:spec-bit-count #:spec-designator-p #:spec-documentation
   #:spec-events #:spec-forms #:spec-file-fail #:spec-form-places #:spec-code-forms #:code-fail #:code-condition #:reader-limit-problem #:spec-label-count #:spec-max-depth
   #:spec-name #:spec-ops #:spec-options #:spec-p #:spec-package #:spec-source-file
   #:spec-start-state-asts #:spec-state-space #:spec-timers #:spec-triggers
   #:spec-unplanned-states #:spec-variables #:start #:state-assignments #:state-in-cube-p
   #:state-only-p #:sub-form-places #:timed-scenario-p #:timer-after #:timer-def
   #:timer-event #:timer-name #:timer-repeat #:timer-restart-on #:top-cube
   #:trigger-condition #:trigger-def #:trigger-event #:trigger-name #:value-index-in-state
   #:value-name #:var-bit-offset #:var-domain #:var-domain-size #:var-field-mask
   #:var-initial #:var-kind #:var-name #:var-slot #:var-type #:var-value-bit #:variable-def
   #:when-busy-policy #:with-spec-context #:word-p))
