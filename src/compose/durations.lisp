;;;; durations.lisp -- timed transitions: each edge of a graph annotated with
;;;; the time its move takes.
;;;;
;;;; Clark & Palmer (§5): "all of the transitions which are performed in the
;;;; Newton's Cradle example, assume a constant unit of time ... transitions
;;;; could be annotated with a length of time which it takes to move from the
;;;; source state to the target state." A graph's durations are a table edge ->
;;;; seconds beside its edges; the algebra's operations make untimed graphs
;;;; (a sum or product of timed moves has no single time), so durations are
;;;; given last, to the behaviour that is played. GRAPH->SPEC turns them into
;;;; the ops' :duration.

(in-package #:player.compose)

(defun duration-p (x)
  "Is X a duration: a non-negative real number of seconds?"
  (and (realp x) (not (minusp x))))

(defun graph-with-durations (graph durations &key (default 1))
  "A copy of GRAPH (same nodes and edges) whose edges take time: DURATIONS is
a function of SOURCE and TARGET returning seconds (or NIL for DEFAULT), or a
list of (PREDICATE . SECONDS), the first predicate (a function of SOURCE and
TARGET) holding giving an edge its time, DEFAULT when none does. An
ARGUMENT-ERROR for a duration that is not a non-negative number."
  (check-graph 'graph-with-durations graph)
  (check-argument 'graph-with-durations :default default #'duration-p "a number of seconds >= 0")
  (check-argument 'graph-with-durations 'durations durations
                  (lambda (x) (or (functionp x)
                                  (and (proper-list-p x)
                                       (every (lambda (rule) (and (consp rule) (functionp (car rule)) (duration-p (cdr rule))))
                                              x))))
                  "a function of SOURCE and TARGET, or a list of (PREDICATE . SECONDS)")
  (let ((table (make-node-table))
        (lookup (if (functionp durations)
                    durations
                    (lambda (source target)
                      (cdr (find-if (lambda (rule) (funcall (car rule) source target)) durations))))))
    (loop for edge being the hash-keys of (graph-edge-table graph)
          do (let ((seconds (or (funcall lookup (car edge) (cdr edge)) default)))
               (unless (duration-p seconds)
                 (graph-fail edge "graph-with-durations: the edge ~A would take ~A, not a number of seconds >= 0"
                             (node-text edge) (node-text seconds)))
               (setf (gethash edge table) seconds)))
    (let ((timed (%make-graph (graph-node-table graph) (graph-edge-table graph))))
      (setf (graph-duration-table timed) table)
      timed)))

(defun graph-timed-p (graph)
  "Do GRAPH's edges carry durations?"
  (and (graph-duration-table (check-graph 'graph-timed-p graph)) t))

(defun graph-edge-duration (graph source target)
  "The seconds the move from SOURCE to TARGET takes in GRAPH: its duration, or
1 (the paper's unit of time) in an untimed graph. A GRAPH-ERROR when GRAPH has
no such edge."
  (check-graph 'graph-edge-duration graph)
  (unless (graph-has-edge-p graph source target)
    (graph-fail (cons source target) "graph-edge-duration: no edge from ~A to ~A" (node-text source) (node-text target)))
  (if (graph-duration-table graph)
      (values (gethash (cons source target) (graph-duration-table graph)))
      1))
