;;;; explain.lisp -- why this plan: the ops a planned machine runs from one
;;;; state towards a goal (or through an event's directives), each with the
;;;; literal it makes true for a later step's precondition or for the goal;
;;;; and, for a goal it cannot reach, why: goal literals no op adds, or the
;;;; preconditions that block in the reachable states nearest the goal.
;;;;
;;;; EXPLAIN-PLAN returns a list of steps, one struct per kind of line, and
;;;; PRINT-EXPLANATION writes them (one WRITE-EXPLANATION-STEP method each).
;;;; The ops are the controller's: the first plan whose condition holds, as
;;;; COMPILE-ACHIEVER picks it, from the state the previous step leaves.

(in-package #:player)

;;;# Literals and states as text
;;; A literal is (VARIABLE . FIELD): the values a cube allows one variable,
;;; as bits shifted to bit 0.

(defun literal-state-index (state var)
  "The index of the value plannable VAR has in one-hot STATE."
  (1- (integer-length (ldb (byte (var-domain-size var) (var-bit-offset var)) state))))

(defun literal-value-text (var index)
  "VAR's INDEXth value as text: true or false for a boolean, else its name."
  (if (eq (var-kind var) :boolean)
      (if (= index 1) "true" "false")
      (lisp-text (aref (var-domain var) index))))

(defun explained-state-text (state spec)
  "One-hot STATE as var=value words, in SPEC's declaration order."
  (format nil "~{~A~^ ~}"
          (loop for var in (plannable-variables spec)
                collect (format nil "~A=~A" (lisp-text (var-name var))
                                (literal-value-text var (literal-state-index state var))))))

(defun cube-literals (cube spec)
  "The literals (VARIABLE . FIELD) of the variables CUBE constrains."
  (loop for var in (plannable-variables spec)
        for field = (ldb (byte (var-domain-size var) (var-bit-offset var)) cube)
        unless (= field (1- (ash 1 (var-domain-size var))))
          collect (cons var field)))

(defun literal-holds-p (literal state)
  "Does one-hot STATE satisfy LITERAL?"
  (logbitp (literal-state-index state (car literal)) (cdr literal)))

(defun missing-literals (cube state spec)
  "CUBE's literals that STATE does not satisfy."
  (remove-if (lambda (literal) (literal-holds-p literal state)) (cube-literals cube spec)))

(defun literal-expression (literal spec)
  "LITERAL as a readable state expression: posture.sit, wing-at-ear, (not wing-at-ear)."
  (field-expression (car literal) (cdr literal) spec))

(defun first-cube-containing (cubes state)
  "The first of CUBES that STATE lies in, or NIL."
  (find-if (lambda (cube) (state-in-cube-p state cube)) cubes))

(defun state-after-op (op state)
  "The one-hot state after OP's effects act on STATE."
  (logior (logandc2 state (op-effect-mask op)) (op-effect-bits op)))

(defun explained-changes (before after spec)
  "The plannable variables that differ between BEFORE and AFTER, as
(NAME OLD NEW) with the values as text."
  (loop for var in (plannable-variables spec)
        for old = (literal-state-index before var)
        for new = (literal-state-index after var)
        unless (= old new)
          collect (list (var-name var) (literal-value-text var old) (literal-value-text var new))))

;;;# The steps

(defstruct (explanation-step (:constructor nil))
  "One part of an explanation, as EXPLAIN-PLAN returns it; WRITE-EXPLANATION-STEP
prints it.")

(defstruct (explanation-start (:include explanation-step)
                              (:constructor make-explanation-start (spec-name state)))
  "Where the explanation starts: SPEC-NAME and the STATE (var=value text)."
  spec-name (state "" :type string))

(defstruct (explained-directive (:include explanation-step)
                                (:constructor make-explained-directive (text)))
  "A heading: an event (\"event ev-thanks\") or one of its :op directives."
  (text "" :type string))

(defstruct (explained-goal (:include explanation-step)
                           (:constructor make-explained-goal (kind expression holds &optional op-name)))
  "A goal about to be planned for. KIND is :GOAL (EXPLAIN-PLAN's :goal), :STATE
(an event's :state) or :PRECONDITION (of the op OP-NAME); EXPRESSION is the goal
as written; HOLDS is true when it holds already, so no op is needed."
  (kind :goal :type (member :goal :state :precondition))
  expression holds op-name)

(defstruct (explained-op (:include explanation-step)
                         (:constructor make-explained-op
                             (number name changes reason target literals &optional later)))
  "Op NUMBER (counted from 1 over the whole explanation) NAME, which changes
CHANGES ((VARIABLE OLD NEW) ...). REASON says why it runs: :PRECONDITION (it
makes LITERALS of op TARGET's precondition true; LATER is TARGET's step number
when that is not the next step), :GOAL (it makes LITERALS of the goal TARGET
true), :REQUESTED (an event's :op, TARGET the event) or NIL (nothing later needs
what it sets)."
  (number 0 :type (integer 0))
  name changes reason target literals later)

(defstruct (explained-assignment (:include explanation-step)
                                 (:constructor make-explained-assignment (text changes)))
  "An event's :add or :sub of a literal: TEXT, and the CHANGES it makes."
  (text "" :type string)
  changes)

(defstruct (explained-condition (:include explanation-step)
                                (:constructor make-explained-condition (expression outcome)))
  "An event's :if: the condition EXPRESSION and its OUTCOME, :TRUE or :FALSE in
this state, or :ASSUMED when it compares run-time values (the body is then
explained as if it held)."
  expression (outcome :true :type (member :true :false :assumed)))

(defstruct (blocked-state (:constructor make-blocked-state (state missing blockers)))
  "A reachable state nearest an unreachable goal: its STATE (text), the goal
literals MISSING there, and BLOCKERS, one (OP FAILING UNDONE) per op that would
set a missing literal: the literals of its precondition that fail there, or
else the goal literals its other effects would undo."
  state missing blockers)

(defstruct (explained-unreachable (:include explanation-step)
                                  (:constructor make-explained-unreachable
                                      (expression &key contradictory unadded nearest
                                                    more-states max-depth event)))
  "Goal EXPRESSION cannot be reached from the state. CONTRADICTORY: it can never
hold. UNADDED: ((LITERAL MUST-ASK-OP-NAMES) ...), goal literals no plannable op
adds. NEAREST: BLOCKED-STATEs, the reachable states fewest goal literals away
(MORE-STATES more as near are not shown). MAX-DEPTH: the goal is reachable, but
only by plans longer than the spec's :max-depth. EVENT: the event that stops
here, skipping the rest of its directives."
  expression contradictory unadded nearest (more-states 0) max-depth event)

;;;# Printing

(defgeneric write-explanation-step (step stream)
  (:documentation "Write STEP's lines, each ending in a newline, to STREAM."))

(defun print-explanation (steps &optional (stream *standard-output*))
  "Write STEPS (what EXPLAIN-PLAN returns) to STREAM (default standard output),
a line or a few per step. Signals an ARGUMENT-ERROR when STEPS is not a list of
explanation steps or STREAM no output stream."
  (check-argument 'print-explanation 'steps steps
                  (lambda (x) (and (alexandria:proper-list-p x) (every #'explanation-step-p x)))
                  "a list of explanation steps (from explain-plan)")
  (check-argument 'print-explanation 'stream stream #'output-stream-designator-p
                  "an output stream, T (standard output) or NIL")
  (let ((stream (if (member stream '(t nil)) *standard-output* stream)))
    (dolist (step steps steps)
      (write-explanation-step step stream))))

(defmethod print-object ((step explanation-step) stream)
  ;; One line at the REPL: the step's first printed line.
  (print-unreadable-object (step stream :type t)
    (let ((text (with-output-to-string (out) (write-explanation-step step out))))
      (write-string (truncate-text (string-trim " " (subseq text 0 (position #\Newline text))) 100)
                    stream))))

(defun changes-text (changes)
  "CHANGES as \"posture: sit -> stand, holding-note: false -> true\"."
  (format nil "~{~A~^, ~}" (loop for (name old new) in changes
                                 collect (format nil "~A: ~A -> ~A" (lisp-text name) old new))))

(defun literals-text (literals)
  "LITERALS (expressions) joined by \" and \"."
  (format nil "~{~A~^ and ~}" (mapcar #'lisp-text literals)))

(defmethod write-explanation-step ((step explanation-start) stream)
  (format stream "~A, from ~A~%" (lisp-text (explanation-start-spec-name step))
          (explanation-start-state step)))

(defmethod write-explanation-step ((step explained-directive) stream)
  (format stream "~A~%" (explained-directive-text step)))

(defmethod write-explanation-step ((step explained-goal) stream)
  (let ((goal (lisp-text (explained-goal-expression step)))
        (holds (explained-goal-holds step)))
    (ecase (explained-goal-kind step)
      (:goal (format stream "goal ~A~:[:~; already holds: nothing to do~]~%" goal holds))
      (:state (format stream ":state ~A~:[~; already holds~]~%" goal holds))
      (:precondition
       (format stream "  ~A's precondition ~A~:[:~; already holds~]~%"
               (lisp-text (explained-goal-op-name step)) goal holds)))))

(defun op-reason-text (step)
  "Why the op of STEP, an EXPLAINED-OP, runs, as a phrase."
  (let ((target (explained-op-target step))
        (literals (explained-op-literals step)))
    (ecase (explained-op-reason step)
      (:precondition (format nil "for ~A's precondition ~A~@[, at step ~D~]"
                             (lisp-text target) (literals-text literals) (explained-op-later step)))
      (:goal (if (equal (lisp-text target) (if (rest literals)
                                               (lisp-text (cons 'and literals))
                                               (lisp-text (first literals))))
                 (format nil "achieves the goal ~A" (lisp-text target))
                 (format nil "achieves ~A of the goal ~A" (literals-text literals) (lisp-text target))))
      (:requested (format nil "requested by ~A" (lisp-text target)))
      ((nil) "needed by no later step"))))

(defmethod write-explanation-step ((step explained-op) stream)
  (let ((changes (explained-op-changes step)))
    (format stream "  ~D. ~14A~@[ (~A)~]  ~A~%" (explained-op-number step)
            (lisp-text (explained-op-name step)) (and changes (changes-text changes))
            (op-reason-text step))))

(defmethod write-explanation-step ((step explained-assignment) stream)
  (format stream "~A~@[   (~A)~]~%" (explained-assignment-text step)
          (and (explained-assignment-changes step)
               (changes-text (explained-assignment-changes step)))))

(defmethod write-explanation-step ((step explained-condition) stream)
  (format stream ":if ~A ~A~%" (lisp-text (explained-condition-expression step))
          (ecase (explained-condition-outcome step)
            (:true "holds in this state")
            (:false "does not hold in this state: its directives are skipped")
            (:assumed "compares run-time values: explained as if it held"))))

(defun write-blocked-state (blocked stream)
  "Write one BLOCKED-STATE of an unreachable goal's explanation."
  (format stream "  from ~A, the goal lacks ~A:~%" (blocked-state-state blocked)
          (literals-text (blocked-state-missing blocked)))
  (if (null (blocked-state-blockers blocked))
      (format stream "    no op sets ~:[it~;them~]~%" (rest (blocked-state-missing blocked)))
      (loop for (op failing undone) in (blocked-state-blockers blocked)
            do (if failing
                   (format stream "    ~A is blocked: its precondition needs ~A~%"
                           (lisp-text op) (literals-text failing))
                   (format stream "    ~A would undo ~A~%" (lisp-text op) (literals-text undone))))))

(defmethod write-explanation-step ((step explained-unreachable) stream)
  (let ((goal (lisp-text (explained-unreachable-expression step))))
    (cond ((explained-unreachable-contradictory step)
           (format stream "goal ~A can never hold: no state satisfies it~%" goal))
          ((explained-unreachable-max-depth step)
           (format stream "goal ~A is reachable, but only by a plan longer than :max-depth ~D~%"
                   goal (explained-unreachable-max-depth step)))
          ((explained-unreachable-unadded step)
           (format stream "goal ~A is unreachable from this state: no op adds what it needs~%" goal)
           (loop for (literal must-ask) in (explained-unreachable-unadded step)
                 do (format stream "  no op's effects set ~A~@[ (only must-ask ~{~A~^, ~}, which plans cannot use)~]~%"
                            (lisp-text literal) (mapcar #'lisp-text must-ask))))
          (t
           (format stream "goal ~A is unreachable from this state: preconditions block it~%" goal)
           (dolist (blocked (explained-unreachable-nearest step))
             (write-blocked-state blocked stream))
           (when (plusp (explained-unreachable-more-states step))
             (format stream "  (and ~D more reachable state~:P as near)~%"
                     (explained-unreachable-more-states step)))))
    (when (explained-unreachable-event step)
      (format stream "~A stops here: the rest of its directives are skipped~%"
              (lisp-text (explained-unreachable-event step))))))

;;;# Why a goal cannot be reached

(defun op-sets-literal-p (op literal)
  "Do OP's effects set LITERAL's variable to a value LITERAL allows?"
  (let ((effect (assoc (car literal) (op-effects op))))
    (and effect (logbitp (cdr effect) (cdr literal)))))

(defun plan-op-defs (machine)
  "The OP-DEFs MACHINE's plans may use."
  (mapcar #'planner-op-op (machine-operators machine)))

(defun unadded-literals (cubes state machine)
  "When every cube of goal CUBES lacks, in STATE, a literal that no op plans may
use adds: those literals, each as (EXPRESSION MUST-ASK-OP-NAMES), the must-ask
ops being those that would set it; else NIL."
  (let* ((spec (machine-spec machine))
         (ops (plan-op-defs machine))
         (per-cube (mapcar (lambda (cube)
                             (remove-if (lambda (literal)
                                          (some (lambda (op) (op-sets-literal-p op literal)) ops))
                                        (missing-literals cube state spec)))
                           cubes)))
    (when (every #'identity per-cube)
      (loop for literal in (remove-duplicates (reduce #'append per-cube) :test #'equal :from-end t)
            collect (list (literal-expression literal spec)
                          (loop for op in (spec-ops spec)
                                when (and (op-must-ask op) (op-sets-literal-p op literal))
                                  collect (op-name op)))))))

(defun states-reachable-from (state machine)
  "Every state MACHINE's plannable ops reach from STATE with their preconditions
respected, STATE first, in breadth-first order."
  (let* ((layout (machine-layout machine))
         (seen (make-array (layout-state-count layout) :element-type 'bit :initial-element 0))
         (queue (make-queue))
         (found '()))
    (setf (sbit seen (state-to-dense state layout)) 1)
    (enqueue state queue)
    (loop until (queue-empty-p queue)
          do (let ((current (dequeue queue)))
               (push current found)
               (dolist (op (machine-operators machine))
                 (when (first-cube-containing (planner-op-precondition op) current)
                   (let* ((next (apply-effects current op))
                          (dense (state-to-dense next layout)))
                     (when (zerop (sbit seen dense))
                       (setf (sbit seen dense) 1)
                       (enqueue next queue)))))))
    (nreverse found)))

(defun goal-literal-distance (cubes state spec)
  "(VALUES COUNT CUBE): the fewest literals of a cube of CUBES that STATE lacks, and that cube."
  (let ((best nil) (best-cube nil))
    (dolist (cube cubes (values best best-cube))
      (let ((count (length (missing-literals cube state spec))))
        (when (or (null best) (< count best))
          (setf best count best-cube cube))))))

(defun closest-precondition-failures (op state spec)
  "The literals of OP's precondition that fail in STATE, for the precondition
cube that fails on fewest; NIL when the precondition holds."
  (if (null (op-precond op))
      '()
      (let ((failures (mapcar (lambda (cube) (missing-literals cube state spec))
                              (expression-cubes (op-precond op) spec))))
        (reduce (lambda (a b) (if (< (length b) (length a)) b a)) failures))))

(defun literal-blockers (missing cube state machine)
  "For each plannable op that would set a literal of MISSING (CUBE's literals
STATE lacks): (OP-NAME FAILING UNDONE), FAILING its precondition's literals
that fail in STATE, or, when it applies, UNDONE the literals of CUBE its effects
would make false."
  (let ((spec (machine-spec machine)))
    (loop for op in (plan-op-defs machine)
          when (some (lambda (literal) (op-sets-literal-p op literal)) missing)
            collect (let ((failing (closest-precondition-failures op state spec))
                          (next (state-after-op op state)))
                      (list (op-name op)
                            (mapcar (lambda (l) (literal-expression l spec)) failing)
                            (and (null failing)
                                 (loop for literal in (cube-literals cube spec)
                                       when (and (literal-holds-p literal state)
                                                 (not (literal-holds-p literal next)))
                                         collect (literal-expression literal spec))))))))

(defparameter *nearest-states-shown* 3
  "How many of the reachable states nearest an unreachable goal an explanation shows.")

(defun blocked-states (cubes states machine)
  "(VALUES BLOCKED-STATES MORE DISTANCE): for the STATES (reachable ones) fewest
goal literals away from goal CUBES, the first *NEAREST-STATES-SHOWN* as
BLOCKED-STATEs, how many more are as near, and that number of literals."
  (let* ((spec (machine-spec machine))
         (distance (reduce #'min states :key (lambda (s) (goal-literal-distance cubes s spec))))
         (nearest (remove-if-not (lambda (s) (= distance (goal-literal-distance cubes s spec))) states)))
    (values (loop for state in nearest
                  repeat *nearest-states-shown*
                  collect (let* ((cube (nth-value 1 (goal-literal-distance cubes state spec)))
                                 (missing (missing-literals cube state spec)))
                            (make-blocked-state (explained-state-text state spec)
                                                (mapcar (lambda (l) (literal-expression l spec)) missing)
                                                (literal-blockers missing cube state machine))))
            (max 0 (- (length nearest) *nearest-states-shown*))
            distance)))

(defun explain-unreachable (goal expression state machine &optional event)
  "The EXPLAINED-UNREACHABLE for GOAL (written EXPRESSION), which no plan of
MACHINE reaches from STATE; EVENT, if any, stops there."
  (let ((cubes (goal-cubes goal))
        (spec (machine-spec machine)))
    (cond ((null cubes)
           (make-explained-unreachable expression :contradictory t :event event))
          ((unadded-literals cubes state machine)
           (make-explained-unreachable expression :unadded (unadded-literals cubes state machine)
                                                  :event event))
          (t (multiple-value-bind (nearest more distance)
                 (blocked-states cubes (states-reachable-from state machine) machine)
               (if (zerop distance)
                   (make-explained-unreachable expression :max-depth (spec-max-depth spec) :event event)
                   (make-explained-unreachable expression :nearest nearest :more-states more
                                                          :event event)))))))

;;;# Why each op of a plan

(defstruct (explainer (:constructor make-explainer (machine state)))
  "What EXPLAIN-PLAN carries from step to step: the MACHINE, the STATE the
steps so far leave, how many ops they ran (COUNT), and the STEPS, latest first."
  machine state (count 0 :type (integer 0)) (steps '()))

(defun add-explanation-step (explainer step)
  "Add STEP to EXPLAINER's steps."
  (push step (explainer-steps explainer)))

(defun op-precondition-cubes (op spec)
  "OP's precondition as cubes: every state when it has none."
  (if (op-precond op)
      (expression-cubes (op-precond op) spec)
      (list (top-cube spec))))

(defun plan-run-states (ops state)
  "The states a run of OPS passes through: STATE, then the state after each op."
  (cons state (loop for op in ops
                    do (setf state (state-after-op op state))
                    collect state)))

(defun need-cubes (ops states final-cubes spec)
  "For each op of OPS, the cube of what the step after it needs, holding in the
state it leaves (STATES from RUN-STATES): the next op's precondition, or
FINAL-CUBES after the last op."
  (loop for (nil . rest) on ops
        for after in (rest states)
        collect (or (first-cube-containing (if rest (op-precondition-cubes (first rest) spec) final-cubes)
                                     after)
                    (top-cube spec))))

(defun op-purpose (i ops states needs spec)
  "(VALUES J LITERALS): the first step J, from op I of OPS on, whose need (of
NEEDS) constrains a variable op I changed, still at the value op I gave it;
the literals it needs of those variables. NIL when no step does."
  (let* ((before (nth i states))
         (after (nth (1+ i) states))
         (changed (loop for (var) in (op-effects (nth i ops))
                        unless (= (literal-state-index before var) (literal-state-index after var))
                          collect var)))
    (loop for j from i below (length ops)
          for cube in (nthcdr i needs)
          for state in (nthcdr (1+ j) states)
          for literals = (loop for literal in (cube-literals cube spec)
                               when (and (member (car literal) changed)
                                         (= (literal-state-index state (car literal))
                                            (literal-state-index after (car literal))))
                                 collect literal)
          when literals
            return (values j literals))))

(defun explain-op-purpose (explainer i ops states needs final)
  "The EXPLAINED-OP for op I of OPS, run as the plan for FINAL: (:GOAL
EXPRESSION) or (:PRECONDITION OP-NAME STEP-NUMBER)."
  (let* ((spec (machine-spec (explainer-machine explainer)))
         (base (explainer-count explainer))
         (last (1- (length ops))))
    (multiple-value-bind (j literals) (op-purpose i ops states needs spec)
      (make-explained-op (+ base i 1) (op-name (nth i ops))
                         (explained-changes (nth i states) (nth (1+ i) states) spec)
                         (cond ((null j) nil) ((< j last) :precondition) (t (first final)))
                         (cond ((null j) nil) ((< j last) (op-name (nth (1+ j) ops))) (t (second final)))
                         (mapcar (lambda (l) (literal-expression l spec)) literals)
                         (cond ((or (null j) (= j i)) nil)
                               ((< j last) (+ base j 2))
                               (t (third final)))))))

(defun explain-plan-ops (explainer ops final-cubes final)
  "Add an EXPLAINED-OP for each of OPS, the plan run from EXPLAINER's state to
reach FINAL-CUBES (described by FINAL, see EXPLAIN-OP-PURPOSE); move the state
and the count past them."
  (let* ((spec (machine-spec (explainer-machine explainer)))
         (states (plan-run-states ops (explainer-state explainer)))
         (needs (need-cubes ops states final-cubes spec)))
    (loop for i below (length ops)
          do (add-explanation-step explainer (explain-op-purpose explainer i ops states needs final)))
    (incf (explainer-count explainer) (length ops))
    (setf (explainer-state explainer) (car (last states)))))

(defun plan-applying-in (goal state)
  "The plan of GOAL the controller runs from STATE (the first whose condition
holds), or NIL."
  (find-if (lambda (plan) (state-in-cube-p state (plan-condition plan))) (goal-plans goal)))

(defun explain-goal (explainer goal kind expression &key op event)
  "Add the steps achieving planned GOAL from EXPLAINER's state: a heading (KIND
and EXPRESSION as for MAKE-EXPLAINED-GOAL; OP the op whose precondition it is),
then each op of the plan. Returns true; when no plan applies, adds why (EVENT
stopping there) and returns NIL."
  (let* ((machine (explainer-machine explainer))
         (plan (plan-applying-in goal (explainer-state explainer))))
    (if (null plan)
        (progn (add-explanation-step explainer (explain-unreachable goal expression (explainer-state explainer)
                                                        machine (and event (event-name event))))
               nil)
        (let ((ops (plan-ops plan)))
          (add-explanation-step explainer (make-explained-goal kind expression (null ops) (and op (op-name op))))
          (explain-plan-ops explainer ops (goal-cubes goal)
                            (if op
                                (list :precondition (op-name op) (+ (explainer-count explainer) (length ops) 1))
                                (list :goal expression)))
          t))))

;;;# Goals and events

(defun machine-goal-with-cubes (machine cubes form)
  "MACHINE's goal with canonical CUBES, or a new goal (written FORM) planned on the spot."
  (let ((spec (machine-spec machine)))
    (or (find-goal cubes (coerce (machine-goal-table machine) 'list))
        (solve-goal (%make-goal :cubes cubes :forms (list form) :expression (cubes-expression cubes spec))
                    (machine-operators machine) (machine-layout machine) spec))))

(defun explain-goal-form (explainer form)
  "Add the steps reaching the state expression FORM. Signals a SPEC-ERROR when
FORM is not a state expression of the spec."
  (let* ((machine (explainer-machine explainer))
         (spec (machine-spec machine))
         (cubes (let ((*spec* spec) (*current-spec-name* (spec-name spec)))
                  (expression-cubes (parse-expression form) spec))))
    (explain-goal explainer (machine-goal-with-cubes machine cubes form) :goal form)))

(defgeneric explain-directive (kind directive explainer event)
  (:documentation "Add the steps of EVENT's parsed DIRECTIVE, whose first element
is KIND, to EXPLAINER. True to go on with the next directive, NIL when the
event fails here."))

(defmethod explain-directive (kind directive explainer event)
  ;; :label, :time, :code, :c++ and number increments leave the planned state alone.
  (declare (ignore kind directive explainer event))
  t)

(defmethod explain-directive ((kind (eql :achieve)) directive explainer event)
  (destructuring-bind (ast form) (rest directive)
    (explain-goal explainer (machine-goal-for (explainer-machine explainer) ast) :state form
                  :event event)))

(defun explain-requested-op (explainer op event)
  "Add the EXPLAINED-OP for OP, run because EVENT's :op asks for it."
  (let* ((spec (machine-spec (explainer-machine explainer)))
         (before (explainer-state explainer))
         (after (state-after-op op before)))
    (add-explanation-step explainer (make-explained-op (incf (explainer-count explainer)) (op-name op)
                                           (explained-changes before after spec)
                                           :requested (event-name event) '()))
    (setf (explainer-state explainer) after)))

(defmethod explain-directive ((kind (eql :op)) directive explainer event)
  (let ((op (second directive)))
    (add-explanation-step explainer (make-explained-directive (format nil ":op ~A" (lisp-text (op-name op)))))
    (when (or (null (op-precond op))
              (explain-goal explainer (machine-goal-for (explainer-machine explainer) (op-precond op))
                            :precondition (op-precond-form op) :op op :event event))
      (explain-requested-op explainer op event)
      t)))

(defmethod explain-directive ((kind (eql :assign)) directive explainer event)
  (declare (ignore event))
  (destructuring-bind (var index) (rest directive)
    (let* ((spec (machine-spec (explainer-machine explainer)))
           (before (explainer-state explainer))
           (after (logior (logandc2 before (var-field-mask var)) (var-value-bit var index))))
      (add-explanation-step explainer (make-explained-assignment
                           (format nil "sets ~A" (lisp-text (field-expression var (ash 1 index) spec)))
                           (explained-changes before after spec)))
      (setf (explainer-state explainer) after)
      t)))

(defmethod explain-directive ((kind (eql :if)) directive explainer event)
  (destructuring-bind (condition body form) (rest directive)
    (let* ((spec (machine-spec (explainer-machine explainer)))
           (outcome (cond ((not (state-only-p condition)) :assumed)
                          ((first-cube-containing (expression-cubes condition spec) (explainer-state explainer))
                           :true)
                          (t :false))))
      (add-explanation-step explainer (make-explained-condition (first form) outcome))
      (or (eq outcome :false)
          (explain-directives body explainer event)))))

(defun explain-directives (directives explainer event)
  "Explain EVENT's parsed DIRECTIVES in turn, until one fails; true when none does."
  (loop for directive in directives
        always (explain-directive (first directive) directive explainer event)))

(defun find-explained-event (spec name)
  "SPEC's event NAME (a symbol or string); UNKNOWN-EVENT when there is none."
  (or (find (if (stringp name) (string-upcase name) (name-key name)) (spec-events spec)
            :key (lambda (event) (name-key (event-name event))) :test #'string=)
      (error 'unknown-event :name name :known (mapcar #'event-name (spec-events spec)))))

;;;# The entry point

(defun explanation-initial-state (spec initial)
  "The one-hot state of SPEC's initial values with INITIAL (an alist of variable
name -> value) applied; a SPEC-ERROR for an unknown variable or a bad value."
  (loop for (var . value) in (initial-assignments spec initial)
        when (plannable-p var) sum (var-value-bit var value)))

(defun initial-alist-p (x)
  "Is X a proper alist ((VARIABLE . VALUE) ...) of bounded, finite forms, symbols for variables?"
  (and (proper-form-list-p x) (finite-form-p x)
       (every (lambda (entry) (and (consp entry) (symbolp (car entry)))) x)))

(defun explain-plan (machine &key initial (goal nil goal-p) event)
  "Explain what MACHINE (a machine, a spec or a spec's name) does from the
state of its initial values overridden by INITIAL (an alist ((VARIABLE . VALUE)
...)), for exactly one of GOAL (a state expression, as in :state) or EVENT (an
event's name, a symbol or string). Returns a list of EXPLANATION-STEPs, for
PRINT-EXPLANATION: where it starts; then for GOAL, or for each directive of
EVENT in turn, the ops the controller would run, each EXPLAINED-OP saying which
literal of a later op's precondition or of the goal it makes true; a goal that
already holds says so; an unreachable goal ends it with an EXPLAINED-UNREACHABLE
saying why (goal literals no op adds, or the preconditions that block in the
reachable states nearest the goal). Signals UNKNOWN-EVENT for an event the spec
lacks, a SPEC-ERROR for a GOAL that is no state expression of the spec or an
unknown variable or bad value in INITIAL, and an ARGUMENT-ERROR for an argument
of the wrong kind or for giving both or neither of GOAL and EVENT."
  (check-argument 'explain-plan 'machine machine #'machine-designator-p *machine-designator*)
  (check-argument 'explain-plan :initial initial #'initial-alist-p
                  "a proper alist ((variable . value) ...) with symbols for variables and finite numbers")
  (unless (if goal-p (null event) event)
    (argument-fail 'explain-plan :event event
                   (if goal-p "NIL when :goal is given (give one of :goal and :event)" "an event's name, or give :goal")))
  (when goal-p
    (check-argument 'explain-plan :goal goal (lambda (x) (and (bounded-form-p x) (finite-form-p x)))
                    "a state expression"))
  (when event
    (check-argument 'explain-plan :event event #'name-designator-p "an event's name (a symbol or string)"))
  (let* ((machine (ensure-machine machine 'explain-plan))
         (spec (machine-spec machine))
         (explainer (make-explainer machine (explanation-initial-state spec initial))))
    (add-explanation-step explainer (make-explanation-start (spec-name spec)
                                                (explained-state-text (explainer-state explainer) spec)))
    (if goal-p
        (explain-goal-form explainer goal)
        (let ((event (find-explained-event spec event)))
          (add-explanation-step explainer (make-explained-directive (format nil "event ~A" (lisp-text (event-name event)))))
          (explain-directives (event-directives event) explainer event)))
    (reverse (explainer-steps explainer))))
