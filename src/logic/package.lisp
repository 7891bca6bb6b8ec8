;;;; package.lisp -- player.logic: a logic for the behaviours of transition systems (CTL), its model checker, counterexamples and the comparison of two behaviours.

(defpackage #:player.logic
  (:use #:cl #:player.base #:player.spec #:player.planner #:player.compose)
  (:import-from #:alexandria #:when-let #:if-let #:hash-table-keys)
  (:documentation "A logic for the behaviours of transition systems (CTL), its model checker, counterexamples and the comparison of two behaviours.")
  (:export
   #:*verify-state-limit* #:behaviour #:behaviour-p #:behaviour-state-count #:behaviour-state-name
   #:behaviour-dead-ends #:behaviour-initial-states #:counterexample #:counterexample-p
   #:counterexample-states #:counterexample-loop #:counterexample-names #:formula-error
   #:make-behaviour #:spec-behaviour #:graph-behaviour #:verify #:formula-holds-states
   #:write-counterexample-dot #:print-counterexample
   #:diff-graphs #:graph-diff #:graph-diff-p #:graph-diff-dead-ends #:graph-diff-removed
   #:graph-diff-added #:graph-diff-removed-states #:graph-diff-added-states #:graph-diff-consistent-p #:graph-spec-p #:graph-spec-diagnostics))
