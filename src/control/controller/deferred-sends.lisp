;;;; deferred-sends.lisp -- a SEND-EVENT to a controller from inside its own
;;;; running event (a :code directive calling (send-event *controller* ...),
;;;; say) is deferred: the event is queued, and sent once the running event is over,
;;;; as a timed controller's timers and triggers send theirs.  Run at once, it
;;;; would play in the middle of the other's plan: that plan would go on from a
;;;; state it did not make, and a timed controller planning ahead would lose
;;;; the ops it had recorded so far.

(in-package #:player.control)

(defparameter *max-deferred-sends* 100000
  "How many deferred sends one SEND-EVENT plays after its event before it
decides that events keep sending each other for ever, and signals a
DEFERRED-SENDS-ERROR.")

(define-condition deferred-sends-error (player-error)
  ((controller :initarg :controller :reader deferred-sends-error-controller)
   (event :initarg :event :reader deferred-sends-error-event))
  (:report (lambda (condition stream)
             (format stream "events keep sending each other: over ~:D deferred sends after one event, the last ~A (a :code send-event in a loop)"
                     *max-deferred-sends* (lisp-text (deferred-sends-error-event condition)))))
  (:documentation "The :code of the events a whole-event controller plays keeps
sending it more events, without end."))

(declaim (inline running-event-p))
(defun running-event-p (controller)
  "Is CONTROLLER running an event's closures now, so that a SEND-EVENT to it
comes from inside that event?  *CONTROLLER* says: SEND-EVENT binds it while a
whole-event controller runs an event, RUN-EVENT-PLAN while a timed one plans
one (a binding each already made, so asking costs a compare).  A send from
inside another controller's event that CONTROLLER's own event started is not
seen so: it runs at once, as before."
  (eq controller *controller*))

(defun defer-send (controller event at when-busy)
  "SEND-EVENT of EVENT (AT, WHEN-BUSY) to CONTROLLER while an event of it
runs: check the arguments as SEND-EVENT does, then queue the event, to be sent
once the running one is over.  Returns (VALUES NIL :DEFERRED).  A timed
controller's is DEFER-TIMED-SEND's."
  (when (controller-timeline controller)
    (return-from defer-send (defer-timed-send controller event at when-busy)))
  (when when-busy
    (argument-fail 'send-event :when-busy when-busy
                   "NIL: only a timed controller (make-controller ... :timed t) resolves busy events"))
  (let ((at (and at (check-seconds 'send-event :at at))))
    ;; An unknown event is the sender's error, signalled where it sends.
    ;; (Out of line: the inline definition comes later, in controller.lisp.)
    (locally (declare (notinline find-compiled-event))
      (find-compiled-event controller event))
    (setf (controller-deferred-sends controller)
          (append (controller-deferred-sends controller) (list (cons event at))))
    (values nil :deferred)))

(defvar *sending-deferred* '()
  "The controllers whose deferred sends SEND-DEFERRED-EVENTS is sending: a
deferred event that defers more leaves them to that loop, so a chain of
sends runs in a loop, not ever deeper in the stack.")

(defun send-deferred-events (controller)
  "Send, oldest first, the events deferred while CONTROLLER's event ran, and
those they defer in turn (unless an outer call of this is doing so); a
DEFERRED-SENDS-ERROR after *MAX-DEFERRED-SENDS*."
  (unless (member controller *sending-deferred*)
    ;; Its event is over: what it sent is sent from outside it.
    (let ((*sending-deferred* (cons controller *sending-deferred*))
          (*controller* nil))
      (loop for count of-type fixnum from 1
            while (controller-deferred-sends controller)
            do (destructuring-bind (event . at) (pop (controller-deferred-sends controller))
                 (when (> count *max-deferred-sends*)
                   (setf (controller-deferred-sends controller) '())
                   (error 'deferred-sends-error :controller controller :event event))
                 (send-event* controller event at nil))))))
