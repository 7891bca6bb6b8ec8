;;;; advance.lisp -- moving a timed controller's clock: everything due up to
;;;; the new time is applied in (TIME, SEQ) order, each item doing what it
;;;; says (an op's start shown, a state change made, an event ended and the
;;;; waiting ones started).

(in-package #:player.control)

(declaim #.*timeline-optimize*)                 ; the engine's policy (agenda.lisp)

(declaim (inline note-instant))
(defun note-instant (timeline time)
  "Count items applied at TIME; signal a TIMELINE-ERROR when they never end."
  (declare (integer time))
  (if (eql time (timeline-now timeline))        ; integers: = is EQL
      (when (> (incf (timeline-instant-count timeline)) *max-items-per-instant*)
        (setf (timeline-instant-count timeline) 0)
        (stuck-instant-error time))
      (setf (timeline-instant-count timeline) 0)))

;; The errors of ADVANCE-TIMELINE's loop are functions of their own: their
;; FORMATs inline would make the code that runs for every item much longer.
(defun stuck-instant-error (time)
  "Signal that the timeline does not move on at TIME."
  (error 'timeline-error
         :message (format nil "the timeline does not move on at time ~A: over ~D things happen at that instant (triggers firing each other, or zero-length ops in a loop)"
                          (format-number time) *max-items-per-instant*)))

(defun never-idle-error (time)
  "Signal that events keep coming at TIME, when the timeline was to run until idle."
  (error 'timeline-error
         :message (format nil "events never stop coming: still busy at time ~A after ~:D steps (timers or triggers keep sending events); advance to a time instead"
                          (format-number time) *finish-events-limit*)))

;; Inline: it is asked for every state change while a trigger is armed.
(declaim (inline check-triggers-if-turned))
(defun check-triggers-if-turned (timeline controller changed)
  "CHECK-TRIGGERS, after a change of the plannable fields CHANGED (0 for a
runtime value), unless no trigger reads those fields: then only what it does
besides, CONTROLLER's scheduling clock set to NOW."
  (if (triggers-may-turn-p timeline changed)
      (check-triggers timeline changed)
      ;; NIL: the double just set, returned, would be boxed.
      (progn (setf (controller-schedule controller) (timeline-now timeline))
             nil)))

;; Inline: ADVANCE-TIMELINE, its one caller, applies every item with it.
(declaim (inline apply-item))
(defun apply-item (timeline item)
  "Do what ITEM says, now that its time has come."
  ;; ITEM's time is read where it is passed on, never bound: a double variable
  ;; that several calls take boxed is boxed where it is bound, on every item.
  (let ((controller (timeline-controller timeline))
        (presenter (timeline-presenter timeline)))
    (ecase (agenda-item-kind item)
      (:op
       (unless (timeline-quiet timeline)
         (present-op presenter (agenda-item-op item) (micros->seconds (agenda-item-start item)))))
      (:delta
       (let ((bits (state-with-fields (controller-bits controller) (agenda-item-a item)
                                      (agenda-item-b item))))
         (if (timeline-quiet-autoscripts timeline)
             (setf (controller-bits controller) bits)
             (transition-state controller bits (agenda-item-time item))))
       (when (timeline-triggers timeline)
         (check-triggers-if-turned timeline controller (agenda-item-a item))))
      (:value
       (if (timeline-quiet-autoscripts timeline)
           (setf (svref (controller-values controller) (var-slot (agenda-item-a item))) (agenda-item-b item))
           (set-runtime-value controller (agenda-item-a item) (agenda-item-b item) (agenda-item-time item)))
       (when (timeline-triggers timeline)
         (check-triggers-if-turned timeline controller 0)))
      (:macro-start
       (unless (timeline-quiet timeline)
         (present-macro-start presenter (agenda-item-op item) (micros->seconds (agenda-item-start item)))))
      (:macro-end
       (unless (timeline-quiet timeline)
         (present-macro-end presenter (agenda-item-op item) (micros->seconds (agenda-item-start item))
                             (micros->seconds (agenda-item-time item)))))
      (:fail
       (unless (timeline-quiet timeline)
         (present-failure presenter (run-name (agenda-item-run item)) (agenda-item-b item)
                          (micros->seconds (agenda-item-time item)))))
      (:finish (finish-run timeline (agenda-item-run item)))
      (:timer (fire-timer timeline (agenda-item-a item) item (agenda-item-time item))))))

(defun advance-timeline (timeline time &optional (dispatch t) until-idle)
  "Present and apply, in time order, everything due on TIMELINE up to TIME;
then NOW is TIME.  Events that timers and triggers send at an instant are
dispatched when everything else due then has happened (unless DISPATCH is
false: then they wait for the ADVANCE-TIMELINE that called this one).  With
UNTIL-IDLE, stop instead at the first instant after which no event runs or
waits (NOW is then that instant), signalling a TIMELINE-ERROR after
*FINISH-EVENTS-LIMIT* items if that never comes."
  (advance-timeline* timeline time dispatch until-idle))

;; Every argument required: it is called twice for every event, and an
;; &optional entry sorts its arguments out on each call.  The engine calls
;; it; ADVANCE-TIMELINE is the same with the defaults.
(defun advance-timeline* (timeline time dispatch until-idle)
  "ADVANCE-TIMELINE with all its arguments given."
  (let ((agenda (timeline-agenda timeline))
        (time time)
        (steps 0)
        ;; Read once: a special variable's value is looked up on each read.
        (step-limit (if until-idle *finish-events-limit* most-positive-fixnum)))
    (declare (fixnum steps step-limit) (integer time))
    (loop
      (let ((item (agenda-next agenda)))
        (cond ((and until-idle (null (timeline-deferred timeline))
                    (or (null item) (micros< (timeline-now timeline) (agenda-item-time item)))
                    (or (null item) (not (timeline-busy-p timeline))))
               (setf time (timeline-now timeline))
               (return))
              ((and item (micros<= (agenda-item-time item) time)
                    (not (and dispatch (timeline-deferred timeline)
                              (micros< (timeline-now timeline) (agenda-item-time item)))))
               (when (> (incf steps) step-limit)
                 (never-idle-error (timeline-now timeline)))
               #-player-unchecked-engine
               (when (item-status-p item :free)
                 (retired-item-error item "applied"))
               (agenda-pop agenda item)
               (note-instant timeline (agenda-item-time item))
               (setf (timeline-now timeline) (agenda-item-time item)
                     (agenda-item-status item) :done)
               ;; An item of a run already over is reached by nothing once
               ;; applied.  (Asked before: applying a :FINISH ends its run.)
               (let ((after (let ((run (agenda-item-run item))) (and run (run-finished run)))))
                 (apply-item timeline item)
                 (when after
                   (retire-item agenda item))))
              ((and dispatch (timeline-deferred timeline))
               (let ((sends (reverse (timeline-deferred timeline))))
                 (setf (timeline-deferred timeline) '())
                 (mapc #'funcall sends)))
              (t (return)))))
    (setf (timeline-now timeline) time)
    (when (and (timeline-live-ops timeline) (micros<= (timeline-live-ops-end timeline) time))
      (forget-ended-ops timeline))
    (setf (controller-clock-micros (timeline-controller timeline)) time)
    ;; No value: a double returned would be boxed, twice per event.
    (values)))

(defun forget-ended-ops (timeline)
  "Drop (destructively) from TIMELINE's live ops the :OP items that end by its
NOW, and retire them: their runs are over, so nothing else reaches them."
  ;; NOW read here, not passed: a double argument of a full call is boxed.
  (let ((live-ops (timeline-live-ops timeline))
        (time (timeline-now timeline))
        (agenda (timeline-agenda timeline)))
    (flet ((ended-p (item) (micros<= (agenda-item-end item) time)))
      (declare (inline ended-p))              ; not a local call per op
      (loop while (and live-ops (ended-p (first live-ops)))
            do (retire-item agenda (first live-ops))
               (give-back-cons agenda (shiftf live-ops (rest live-ops))))
      (loop for cell on live-ops
            do (loop while (and (rest cell) (ended-p (second cell)))
                     do (retire-item agenda (second cell))
                        (give-back-cons agenda (shiftf (rest cell) (cddr cell)))))
      (setf (timeline-live-ops timeline) live-ops
            (timeline-live-ops-end timeline)
            (loop for item in live-ops minimize (agenda-item-end item) of-type integer)))))

(defun finish-run (timeline run)
  "RUN is over at TIMELINE's NOW: show the state, and start the waiting events
that no running event meets any more, first first."
  (setf (run-finished run) t)
  (unless (timeline-quiet timeline)
    (present-state (timeline-presenter timeline) (timeline-controller timeline)))
  (drop-run timeline run)
  ;; Every item of a run that played to its end has come off the agenda,
  ;; so nothing reaches them now -- unless a :time directive left changes due
  ;; after its end: those are retired as they are applied.
  (when (null (run-pending run))
    (retire-item-list (timeline-agenda timeline) (shiftf (run-items run) '()) run)
    (retire-item (timeline-agenda timeline) (run-finish run)))
  (when (timeline-queue timeline)
    (start-waiting-runs timeline (timeline-now timeline))))

(defun start-waiting-runs (timeline time)
  "Start the waiting runs, first first, each at TIME or when the start gate
lets it (GATE-RUN), until one finds a running event in its way."
  (loop for next = (first (timeline-queue timeline))
        while next
        do (let ((start (gate-run timeline next time)))
             (if start
                 (install-run timeline (pop-run timeline) start)
                 (return)))))
