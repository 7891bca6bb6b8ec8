;;;; timeline-state.lisp -- the TIMELINE structure, a timed controller's
;;;; clock and what it holds (made and explained in timeline.lisp).  Defined
;;;; before the files that read it, so its accessors compile inline there.

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
  ;; Every time here is whole microseconds (EXACT-TIMES.LISP in base).
  (now 0 :type integer)
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
  (live-ops-end 0 :type integer)
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
  (cuts-end 0 :type integer)
  ;; A cons that held the one run playing, to hold the next one (DROP-RUN).
  (spare-runs-cons nil :type list)
  ;; Items applied at the current instant, against loops of zero-length work.
  (instant-count 0 :type fixnum)
  ;; The runtime values an event planned ahead works on (the controller's are
  ;; copied in, and put back after), so planning allocates no vector.
  (scratch-values #() :type simple-vector)
  ;; The last NOW handed out in seconds (BOXED-NOW), or NIL, and that NOW.
  (now-box nil)
  (now-box-micros -1 :type integer)
  ;; Does it tape and replay its events' plans (*REPLAY-PLAN-TAPES* when it
  ;; was made)?  See TAPES.LISP.
  (replay-tapes nil :type boolean))

(defun controller-presenter* (timeline)
  "The presenter TIMELINE's controller presents to."
  (timeline-presenter timeline))

(declaim (inline timeline-busy-p))
(defun timeline-busy-p (timeline)
  "Is an event running (or waiting) on TIMELINE?"
  (or (timeline-runs timeline) (timeline-queue timeline)))
