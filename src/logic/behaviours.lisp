;;;; behaviours.lisp -- a behaviour: the finite state graph a formula is
;;;; checked on (a Kripke structure): states numbered 0 ... n-1, each state's
;;;; successors, the initial states, and how a formula's atoms read a state.
;;;;
;;;; A behaviour comes from a graph of the algebra (its nodes are the states;
;;;; an atom is a node, a pattern (match P) or a Lisp predicate) or from a
;;;; spec (the states its planner's ops reach from its initial state; an atom
;;;; is a state expression as specs write them, cradle.cs-cs-cs or (not lit)).

(in-package #:player.logic)

(defparameter *verify-state-limit* 1000000
  "The most states a behaviour built from a spec or a lazy graph may have.")

(defstruct (behaviour (:constructor %make-behaviour))
  "STATES (a vector), SUCCESSORS (a vector of index lists), INITIAL (index
list), NAMER (state -> string), ATOM (a function of an atom form and the
behaviour returning a predicate of a state, or signalling FORMULA-ERROR)."
  (states #() :type simple-vector)
  (successors #() :type simple-vector)
  (initial '() :type list)
  (namer #'princ-to-string :type function)
  (atom nil :type function)
  (predecessors nil))

(defmethod print-object ((behaviour behaviour) stream)
  (print-unreadable-object (behaviour stream :type t)
    (format stream "~D state~:P" (behaviour-state-count behaviour))))

(defun behaviour-successors-of (behaviour index)
  "The indexes of the successors of BEHAVIOUR's state number INDEX."
  (svref (behaviour-successors behaviour) index))

(defun behaviour-state-count (behaviour)
  "How many states BEHAVIOUR has."
  (length (behaviour-states behaviour)))

(defun behaviour-state-name (behaviour index)
  "The name of BEHAVIOUR's state number INDEX, as messages print it."
  (funcall (behaviour-namer behaviour) (svref (behaviour-states behaviour) index)))

(defun behaviour-initial-states (behaviour)
  "The indexes of BEHAVIOUR's initial states."
  (behaviour-initial behaviour))

(defun behaviour-dead-ends (behaviour)
  "The indexes of BEHAVIOUR's states with no successor."
  (loop for i below (behaviour-state-count behaviour)
        unless (svref (behaviour-successors behaviour) i) collect i))

(defun behaviour-predecessor-vector (behaviour)
  "For each state, the indexes of the states with an edge to it (built once)."
  (or (behaviour-predecessors behaviour)
      (let ((predecessors (make-array (behaviour-state-count behaviour) :initial-element '())))
        (loop for i from 0
              for targets across (behaviour-successors behaviour)
              do (dolist (j targets) (pushnew i (svref predecessors j))))
        (setf (behaviour-predecessors behaviour) predecessors))))

(defun make-behaviour (states successor-function initial &key (namer #'princ-to-string) atom (test 'equal))
  "A behaviour of the states STATES (a list): SUCCESSOR-FUNCTION gives each
state's successor states, INITIAL lists the initial states, NAMER names a
state, ATOM makes a state predicate of an atom form. TEST compares states."
  (let* ((vector (coerce states 'simple-vector))
         (index (make-hash-table :test test)))
    (loop for state across vector for i from 0 do (setf (gethash state index) i))
    (%make-behaviour
     :states vector
     :successors (map 'simple-vector
                      (lambda (state)
                        (sort (remove-duplicates
                               (mapcar (lambda (next) (or (gethash next index)
                                                          (error "behaviour: successor ~S is not a state" next)))
                                       (funcall successor-function state)))
                              #'<))
                      vector)
     :initial (mapcar (lambda (state) (gethash state index)) initial)
     :namer namer
     :atom (or atom (lambda (form behaviour) (declare (ignore behaviour))
                      (formula-fail form "this behaviour has no atoms"))))))

;;; From a graph of the algebra

(defun node-name (node)
  "A graph node's name: a cradle's as its spec names it (ls-cs-cs), any other printed."
  (if (and (consp node) (tree-p node :leafp #'sphere-state-p))
      (string-downcase (cradle-node-name node))
      (let ((*print-pretty* nil)) (string-downcase (prin1-to-string node)))))

(defun graph-atom (form behaviour)
  "The state predicate of the atom FORM of a graph's formula: a function is
itself, (match PATTERN) matches the paper's patterns, anything else is a node,
which the graph must have."
  (cond ((functionp form) form)
        ((and (consp form) (symbolp (first form)) (word-p (first form) "MATCH"))
         (unless (and (consp (rest form)) (null (cddr form)))
           (formula-fail form "write (match PATTERN)"))
         (let ((pattern (handler-case (pattern (second form))
                          (graph-error (c) (formula-fail form "~A" c)))))
           (lambda (node) (values (match-pattern pattern node)))))
        (t (unless (find form (behaviour-states behaviour) :test #'equal)
             (formula-fail form "~A is not a state of the graph" (bounded-lisp-text form 60)))
           (lambda (node) (equal node form)))))

(defun graph-behaviour (graph &key (start nil start-p) starts)
  "The behaviour of GRAPH (a graph, or a LAZY-GRAPH, which then needs a start):
its nodes, initial states START (one node) or STARTS (a list of nodes; by
default every node of an eager graph), atoms as GRAPH-ATOM reads them. A
FORMULA-ERROR when a start is not a node."
  (let* ((starts (if start-p (cons start starts) starts))
         (graph (if (lazy-graph-p graph)
                    (progn
                      (unless starts (formula-fail graph "a lazy graph needs :start"))
                      (let ((*lazy-node-limit* *verify-state-limit*))
                        (apply #'lazy-reachable graph starts)))
                    graph)))
    (dolist (s starts)
      (unless (graph-has-node-p graph s)
        (formula-fail s "the start ~A is not a node of the graph" (bounded-lisp-text s 60))))
    (let ((nodes (graph-nodes graph)))
      (make-behaviour nodes (lambda (node) (graph-successors graph node)) (or starts nodes)
                      :namer #'node-name :atom #'graph-atom))))

;;; From a spec

(defun spec-atom (spec)
  "The state predicate maker for SPEC's formulas: an atom is a state
expression of SPEC, parsed as :state parses one."
  (lambda (form behaviour)
    (declare (ignore behaviour))
    (let ((cubes (handler-case (with-spec-context (:spec spec :spec-name (spec-name spec) :form-places nil)
                                 (expression-cubes (parse-expression form) spec))
                   (spec-error (c)
                     (formula-fail form "~A is not a state expression of spec ~A: ~A"
                                   (bounded-lisp-text form 60) (lisp-text (spec-name spec)) (spec-error-message c))))))
      (lambda (state) (some (lambda (cube) (state-in-cube-p state cube)) cubes)))))

(defun spec-behaviour (spec)
  "The behaviour of SPEC (a spec, its name or a machine): the one-hot states
its planner's ops reach from its initial state, an edge wherever an op
applies (a loop when it changes nothing), atoms its state expressions. A
FORMULA-ERROR past *VERIFY-STATE-LIMIT* states."
  (let* ((spec (if (machine-p spec) (machine-spec spec) (designated-spec spec 'verify)))
         (ops (planner-ops spec))
         (initial (initial-state spec))
         (seen (or (states-reached (list initial) ops *verify-state-limit*)
                   (formula-fail (spec-name spec) "spec ~A has more than ~D reachable states (*verify-state-limit*)"
                                 (lisp-text (spec-name spec)) *verify-state-limit*))))
    (make-behaviour (sort (hash-table-keys seen) #'<)
                    (lambda (state) (loop for op in ops
                                          when (op-applies-p op state) collect (apply-effects state op)))
                    (list initial)
                    :test 'eql
                    :namer (lambda (state) (let ((*print-pretty* nil)
                                                 (*package* (or (spec-package spec) (find-package '#:player-user))))
                                             (string-downcase (prin1-to-string (cube-expression state spec)))))
                    :atom (spec-atom spec))))
