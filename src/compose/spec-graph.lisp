;;;; spec-graph.lisp -- SPEC->GRAPH: a spec's state graph as a graph of the
;;;; algebra, so specs combine with ×, & and ⊗ (and come back by GRAPH->SPEC).
;;;;
;;;; The states and transitions are those the planner sees (state-graph.lisp's
;;;; rule, with the planner's ops): a node is a plannable state, an edge joins a
;;;; state to the state an op the planner may use (not must-ask; macro-ops
;;;; included) leads to from it. An op that applies but changes nothing is a
;;;; loop: the system may stay where it is. A node is the state's values, one
;;;; per plannable variable in declaration order, as a right-nested tuple
;;;; (V1 . (V2 . ... Vn)) -- the shape products and merges build -- and the value
;;;; alone when there is one variable. A boolean's value is the symbol TRUE or
;;;; FALSE of the spec's package, an enumerated variable's its value as declared (a symbol, string or
;;;; integer). The algebra's edges carry no labels, so the op names come back
;;;; as a second value.

(in-package #:player.compose)

(defparameter *spec-graph-state-limit* 100000
  "The most states SPEC->GRAPH builds a graph of.")

(defun state-node-value (var index spec)
  "The node value of plannable VAR's INDEXth value: TRUE or FALSE (symbols of
SPEC's package, as its enumerated values are) for a boolean, the declared
value otherwise."
  (if (eq (var-kind var) :boolean)
      (intern (if (= index 1) "TRUE" "FALSE") (or (spec-package spec) '#:player-user))
      (svref (var-domain var) index)))

(defun state-node (state spec)
  "The one-hot STATE of SPEC as a node: its plannable variables' values,
right-nested, or the one value when SPEC has one plannable variable."
  (let ((values (loop for (var . index) in (state-assignments state spec)
                      collect (state-node-value var index spec))))
    (if (rest values)
        (reduce #'cons values :from-end t)
        (first values))))

(defun spec-graph-states (spec layout from)
  "The one-hot states of SPEC to draw: every state when FROM is :ALL, else
those the planner's ops reach from SPEC's initial state. A GRAPH-ERROR past
*SPEC-GRAPH-STATE-LIMIT*."
  (flet ((too-many ()
           (graph-fail (spec-name spec) "spec->graph: spec ~A has more than ~D states~:[ reachable from its initial state~;~]"
                       (lisp-text (spec-name spec)) *spec-graph-state-limit* (eq from :all))))
    (if (eq from :all)
        (let ((count (layout-state-count layout)))
          (when (> count *spec-graph-state-limit*) (too-many))
          (loop for dense below count collect (dense-to-state dense layout)))
        (let ((seen (or (states-reached (list (initial-state spec)) (planner-ops spec) *spec-graph-state-limit*)
                        (too-many))))
          (sort (hash-table-keys seen) #'< :key (lambda (state) (state-to-dense state layout)))))))

(defun spec->graph (spec &key (from :initial))
  "The state graph of SPEC (a spec, its name, or a planned machine) as a
graph of the algebra (see the file header): the states reachable from SPEC's
initial state by the ops the planner may use (FROM :INITIAL, the default), or
every plannable state (FROM :ALL); an edge from each state to where each of
those ops, applying there, leads (a loop when it changes nothing). Returns
the graph and a second value, a table from each edge (SOURCE . TARGET) to the
names of the ops making it, in declaration order (look edges up with GETHASH:
its test is the algebra's node equality). A GRAPH-ERROR past
*SPEC-GRAPH-STATE-LIMIT* states; an ARGUMENT-ERROR for a SPEC or FROM of the
wrong kind."
  (check-argument 'spec->graph 'spec spec #'machine-designator-p *machine-designator*)
  (check-argument 'spec->graph :from from (lambda (x) (member x '(:initial :all))) ":initial or :all")
  (let* ((spec (if (machine-p spec) (machine-spec spec) (designated-spec spec 'spec->graph)))
         (layout (make-layout spec))
         (ops (planner-ops spec))
         (graph (empty-graph))
         (labels (make-node-table))
         (nodes (make-hash-table)))
    (dolist (state (spec-graph-states spec layout from))
      (add-node graph (setf (gethash state nodes) (state-node state spec))))
    (loop for state being the hash-keys of nodes using (hash-value node)
          do (dolist (op ops)
               (when (op-applies-p op state)
                 (let* ((next (apply-effects state op))
                        (target (or (gethash next nodes) (state-node next spec))))
                   (add-edge graph node target)
                   (push (op-name (planner-op-op op)) (gethash (cons node target) labels))))))
    (loop for edge being the hash-keys of labels using (hash-value names)
          do (setf (gethash edge labels) (nreverse names)))
    (values graph labels)))
