;;;; merge.lisp -- G1 ⊗ G2, two graphs merged on a common element
;;;; (Clark & Palmer, Appendix A).
;;;;
;;;; "The outcome is a graph whose nodes are defined to be those of the product
;;;; G1 × G2 where the rightmost component of the node originating in G1 is the
;;;; same as the leftmost component of the node originating in G2. The merge is
;;;; defined to produce (merge, I)((G1 × G2) \ p) where p is a predicate holding
;;;; between pairs of binary trees and is defined p(t1, t2) = equal(right(t1),
;;;; left(t2))."
;;;;
;;;; p is a condition on a node (T1 . T2) of the product -- the text says the
;;;; nodes are those whose components agree -- while G \ p applies its predicate
;;;; to the source and target of each edge. So the restriction keeps the edges
;;;; of G1 × G2 both of whose ends satisfy p: the common element agrees before
;;;; and after the step, i.e. the two copies make the same move with it. Then
;;;; each node is mapped by merge and edges by the identity.
;;;;
;;;; GRAPH-MERGE computes exactly that, but without building G1 × G2: it joins
;;;; the edges of G1 and G2 on the move of the common element.

(in-package #:player.compose)

(defun check-merge-nodes (graph which leafp)
  "Signal a GRAPH-ERROR unless every node of GRAPH is a binary tree of at least
two leaves under LEAFP."
  (loop for node being the hash-keys of (graph-node-table graph)
        do (unless (and (consp node) (not (funcall leafp node)) (tree-p node :leafp leafp))
             (graph-fail node "graph-merge: node ~A of the ~A graph is not a binary tree of ~
                               two or more leaves (a cons (LEFT . RIGHT)), so it has no common element to merge on"
                         (node-text node) which))))

(defun merge-predicate (leafp)
  "The paper's p(t1, t2) = equal(right(t1), left(t2)), on a product node (T1 . T2)."
  (lambda (node)
    (equal (tree-right (car node) :leafp leafp) (tree-left (cdr node) :leafp leafp))))

(defun map-merged-edges (graph1 graph2 leafp function)
  "Call FUNCTION on the source and target of each edge of
(merge, I)((GRAPH1 × GRAPH2) \\ p), found by joining on the common element."
  (let ((index (make-node-table)))
    (loop for e2 being the hash-keys of (graph-edge-table graph2)
          do (push e2 (gethash (cons (tree-left (car e2) :leafp leafp) (tree-left (cdr e2) :leafp leafp))
                               index)))
    (loop for e1 being the hash-keys of (graph-edge-table graph1)
          do (let ((key (cons (tree-right (car e1) :leafp leafp) (tree-right (cdr e1) :leafp leafp))))
               (dolist (e2 (gethash key index))
                 (funcall function
                          (tree-merge (car e1) (car e2) :leafp leafp)
                          (tree-merge (cdr e1) (cdr e2) :leafp leafp)))))))

(defun graph-merge (graph1 graph2 &key (leafp #'atom))
  "G1 ⊗ G2: the graphs merged on a common element, (merge, I)((G1 × G2) \\ p)
with p(t1, t2) = equal(right(t1), left(t2)) holding at both ends of every
edge kept (see the file header), and merge replacing the rightmost leaf of t1
by t2. The nodes of the result are the merged ends of those edges (a
restriction keeps only the ends of its edges). Every node of both graphs must
be a binary tree of two or more leaves under LEAFP (default ATOM): anything
else is a GRAPH-ERROR naming the node."
  (check-graph 'graph-merge graph1)
  (check-graph 'graph-merge graph2)
  (check-merge-nodes graph1 "first" leafp)
  (check-merge-nodes graph2 "second" leafp)
  (let ((result (empty-graph)))
    (map-merged-edges graph1 graph2 leafp (lambda (source target) (add-edge result source target)))
    result))

(defun graph-merge-by-definition (graph1 graph2 &key (leafp #'atom))
  "G1 ⊗ G2 computed literally, (graph-map (restrict (graph-product G1 G2) p)
merge): slow, for checking GRAPH-MERGE."
  (check-merge-nodes graph1 "first" leafp)
  (check-merge-nodes graph2 "second" leafp)
  (let ((p (merge-predicate leafp)))
    (graph-map (restrict (graph-product graph1 graph2)
                         (lambda (source target) (and (funcall p source) (funcall p target))))
               (lambda (node) (tree-merge (car node) (cdr node) :leafp leafp)))))
