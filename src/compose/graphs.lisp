;;;; graphs.lisp -- graphs over finite node sets, the complete graph C(Σ), sum
;;;; and intersection (Clark & Palmer, Appendix A).
;;;;
;;;; "A graph is a 4-tuple (N, E, s, t) where N is a set of nodes, E is a set of
;;;; edges, and both s and t are total functions s : E -> N and t : E -> N."
;;;; Here an edge is identified by its ends: it is the cons (SOURCE . TARGET), so
;;;; s is CAR and t is CDR, and there is at most one edge from a node to
;;;; another. Nodes and edges are kept in NODE= hash tables (see nodes.lisp);
;;;; the accessors return fresh sorted lists.

(in-package #:player.compose)

(defstruct (graph (:constructor %make-graph (node-table edge-table)) (:copier nil))
  "A finite graph: NODE-TABLE maps each node to T, EDGE-TABLE each edge
(SOURCE . TARGET) to T. Never modified once built."
  (node-table (make-node-table) :type hash-table :read-only t)
  (edge-table (make-node-table) :type hash-table :read-only t)
  ;; Node -> its targets, sorted; built on first use.
  (successor-table nil)
  ;; Edge -> seconds the move takes, when the transitions are timed
  ;; (durations.lisp); NIL for the paper's unit of time on every edge.
  (duration-table nil))

(defmethod print-object ((graph graph) stream)
  (print-unreadable-object (graph stream :type t)
    (format stream "~D node~:P, ~D edge~:P" (graph-node-count graph) (graph-edge-count graph))))

;;; A graph known by its successors instead (lazy.lisp), declared here so that
;;; the functions below that accept either test for it inline.
(defstruct (lazy-graph (:constructor %make-lazy-graph (successor-function description)) (:copier nil))
  "A graph known by its SUCCESSOR-FUNCTION (a node -> a list of its targets,
computed on demand and remembered in MEMO)."
  (successor-function nil :type function :read-only t)
  (description "" :type string :read-only t)
  (memo (make-node-table) :type hash-table :read-only t))

(defmethod print-object ((graph lazy-graph) stream)
  (print-unreadable-object (graph stream :type t)
    (format stream "~A, ~D node~:P expanded" (lazy-graph-description graph)
            (hash-table-count (lazy-graph-memo graph)))))

(defun check-graph (function graph)
  "GRAPH, or an ARGUMENT-ERROR of FUNCTION when it is not a graph."
  (check-argument function 'graph graph #'graph-p "a graph (from make-graph, complete-graph...)"))

(defun add-node (graph node)
  "Add NODE to GRAPH under construction."
  (setf (gethash node (graph-node-table graph)) t))

(defun add-edge (graph source target)
  "Add the edge SOURCE -> TARGET, and its ends, to GRAPH under construction."
  (setf (gethash source (graph-node-table graph)) t
        (gethash target (graph-node-table graph)) t
        (gethash (cons source target) (graph-edge-table graph)) t))

(defun empty-graph ()
  "A graph with no nodes and no edges, to be filled by ADD-NODE and ADD-EDGE."
  (%make-graph (make-node-table) (make-node-table)))

(defun make-graph (nodes edges)
  "The graph (N, E, s, t) with N the list NODES and E the list EDGES, each edge
a cons (SOURCE . TARGET): s is CAR, t is CDR. The ends of EDGES are nodes too
(s and t are total functions into N), so they need not be listed in NODES.
Duplicates (under EQUAL) are merged."
  (check-argument 'make-graph 'nodes nodes #'proper-list-p "a list of nodes")
  (check-argument 'make-graph 'edges edges
                  (lambda (x) (and (proper-list-p x) (every #'consp x)))
                  "a list of edges, each a cons (SOURCE . TARGET)")
  (let ((graph (empty-graph)))
    (dolist (node nodes) (add-node graph node))
    (dolist (edge edges) (add-edge graph (car edge) (cdr edge)))
    graph))

(defun complete-graph (nodes)
  "C(Σ): the totally connected graph on the set NODES. \"A graph is totally
connected when, for any pair of nodes n1, n2 in N there exists an edge e in E
such that s(e) = n1 and t(e) = n2\" -- every ordered pair, so every node has a
loop too."
  (check-argument 'complete-graph 'nodes nodes #'proper-list-p "a list of nodes")
  (let ((graph (empty-graph))
        (nodes (remove-duplicates nodes :test #'equal)))
    (dolist (a nodes)
      (dolist (b nodes)
        (add-edge graph a b)))
    graph))

;;; Reading a graph

(defun graph-node-count (graph)
  "How many nodes GRAPH has."
  (hash-table-count (graph-node-table (check-graph 'graph-node-count graph))))

(defun graph-edge-count (graph)
  "How many edges GRAPH has."
  (hash-table-count (graph-edge-table (check-graph 'graph-edge-count graph))))

(defun graph-empty-p (graph)
  "True when GRAPH has no nodes (so no edges)."
  (zerop (graph-node-count graph)))

(defun graph-nodes (graph)
  "N: GRAPH's nodes, a fresh list in NODE< order."
  (sort-nodes (hash-table-keys (graph-node-table (check-graph 'graph-nodes graph)))))

(defun graph-edges (graph)
  "E: GRAPH's edges, a fresh list of (SOURCE . TARGET) in NODE< order (by
source, then target)."
  (sort-nodes (hash-table-keys (graph-edge-table (check-graph 'graph-edges graph)))))

(defun graph-has-node-p (graph node)
  "True when NODE is a node of GRAPH."
  (values (gethash node (graph-node-table (check-graph 'graph-has-node-p graph)))))

(defun graph-has-edge-p (graph source target)
  "True when GRAPH has an edge from SOURCE to TARGET."
  (values (gethash (cons source target) (graph-edge-table (check-graph 'graph-has-edge-p graph)))))

(defun successor-table (graph)
  "GRAPH's table node -> sorted list of targets, built on first use."
  (or (graph-successor-table graph)
      (let ((table (make-node-table)))
        (loop for edge being the hash-keys of (graph-edge-table graph)
              do (push (cdr edge) (gethash (car edge) table)))
        (loop for node being the hash-keys of table using (hash-value targets)
              do (setf (gethash node table) (sort targets #'node<)))
        (setf (graph-successor-table graph) table))))

(defun require-node (function graph node)
  "Signal a GRAPH-ERROR of FUNCTION unless NODE is a node of GRAPH."
  (unless (gethash node (graph-node-table graph))
    (graph-fail node "~(~A~): ~A is not a node of the graph~@[ (its nodes: ~{~A~^, ~}~@[, ...~])~]"
                function (node-text node)
                (mapcar #'node-text (subseq (graph-nodes graph) 0 (min 8 (graph-node-count graph))))
                (> (graph-node-count graph) 8))))

(defun graph-successors (graph node)
  "The targets of the edges leaving NODE, sorted. A GRAPH-ERROR when NODE is
not a node of GRAPH. GRAPH may be a LAZY-GRAPH (lazy.lisp): then NODE's
successors are computed on demand."
  (when (lazy-graph-p graph)
    (return-from graph-successors (copy-list (lazy-successors graph node))))
  (check-graph 'graph-successors graph)
  (require-node 'graph-successors graph node)
  (copy-list (values (gethash node (successor-table graph)))))

(defun graph-equal (graph1 graph2)
  "True when the graphs have the same nodes and the same edges."
  (check-graph 'graph-equal graph1)
  (check-graph 'graph-equal graph2)
  (flet ((same-keys (a b)
           (and (= (hash-table-count a) (hash-table-count b))
                (loop for key being the hash-keys of a always (gethash key b)))))
    (and (same-keys (graph-node-table graph1) (graph-node-table graph2))
         (same-keys (graph-edge-table graph1) (graph-edge-table graph2)))))

(defun subgraph-p (graph1 graph2)
  "\"If (N1, E1, s1, t1) is a sub-graph of (N2, E2, s2, t2) then each component
of the first graph is a subset of the corresponding component of the second
graph.\" True when GRAPH1 is a sub-graph of GRAPH2."
  (check-graph 'subgraph-p graph1)
  (check-graph 'subgraph-p graph2)
  (flet ((subset (a b) (loop for key being the hash-keys of a always (gethash key b))))
    (and (subset (graph-node-table graph1) (graph-node-table graph2))
         (subset (graph-edge-table graph1) (graph-edge-table graph2)))))

;;; Sum and intersection

(defun graph-sum (graph &rest graphs)
  "G1 + G2: \"the graph which contains all of the nodes and edges from both
graphs. Where the two graphs have nodes in common these are merged. The result
of the sum is the following graph (N1 ∪ N2, E1 ∪ E2, s1 ∪ s2, t1 ∪ t2).\"
With more arguments, the sum of all of them."
  (let ((result (empty-graph)))
    (dolist (g (cons graph graphs) result)
      (check-graph 'graph-sum g)
      (loop for node being the hash-keys of (graph-node-table g) do (add-node result node))
      (loop for edge being the hash-keys of (graph-edge-table g)
            do (setf (gethash edge (graph-edge-table result)) t)))))

(defun graph-intersection (graph &rest graphs)
  "G1 & G2: \"the graph which contains all of the nodes and edges which the
operand graphs have in common. The result of the intersection is the following
graph (N1 ∩ N2, E1 ∩ E2, s1 ∩ s2, t1 ∩ t2).\" With more arguments, the
intersection of all of them."
  (check-graph 'graph-intersection graph)
  (dolist (g graphs) (check-graph 'graph-intersection g))
  (let ((result (empty-graph)))
    (flet ((everywhere (key accessor)
             (every (lambda (g) (gethash key (funcall accessor g))) graphs)))
      (loop for node being the hash-keys of (graph-node-table graph)
            when (everywhere node #'graph-node-table) do (add-node result node))
      (loop for edge being the hash-keys of (graph-edge-table graph)
            when (everywhere edge #'graph-edge-table)
              do (setf (gethash edge (graph-edge-table result)) t)))
    result))

(defun graph-reachable (graph &rest starts)
  "The sub-graph of GRAPH on the nodes reachable from the nodes STARTS (they
included), with every edge of GRAPH between them. A GRAPH-ERROR when a start
is not a node of GRAPH. GRAPH may be a LAZY-GRAPH: then only the reachable
part is ever built (LAZY-REACHABLE)."
  (when (lazy-graph-p graph)
    (return-from graph-reachable (apply #'lazy-reachable graph starts)))
  (check-graph 'graph-reachable graph)
  (dolist (start starts) (require-node 'graph-reachable graph start))
  (let ((result (empty-graph))
        (successors (successor-table graph))
        (queue (copy-list starts)))
    (dolist (start starts) (add-node result start))
    (loop while queue
          do (let ((node (pop queue)))
               (dolist (next (gethash node successors))
                 (unless (gethash next (graph-node-table result))
                   (add-node result next)
                   (setf queue (nconc queue (list next))))
                 (add-edge result node next))))
    result))
