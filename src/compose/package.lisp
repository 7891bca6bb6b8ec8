;;;; package.lisp -- player.compose: Clark & Palmer's algebra of transition systems: graphs, products, merges, the cradle, graphs as specs.

(defpackage #:player.compose
  (:use #:cl #:player.base #:player.spec #:player.planner)
  (:import-from #:alexandria
                #:when-let #:if-let #:ensure-list #:hash-table-keys
                #:with-gensyms #:once-only #:appendf #:read-file-into-string)
  (:documentation "Clark & Palmer's algebra of transition systems: graphs, products, merges, the cradle, graphs as specs.")
  (:export
   #:binding #:complete-graph #:cradle-ode-script-forms #:cradle-ode-scripts-text #:write-cradle-ode-scripts-file #:cradle-node #:cradle-node-name #:cradle-spheres #:cradle-stage #:cradle-stages
   #:define-graph #:edge-predicate #:find-graph #:graph #:graph->spec #:graph->spec-forms
   #:graph-edge-count #:graph-edges #:graph-empty-p #:graph-equal #:graph-error
   #:graph-error-value #:graph-expression #:graph-expression-error #:graph-has-edge-p
   #:graph-has-node-p #:graph-intersection #:graph-map #:graph-merge #:graph-node-count
   #:graph-nodes #:graph-p #:graph-product #:graph-reachable #:graph-successors #:graph-sum
   #:graph-traces #:make-graph #:map-graph-traces #:match-pattern #:newton-cradle #:node<
   #:pattern #:pred-and #:pred-edge #:pred-implies #:pred-nodes #:random-trace
   #:register-graph #:restrict #:seq-all #:seq-count #:seq-exists #:seq-restrict #:seq-rev
   #:seq-suffixes #:spec->graph #:sphere-state-p #:subgraph-p #:tree-flatten #:tree-left
   #:tree-merge #:tree-p #:tree-product #:tree-right
   #:*lazy-node-limit* #:graph-with-durations #:graph-timed-p #:graph-edge-duration #:cradle-refinement #:timed-cradle #:lazy-product #:lazy-sum #:friction-cradle #:friction-amplitude #:guarded-graph #:guarded-cradle #:cradle-well-behaved-p #:cradle-free-swing #:cradle-start #:cradle-run #:cradle-figure #:lazy-cradle #:lazy-graph #:lazy-graph-p #:make-lazy-graph #:lazy-successors #:lazy-restrict #:lazy-reachable #:cradle-paper #:physical-successor))
