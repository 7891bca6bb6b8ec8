;;;; reference-bfs.lisp -- an independent reference planner for random specs.
;;;;
;;;; A plain explicit-state breadth-first search over a SPEC-MODEL (see
;;;; random-specs.lisp). It enumerates every state of the model, evaluates
;;;; preconditions and goals with its own evaluator over the model's own
;;;; expression ASTs, and never calls the planner or anything else of Player,
;;;; so Player's plans can be checked against it.
;;;;
;;;; The semantics it encodes (the language's, restated):
;;;;  * a state gives each variable one value (a vector of value indices);
;;;;  * the operators plans may use are the ops that are not :must-ask, and every
;;;;    macro-op; an operator applies where its precondition holds (none: always)
;;;;    and leads to the state with its declared effects set, everything else kept
;;;;    (a macro's :seq does not matter to the state it leads to);
;;;;  * a plan has at most MAX-DEPTH operators, so a state whose shortest path to
;;;;    the goal is longer counts as unreachable.

(in-package #:player-tests)

;;; States

(defun model-state-count (model)
  "How many states MODEL has: the product of its domain sizes."
  (reduce #'* (model-variables model) :key (lambda (var) (length (mvar-domain var)))))

(defun model-state-index (model state)
  "The number of STATE (a vector of value indices), mixed radix, variable 0 lowest."
  (loop with index = 0
        for i from (1- (model-variable-count model)) downto 0
        do (setf index (+ (* index (length (mvar-domain (svref (model-variables model) i))))
                          (svref state i)))
        finally (return index)))

(defun model-index-state (model index)
  "The state numbered INDEX, as a fresh vector of value indices."
  (let ((state (make-array (model-variable-count model))))
    (loop for var across (model-variables model)
          for i from 0
          do (multiple-value-bind (rest value) (floor index (length (mvar-domain var)))
               (setf (svref state i) value
                     index rest)))
    state))

(defun model-state-alist (model state)
  "STATE as ((NAME . VALUE) ...) with the domain values themselves (T/NIL for booleans)."
  (loop for var across (model-variables model)
        for value across state
        collect (cons (mvar-name var) (svref (mvar-domain var) value))))

(defun model-state-from-alist (model alist)
  "The state vector of ALIST ((NAME . VALUE) ...): names and enumerated values
are matched by symbol name, booleans by truth. NIL if a variable is missing or
a value is not in its domain."
  (let ((state (make-array (model-variable-count model))))
    (loop for var across (model-variables model)
          for i from 0
          for entry = (assoc (symbol-name (mvar-name var)) alist
                             :key (lambda (name) (and (symbolp name) (symbol-name name)))
                             :test #'equal)
          do (unless entry (return-from model-state-from-alist nil))
             (setf (svref state i)
                   (if (eq (mvar-kind var) :boolean)
                       (if (cdr entry) 1 0)
                       (or (position (cdr entry) (mvar-domain var)
                                     :test (lambda (a b) (and (symbolp a) (symbolp b)
                                                              (string= (symbol-name a) (symbol-name b)))))
                           (return-from model-state-from-alist nil)))))
    state))

;;; Expressions and operators

(defun model-eval (ast state)
  "The truth of model expression AST in STATE."
  (ecase (first ast)
    (:const (and (second ast) t))
    (:is (= (svref state (second ast)) (third ast)))
    (:not (not (model-eval (second ast) state)))
    (:and (every (lambda (e) (model-eval e state)) (rest ast)))
    (:or (some (lambda (e) (model-eval e state)) (rest ast)))))

(defun model-op-applicable-p (op state)
  "True when OP's precondition (none: always) holds in STATE."
  (or (null (mop-precond op)) (model-eval (mop-precond op) state)))

(defun model-apply-effects (op state)
  "The state after OP's declared effects act on STATE (a fresh vector)."
  (let ((next (copy-seq state)))
    (loop for (i . k) in (mop-effects op) do (setf (svref next i) k))
    next))

(defun model-plan-operators (model)
  "The operators plans may use: ops that are not :must-ask, and macro-ops."
  (remove-if (lambda (op) (and (eq (mop-kind op) :op) (mop-must-ask op))) (model-ops model)))

;;; The search

(defun reference-predecessors (model)
  "A vector: for each state number, the numbers of the states one plan operator
leads from into it (self-loops left out)."
  (let* ((count (model-state-count model))
         (predecessors (make-array count :initial-element '()))
         (operators (model-plan-operators model)))
    (dotimes (index count predecessors)
      (let ((state (model-index-state model index)))
        (dolist (op operators)
          (when (model-op-applicable-p op state)
            (let ((next (model-state-index model (model-apply-effects op state))))
              (unless (= next index)
                (pushnew index (svref predecessors next))))))))))

(defun reference-distances (model goal &key (max-depth (model-max-depth model))
                                            (predecessors (reference-predecessors model)))
  "For every state number of MODEL, the length of the shortest plan from that
state to one where model expression GOAL holds, or NIL when there is none of at
most MAX-DEPTH operators. A breadth-first search backwards from the goal states
over PREDECESSORS (from REFERENCE-PREDECESSORS, which may be passed in to share
it between goals)."
  (let* ((count (model-state-count model))
         (distances (make-array count :initial-element nil))
         (frontier '()))
    (dotimes (index count)
      (when (model-eval goal (model-index-state model index))
        (setf (svref distances index) 0)
        (push index frontier)))
    (loop for depth from 1 to max-depth
          while frontier
          do (let ((next '()))
               (dolist (index frontier)
                 (dolist (previous (svref predecessors index))
                   (unless (svref distances previous)
                     (setf (svref distances previous) depth)
                     (push previous next))))
               (setf frontier next)))
    distances))
