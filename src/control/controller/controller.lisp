;;;; controller.lisp -- the controller API: make agents, send them events,
;;;; read their state.  Switching one to a new spec is redefinition.lisp's.

(in-package #:player.control)

(defun install-assignments (controller assignments)
  "Set CONTROLLER's state and runtime values from ASSIGNMENTS ((VAR . VALUE) ...)."
  (let ((values (make-array (count-if-not #'plannable-p (mapcar #'car assignments))
                            :initial-element nil)))
    (setf (controller-bits controller)
          (loop for (var . value) in assignments
                if (plannable-p var) sum (var-value-bit var value)
                else do (setf (svref values (var-slot var)) value))
          (controller-values controller) values)))

(defun initial-state-p (x)
  "Is X a proper, non-circular alist ((VARIABLE . VALUE) ...) with symbols for
variables, and no NaN or infinity among the values?"
  (and (proper-form-list-p x)
       (every (lambda (entry) (and (consp entry) (symbolp (car entry)))) x)
       (finite-form-p x)))

(defparameter *initial-state-phrase*
  "a proper alist ((variable . value) ...) with symbols for variables and finite numbers"
  "How argument errors describe an initial state.")

(defun presenter-p (x)
  "Is X a presenter?"
  (typep x 'presenter))

(defun make-controller (machine &key initial-state
                                     (presenter (make-trace-presenter :limit *default-trace-limit*))
                                     (clock 0) timed)
  "A new agent running MACHINE (from COMPILE-SPEC, or a spec or its name, which
is compiled). INITIAL-STATE is an alist ((VARIABLE . VALUE) ...) overriding the
declared initial values; booleans take true/false/t/nil. PRESENTER receives
what the agent does (default: a TRACE-PRESENTER). Autoscripts of the initial
values start at CLOCK (seconds). With TIMED, the controller has a timeline:
SEND-EVENT plans the event and ADVANCE presents it as its time comes, so an
event can arrive while another plays and be resolved by its :when-busy
policy; its timers and triggers run. Signals a SPEC-ERROR for an unknown variable
or a value outside its domain, an ARGUMENT-ERROR for an argument of the wrong
kind, STATE-OUTSIDE-PLANNED-SET for a start its machine has no plans from (a
spec planned for its reachable states only, without (:unplanned-states :search))."
  (check-argument 'make-controller 'machine machine #'machine-designator-p *machine-designator*)
  (check-argument 'make-controller :initial-state initial-state #'initial-state-p *initial-state-phrase*)
  (check-argument 'make-controller :presenter presenter #'presenter-p
                  "a presenter (from make-trace-presenter or make-null-presenter, say)")
  (check-seconds 'make-controller :clock clock)
  (let* ((clock (seconds-value->micros clock))
         (machine (ensure-compiled-machine machine))
         (spec (machine-spec machine))
         (assignments (initial-assignments spec initial-state))
         (controller (%make-controller
                      :machine machine :presenter presenter :clock-micros clock
                      :labels (make-array (spec-label-count spec) :initial-element 0))))
    (install-assignments controller assignments)
    (check-planned-state machine (controller-bits controller))
    (present-initial-state presenter controller)
    (start-initial-autoscripts controller (controller-clock-micros controller))
    (when timed
      (setf (controller-timeline controller) (make-timeline controller)))
    controller))

(defun event-names (machine)
  "The names of the events MACHINE (a machine, a controller, a spec or a spec's
name) accepts, in spec order."
  (check-argument 'event-names 'machine machine
                  (lambda (x) (or (controller-p x) (machine-designator-p x)))
                  "a controller, a machine, a spec or a spec's name")
  (let ((spec (typecase machine
                (controller (spec-of machine))
                (machine (machine-spec machine))
                (spec machine)
                (t (find-spec machine)))))
    (mapcar #'event-name (spec-events spec))))

(defun remember-event-symbol (machine symbol compiled)
  "Publish a copy of MACHINE's symbol table with SYMBOL -> COMPILED added (the
table is never changed in place, so readers need no lock); return COMPILED."
  (let ((table (alexandria:copy-hash-table (compiled-machine-event-symbols machine))))
    (setf (gethash symbol table) compiled)
    ;; The index first: a reader that sees the new table may find its pair
    ;; missing from the old index, and look the name up the slow way.
    (setf (compiled-machine-symbol-index machine)
          (make-symbol-index (loop for key being the hash-keys of table using (hash-value value)
                                   collect (cons key value)))
          (compiled-machine-event-symbols machine) table)
    compiled))

;; Inline, the usual case: a symbol remembered in the machine's index.  The
;; rest is FIND-COMPILED-EVENT-SLOWLY's.
(declaim (inline find-compiled-event))
(defun find-compiled-event (controller name &optional (function 'send-event))
  "The compiled event NAME of CONTROLLER's machine; UNKNOWN-EVENT if none, an
ARGUMENT-ERROR of FUNCTION when NAME is neither a symbol nor a string.
Interned symbols are remembered in an EQ table so the usual lookup allocates
nothing; the table holds only interned symbols that name events, so it stays
as small as the spec's events (an uninterned symbol is looked up by name each
time)."
  (or (and (symbolp name)
           (symbol-index-value (compiled-machine-symbol-index (controller-machine controller)) name))
      (find-compiled-event-slowly controller name function)))

(defun find-compiled-event-slowly (controller name function)
  "FIND-COMPILED-EVENT of a NAME not in the symbol index (yet)."
  (let* ((machine (controller-machine controller))
         (compiled (gethash (if (stringp name)
                                (string-upcase name)
                                (name-key (check-argument function 'event name #'name-designator-p
                                                          "an event name (a symbol or string)")))
                            (compiled-machine-events machine))))
    (cond ((null compiled)
           (error 'unknown-event :name name :known (event-names controller)))
          ((and (symbolp name) (symbol-package name))
           (remember-event-symbol machine name compiled))
          (t compiled))))

;;; Something that is not a controller but takes events for one, a viewer
;;; session on another thread say, subclasses EVENT-TARGET: SEND-EVENT hands
;;; such a target the call.
(defclass event-target () ()
  (:documentation "Something SEND-EVENT may be given instead of a controller: it
takes the event through TARGET-SEND-EVENT."))

(defgeneric target-send-event (target event at when-busy)
  (:documentation "SEND-EVENT's work for an EVENT-TARGET TARGET: send EVENT,
with AT and WHEN-BUSY as SEND-EVENT's keywords, and return what SEND-EVENT returns."))

(defun send-event (controller event &key at when-busy)
  "Process EVENT (a symbol or string) on CONTROLLER, starting at time AT
(seconds; default: when the previous event's last op ended). Returns T when
every directive succeeded; otherwise (VALUES NIL GOAL) with the goal, as
written, that could not be achieved: the rest of the event is skipped and the
state is the one after the last completed op. Signals UNKNOWN-EVENT for an
event the spec does not define and ARGUMENT-ERROR for an argument of the wrong
kind (AT not a finite number of seconds within +-1e15), changing nothing.

On a timed controller (MAKE-CONTROLLER :TIMED T) the event arrives at AT
(default: now; not before now), the clock advancing there first. If another
event is running, WHEN-BUSY (default: the event's :when-busy policy, else the
spec's) decides: :QUEUE, :PREEMPT, :OVERRIDE or :INTERLEAVE. Returns T when
the event was accepted, (VALUES NIL :DROPPED) when it was dropped, and (VALUES
NIL GOAL) when it started at once and its plan failed.

Sent to CONTROLLER from inside its own running event (a :code directive
calling (send-event *controller* ...)), EVENT is deferred, its arguments
checked now: a whole-event controller sends it once the running event is
over, a timed one dispatches it at the current instant once everything due
then has happened (AT must then be NIL or now). Returns (VALUES NIL :DEFERRED).

CONTROLLER may also be an EVENT-TARGET, such as the VIEWER-SESSION of VIEW:
the event is then sent to the controller it stands for, at the viewer's
playback time unless AT is given."
  (send-event* controller event at when-busy))

;; A call with its keywords written out goes straight to SEND-EVENT*: parsing
;; the keywords was over half of SEND-EVENT's own work, on every event.
(define-compiler-macro send-event (&whole form controller event &rest keys)
  "(SEND-EVENT* CONTROLLER EVENT AT WHEN-BUSY), the arguments evaluated in
the order written, when KEYS are :AT and :WHEN-BUSY at most once each; else
FORM, left to SEND-EVENT."
  (if (and (evenp (length keys))
           (loop for (key) on keys by #'cddr always (member key '(:at :when-busy)))
           (= (length (remove-duplicates (loop for (key) on keys by #'cddr collect key)))
              (floor (length keys) 2)))
      (let ((bindings (list* (list (gensym "CONTROLLER") controller)
                             (list (gensym "EVENT") event)
                             (loop for (key value) on keys by #'cddr
                                   collect (list (gensym (symbol-name key)) value)))))
        (flet ((keyword-variable (key)
                 (loop for (variable) in (cddr bindings)
                       for (k) on keys by #'cddr
                       when (eq k key) return variable)))
          `(let ,bindings
             (send-event* ,(first (first bindings)) ,(first (second bindings))
                          ,(keyword-variable :at) ,(keyword-variable :when-busy)))))
      form))

(defun send-event* (controller event at when-busy)
  "SEND-EVENT with its keyword arguments AT and WHEN-BUSY passed by position."
  ;; A controller is asked about first: the class test for a target costs
  ;; more than the structure test, and controllers are the usual case.  Asked
  ;; once: below it, CONTROLLER is known to be one.
  (unless (controller-p controller)
    (return-from send-event*
      (if (typep controller 'event-target)
          (target-send-event controller event at when-busy)
          (argument-fail 'send-event 'controller controller "a controller (from make-controller)"))))
  ;; Sent from inside its own running event (its :code): sent after it.
  (when (running-event-p controller)
    (return-from send-event* (defer-send controller event at when-busy)))
  (when (controller-timeline controller)
    (return-from send-event* (send-timed-event controller event at when-busy)))
  (when (controller-pending controller)
    (install-pending-machine controller))
  (when when-busy
    (argument-fail 'send-event :when-busy when-busy
                   "NIL: only a timed controller (make-controller ... :timed t) resolves busy events"))
  (let* ((start (if at (progn (check-seconds 'send-event :at at) (seconds-value->micros at)) (controller-clock-micros controller)))
         (compiled (find-compiled-event controller event))
         (event (compiled-event-event compiled))
         (presenter (controller-presenter controller))
         (*controller* controller))
    (note-presenter-silence controller)
    (setf (controller-schedule controller) start
          (controller-span-start controller) start
          (controller-span-end controller) start)
    (unless (silent-p controller)
      (present-event presenter (event-name event) (micros->seconds start)))
    (dolist (var (event-time-variables event))
      (set-runtime-value controller var (micros->double start) start))
    ;; No macro-op is open as an event starts, even one an error left open.
    (setf (controller-active-macros controller) 0)
    (let ((result (funcall (the function (compiled-event-run compiled)) controller)))
      (unless (or (eq result t) (silent-p controller))
        (present-failure presenter (event-name event) (failure-goal-form result)
                         (micros->seconds (controller-schedule controller))))
      (setf (controller-clock-micros controller) (controller-span-end controller))
      (unless (silent-p controller)
        (present-state presenter controller))
      (when (controller-deferred-sends controller)
        (send-deferred-events controller))
      (if (eq result t)
          t
          (values nil (failure-goal-form result))))))

(defun find-controller-variable (function controller name)
  "The variable NAME of CONTROLLER's spec, or an UNKNOWN-NAME-ERROR of FUNCTION."
  (check-argument function 'name name #'name-designator-p "a variable's name (a symbol or string)")
  (with-spec-context (:spec (spec-of controller))
    (or (find-variable-named name)
        (spec-fail 'unknown-name-error nil "~A: unknown variable ~A (variables: ~{~A~^, ~})"
                   (lisp-text function) (bounded-lisp-text name 80)
                   (mapcar (lambda (var) (lisp-text (var-name var))) (spec-variables *spec*))))))

(defun state-value (controller name)
  "The current value of variable NAME in CONTROLLER: T/NIL for booleans, the
domain value for enumerated variables, a number (or NIL for a time never set)."
  (check-argument 'state-value 'controller controller #'controller-p "a controller (from make-controller)")
  (let ((var (find-controller-variable 'state-value controller name)))
    (if (eq (var-kind var) :boolean)
        (= 1 (value-index-of controller var))
        (variable-value controller var))))

(defun controller-state (controller)
  "CONTROLLER's state as an alist ((VARIABLE . VALUE) ...) in declaration order."
  (check-argument 'controller-state 'controller controller #'controller-p "a controller (from make-controller)")
  (loop for var in (spec-variables (spec-of controller))
        collect (cons (var-name var)
                      (if (eq (var-kind var) :boolean)
                          (= 1 (value-index-of controller var))
                          (variable-value controller var)))))

(defun active-autoscripts (controller)
  "The (PROC VARIABLE-NAME VALUE) triples running in CONTROLLER now."
  (loop for auto in (spec-autoscripts (spec-of controller))
        for var = (autoscript-variable auto)
        when (eql (autoscript-value-index auto)
                  (if (plannable-p var)
                      (value-index-of controller var)
                      (svref (controller-values controller) (var-slot var))))
          append (mapcar (lambda (proc) (list proc (var-name var) (autoscript-value auto)))
                         (autoscript-procs auto))))
