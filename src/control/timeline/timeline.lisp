;;;; timeline.lisp -- a timed controller's clock: the TIMELINE structure, made
;;;; with a controller, and what it holds.  Ops occupy intervals and change the
;;;; state when they end; ADVANCE moves the clock and presents op starts,
;;;; state changes (with their autoscripts) and event ends as they fall due
;;;; (ADVANCE.LISP).  An event is planned ahead when it starts (PLANNING.LISP,
;;;; RECORDER.LISP) and passes the start gate (START-GATE.LISP), so until
;;;; something interrupts it, it does exactly what the whole-event API does.

(in-package #:player.control)

(declaim #.*timeline-optimize*)                 ; the engine's policy (agenda.lisp)

(defstruct (timeline (:constructor %make-timeline (controller presenter)))
  "The timed part of a controller: its current time NOW, the AGENDA of what is
due, the events running (RUNS: one, or several on disjoint channels) and those
waiting (QUEUE), and its timers and triggers."
  (controller nil :type controller)
  ;; The controller's own presenter (the controller's slot holds the recorder
  ;; while an event is planned ahead).
  presenter
  ;; Does that presenter do nothing with op starts, macro spans, event starts
  ;; and ends, failures and cuts (QUIET-PRESENTER-P)?  Then it is not told.
  (quiet nil :type boolean)
  ;; Does it do nothing when autoscripts start and stop (QUIET-AUTOSCRIPTS-P)?
  ;; Then a state change due is applied without looking for autoscripts.
  (quiet-autoscripts nil :type boolean)
  (now 0d0 :type double-float)
  (agenda (make-agenda) :type agenda)
  ;; The EVENT-RUNs playing, oldest first.
  (runs '() :type list)
  ;; Op -> (CHANNELS . FIELDS), see OP-FOOTPRINT.
  (op-footprints (make-hash-table :test 'eq) :type hash-table)
  ;; Does the presenter give an op its declared channels, :ALL when it has
  ;; none (DECLARED-CHANNELS-P)?  Then an op without :channels meets
  ;; everything, and a run playing one needs no table look-up to say so.
  (declared-channels nil :type boolean)
  ;; Runs waiting, first first; QUEUE-TAIL is its last cons, for O(1) appending.
  (queue '() :type list)
  (queue-tail '() :type list)
  ;; The :OP items of interrupted events that still play out (their possibly
  ;; cut end is still to come): what a new event may have to wait for.  Only
  ;; a cut adds to it; an event that is not cut has no op left at its end.
  (live-ops '() :type list)
  ;; The earliest end among the live ops (meaningless when there are none):
  ;; ADVANCE-TIMELINE looks for ended ones only once that has come.
  (live-ops-end 0d0 :type double-float)
  ;; Op -> its interruption points in seconds, sorted.
  (cut-points (make-hash-table :test 'eq) :type hash-table)
  (recorder nil)
  ;; The presenter forwarding to RECORDER, the controller's while it plans.
  (recording-presenter nil)
  (timers '() :type list)
  (triggers '() :type list)
  ;; The plannable fields the triggers read, or T when one of them compares
  ;; numbers (START-TRIGGERS): a change of no field of these cannot fire a
  ;; trigger, so it is not asked (TRIGGERS-MAY-TURN-P).
  (trigger-fields 0 :type (or (eql t) integer))
  ;; Sends of timers and triggers that went off at NOW, newest first: they are
  ;; dispatched once everything else due at NOW has happened, as a send from
  ;; outside at that time would be.
  (deferred '() :type list)
  ;; When the ops cut for the event arriving now are all over (CUT-RUN).
  (cuts-end 0d0 :type double-float)
  ;; A cons that held the one run playing, to hold the next one (DROP-RUN).
  (spare-runs-cons nil :type list)
  ;; Items applied at the current instant, against loops of zero-length work.
  (instant-count 0 :type fixnum)
  ;; The runtime values an event planned ahead works on (the controller's are
  ;; copied in, and put back after), so planning allocates no vector.
  (scratch-values #() :type simple-vector)
  ;; The last NOW handed out boxed (BOXED-NOW), or NIL.
  (now-box nil)
  ;; Does it tape and replay its events' plans (*REPLAY-PLAN-TAPES* when it
  ;; was made)?  See TAPES.LISP.
  (replay-tapes nil :type boolean))

(defun controller-presenter* (timeline)
  "The presenter TIMELINE's controller presents to."
  (timeline-presenter timeline))

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
    (setf (timeline-now timeline) (controller-clock controller)
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
  "TIMELINE's NOW as a boxed double, the same box for as long as NOW stays:
FINISH-EVENTS answers it, and a send at the current time after it passes it
on, so the pair conses one box, not two."
  (let ((box (timeline-now-box timeline)))
    (if (and box (= (the double-float box) (timeline-now timeline)))
        box
        (setf (timeline-now-box timeline) (timeline-now timeline)))))

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

(declaim (inline timeline-busy-p))
(defun timeline-busy-p (timeline)
  "Is an event running (or waiting) on TIMELINE?"
  (or (timeline-runs timeline) (timeline-queue timeline)))

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
