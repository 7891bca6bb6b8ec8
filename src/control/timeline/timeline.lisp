;;;; timeline.lisp -- a timed controller's clock: the TIMELINE (TIMELINE-STATE.LISP) made
;;;; with a controller, and what it holds.  Ops occupy intervals and change the
;;;; state when they end; ADVANCE moves the clock and presents op starts,
;;;; state changes (with their autoscripts) and event ends as they fall due
;;;; (ADVANCE.LISP).  An event is planned ahead when it starts (PLANNING.LISP,
;;;; RECORDER.LISP) and passes the start gate (START-GATE.LISP), so until
;;;; something interrupts it, it does exactly what the whole-event API does.

(in-package #:player.control)

(declaim #.*timeline-optimize*)                 ; the engine's policy (agenda.lisp)

;; Typed, so the checks against them in ADVANCE-TIMELINE's loop compare fixnums.
(declaim (type fixnum *finish-events-limit* *max-items-per-instant*))

(defparameter *finish-events-limit* 1000000
  "How many agenda items FINISH-EVENTS applies before it decides that timers
or triggers keep the controller busy for ever, and signals a TIMELINE-ERROR.")

(defparameter *max-items-per-instant* 100000
  "How many items a timeline applies at one instant before it decides that
triggers or zero-length ops loop, and signals a TIMELINE-ERROR.")

(defvar *replay-plan-tapes* t
  "Do the timed controllers made while it is true tape and replay the plans of
their events (TAPES.LISP)?  Off, every plan runs the compiled closures: a
test compares the two.")

(defun make-timeline (controller)
  "A timeline for CONTROLLER from its clock on: interruption points resolved
(a SPEC-ERROR for a critical time the presenter cannot give), timers armed,
triggers noting whether their conditions hold now."
  (let ((timeline (%make-timeline controller (controller-presenter controller))))
    (setf (timeline-now timeline) (controller-clock-micros controller)
          (timeline-quiet timeline) (quiet-presenter-p (timeline-presenter timeline))
          (agenda-silent-ops (timeline-agenda timeline)) (timeline-quiet timeline)
          (timeline-quiet-autoscripts timeline) (quiet-autoscripts-p (timeline-presenter timeline))
          (timeline-declared-channels timeline) (declared-channels-p (timeline-presenter timeline))
          (timeline-recorder timeline) (make-recorder timeline controller)
          (recorder-agenda (timeline-recorder timeline)) (timeline-agenda timeline)
          (recorder-declared-durations (timeline-recorder timeline))
          (declared-durations-p (timeline-presenter timeline))
          (recorder-declared-channels (timeline-recorder timeline)) (timeline-declared-channels timeline)
          (timeline-recording-presenter timeline)
          (make-instance 'recording-presenter :recorder (timeline-recorder timeline))
          (timeline-scratch-values timeline) (copy-seq (controller-values controller))
          (timeline-replay-tapes timeline) *replay-plan-tapes*)
    (resolve-cut-points timeline)
    (start-timers timeline)
    (start-triggers timeline)
    timeline))

(declaim (inline boxed-now))
(defun boxed-now (timeline)
  "TIMELINE's NOW in seconds, a boxed double, the same box for as long as NOW
stays: FINISH-EVENTS answers it, so a stream of them conses one box per instant."
  (let ((box (timeline-now-box timeline)))
    (if (and box (eql (timeline-now-box-micros timeline) (timeline-now timeline)))
        box
        (setf (timeline-now-box-micros timeline) (timeline-now timeline)
              (timeline-now-box timeline) (micros->seconds-double (timeline-now timeline))))))

(declaim (inline triggers-may-turn-p))
(defun triggers-may-turn-p (timeline changed)
  "Can a trigger of TIMELINE fire when the plannable fields CHANGED (a mask, 0
for a runtime value) do (see TRIGGER-MAY-TURN-P, for one)?"
  (let ((reads (timeline-trigger-fields timeline)))
    (or (eq reads t)
        ;; Fixnum masks (the usual states) test in a machine instruction.
        (if (and (typep reads 'fixnum) (typep changed 'fixnum))
            (logtest reads changed)
            (logtest reads changed)))))

(declaim (inline next-seq))
(defun next-seq (timeline)
  "A fresh sequence number: items made later sort later at equal times."
  (agenda-next-seq (timeline-agenda timeline)))

(defun timeline-seq (timeline)
  "The last sequence number TIMELINE gave an item (how many it made)."
  (agenda-seq (timeline-agenda timeline)))

(declaim (inline drop-run))
(defun drop-run (timeline run)
  "Take RUN out of TIMELINE's running runs: a fresh list unless RUN is absent
or alone in it.  A list of RUN alone is kept for the next run to play alone;
its REST stays NIL, as a caller may be walking it (MET-RUNS's list)."
  (let ((runs (timeline-runs timeline)))
    (setf (timeline-runs timeline)
          (if (and (eq (first runs) run) (null (rest runs)))
              (progn (setf (first runs) nil
                           (timeline-spare-runs-cons timeline) runs)
                     '())
              (remove run runs)))))
