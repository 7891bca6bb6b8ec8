;;;; scenarios.lisp -- facts about events and scenarios that both back ends
;;;; and the runtime ask: does an event run Lisp of its own, what a cut op's
;;;; :if-cut effects change, and what a scenario's entries look like.

(in-package #:player.spec)

(defun directives-run-code-p (directives)
  "Do parsed DIRECTIVES hold a :code directive (at any depth of :if)?"
  (some (lambda (directive)
          (case (first directive)
            (:code t)
            (:if (directives-run-code-p (third directive)))))
        directives))

(defun event-runs-code-p (event)
  "Does EVENT run Lisp of its own (a :code directive)?  Such an event is never
planned on trial, since planning it runs the code."
  (directives-run-code-p (event-directives event)))

(defun cut-effect-fields (op)
  "The MASK and BITS (two values) of OP's :if-cut effects: 0 and 0 when it has none."
  (let ((effects (op-cut-effects op)))
    (values (loop for (var) in effects sum (var-field-mask var))
            (loop for (var . index) in effects sum (var-value-bit var index)))))

(defun cut-effect-delta (op)
  "The (MASK . BITS) of OP's :if-cut effects, or NIL when it has none."
  (when (op-cut-effects op)
    (multiple-value-call #'cons (cut-effect-fields op))))

(defun event-entry-name (entry)
  "The event name of a scenario ENTRY: NAME, or (NAME . SECONDS)."
  (if (consp entry) (car entry) entry))

(defun event-entry-p (x)
  "Is X a scenario entry: an event name (symbol or string), or (NAME . SECONDS)?"
  (or (name-designator-p x)
      (and (consp x) (name-designator-p (car x)) (seconds-p (cdr x)) (>= (cdr x) 0))))

(defun timed-scenario-p (events until)
  "Does a scenario of EVENTS (stopping at UNTIL) need a timed controller: does
an entry give its arrival time, or is there a time to stop at?"
  (or until (some #'consp events)))
