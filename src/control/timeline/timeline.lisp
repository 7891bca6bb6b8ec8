;;;; timeline.lisp -- a timed controller's clock.  Ops occupy intervals and
;;;; change the state when they end; ADVANCE moves the clock and presents op
;;;; starts, state changes (with their autoscripts) and event ends as they fall
;;;; due (ADVANCE.LISP).  An event is planned ahead when it starts
;;;; (RECORDER.LISP, and below), so until something interrupts it, it does
;;;; exactly what the whole-event API does.

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

(define-condition timeline-error (player-error)
  ((message :initarg :message :reader timeline-error-message))
  (:report (lambda (condition stream) (write-string (timeline-error-message condition) stream)))
  (:documentation "A timed controller cannot go on (e.g. triggers firing each other for ever)."))

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

;;;# Starting an event

(declaim (inline next-seq))
(defun next-seq (timeline)
  "A fresh sequence number: items made later sort later at equal times."
  (agenda-next-seq (timeline-agenda timeline)))

(defun timeline-seq (timeline)
  "The last sequence number TIMELINE gave an item (how many it made)."
  (agenda-seq (timeline-agenda timeline)))

(defun project-state (timeline time)
  "Put into the controller the state it will have at TIME (after NOW): the
pending state changes due by then, applied without telling anyone."
  (declare (double-float time))
  (let ((controller (timeline-controller timeline))
        (agenda (timeline-agenda timeline))
        (due '()))
    (map-agenda (lambda (item)
                  (when (and (member (agenda-item-kind item) '(:delta :value))
                             (<= (agenda-item-time item) time))
                    (setf due (spare-cons agenda item due))))
                agenda)
    (setf due (if (rest due) (sort due #'item-before-p) due))
    (dolist (item due)
      (apply-change controller item))
    ;; SORT reuses the conses it was given: all of them are the list's.
    (give-back-list agenda due)))

(defun apply-change (controller item)
  "Apply state change ITEM to CONTROLLER's state, silently."
  (if (eq (agenda-item-kind item) :delta)
      (setf (controller-bits controller)
            (state-with-fields (controller-bits controller) (agenda-item-a item) (agenda-item-b item)))
      (setf (svref (controller-values controller) (var-slot (agenda-item-a item))) (agenda-item-b item))))

(defun start-run (timeline run time)
  "Start RUN at TIME (at or after NOW): show it, plan it ahead and put its items
on the agenda.  Returns T, or the FAILURE its plan ran into."
  (let ((result (plan-run-ahead timeline run time)))
    (install-run timeline run time)
    result))

(defun install-run (timeline run time)
  "RUN, planned ahead from TIME, starts: show it, note its footprint, put its
items on the agenda."
  (unless (timeline-quiet timeline)
    (let ((presenter (timeline-presenter timeline)))
      (if (run-resumed run)
          (present-resume presenter (run-name run) time)
          (present-event presenter (run-name run) time))))
  (setf (timeline-runs timeline) (cond ((timeline-runs timeline)
                                        (append (timeline-runs timeline) (list run)))
                                       ((timeline-spare-runs-cons timeline)
                                        (let ((cell (shiftf (timeline-spare-runs-cons timeline) nil)))
                                          (setf (first cell) run)
                                          cell))
                                       (t (list run))))
  (let* ((agenda (timeline-agenda timeline))
         (pending (setf (run-pending run)
                        (with-finish agenda run
                          (skip-pending agenda (run-pending run) (timeline-now timeline) t)))))
    (agenda-push agenda (first pending))))

(defun planned-footprint (timeline run)
  "The footprint of RUN, planned ahead."
  (run-footprint-from-items timeline run))

(defun run-footprint* (timeline run)
  "RUN's footprint, worked out from its items when first asked (before a cut
trims them)."
  (or (run-footprint run)
      (setf (run-footprint run) (planned-footprint timeline run))))

;; Inline: it runs for every event arriving while others play.
(declaim (inline untried-p))
(defun untried-p (timeline run)
  "Is RUN taken to meet everything without being planned: its event runs code
(planning it would run the code), or a running event meets everything anyway?"
  (or (compiled-event-runs-code-p (run-compiled run))
      (some (lambda (other) (meets-everything-p (run-footprint* timeline other))) (timeline-runs timeline))))

(defun plan-on-trial (timeline run time)
  "Plan RUN ahead from TIME to learn its footprint, unless it is UNTRIED-P.
Returns the planning result, or :UNTRIED; RUN keeps its items and footprint."
  (if (untried-p timeline run)
      :untried
      (plan-footprint timeline run time)))

(defun plan-footprint (timeline run time &optional all-due)
  "Plan RUN ahead from TIME (ALL-DUE: see PLAN-RUN-AHEAD) and note its
footprint; return the planning result."
  (prog1 (plan-run-ahead timeline run time all-due)
    (setf (run-footprint run) (planned-footprint timeline run))))

(defun meets-running-p (timeline run)
  "Does planned RUN (its footprint known) meet a running event?"
  (some (lambda (other) (footprints-meet-p (run-footprint run) (run-footprint* timeline other)))
        (timeline-runs timeline)))

(defun forget-plan (timeline run)
  "Drop what RUN planned on trial (it will be planned again when it starts):
its items were never on the agenda, so they are retired."
  (retire-item-list (timeline-agenda timeline) (shiftf (run-items run) '()))
  (setf (run-pending run) '()
        (run-footprint run) nil))

;;;# The start gate
;;;
;;; Every run about to start -- an event arriving while nothing plays or beside
;;; the events playing, a preempting or interleaving event after its cuts, a
;;; waiting run or a resumption leaving the queue -- passes one gate, at the
;;; time S it would start: it is planned from the state due at S, and it starts
;;; at S only if that plan's footprint meets no running event and no op of an
;;; interrupted event still playing after S.  When only such ops are in the
;;; way, S becomes the time they are over and it is planned again (S only
;;; grows, over the ends of finitely many ops, so this ends).  When a running
;;; event is in the way, it waits first in the queue (a preemptor ahead of the
;;; runs it interrupted), looked at again when a run finishes; its policy is
;;; not applied again.  A plan made later than the trial that resolved the
;;; event's arrival (a preemptor's, from the state its cuts leave; one made
;;; after ops still playing) may meet what the trial plan did not -- a plan
;;; with no op meets everything -- so the gate checks exactly the plan that
;;; will play.  "The state due at S" counts every change due by S, those due
;;; at S = NOW and not applied yet too: a run leaving the queue when another
;;; finishes starts in the middle of an instant.

(defun gate-run (timeline run time &optional trial)
  "The start gate (above) for RUN at TIME (at or after NOW).  TRIAL, if given,
is the result of RUN's plan already made from TIME (its plan on trial).
Returns the time RUN may start, RUN planned from then, and its planning result
(two values); or NIL, RUN holding no plan, when a running event is in its way."
  (declare (double-float time)
           ;; Defined (inline, for CUT-RUN) in cuts.lisp, compiled after this file.
           (notinline settled-time))
  (when (untried-p timeline run)
    ;; Taken to meet everything: planned (once: it may run code) only when
    ;; nothing plays, after every op still playing.
    (return-from gate-run
      (unless (timeline-runs timeline)
        (let ((start (settled-time timeline nil time *everything-footprint*)))
          (values start (plan-run-ahead timeline run start t))))))
  (let ((result (or trial (plan-footprint timeline run time t))))
    (loop
      (when (meets-running-p timeline run)
        (forget-plan timeline run)
        (return nil))
      (let ((settled (settled-time timeline nil time (run-footprint run))))
        (declare (double-float settled))
        (when (= settled time)
          (return (values time result)))
        ;; Ops still playing are in its way: plan again from when they are over.
        (forget-plan timeline run)
        (setf time settled
              result (plan-footprint timeline run time t))))))

(declaim (inline live-ops-over-p))
(defun live-ops-over-p (timeline time)
  "Are the ops of interrupted events still playing all over by TIME?"
  (declare (double-float time))
  (loop for item in (timeline-live-ops timeline)
        never (> (agenda-item-end item) time)))

(defun start-or-wait (timeline run time &optional trial)
  "RUN passes the start gate at TIME: it starts then or later, or it waits
first in the queue.  TRIAL, if given, is the result of RUN's plan on trial
from TIME, which meets no running event.  Returns :STARTED and its planning
result, or :QUEUED and T."
  (declare (double-float time))
  (if (and (or trial (null (timeline-runs timeline))) (live-ops-over-p timeline time))
      ;; Nothing can be in its way (the usual case, a preemptor after its
      ;; cuts included: the ops it cut end when it starts): it starts now.
      ;; Nothing due by TIME is left unapplied here either, so the plan from
      ;; the state due at TIME is the gate's.
      (if trial
          (progn (install-run timeline run time) (values :started trial))
          (values :started (start-run timeline run time)))
      (multiple-value-bind (start result) (gate-run timeline run time trial)
        (cond (start (install-run timeline run start)
                     (values :started result))
              (t (push-run-first timeline run)
                 (values :queued t))))))

(defun plan-run-ahead (timeline run time &optional all-due)
  "Run RUN's compiled event on the controller with the recorder as presenter,
from the state due at TIME, then put the controller's state back.  The
recorded items end with a :FAIL (if the plan failed) and the :FINISH.  With
ALL-DUE, the changes due at TIME = NOW not applied yet count too (a run
starting while the items of the instant are being applied)."
  (declare (double-float time))
  (let* ((controller (timeline-controller timeline))
         (recorder (timeline-recorder timeline))
         (bits (controller-bits controller))
         (values (controller-values controller))
         (result nil))
    (unwind-protect
         (progn
           (when (plusp (length values))
             (setf (controller-values controller)
                   (replace (the simple-vector (timeline-scratch-values timeline))
                            (the simple-vector values))))
           (when (or all-due (> time (timeline-now timeline)))
             (project-state timeline time))
           (start-recording recorder run)
           (setf (controller-presenter controller) (timeline-recording-presenter timeline)
                 (controller-recorder controller) recorder
                 (controller-step controller) (run-first-step run)
                 (controller-schedule controller) time
                 (controller-span-start controller) time
                 (controller-span-end controller) time)
           (dolist (var (event-time-variables (run-event run)))
             (set-runtime-value controller var time time))
           (setf result (run-event-plan timeline run controller))
           (unless (eq result t)
             (record-failure recorder (failure-goal-form result) (controller-schedule controller)))
           ;; Its :FINISH is made when the run gets there (FINISH-ITEM).
           (setf (run-finish-time run) (controller-span-end controller)
                 (run-finish-seq run) (agenda-next-seq (timeline-agenda timeline))
                 (run-finish run) nil)
           (finish-recording recorder))
      (setf (recorder-taping recorder) nil
            (controller-presenter controller) (timeline-presenter timeline)
            (controller-recorder controller) nil
            (controller-bits controller) bits
            (controller-values controller) values))
    result))

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
