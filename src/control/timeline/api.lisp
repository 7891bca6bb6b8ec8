;;;; api.lisp -- the timed controller's API: send an event at a time, move the
;;;; clock, ask whether the character is busy.

(in-package #:player.control)

;; Inline: FINISH-EVENTS asks it for every other event of a stream.
(declaim (inline check-timed-controller))
(defun check-timed-controller (function controller)
  "CONTROLLER's timeline; an ARGUMENT-ERROR of FUNCTION when it has none."
  (check-argument function 'controller controller #'controller-p "a controller (from make-controller)")
  (or (controller-timeline controller)
      (argument-fail function 'controller controller "a timed controller (make-controller ... :timed t)")))

;; Inline, its usual case: a double from now on, converted.  The rest,
;; and the error, are CHECK-TIME-FROM-NOW-SLOWLY's.
(declaim (inline check-time-from-now))
(defun check-time-from-now (function argument time timeline)
  "TIME (seconds) in whole microseconds (SECONDS->MICROS), at or after
TIMELINE's NOW; else an ARGUMENT-ERROR."
  (let ((micros (and (plain-seconds-p time) (seconds->micros time))))
    (if (and micros (micros<= (timeline-now timeline) micros))
        micros
        (check-time-from-now-slowly function argument time timeline))))

(defun check-time-from-now-slowly (function argument time timeline)
  "CHECK-TIME-FROM-NOW for any TIME."
  (check-seconds function argument time)
  (let ((micros (seconds-value->micros time)))
    (when (micros< micros (timeline-now timeline))
      (argument-fail function argument time
                     (format nil "a time no earlier than now (~A s): a timed controller cannot go back"
                             (format-micros (timeline-now timeline)))))
    micros))

;; Inline, its usual case: no policy given, or one of *WHEN-BUSY-POLICIES*.
(declaim (inline timed-event-policy))
(defun timed-event-policy (compiled when-busy)
  "The :when-busy policy of compiled event COMPILED: WHEN-BUSY
if given (an ARGUMENT-ERROR unless it names a policy), else the event's or the spec's."
  (if when-busy
      ;; The keyword itself, looked for inline (no string compare, no call).
      (if (loop for policy in *when-busy-policies* thereis (eq policy when-busy))
          when-busy
          (named-when-busy-policy when-busy))
      (compiled-event-policy compiled)))

(defun named-when-busy-policy (when-busy)
  "The policy WHEN-BUSY, not a keyword of *WHEN-BUSY-POLICIES*, names; else an ARGUMENT-ERROR."
  (or (and (symbolp when-busy) (when-busy-policy when-busy))
      (argument-fail 'send-event :when-busy when-busy
                     (format nil "one of ~{~A~^, ~}" (mapcar #'lisp-text *when-busy-policies*)))))

(defun send-timed-event (controller event at when-busy)
  "SEND-EVENT on a timed controller (see there)."
  (let* ((timeline (controller-timeline controller))
         (time (if at (check-time-from-now 'send-event :at at timeline) (timeline-now timeline)))
         (compiled (find-compiled-event controller event))
         (policy (timed-event-policy compiled when-busy)))
    (advance-timeline* timeline time t nil)
    ;; A redefinition waiting for the controller to be idle happens now, and
    ;; the event is the new machine's (the switch made a new timeline).
    (when (and (controller-pending controller) (install-pending-machine controller))
      (setf timeline (controller-timeline controller)
            compiled (find-compiled-event controller event)
            policy (timed-event-policy compiled when-busy)))
    (multiple-value-bind (disposition result)
        (dispatch-event timeline compiled time policy :user)
      (cond ((eq disposition :dropped) (values nil :dropped))
            ((eq result t) t)
            (t (values nil (failure-goal-form result)))))))

(defun defer-timed-send (controller event at when-busy)
  "DEFER-SEND on timed CONTROLLER, planning an event ahead whose :code sends
EVENT: the event arrives at NOW once everything else due then has happened,
as a timer's or trigger's does, resolved by WHEN-BUSY or its own policy
against the event planned (which is running by then).  AT, if given, must be
NOW: the clock cannot move while an event is planned (an ARGUMENT-ERROR
otherwise).  Returns (VALUES NIL :DEFERRED)."
  (let* ((timeline (controller-timeline controller))
         (time (if at (check-time-from-now 'send-event :at at timeline) (timeline-now timeline)))
         (compiled (find-compiled-event controller event))
         (policy (timed-event-policy compiled when-busy)))
    (when (> time (timeline-now timeline))
      (argument-fail 'send-event :at at
                     (format nil "NIL or now (~A s): an event sent from inside the controller's own event arrives when that one is planned; send later events from outside"
                             (format-micros (timeline-now timeline)))))
    (push (lambda ()
            (dispatch-event timeline compiled (timeline-now timeline) policy :user))
          (timeline-deferred timeline))
    (values nil :deferred)))

(defun advance (controller time)
  "Move timed CONTROLLER's clock to TIME (seconds, not before now), presenting
in time order what falls due: op starts, state changes with their autoscripts,
event ends (a :state line), waiting events starting, timers and triggers; then
a redefinition waiting for the controller to be idle (REDEFINE-CONTROLLER)
happens, if it is.
Returns TIME (as a double). Signals an ARGUMENT-ERROR for an untimed controller
or a time in the past."
  (let* ((timeline (check-timed-controller 'advance controller))
         (micros (check-time-from-now 'advance 'time time timeline)))
    (advance-timeline* timeline micros t nil)
    (when (controller-pending controller)
      (install-pending-machine controller))
    (micros->seconds-double micros)))

(declaim (inline controller-time*))
(defun controller-time* (controller)
  "CONTROLLER-TIME of CONTROLLER, known to be a controller."
  (if (controller-timeline controller)
      (boxed-now (controller-timeline controller))
      (controller-clock controller)))

(defun finish-events (controller)
  "Advance timed CONTROLLER until no event runs or waits (timers that are
still armed stay pending), then make a pending redefinition happen. Returns
the time it stopped at. Signals a
TIMELINE-ERROR, at the time reached, when events never stop coming (a timer
that repeats faster than its event plays, say): ADVANCE to a time instead."
  (let ((timeline (check-timed-controller 'finish-events controller)))
    (advance-timeline* timeline +never-micros+ t t)
    (when (controller-pending controller)
      (install-pending-machine controller))
    ;; CONTROLLER-TIME without checking CONTROLLER again.
    (controller-time* controller)))

(defun controller-busy-p (controller)
  "Is an event running on timed CONTROLLER now (or waiting to)?"
  (timeline-busy-p (check-timed-controller 'controller-busy-p controller)))

(defun controller-time (controller)
  "CONTROLLER's current time in seconds (a double): a timed controller's clock,
or else when the next event would start (the end of the last one)."
  (check-argument 'controller-time 'controller controller #'controller-p "a controller (from make-controller)")
  (controller-time* controller))

(defun controller-microseconds (controller)
  "CONTROLLER-TIME exactly, as the whole number of microseconds a controller
keeps its times in (up to 1e21 for 1e15 s: an integer, a bignum past 4.6e12 s)."
  (check-argument 'controller-microseconds 'controller controller #'controller-p
                  "a controller (from make-controller)")
  (if (controller-timeline controller)
      (timeline-now (controller-timeline controller))
      (controller-clock-micros controller)))

;;;# A scenario of events

(defun play-events (controller events &key until when-busy)
  "Send EVENTS to CONTROLLER in order: each NAME when the events before it have
ended, each (NAME . SECONDS) at that time whatever is running (a timed
controller's policies decide; WHEN-BUSY, if given, overrides every event's).
A timed controller then advances to UNTIL, or until no event runs or waits.
Signals an ARGUMENT-ERROR for an entry timed before now or after UNTIL."
  (if (null (controller-timeline controller))
      (dolist (entry events)
        (send-event controller (event-entry-name entry)))
      (progn
        (dolist (entry events)
          (cond ((not (consp entry))
                 (finish-events controller)
                 (send-event controller entry))
                ((and until (> (cdr entry) until))
                 (argument-fail 'play-events :until until
                                (format nil "a time no earlier than the events' (~A arrives at ~A)"
                                        (lisp-text (car entry)) (format-number (cdr entry)))))
                (t (send-event controller (car entry) :at (cdr entry) :when-busy when-busy))))
        (if until (advance controller until) (finish-events controller))))
  controller)
