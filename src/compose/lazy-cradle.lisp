;;;; lazy-cradle.lisp -- the cradle built on demand: G17+ ⊗ ... ⊗ G17+ and its
;;;; restrictions enumerate only the edges leaving the states a query visits.
;;;;
;;;; An edge of the merge of N - 1 copies of a two-sphere graph P on common
;;;; spheres is a move of every sphere such that each pair of neighbours makes
;;;; an edge of P (merge.lisp: the common sphere agrees at both ends). So the
;;;; successors of a node are found sphere by sphere, left to right, keeping
;;;; only the moves of sphere i that form an edge of P with the move chosen
;;;; for sphere i - 1: the same edges GRAPH-MERGE joins, for one source.

(in-package #:player.compose)

(defun pair-move-table (pair-graph)
  "PAIR-GRAPH's edges ((A . B) . (A2 . B2)) indexed by (A B A2) -> list of B2:
the moves of a right sphere B allowed when its left neighbour moves A -> A2."
  (let ((table (make-node-table)))
    (loop for (source . target) in (graph-edges pair-graph)
          do (push (cdr target) (gethash (list (car source) (cdr source) (car target)) table)))
    table))

(defun chain-merge-successors (pair-graph single-graph)
  "A function of a cradle node -> its successors in PAIR-GRAPH ⊗ ... ⊗
PAIR-GRAPH (as many copies as the node has spheres less one); a one-sphere
node takes its successors from SINGLE-GRAPH."
  (let ((moves (pair-move-table pair-graph))
        (firsts (make-node-table)))
    ;; The first sphere's possible moves: the left ends of PAIR-GRAPH's edges.
    (loop for (source . target) in (graph-edges pair-graph)
          do (pushnew (car target) (gethash (car source) firsts) :test #'equal))
    (lambda (node)
      (let ((spheres (cradle-spheres node))
            (results '()))
        (if (null (rest spheres))
            (graph-successors single-graph (first spheres))
            (labels ((extend (previous previous-target rest reversed)
                       (if (null rest)
                           (push (apply #'cradle-node (reverse reversed)) results)
                           (dolist (next (gethash (list previous (first rest) previous-target) moves))
                             (extend (first rest) next (rest rest) (cons next reversed))))))
              (dolist (first-target (gethash (first spheres) firsts))
                (extend (first spheres) first-target (rest spheres) (list first-target)))
              results))))))

(defun lazy-cradle (n &key (stage :g^n))
  "The N-sphere cradle as a LAZY-GRAPH: STAGE :G^N (the default) is
NEWTON-CRADLE's graph, :COLLISIONS the one before the RESOLVED restriction,
:PAPER the paper's G^n. Each node's successors are the merge's edges leaving
it that the restrictions keep (see the file header), so a query costs what
the states it visits cost. An ARGUMENT-ERROR for a bad N or STAGE."
  (check-argument 'lazy-cradle 'n n (lambda (x) (typep x '(integer 1))) "a number of spheres (an integer >= 1)")
  (check-argument 'lazy-cradle :stage stage (lambda (x) (member x '(:g^n :collisions :paper)))
                  ":g^n, :collisions or :paper")
  (let* ((paper (eq stage :paper))
         (merged (make-lazy-graph (chain-merge-successors (cradle-stage 2 (if paper :g17 :g17+))
                                                          (cradle-stage 1 (if paper :g^1 :g^1+)))
                                  :description (format nil "~D-sphere merge" n)))
         (collisions (if (= n 1) merged (lazy-restrict merged (collision-predicate)))))
    (if (eq stage :g^n)
        (lazy-restrict collisions (resolved-predicate))
        collisions)))
