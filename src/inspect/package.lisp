;;;; package.lisp -- player.inspect: Looking at a planned machine: its state graph as Graphviz, explanations of plans.

(defpackage #:player.inspect
  (:use #:cl #:player.base #:player.spec #:player.planner)
  (:import-from #:alexandria
                #:when-let #:if-let #:ensure-list #:hash-table-keys
                #:with-gensyms #:once-only #:appendf #:read-file-into-string)
  (:documentation "Looking at a planned machine: its state graph as Graphviz, explanations of plans.")
  (:export
   #:*dot-program* #:build-state-graph #:explain-plan #:explained-goal
   #:explained-goal-holds #:explained-goal-p #:explained-op #:explained-op-literals
   #:explained-op-name #:explained-op-p #:explained-op-reason #:explained-op-target
   #:explained-unreachable #:explained-unreachable-p #:explanation-step #:graph-file-format
   #:graphviz-error #:print-explanation #:state-graph-error #:write-state-graph
   #:write-state-graph-file))
