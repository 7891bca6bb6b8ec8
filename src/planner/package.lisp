;;;; package.lisp -- player.planner: Goal regression: plans from every state (or every reachable one) to every goal, the machine.

(defpackage #:player.planner
  (:use #:cl #:player.base #:player.spec)
  (:import-from #:alexandria
                #:when-let #:if-let #:ensure-list #:hash-table-keys
                #:with-gensyms #:once-only #:appendf #:read-file-into-string)
  (:documentation "Goal regression: plans from every state (or every reachable one) to every goal, the machine.")
  (:export
   #:*machine-designator* #:*plan-rows-built* #:apply-effects #:check-spec
   #:cost-queue-empty-p #:costed-plan-cost #:costed-plan-length #:costed-plan-plan
   #:cut-ops #:dense-to-state #:dequeue #:dequeue-cheapest #:designated-spec #:diagnostic
   #:diagnostic-details #:diagnostic-kind #:diagnostic-message #:diagnostic-p #:enqueue
   #:enqueue-by-cost #:ensure-machine #:event-assignment-ops #:goal #:goal-cubes
   #:goal-expression #:goal-forms #:goal-holds-p #:goal-id #:goal-p #:goal-plan-table
   #:goal-plans #:goal-solved-count #:initial-state #:layout #:layout-reachable
   #:layout-state-count #:machine #:machine-autoscript-mask #:machine-compile-seconds
   #:machine-designator-p #:machine-goal-for #:machine-goal-table #:machine-goal-with-cubes
   #:machine-goals #:machine-initial-state #:machine-layout #:machine-operators #:machine-p #:machine-planning-work #:*planning-budget*
   #:planning-budget-exceeded #:planning-budget-spec #:planning-budget-file
   #:planning-budget-budget #:planning-budget-stage
   #:machine-rows-built #:machine-spec #:machine-state-count #:machine-watched-variables
   #:make-cost-queue #:make-diagnostic #:make-layout #:make-plan #:make-queue
   #:op-applies-p #:plan #:plan-condition #:plan-ops #:plan-spec #:planned-state-p
   #:planner-op-duration #:planner-op-op #:planner-op-precondition #:planner-ops #:plans
   #:queue-empty-p #:reachable-index-numbers #:refuse-unplanned-state #:spec-optimize
   #:state-to-dense #:states-reached #:transition-ops))
