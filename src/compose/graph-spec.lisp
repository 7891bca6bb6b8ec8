;;;; graph-spec.lisp -- GRAPH->SPEC: a graph as a Player spec, so the planner
;;;; finds paths through the behaviour and a controller plays them.
;;;;
;;;; One enumerated state variable holds the node; each edge is an op whose
;;;; precondition is its source and whose effect is its target; each node X has
;;;; an event GO-X whose goal is X. Plans then follow the graph's edges: a
;;;; shortest plan from a node to a goal is a shortest path in the graph.

(in-package #:player.compose)

(defparameter *name-characters* "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789-_<>+*/=!?%&$^~"
  "The characters a node's name may use: no dot (var.value splits at it), and
nothing the Lisp reader would take for syntax.")

(defun default-node-name (node)
  "NODE's name: an integer K is NK, or MK when negative (-1 is M1); a symbol its
name; a string itself; a cons (A . B) <A_B>. Anything else is a GRAPH-ERROR."
  (typecase node
    (integer (format nil "~:[N~;M~]~D" (minusp node) (abs node)))
    (symbol (symbol-name node))
    (string node)
    (cons (format nil "<~A_~A>" (default-node-name (car node)) (default-node-name (cdr node))))
    (t (graph-fail node "graph->spec: no name for the node ~A; pass :node-namer" (node-text node)))))

(defun spec-symbol (control &rest arguments)
  "A symbol of PLAYER-USER named by CONTROL/ARGUMENTS, upcased."
  (intern (string-upcase (apply #'format nil control arguments)) '#:player-user))

(defun node-names (nodes namer)
  "A NODE= table node -> name (upcased string) for NODES; a GRAPH-ERROR when a
name is empty, uses a character outside *NAME-CHARACTERS*, reads as a number,
or is the name of another node."
  (let ((names (make-node-table))
        (owners (make-hash-table :test 'equal)))
    (dolist (node nodes names)
      (let ((name (funcall namer node)))
        (unless (and (stringp name) (plusp (length name))
                     (every (lambda (c) (find c *name-characters*)) name)
                     (not (numberp (let ((*read-eval* nil)) (ignore-errors (read-from-string name))))))
          (graph-fail node "graph->spec: the name ~S of node ~A is not a plain symbol name (letters, digits and -_<>+*/=!?%&$^~~, not a number)"
                      name (node-text node)))
        (let* ((name (string-upcase name))
               (owner (gethash name owners)))
          (when owner
            (graph-fail node "graph->spec: nodes ~A and ~A have the same name ~A"
                        (node-text (car owner)) (node-text node) name))
          (setf (gethash name owners) (list node)
                (gethash node names) name))))))

(defun graph->spec-forms (graph &key start op-namer (node-namer #'default-node-name)
                                     (variable 'node) events documentation max-depth options
                                     (go-events t))
  "The DEFSPEC body (a list of forms, symbols in PLAYER-USER) GRAPH->SPEC
defines; see there. Written to a file after (in-package :player-user) and
(defspec NAME, it is a spec file. OPTIONS, (:KEY VALUE) spec options such as
(:scripts \"FILE\"), come after the :max-depth; without GO-EVENTS there are
no GO-X events."
  (check-graph 'graph->spec graph)
  (check-argument 'graph->spec :variable variable (lambda (x) (and (symbolp x) x (not (keywordp x))))
                  "a variable name (a symbol)")
  (check-argument 'graph->spec :events events #'proper-list-p "a list of event forms")
  (when (graph-empty-p graph)
    (graph-fail graph "graph->spec: the graph has no nodes, so its state variable would have no values"))
  (let* ((nodes (graph-nodes graph))
         (start (if start (progn (require-node 'graph->spec graph start) start) (first nodes)))
         (names (node-names nodes node-namer))
         (var (spec-symbol "~A" (symbol-name variable)))
         (value (lambda (node) (spec-symbol "~A" (gethash node names))))
         (literal (lambda (node) (spec-symbol "~A.~A" (symbol-name var) (gethash node names))))
         (op-namer (or op-namer
                       (lambda (source target)
                         (spec-symbol "from-~A-to-~A" (gethash source names) (gethash target names)))))
         (op-names (make-hash-table :test 'equal))
         (depth (or max-depth (min 1000 (max 1 (1- (length nodes)))))))
    (append
     (and documentation (list documentation))
     (list (list :max-depth depth))
     options
     (list (list (spec-symbol "state-variable") var 'string (funcall value start) (mapcar value nodes)))
     (loop for (source . target) in (graph-edges graph)
           for op = (let ((name (funcall op-namer source target)))
                      (if (stringp name) (spec-symbol "~A" name) name))
           do (unless (and (symbolp op) op (not (keywordp op)))
                (graph-fail (cons source target) "graph->spec: op-namer named the edge ~A ~A, not a symbol"
                            (node-text (cons source target)) (node-text op)))
              (when (gethash (symbol-name op) op-names)
                (graph-fail (cons source target) "graph->spec: two edges get the op name ~A" (symbol-name op)))
              (setf (gethash (symbol-name op) op-names) t)
           collect (append (list (spec-symbol "op") op :precond (funcall literal source) :add (funcall literal target))
                           ;; timed moves (durations.lisp) take their own time, not the unit
                           (and (graph-timed-p graph)
                                (list :duration (graph-edge-duration graph source target)))))
     (loop for node in nodes
           when go-events collect (list (spec-symbol "event") (spec-symbol "go-~A" (gethash node names)) :state (funcall literal node)))
     events)))

(defun graph->spec (graph name &rest keys &key start op-namer node-namer variable events documentation max-depth
                                                options (go-events t))
  "Define (with DEFINE-SPEC) and return the spec NAME whose planner walks GRAPH:
one enumerated state variable VARIABLE (default NODE) whose values are the
nodes, named by NODE-NAMER (a function of a node returning a string; by
default DEFAULT-NODE-NAME: N0, M1, <N0_M1>, ...), initial value START (default
the first node in NODE< order); for each edge from X to Y, an op named by
OP-NAMER (a function of the source and target nodes returning a symbol or
string; default FROM-X-TO-Y) with :precond VARIABLE.X and :add VARIABLE.Y;
the op's :duration is the edge's (GRAPH-EDGE-DURATION) when GRAPH is timed (GRAPH-WITH-DURATIONS);
for each node X, an event GO-X with :state VARIABLE.X (unless GO-EVENTS is
NIL); then the event forms EVENTS. OPTIONS are spec options, such as
((:scripts \"FILE\")). :max-depth is MAX-DEPTH, by default the number of
nodes less one (at most 1000), so every shortest path is planned. A GRAPH-ERROR for an empty
graph, a START that is not a node, or names that clash or are not plain."
  (declare (ignore start op-namer node-namer variable events documentation max-depth options go-events))
  (check-argument 'graph->spec 'name name (lambda (x) (and (symbolp x) x (not (keywordp x)))) "a spec name (a symbol)")
  (define-spec name (apply #'graph->spec-forms graph (loop for (key value) on keys by #'cddr
                                                             when (or value (eq key :go-events))
                                                               append (list key value)))
               :package (find-package '#:player-user)))
