;;;; start-gate.lisp -- every run about to start passes one gate (below): it
;;;; starts at the time asked, later, once ops of interrupted events are over,
;;;; or it waits in the queue; a run that starts is shown and fed to the agenda.

(in-package #:player.control)

(declaim #.*timeline-optimize*)                 ; the engine's policy (agenda.lisp)

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
          (present-resume presenter (run-name run) (micros->seconds time))
          (present-event presenter (run-name run) (micros->seconds time)))))
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
  (declare (integer time)
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
        (declare (integer settled))
        (when (= settled time)
          (return (values time result)))
        ;; Ops still playing are in its way: plan again from when they are over.
        (forget-plan timeline run)
        (setf time settled
              result (plan-footprint timeline run time t))))))

(declaim (inline live-ops-over-p))
(defun live-ops-over-p (timeline time)
  "Are the ops of interrupted events still playing all over by TIME?"
  (declare (integer time))
  (loop for item in (timeline-live-ops timeline)
        never (micros< time (agenda-item-end item))))

(defun start-or-wait (timeline run time &optional trial)
  "RUN passes the start gate at TIME: it starts then or later, or it waits
first in the queue.  TRIAL, if given, is the result of RUN's plan on trial
from TIME, which meets no running event.  Returns :STARTED and its planning
result, or :QUEUED and T."
  (declare (integer time))
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
