;;;; traces.lisp -- the traces of a graph, all of them or one at random
;;;; (Clark & Palmer, Appendix A).
;;;;
;;;; "The traces of a graph is a set of all possible sequences of nodes which are
;;;; encountered by starting at a particular node and then traversing the graph,
;;;; choosing a single edge to traverse at each point, until a decision is made
;;;; to stop (or the decision is forced because a terminal node is
;;;; encountered)."  Traces can be infinite; these functions stop after LENGTH
;;;; steps.

(in-package #:player.compose)

(defun check-trace-arguments (function graph start length)
  "Check GRAPH, START (a node of it) and LENGTH (steps) for FUNCTION."
  (check-graph function graph)
  (check-argument function 'length length (lambda (x) (typep x '(integer 0))) "a number of steps (an integer >= 0)")
  (require-node function graph start))

(defun map-graph-traces (function graph start length &key maximal)
  "Call FUNCTION on each trace of GRAPH from START of at most LENGTH steps (a
fresh list of nodes, START first), in depth-first order with successors in
NODE< order. With MAXIMAL, only on the traces that cannot be extended: LENGTH
steps long, or ending at a terminal node."
  (check-trace-arguments 'map-graph-traces graph start length)
  (let ((successors (successor-table graph)))
    (labels ((walk (node reversed steps)
               (let ((next (and (< steps length) (gethash node successors))))
                 (when (or (not maximal) (null next))
                   (funcall function (reverse reversed)))
                 (dolist (target next)
                   (walk target (cons target reversed) (1+ steps))))))
      (walk start (list start) 0)))
  (values))

(defun graph-traces (graph start length &key maximal)
  "The traces of GRAPH from START of at most LENGTH steps: every finite walk
prefix, each a list of nodes starting with START (the trace of 0 steps is
(START)), in depth-first order with successors in NODE< order. With MAXIMAL,
only the walks that cannot be extended within LENGTH steps. A GRAPH-ERROR
when START is not a node of GRAPH."
  (let ((traces '()))
    (map-graph-traces (lambda (trace) (push trace traces)) graph start length :maximal maximal)
    (nreverse traces)))

(defun random-trace (graph start length seed)
  "One trace of GRAPH from START: at each node an edge is chosen pseudo-randomly
among its successors (in NODE< order) by a generator seeded with the integer
SEED, so the same arguments give the same trace on every run; it stops after
LENGTH steps or at a terminal node. A list of nodes, START first."
  (check-trace-arguments 'random-trace graph start length)
  (check-argument 'random-trace 'seed seed #'integerp "an integer")
  (let ((state (ldb (byte 64 0) (logxor seed #x9E3779B97F4A7C15)))
        (successors (successor-table graph))
        (node start)
        (trace (list start)))
    (flet ((next-random ()
             (setf state (ldb (byte 64 0) (+ (* state 6364136223846793005) 1442695040888963407)))
             (ldb (byte 31 33) state)))
      (loop repeat 4 do (next-random))
      (loop repeat length
            for next = (gethash node successors)
            while next
            do (setf node (nth (mod (next-random) (length next)) next))
               (push node trace)))
    (nreverse trace)))
