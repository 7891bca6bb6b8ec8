;;;; interruption.lisp -- what a timed controller may do with a busy character:
;;;; the event's (:when-busy POLICY), the op's :interrupt points and the
;;;; state an op leaves when it is cut (:if-cut).  The CHI'95 paper's open
;;;; problem: fly, then sit a moment later -- sequential, preempt, override or
;;;; interleave.

(in-package #:player.spec)

(defparameter *when-busy-policies* '(:queue :preempt :override :interleave)
  "What a timed controller may do with an event that arrives while it is busy:
wait for the running event (:QUEUE, the default), cut it and run the new one
(:PREEMPT), drop the new one (:OVERRIDE), or cut it, run the new one and then
finish the old one from wherever that left the character (:INTERLEAVE).")

(defparameter *default-when-busy* :queue
  "The policy of an event when neither it nor its spec's (:when-busy POLICY) names one.")

(defun when-busy-policy (thing)
  "The policy keyword THING names (any package, any case), or NIL."
  (find-if (lambda (known) (word-p thing (symbol-name known))) *when-busy-policies*))

(defun parse-when-busy (thing form)
  "THING as a policy of *WHEN-BUSY-POLICIES*; else a SPEC-SYNTAX-ERROR about FORM."
  (or (when-busy-policy (unquote thing))
      (spec-fail 'spec-syntax-error form "unknown :when-busy policy ~A (allowed: ~{~A~^, ~})"
                 (bounded-lisp-text (unquote thing) 40) (mapcar #'lisp-text *when-busy-policies*))))

(defun spec-when-busy (spec)
  "The policy SPEC's events follow when they name none."
  (getf (spec-options spec) :when-busy *default-when-busy*))

(defun event-policy (event spec)
  "EVENT's :when-busy policy, else SPEC's default."
  (or (event-when-busy event) (spec-when-busy spec)))

(defparameter *event-option-keys* '(:when-busy)
  "Options an event may give as (:KEY VALUE) lists between its name and its directives.")

(defun parse-event-options (event form)
  "Read the (:KEY VALUE) option lists at the head of EVENT's FORM into EVENT;
return the directives after them."
  (let ((body (cddr form)))
    (loop while (consp (first body))
          do (let ((option (pop body)))
               (unless (and (proper-list-p option) (= (length option) 2)
                            (member (first option) *event-option-keys*))
                 (spec-fail 'spec-syntax-error form
                            "unknown or malformed event option ~A (allowed: ~{(~A POLICY)~^ ~}, then directives)"
                            (bounded-lisp-text option 40) (mapcar #'lisp-text *event-option-keys*)))
               (setf (event-when-busy event) (parse-when-busy (second option) form))))
    body))

;;; Ops: :interrupt and :if-cut

(defun parse-interrupt (value form)
  "An op's :INTERRUPT: :NEVER, :ANYTIME, or (:AT POINT...) with each POINT
seconds into the op or the name of a critical time of its script."
  (cond ((word-p value "NEVER") :never)
        ((word-p value "ANYTIME") :anytime)
        ((and (proper-list-p value) (word-p (first value) "AT") (rest value))
         (mapcar (lambda (point) (parse-interruption-point point form)) (rest value)))
        (t (spec-fail 'spec-syntax-error form
                      ":interrupt takes :never, :anytime or (:at CRITICAL-TIME...), not ~A"
                      (bounded-lisp-text value 40)))))

(defun parse-interruption-point (point form)
  "One point of (:at ...): seconds (a number from 0) or a critical time's name."
  (cond ((realp point) (spec-seconds point form "an interruption point" :minimum 0))
        ((and (symbolp point) point (not (keywordp point))) point)
        (t (spec-fail 'spec-syntax-error form
                      "an interruption point is a critical time's name or seconds into the op, not ~A"
                      (bounded-lisp-text point 40)))))

(defun parse-cut-effects (value op form)
  "An op's :IF-CUT (:add LITS :sub LITS): the effects OP has instead of its own
when it is cut."
  (when (op-must-ask op)
    (spec-fail 'spec-syntax-error form
               "op ~A is must-ask: the planner never chooses it, so it takes no :if-cut"
               (lisp-text (op-name op))))
  (when (eq (op-interrupt op) :never)
    (spec-fail 'spec-syntax-error form
               ":if-cut needs :interrupt :anytime or (:at ...): op ~A is never cut"
               (lisp-text (op-name op))))
  (unless (proper-list-p value)
    (spec-fail 'spec-syntax-error form ":if-cut takes (:add LITS :sub LITS), not ~A"
               (bounded-lisp-text value 40)))
  (parse-effects (parse-options form value '(:add :sub)) form))

(defun check-interruption-points (op form)
  "Signal when a numeric point of OP's :interrupt lies beyond its :duration."
  (when (listp (op-interrupt op))
    (dolist (point (op-interrupt op))
      (when (and (realp point) (> point (op-duration op)))
        (spec-fail 'type-error-in-spec form "interruption point ~A lies after op ~A's :duration ~A"
                   (format-number point) (lisp-text (op-name op)) (format-number (op-duration op)))))))

;;; Ops: :channels

(defun parse-channels (value form)
  "An op's :CHANNELS (NAME...): the body channels it drives, as lower-case
strings (joint names, joint roles, or names of the author's choosing)."
  (let ((names (if (and value (symbolp value)) (list value) value)))
    (unless (and (proper-list-p names) names
                 (every (lambda (name) (or (stringp name) (and (symbolp name) name (not (eq name t)))))
                        names))
      (spec-fail 'spec-syntax-error form ":channels takes a list of channel names, e.g. (wings head), not ~A"
                 (bounded-lisp-text value 40)))
    (remove-duplicates (mapcar (lambda (name) (string-downcase (string name))) names) :test #'string=)))

(defun cube-fields (cube spec)
  "The fields of the plannable variables CUBE constrains (does not allow every value of)."
  (loop for var in (plannable-variables spec)
        for field = (var-field-mask var)
        unless (= (logand cube field) field) sum field))

(defun expression-fields (ast spec)
  "The fields state expression AST constrains."
  (reduce #'logior (expression-cubes ast spec) :key (lambda (cube) (cube-fields cube spec))
                                               :initial-value 0))

(defun op-variable-fields (op spec)
  "The fields of the plannable variables OP's precondition, effects and
:if-cut effects mention."
  (logior (if (op-precond op) (expression-fields (op-precond op) spec) 0)
          (op-effect-mask op)
          (loop for (var) in (op-cut-effects op) sum (var-field-mask var))))
