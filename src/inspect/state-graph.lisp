;;;; state-graph.lisp -- a planned machine seen as a graph: which plannable
;;;; states to draw, the op edges between them, a goal's region and its plan
;;;; tree.  dot.lisp writes such a graph as Graphviz; nothing here knows DOT.
;;;;
;;;; The rule: a node is a plannable state; an edge is an op (must-ask ops and
;;;; macro-ops too) whose precondition holds in the state it leaves and whose
;;;; effects change that state.  A goal's plan tree is the union of the plans
;;;; the machine runs from each drawn state: from S, the first of the goal's
;;;; plans whose condition holds in S, one edge per op it runs.

(in-package #:player.inspect)

(define-condition state-graph-error (player-error-with-message)
  ()
  (:documentation "A state graph cannot be made: the spec has too many states
to draw, or the goal asked for is not a state expression of the spec."))

(defun state-graph-fail (control &rest arguments)
  "Signal a STATE-GRAPH-ERROR with a message from CONTROL and ARGUMENTS."
  (error 'state-graph-error :message (apply #'format nil control arguments)))

;;;# How much is drawn

(defparameter *graph-all-states-limit* 300
  "A spec with at most this many plannable states has every one drawn; a
larger one only the states reachable from its initial state.")

(defparameter *graph-state-limit* 1000
  "The most states drawn with their op edges.  Past it, a goal's plan tree is
drawn alone (one edge or so per state), and without a goal nothing.")

(defparameter *plan-tree-state-limit* 5000
  "The most states drawn in a plan tree drawn alone.")

(defparameter *graph-cluster-threshold* 40
  "A graph with more states than this has them grouped in clusters, one per
value of its cluster variable (see CLUSTER-VARIABLE).")

;;;# The graph

(defstruct (op-edge (:constructor make-op-edge (from to op)))
  "An edge of a state graph: OP (an OP-DEF) leads from the one-hot state FROM
to the one-hot state TO."
  (from 0 :type integer)
  (to 0 :type integer)
  (op nil :type op-def))

(defstruct (state-graph (:constructor %make-state-graph))
  "What a picture of MACHINE shows.  STATES are one-hot states in ascending
dense number; TOTAL is how many plannable states the spec has, and
REACHABLE-ONLY true when STATES are only those reachable from the initial
state.  EDGES are the OP-EDGEs among STATES, or NIL when OP-GRAPH-P is false
(too many states: only the plan tree is drawn).  GOAL is the planner's GOAL
for GOAL-FORM (as written) or NIL; PLAN-EDGES its plan tree.
CLUSTER-VARIABLE is the variable whose values group the states, or NIL."
  (machine nil :type machine)
  (states #() :type simple-vector)
  (total 0 :type (integer 0))
  (reachable-only nil)
  (op-graph-p t)
  (edges '() :type list)
  (goal nil)
  (goal-form nil)
  (plan-edges '() :type list)
  (cluster-variable nil)
  ;; The one-hot state a running controller is in, drawn highlighted, or NIL.
  (current nil))

(defmethod print-object ((graph state-graph) stream)
  (print-unreadable-object (graph stream :type t)
    (format stream "~A ~D state~:P, ~D op edge~:P~@[, plans to ~A~]"
            (lisp-text (spec-name (machine-spec (state-graph-machine graph))))
            (length (state-graph-states graph)) (length (state-graph-edges graph))
            (and (state-graph-goal graph) (bounded-lisp-text (state-graph-goal-form graph) 60)))))

(defun build-state-graph (machine &key goal)
  "The STATE-GRAPH of MACHINE (a machine, a spec or a spec's name): every
plannable state when there are at most *GRAPH-ALL-STATES-LIMIT*, else those
reachable from the initial state.  GOAL, a state expression as written in a
spec (posture.sit, a class name, (and ...)), adds its region and plan tree.
Signals an ARGUMENT-ERROR when MACHINE is none of those, and a
STATE-GRAPH-ERROR when GOAL is not a state expression of the spec,
or when there are too many states: more than *GRAPH-STATE-LIMIT* without a
goal, more than *PLAN-TREE-STATE-LIMIT* with one."
  (let* ((machine (ensure-machine machine 'build-state-graph))
         (planned-goal (and goal (find-or-plan-goal machine goal))))
    (multiple-value-bind (states reachable-only)
        (graph-states machine (if goal *plan-tree-state-limit* *graph-state-limit*))
      (let ((op-graph-p (<= (length states) *graph-state-limit*)))
        (%make-state-graph
         :machine machine :states states
         :total (machine-state-count machine) :reachable-only reachable-only
         :op-graph-p op-graph-p
         :edges (and op-graph-p (op-edges machine states))
         :goal planned-goal :goal-form goal
         :plan-edges (and planned-goal (plan-tree-edges planned-goal states))
         :cluster-variable (and (> (length states) *graph-cluster-threshold*)
                                (cluster-variable (machine-spec machine))))))))

;;;# States

(defun graph-states (machine limit)
  "The one-hot states to draw, ascending by dense number, and whether they
are only those reachable from the initial state: all of them when there are
at most *GRAPH-ALL-STATES-LIMIT* (and LIMIT).  A STATE-GRAPH-ERROR when more
than LIMIT are reachable."
  (let* ((layout (machine-layout machine))
         (count (layout-state-count layout)))
    (if (<= count (min limit *graph-all-states-limit*))
        (values (let ((states (make-array count)))
                  (dotimes (dense count states)
                    (setf (svref states dense) (dense-to-state dense layout))))
                nil)
        (values (or (bounded-reachable-states machine limit)
                    (state-graph-fail "spec ~A has ~D plannable states and more than ~D of them are reachable from its initial state: too many to draw~:[; give a goal (--goal G) to draw only its plan tree~;, even as one goal's plan tree~]"
                                      (lisp-text (spec-name (machine-spec machine))) count limit
                                      (> limit *graph-state-limit*)))
                t))))

(defun bounded-reachable-states (machine limit)
  "The one-hot states reachable from MACHINE's initial state by ops and by
events' :add/:sub (as REACHABLE-STATES finds them), ascending by dense number;
NIL as soon as there are more than LIMIT."
  (let* ((spec (machine-spec machine))
         (layout (machine-layout machine))
         (seen (states-reached (list (machine-initial-state machine))
                               (append (transition-ops spec) (event-assignment-ops spec))
                               limit)))
    (and seen
         (sort (coerce (hash-table-keys seen) 'simple-vector) #'<
               :key (lambda (state) (state-to-dense state layout))))))

(defun state-value-text (var index)
  "The INDEXth value of plannable VAR as written on a command line: true or
false for a boolean, a name in lower case, a string or number as it is."
  (let ((value (svref (var-domain var) index)))
    (cond ((eq (var-kind var) :boolean) (if (= index 1) "true" "false"))
          ((stringp value) value)
          ((symbolp value) (string-downcase (symbol-name value)))
          (t (princ-to-string value)))))

(defun state-literals (state spec)
  "The one-hot STATE as readable literals, one text VAR=VALUE per plannable
variable of SPEC: (\"posture=sit\" \"alert=awake\" ...)."
  (loop for (var . index) in (state-assignments state spec)
        collect (format nil "~A=~A" (lisp-text (var-name var)) (state-value-text var index))))

(defun cluster-variable (spec)
  "The variable whose values group a large graph's states: SPEC's first
enumerated plannable variable, else its first plannable one; NIL when none
has two values."
  (let ((vars (remove-if-not (lambda (var) (> (var-domain-size var) 1)) (plannable-variables spec))))
    (or (find :enumerated vars :key #'var-kind) (first vars))))

;;;# Op edges

(defun op-edges (machine states)
  "The OP-EDGEs among STATES (a vector of one-hot states): for each state, in
order, one per op of MACHINE's spec, in declaration order, that applies there
and changes it."
  (let ((transitions (transition-ops (machine-spec machine))))
    (loop for state across states
          nconc (loop for op in transitions
                      for next = (apply-effects state op)
                      when (and (/= next state) (op-applies-p op state))
                        collect (make-op-edge state next (planner-op-op op))))))

;;;# A goal: its region and plan tree

(defun parse-goal-cubes (form spec)
  "The cubes of the state expression FORM in SPEC; a STATE-GRAPH-ERROR saying
why when FORM is not one."
  (handler-case (with-spec-context (:spec spec :spec-name (spec-name spec) :form-places nil)
                  (check-form-structure form :what "goal")
                  (expression-cubes (parse-expression form) spec))
    (spec-error (condition)
      (state-graph-fail "goal ~A is not a state expression of spec ~A: ~A"
                        (bounded-lisp-text form 80) (lisp-text (spec-name spec))
                        (spec-error-message condition)))))

(defun find-or-plan-goal (machine form)
  "The planner's GOAL for the state expression FORM: the one MACHINE planned
when an event asks for it, else one planned now.  A STATE-GRAPH-ERROR when
FORM is not a state expression of MACHINE's spec."
  (let* ((spec (machine-spec machine))
         (cubes (parse-goal-cubes form spec)))
    (machine-goal-with-cubes machine cubes form)))

(defun state-plan (goal state)
  "The PLAN the machine runs for GOAL from the one-hot STATE: the first of
GOAL's plans whose condition holds there; NIL when GOAL is unreachable from it."
  (find-if (lambda (plan) (state-in-cube-p state (plan-condition plan))) (goal-plans goal)))

(defun op-successor (state op)
  "The one-hot state OP's effects make of STATE."
  (logior (logandc2 state (op-effect-mask op)) (op-effect-bits op)))

(defun plan-path (state plan)
  "The OP-EDGEs PLAN's ops walk from the one-hot STATE, first first."
  (loop for op in (plan-ops plan)
        for next = (op-successor state op)
        collect (make-op-edge state next op)
        do (setf state next)))

(defun plan-tree-edges (goal states)
  "The union of the paths of GOAL's plans from each of STATES (one-hot), each
edge once, in the order first walked."
  (let ((seen (make-hash-table :test 'equal))
        (edges '()))
    (loop for state across states
          for plan = (state-plan goal state)
          when plan
            do (dolist (edge (plan-path state plan))
                 (let ((key (list (op-edge-from edge) (op-edge-to edge) (op-edge-op edge))))
                   (unless (gethash key seen)
                     (setf (gethash key seen) t)
                     (push edge edges)))))
    (nreverse edges)))

(defun state-graph-note (graph)
  "One sentence saying what GRAPH shows, for its caption."
  (let* ((spec (machine-spec (state-graph-machine graph)))
         (count (length (state-graph-states graph))))
    (format nil "spec ~A: ~:[all ~D ~A state~P~*~;the ~D state~:P reachable from the initial state (of ~2*~D plannable states)~]~:[; too many for the op graph, only the plan tree is drawn~;, ~D op edge~:P (dashed: must-ask ops)~]~@[~A~]"
            (lisp-text (spec-name spec)) (state-graph-reachable-only graph) count
            ;; the reachable regime plans (and draws) only the reachable states
            (if (layout-reachable (machine-layout (state-graph-machine graph))) "reachable" "plannable") count
            (state-graph-total graph) (state-graph-op-graph-p graph) (length (state-graph-edges graph))
            (and (state-graph-goal graph)
                 (format nil "; goal ~A shaded~:[~;, its plan tree beside~]"
                         (bounded-lisp-text (state-graph-goal-form graph) 80)
                         (state-graph-op-graph-p graph))))))
