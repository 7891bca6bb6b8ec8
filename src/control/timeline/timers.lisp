;;;; timers.lisp -- events a timed controller sends itself: timers go off a
;;;; while after they are armed (and are re-armed by the events named in
;;;; :restart-on), triggers fire when their condition becomes true.  Both send
;;;; their event through the same policies as an event from outside.

(in-package #:player.control)

(defstruct (timer-state (:constructor make-timer-state (def)))
  "A TIMER-DEF on one timeline: when it is due (DUE, NIL when disarmed, and
SEQ, its place among things due then) and its :TIMER item on the agenda.
Re-arming only moves DUE later; the item, when its old time comes, goes back
on the agenda for the new one, so a timer restarted by every event keeps one
item on the agenda, not one per restart."
  (def nil :type timer-def)
  (due nil :type (or null integer))
  (seq 0 :type fixnum)
  (item nil))

(defstruct (trigger-state (:constructor make-trigger-state (def condition fields)))
  "A TRIGGER-DEF on one timeline: its compiled CONDITION and whether it held at
the last state change (it fires on a rising edge only).  FIELDS: the plannable
fields its condition reads when it reads nothing else, or NIL when it compares
numbers (then any change may turn it)."
  (def nil :type trigger-def)
  (condition nil :type function)
  (fields nil :type (or null integer))
  (held nil :type boolean))

(defun arm-timer (timeline state time)
  "Make STATE's timer go off its :after seconds after TIME."
  (setf (timer-state-due state) (+ time (seconds->micros (timer-after (timer-state-def state))))
        (timer-state-seq state) (next-seq timeline))
  (unless (timer-state-item state)
    (let ((item (make-agenda-item :timer (timer-state-due state) (timer-state-seq state) nil)))
      (setf (agenda-item-a item) state
            (timer-state-item state) item)
      (agenda-push (timeline-agenda timeline) item))))

(defun timer-item-due (timeline state item time)
  "STATE's :TIMER ITEM has come up at TIME: if the timer was re-armed since,
put ITEM back on the agenda for its new time and return NIL; else T."
  (if (and (= (timer-state-due state) time) (= (timer-state-seq state) (agenda-item-seq item)))
      (progn (setf (timer-state-item state) nil) t)
      (progn (setf (agenda-item-time item) (timer-state-due state)
                   (agenda-item-seq item) (timer-state-seq state)
                   (agenda-item-status item) :pending)
             (agenda-push (timeline-agenda timeline) item)
             nil)))

(defun start-timers (timeline)
  "Arm every timer of the controller's spec from NOW."
  (setf (timeline-timers timeline)
        (mapcar #'make-timer-state (spec-timers (spec-of (timeline-controller timeline)))))
  (dolist (state (timeline-timers timeline))
    (arm-timer timeline state (timeline-now timeline))))

(defun note-event-for-timers (timeline compiled source time)
  "Re-arm, from TIME, the timers the event COMPILED restarts: those listing it,
and those with :restart-on :any when it comes from outside (SOURCE :USER)."
  (let ((event (compiled-event-event compiled)))
    (dolist (state (timeline-timers timeline))
      (let ((restart-on (timer-restart-on (timer-state-def state))))
        (when (if (eq restart-on :any) (eq source :user) (member event restart-on))
          (arm-timer timeline state time))))))

(defun fire-timer (timeline state item time)
  "STATE's timer (its :TIMER ITEM come up at TIME) goes off, unless it was
re-armed for later: show it, re-arm it if it repeats, send its event."
  (when (timer-item-due timeline state item time)
    (fire-due-timer timeline state time)))

(defun fire-due-timer (timeline state time)
  "STATE's timer goes off at TIME: show it, re-arm it if it repeats, send its event."
  (let ((def (timer-state-def state)))
    (setf (timer-state-due state) nil)
    (present-timer (timeline-presenter timeline) (timer-name def) (micros->seconds time))
    (when (timer-repeat def)
      (arm-timer timeline state time))
    (send-own-event timeline (timer-event def) time :timer)))

(defun send-own-event (timeline event time source)
  "Send EVENT (an EVENT-DEF) at TIME from a timer or trigger, by its own
policy, once everything else due at TIME has happened."
  (let* ((controller (timeline-controller timeline))
         (compiled (find-compiled-event controller (event-name event))))
    (push (lambda ()
            (dispatch-event timeline compiled time
                            (compiled-event-policy compiled) source))
          (timeline-deferred timeline))))

(defun start-triggers (timeline)
  "Compile the controller's triggers; each notes whether it holds now (a
condition true from the start is not a rising edge)."
  (let ((controller (timeline-controller timeline)))
    (setf (timeline-triggers timeline)
          (loop for def in (spec-triggers (spec-of controller))
                for ast = (trigger-condition def)
                for condition = (compile-condition ast (controller-machine controller))
                collect (let ((state (make-trigger-state def condition
                                                         (and (state-only-p ast)
                                                              (expression-fields ast (spec-of controller))))))
                          (setf (trigger-state-held state) (and (funcall condition controller) t))
                          state)))
    ;; What they read together, for TRIGGERS-MAY-TURN-P.
    (setf (timeline-trigger-fields timeline)
          (let ((reads 0))
            (dolist (state (timeline-triggers timeline) reads)
              (let ((fields (trigger-state-fields state)))
                (if fields
                    (setf reads (logior reads fields))
                    (return t))))))))

(declaim (inline trigger-may-turn-p))
(defun trigger-may-turn-p (state changed)
  "Can the condition of trigger STATE have changed when the plannable fields
CHANGED (a mask, 0 for a runtime value) did?"
  (let ((reads (trigger-state-fields state)))
    (cond ((null reads))
          ;; Fixnum masks (the usual states) test in a machine instruction.
          ((and (typep reads 'fixnum) (typep changed 'fixnum)) (logtest reads changed))
          (t (logtest reads changed)))))

;; A trigger whose condition reads only fields the change left alone holds as
;; it did, so it is not asked again (Peedy's trigger reads one variable).
;; The time is TIMELINE's NOW (the change is being applied), read here rather
;; than passed: a double passed to a full call is boxed, for every change.
(defun check-triggers (timeline changed)
  "After a state change, at TIMELINE's NOW, of the plannable fields CHANGED (a
mask, 0 for a runtime value): fire each trigger whose condition has just
become true."
  (when (timeline-triggers timeline)
    (let ((controller (timeline-controller timeline)))
      (setf (controller-schedule controller) (timeline-now timeline))
      (dolist (state (timeline-triggers timeline))
        (let ((holds (if (trigger-may-turn-p state changed)
                         (and (funcall (trigger-state-condition state) controller) t)
                         (trigger-state-held state))))
          (when (and holds (not (trigger-state-held state)))
            (setf (trigger-state-held state) t)
            (let ((time (timeline-now timeline)))
              (present-trigger (timeline-presenter timeline) (trigger-name (trigger-state-def state))
                               (micros->seconds time))
              (send-own-event timeline (trigger-event (trigger-state-def state)) time :trigger)))
          (setf (trigger-state-held state) holds))))))
