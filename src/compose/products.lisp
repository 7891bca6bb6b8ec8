;;;; products.lisp -- the product G1 × G2 and graph homomorphisms (f, g)
;;;; (Clark & Palmer, Appendix A).

(in-package #:player.compose)

(defun graph-product-2 (graph1 graph2)
  "GRAPH1 × GRAPH2, see GRAPH-PRODUCT."
  (let ((result (empty-graph))
        (nodes2 (hash-table-keys (graph-node-table graph2)))
        (edges2 (hash-table-keys (graph-edge-table graph2))))
    (loop for a being the hash-keys of (graph-node-table graph1)
          do (dolist (b nodes2) (add-node result (cons a b))))
    (loop for e1 being the hash-keys of (graph-edge-table graph1)
          do (dolist (e2 edges2)
               (setf (gethash (cons (cons (car e1) (car e2)) (cons (cdr e1) (cdr e2)))
                              (graph-edge-table result))
                     t)))
    result))

(defun graph-product (graph1 graph2 &rest graphs)
  "G1 × G2: \"the largest graph whose nodes are pairs of nodes from N1 and N2,
whose edges are pairs of edges from E1 and E2 and whose edges are only defined
between pairs of nodes when the original graphs had edges between the pairwise
components. The product is the graph (N1 × N2, E1 × E2, s, t) where
s(e1, e2) = (s1(e1), s2(e2)) and t(e1, e2) = (t1(e1), t2(e2))\".
A node of the product is the cons (A . B); an edge moves both components at
once, from (S1 . S2) to (T1 . T2). A product with an empty graph is empty (no
pairs). With more graphs, the product associates to the left:
(graph-product a b c) = (a × b) × c, whose nodes are ((A . B) . C)."
  (check-graph 'graph-product graph1)
  (check-graph 'graph-product graph2)
  (dolist (g graphs) (check-graph 'graph-product g))
  (reduce #'graph-product-2 (list* graph1 graph2 graphs)))

(defun graph-map (graph f &optional g)
  "The homomorphism (f, g) applied to GRAPH: \"A homomorphism (f, g) is applied
to a graph (N, E, s, t) to produce the following graph ({f(n) | n ∈ N},
{g(e) | e ∈ E}, {g(e) ↦ f(n) | e ↦ n ∈ s}, {g(e) ↦ f(n) | e ↦ n ∈ t})\".
F maps nodes. An edge is identified by its ends, so its image is the edge
from f(s(e)) to f(t(e)); distinct edges whose images coincide become one. G,
if given, maps an edge (SOURCE . TARGET) to its image edge; it must be
(f(SOURCE) . f(TARGET)) for the result to be a graph (the paper's s and t of
the image must be functions), and a GRAPH-ERROR says which edge it is not for.
The paper's (merge, I) is (graph-map graph merge)."
  (check-graph 'graph-map graph)
  (check-argument 'graph-map 'f f #'functionp "a function of a node")
  (check-argument 'graph-map 'g g (lambda (x) (or (null x) (functionp x))) "NIL or a function of an edge")
  (let ((result (empty-graph))
        (images (make-node-table)))
    (flet ((image (node)
             (multiple-value-bind (image found) (gethash node images)
               (if found image (setf (gethash node images) (funcall f node))))))
      (loop for node being the hash-keys of (graph-node-table graph)
            do (add-node result (image node)))
      (loop for edge being the hash-keys of (graph-edge-table graph)
            do (let ((source (image (car edge)))
                     (target (image (cdr edge))))
                 (when g
                   (let ((mapped (funcall g edge)))
                     (unless (and (consp mapped) (equal (car mapped) source) (equal (cdr mapped) target))
                       (graph-fail edge "graph-map: g maps the edge ~A to ~A, not to an edge from ~A to ~A: (f, g) is not a homomorphism"
                                   (node-text edge) (node-text mapped) (node-text source) (node-text target)))))
                 (add-edge result source target))))
    result))
