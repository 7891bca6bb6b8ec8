;;;; lazy.lisp -- graphs built on demand: a node's successors computed when a
;;;; trace, a search or a reachability query first asks for them.
;;;;
;;;; Clark & Palmer's Haskell implementation was lazy ("it evaluates only those
;;;; program expressions which are required to produce the output"); the eager
;;;; algebra here builds every edge of G17 ⊗ ... ⊗ G17 before restricting it,
;;;; which for the 8-sphere cradle is 20 M edges. A LAZY-GRAPH is a successor
;;;; function and a memo: products, merges and restrictions of it enumerate
;;;; only the edges leaving the nodes visited, so a reachability query costs
;;;; what the reachable part costs. LAZY-REACHABLE turns the part a query
;;;; visited into an ordinary (eager) graph.  The LAZY-GRAPH record is
;;;; declared in graphs.lisp, beside GRAPH, which tests for it.

(in-package #:player.compose)

(defun make-lazy-graph (successors &key (description "lazy graph"))
  "A LAZY-GRAPH whose node X has the targets (FUNCALL SUCCESSORS X), a list;
called at most once per node."
  (check-argument 'make-lazy-graph 'successors successors #'functionp "a function of a node")
  (%make-lazy-graph successors description))

(defun lazy-successors (graph node)
  "The targets of the edges leaving NODE in the lazy GRAPH, sorted (computed
on first demand, then remembered)."
  (multiple-value-bind (targets found) (gethash node (lazy-graph-memo graph))
    (if found
        targets
        (setf (gethash node (lazy-graph-memo graph))
              (sort-nodes (remove-duplicates (funcall (lazy-graph-successor-function graph) node)
                                             :test #'equal))))))

(defun lazy-restrict (graph predicate)
  "GRAPH \\ PREDICATE on demand: the edges (SOURCE . TARGET) of the lazy GRAPH
for which PREDICATE (a function of SOURCE and TARGET) holds."
  (make-lazy-graph (lambda (node)
                     (remove-if-not (lambda (target) (funcall predicate node target))
                                    (lazy-successors graph node)))
                   :description (format nil "~A \\ p" (lazy-graph-description graph))))

(defparameter *lazy-node-limit* 2000000
  "The most nodes LAZY-REACHABLE expands before it stops with a GRAPH-ERROR.")

(defun lazy-reachable (graph &rest starts)
  "The sub-graph of the lazy GRAPH reachable from STARTS, as an eager graph
(every edge between the nodes visited). Expands each reachable node once; a
GRAPH-ERROR past *LAZY-NODE-LIMIT* nodes."
  (check-argument 'lazy-reachable 'graph graph #'lazy-graph-p "a lazy graph (make-lazy-graph)")
  (let ((result (empty-graph))
        (queue (copy-list starts))
        (count 0))
    (dolist (start starts) (add-node result start))
    (loop while queue
          do (let ((node (pop queue)))
               (when (> (incf count) *lazy-node-limit*)
                 (graph-fail node "lazy-reachable: more than ~D nodes reachable; the graph is too large"
                             *lazy-node-limit*))
               (dolist (next (lazy-successors graph node))
                 (unless (gethash next (graph-node-table result))
                   (add-node result next)
                   (push next queue))
                 (add-edge result node next))))
    result))

(defun lazy-product (graph1 graph2)
  "G1 × G2 on demand: the node (A . B) moves to (A2 . B2) when A moves to A2
in GRAPH1 and B to B2 in GRAPH2 (each lazy, or an eager graph)."
  (flet ((successors (graph node)
           (if (lazy-graph-p graph) (lazy-successors graph node) (graph-successors graph node))))
    (make-lazy-graph (lambda (node)
                       (loop for a in (successors graph1 (car node))
                             nconc (loop for b in (successors graph2 (cdr node)) collect (cons a b))))
                     :description "product")))

(defun lazy-sum (graph &rest graphs)
  "G1 + G2 ... on demand: a node's successors in any of the lazy GRAPHS."
  (let ((all (cons graph graphs)))
    (make-lazy-graph (lambda (node) (loop for g in all append (lazy-successors g node)))
                     :description "sum")))
