;;;; explanation-steps.lisp -- what EXPLAIN-PLAN returns: one struct per kind
;;;; of line (a goal, an op and what it achieves, a condition, a failure), the
;;;; literals and states they mention as text, and how each prints.

(in-package #:player.inspect)

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
