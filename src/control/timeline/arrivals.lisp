;;;; arrivals.lisp -- an event arriving at a timed controller: queued behind
;;;; the runs before it, or, when the controller is busy, resolved by its
;;;; :when-busy policy (queue, preempt, override, interleave) against the runs
;;;; it meets; an interrupted run resumes from the step it had reached.

(in-package #:player.control)

(declaim #.*timeline-optimize*)                 ; the engine's policy (agenda.lisp)

(defun enqueue-run (timeline run)
  "Put RUN last in TIMELINE's queue."
  (let ((cell (list run)))
    (if (timeline-queue timeline)
        (setf (cdr (timeline-queue-tail timeline)) cell)
        (setf (timeline-queue timeline) cell))
    (setf (timeline-queue-tail timeline) cell)))

(defun push-run-first (timeline run)
  "Put RUN first in TIMELINE's queue."
  (push run (timeline-queue timeline))
  (unless (cdr (timeline-queue timeline))
    (setf (timeline-queue-tail timeline) (timeline-queue timeline))))

(defun pop-run (timeline)
  "Take the first run off TIMELINE's queue."
  (prog1 (pop (timeline-queue timeline))
    (unless (timeline-queue timeline)
      (setf (timeline-queue-tail timeline) '()))))

(defun dispatch-event (timeline compiled time policy source)
  "Event COMPILED arrives at TIME (= NOW) from SOURCE.  It is planned
on trial; if its footprint meets no running event's it starts (START-OR-WAIT:
now, beside any others, unless ops still playing or a plan made later are in
its way); else POLICY decides against those it meets.  Returns the
disposition (:STARTED, :QUEUED, :DROPPED, :PREEMPTED or :INTERLEAVED) and the
planning result (T or a FAILURE; T when it waits)."
  (when (timeline-timers timeline)
    (note-event-for-timers timeline compiled source time))
  (let ((run (fresh-event-run (timeline-agenda timeline) compiled policy source)))
    (if (null (timeline-runs timeline))
        (start-or-wait timeline run time)
        (let ((trial (plan-on-trial timeline run time)))
          (if (or (eq trial :untried) (meets-running-p timeline run))
              (resolve-busy timeline run time policy)
              (start-or-wait timeline run time trial))))))

(defun resolve-busy (timeline run time policy)
  "RUN arrives at TIME while events it meets play: do what POLICY says."
  (let* ((name (run-name run))
         (met (if (run-footprint run)
                  (met-runs timeline run)
                  (timeline-runs timeline)))
         (footprint (or (run-footprint run) *everything-footprint*)))
    (forget-plan timeline run)
    (ecase policy
      (:queue
       (unless (timeline-quiet timeline)
         (present-queued (timeline-presenter timeline) name (micros->seconds time)
                         (run-name (if (timeline-queue timeline)
                                       (first (timeline-queue-tail timeline))
                                       (first met)))))
       (enqueue-run timeline run)
       (values :queued t))
      (:override
       (present-dropped (timeline-presenter timeline) name (micros->seconds time) (run-name (first met))
                        (footprint-clash footprint (run-footprint* timeline (first met))
                                         (spec-of (timeline-controller timeline))))
       (values :dropped nil))
      ((:preempt :interleave)
       (let ((resumptions '()))
         (setf (timeline-cuts-end timeline) time)
         (dolist (other met)
           (let ((resume-step (cut-run timeline other time name footprint)))
             (when (and (eq policy :interleave) resume-step)
               (push (resumption other resume-step) resumptions))
             ;; After RESUMPTION has read OTHER's policy: retiring the items
             ;; it cancelled may retire OTHER.
             (retire-cancelled-items timeline other)))
         ;; A cut falling now leaves its :if-cut state now: apply it
         ;; before the new event plans from it.
         (advance-timeline* timeline time nil nil)
         ;; The interrupted resume in the order they started, before the
         ;; queue -- after RUN, should a running event keep it waiting.
         (dolist (again resumptions)
           (push-run-first timeline again))
         (values (if (eq policy :preempt) :preempted :interleaved)
                 ;; Its plan from the state the cuts leave is not its trial
                 ;; plan: the start gate checks it against the runs left.
                 ;; TIME itself when no cut runs on: it comes boxed.
                 (nth-value 1 (start-or-wait timeline run (if (> (timeline-cuts-end timeline) time)
                                                              (timeline-cuts-end timeline)
                                                              time)))))))))

(defun met-runs (timeline run)
  "The running events whose footprints meet planned RUN's, oldest first."
  (flet ((meets-p (other) (footprints-meet-p (run-footprint run) (run-footprint* timeline other))))
    (let ((runs (timeline-runs timeline)))
      ;; One event running (the usual case): no new list unless it is left out.
      (if (null (rest runs))
          (and runs (meets-p (first runs)) runs)
          (remove-if-not #'meets-p runs)))))

;; Inline: it runs for every event a timed controller plays.
(defun resumption (run step)
  "A run that finishes interrupted RUN from its top-level directive STEP."
  (let ((again (make-event-run (run-compiled run) (run-policy run) (run-source run))))
    (setf (run-first-step again) step
          (run-resumed again) t)
    again))
