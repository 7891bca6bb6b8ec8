;;;; guards.lisp -- two transition systems linked by a guard: while the guard
;;;; holds of a state, a cheaper system gives its moves.
;;;;
;;;; Clark & Palmer (§5): "link a number of state transition systems together
;;;; by guards, the guards would detect when a particular object's state has
;;;; become well behaved in some sense and can be animated with respect to a
;;;; simpler, and therefore more efficient, state machine." A guarded graph
;;;; takes a state's moves from CHEAP where GUARD holds of it, from FULL
;;;; elsewhere. For the cradle, a state is well behaved when no collision is
;;;; about to happen; then each sphere swings on its own (CRADLE-FREE-SWING),
;;;; without enumerating the merge of G17+ and testing its restrictions.

(in-package #:player.compose)

(defun successors-in (graph node)
  "NODE's successors in GRAPH, lazy or eager (none when an eager GRAPH lacks NODE)."
  (cond ((lazy-graph-p graph) (lazy-successors graph node))
        ((graph-has-node-p graph node) (graph-successors graph node))
        (t '())))

(defun guarded-graph (guard cheap full)
  "The LAZY-GRAPH whose node X moves as in CHEAP when (FUNCALL GUARD X), as in
FULL otherwise. CHEAP and FULL are graphs or lazy graphs."
  (check-argument 'guarded-graph 'guard guard #'functionp "a function of a node")
  (make-lazy-graph (lambda (node) (successors-in (if (funcall guard node) cheap full) node))
                   :description "guarded"))

(defun guard-eager (guard cheap full)
  "GUARDED-GRAPH of eager graphs, built: FULL's nodes, each with its moves
from CHEAP where GUARD holds, from FULL elsewhere. A GRAPH-ERROR when GUARD
holds of no node of FULL (the cheap system would never be used)."
  (check-graph 'guard-eager cheap)
  (check-graph 'guard-eager full)
  (let ((nodes (graph-nodes full)))
    (unless (some guard nodes)
      (graph-fail guard "guarded: the guard holds of no state of the graph, so the cheaper system would never drive it"))
    (let ((result (empty-graph)))
      (dolist (node nodes result)
        (add-node result node)
        (dolist (next (successors-in (if (funcall guard node) cheap full) node))
          (add-edge result node next))))))

(defun cradle-well-behaved-p (node)
  "Is the cradle NODE well behaved: no contact block about to collide, so
every sphere can swing on its own this step?"
  (let ((spheres (cradle-spheres node)))
    (loop for (start . end) in (contact-blocks spheres)
          never (approaching-p (mapcar #'cdr (subseq spheres start end))))))

(defun cradle-free-swing (n)
  "The cheap system of N spheres: each swings on its own (FREE-SWING), which
is the cradle's move wherever no collision happens."
  (declare (ignore n))
  (make-lazy-graph (lambda (node) (list (apply #'cradle-node (mapcar #'free-swing (cradle-spheres node)))))
                   :description "free swing"))

(defun guarded-cradle (n)
  "The N-sphere cradle with the guard of the file header: free swing while
well behaved, LAZY-CRADLE at collisions. The same graph, cheaper to build."
  (guarded-graph #'cradle-well-behaved-p (cradle-free-swing n) (lazy-cradle n)))
