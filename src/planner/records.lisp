;;;; records.lisp -- the planner's records, declared before the files that
;;;; read them so that their accessors are inlined everywhere: an operator as
;;;; the planner sees it (made in regression.lisp), a goal with its plans
;;;; (goals.lisp) and a machine, a planned spec (machine.lisp).

(in-package #:player.planner)

(defstruct (planner-op (:constructor %make-planner-op))
  "An operator as the planner sees it: precondition cubes and one-hot effects."
  (op nil :type op-def)
  ;; DNF cubes; (TOP) when unconditional.
  (precondition '() :type list)
  ;; Fields of the variables the op sets.
  (effect-mask 0 :type integer)
  ;; The value bits it sets them to.
  (effect-bits 0 :type integer)
  ;; Seconds, exactly, for duration-optimal plans (uniform-cost.lisp).
  (duration 0 :type rational))

(defstruct (goal (:constructor %make-goal))
  "A distinct goal and its plans."
  (id 0 :type (integer 0))
  ;; Canonical DNF.
  (cubes '() :type list)
  ;; Readable canonical expression.
  (expression nil)
  ;; The goal as written, once per distinct writing.
  (forms '() :type list)
  ;; PLANs in the order they are tried (breadth first, or cheapest first).
  (plans #() :type simple-vector)
  ;; States from which the goal is reachable.
  (solved-count 0 :type (integer 0))
  ;; Bitmap of those states (dense numbering).
  (solved nil)
  ;; True when :MAX-DEPTH cut the search short.
  (truncatedp nil))

(defmethod print-object ((goal goal) stream)
  (print-unreadable-object (goal stream :type t)
    (format stream "~D ~A, ~D plan~:P" (1+ (goal-id goal)) (bounded-lisp-text (goal-expression goal) 80)
            (length (goal-plans goal)))))

(defstruct (machine (:constructor %make-machine))
  "A spec with plans from every state to every goal, ready for a code generator."
  (spec nil :type spec)
  (layout nil :type layout)
  ;; GOALs, by id.
  (goal-table #() :type simple-vector)
  ;; Goal AST -> GOAL.
  (goal-of (make-hash-table :test 'eq))
  ;; The PLANNER-OPs plans are built from.
  (operators '() :type list)
  ;; One-hot state of the declared initial values.
  (initial-state 0 :type integer)
  ;; Plannable variables some autoscript watches, in declaration order.
  (watched-variables '() :type list)
  ;; The one-hot fields of those variables.
  (autoscript-mask 0 :type integer)
  ;; How many goal rows planning built; the others were reused (plan-memo.lisp).
  (rows-built 0 :type (integer 0))
  ;; The units of work planning did (planning-budget.lisp).
  (planning-work 0 :type (integer 0))
  (compile-seconds 0d0 :type double-float))

(defmethod print-object ((machine machine) stream)
  ;; One line at the REPL: the plan tables are for PLANS and DESCRIBE.
  (print-unreadable-object (machine stream :type t)
    (format stream "~A ~D goal~:P, ~D state~:P" (lisp-text (spec-name (machine-spec machine)))
            (length (machine-goal-table machine)) (layout-state-count (machine-layout machine)))))
