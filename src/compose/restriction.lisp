;;;; restriction.lisp -- G \ p, a graph restricted by a predicate on its edges
;;;; (Clark & Palmer, Appendix A).

(in-package #:player.compose)

(defun check-patterns (function graph predicate)
  "Signal a GRAPH-ERROR when a pattern of PREDICATE can match no node of GRAPH
(a constant that is no node's, or a pair pattern on atoms): such a pattern
names something that is not in the graph."
  (when (and (typep predicate 'edge-predicate) (plusp (graph-node-count graph)))
    (dolist (pattern (predicate-patterns predicate))
      (let ((form (pattern-form pattern)))
        (unless (loop for node being the hash-keys of (graph-node-table graph)
                        thereis (could-match-p form node))
          (graph-fail form "~(~A~): pattern ~A matches no node of the graph (nodes such as ~{~A~^, ~})"
                      function (node-text form)
                      (mapcar #'node-text (subseq (graph-nodes graph) 0 (min 4 (graph-node-count graph))))))))))

(defun restrict-edges (map-edges predicate)
  "The graph of the edges MAP-EDGES yields (it calls its argument on each
SOURCE and TARGET) for which PREDICATE holds, with the paper's nodes: the ends
of the edges kept; for a conjunction from PRED-AND, the nodes every conjunct's
restriction keeps (G \\ p1 & p2 = (G \\ p1) & (G \\ p2))."
  (let* ((result (empty-graph))
         (conjuncts (and (typep predicate 'edge-predicate) (predicate-conjuncts predicate))))
    (if (null conjuncts)
        (funcall map-edges (lambda (source target)
                             (when (funcall predicate source target)
                               (add-edge result source target))))
        (let* ((functions (coerce conjuncts 'simple-vector))
               (ends (map 'simple-vector (lambda (c) (declare (ignore c)) (make-node-table)) conjuncts)))
          (funcall map-edges
                   (lambda (source target)
                     (let ((all t))
                       (loop for f across functions
                             for table across ends
                             do (if (funcall (the function f) source target)
                                    (setf (gethash source table) t (gethash target table) t)
                                    (setf all nil)))
                       (when all
                         (setf (gethash (cons source target) (graph-edge-table result)) t)))))
          (loop for node being the hash-keys of (svref ends 0)
                when (every (lambda (table) (gethash node table)) ends)
                  do (add-node result node))))
    result))

(defun restrict (graph predicate)
  "G \\ p: \"The result is the largest sub-graph of the original for which the
predicate holds between all source and target nodes of edges. The restriction
is defined as follows: (N, E, s, t) \\ p = (N', E', s', t') where
E' = {e | e ∈ E, p(s(e), t(e))}, s' = s \\ E', t' = t \\ E' and
N' = ran(s') ∪ ran(t')\" -- the nodes of the result are exactly the ends of the
edges kept; a node without a kept edge is dropped.
PREDICATE is a function of (SOURCE TARGET), or a pattern both ends must match
(see PRED-NODES). A conjunction from PRED-AND is read as the paper translates
it, G \\ p1 & p2 = (G \\ p1) & (G \\ p2): the same edges, but the nodes both
restrictions keep, which may include nodes none of whose edges satisfies both
(so G \\ p \\ p' and G \\ (pred-and p p') have the same edges and may differ by
such nodes). A pattern in PREDICATE that can match no node of GRAPH is a
GRAPH-ERROR."
  (check-graph 'restrict graph)
  (let ((predicate (as-edge-predicate 'restrict predicate)))
    (check-patterns 'restrict graph predicate)
    (restrict-edges (lambda (f)
                      (loop for edge being the hash-keys of (graph-edge-table graph)
                            do (funcall f (car edge) (cdr edge))))
                    predicate)))
