;;;; cuts.lisp -- interrupting a running event.  Each op running when the new
;;;; event arrives is cut at its next interruption point (:interrupt :never
;;;; means at its end, :anytime at once, (:at ...) at the next point of its
;;;; script) and leaves the state before it plus its :if-cut effects.  The
;;;; rest of the event is cancelled.  Because plans exist from every state,
;;;; whatever the cut leaves, the next event's plan starts from there.

(in-package #:player.control)

(declaim #.*timeline-optimize*)                 ; the engine's policy (agenda.lisp)

;; Inline: MEMBER on a list not known at compile time is a full call (to
;; %MEMBER-EQ), for each item of a cut run, though the lists are short and
;; mostly empty.
(declaim (inline memq))
(defun memq (item list)
  "Is ITEM in LIST (by EQ)?  True as MEMBER is: the tail that starts with it."
  (loop for tail on list
        when (eq (first tail) item) return tail))

(defun resolve-cut-points (timeline)
  "Give each op with (:at POINT...) its points in microseconds, sorted; names are
asked of the presenter (CRITICAL-TIME), which signals for an unknown one."
  (let ((presenter (timeline-presenter timeline)))
    (dolist (op (spec-ops (spec-of (timeline-controller timeline))))
      (when (listp (op-interrupt op))
        (setf (gethash op (timeline-cut-points timeline))
              (sort (mapcar (lambda (point)
                              (seconds->micros
                               (if (realp point)
                                   (to-double point)
                                   (presenter-seconds (critical-time presenter op point)
                                                      presenter 'critical-time op))))
                            (op-interrupt op))
                    #'<))))))

;; Typed, so CUT-RUN compares the times it returns as doubles; inline, so
;; they are not boxed to be returned.
(declaim (ftype (function (t agenda-item integer) (values integer &optional)) op-cut-time)
         (inline op-cut-time))
(defun op-cut-time (timeline item time)
  "When the op of :OP ITEM, running at TIME, can stop: its next interruption
point at or after TIME, else its end."
  (let* ((op (agenda-item-op item))
         (start (agenda-item-start item))
         (end (agenda-item-end item))
         (interrupt (op-interrupt op)))
    (cond ((eq interrupt :never) end)
          ((eq interrupt :anytime) (if (micros< time start) start time))
          (t (or (loop for point of-type integer in (gethash op (timeline-cut-points timeline))
                       for at of-type integer = (+ start point)
                       when (and (micros<= time at) (micros<= at end)) return at)
                 end)))))

(declaim (ftype (function (t t integer t) (values integer &optional)) settled-time)
         (inline settled-time))
(defun settled-time (timeline run time footprint)
  "The earliest moment from TIME when the ops of earlier, already cut runs that
meet FOOTPRINT (the interrupting event's) are all over.  RUN's own are cut
below; runs playing beside it on other channels do not matter."
  (let ((settled time))
    (declare (integer settled))
    (dolist (item (timeline-live-ops timeline) settled)
      (let ((other (agenda-item-run item)))
        (when (and (micros< settled (agenda-item-end item))
                   (not (eq other run)) (run-finished other)
                   (footprints-meet-p footprint (run-footprint* timeline other)))
          (setf settled (agenda-item-end item)))))))

;; Inline: a double argument of a full call is boxed, on every cut.
(declaim (inline running-ops))
(defun running-ops (agenda run time)
  "The :OP items of RUN presented and still playing at TIME, newest first, and
whether RUN has a macro-op."
  ;; Newest first as before the run fed the agenda lazily (RUN-ITEMS was then
  ;; newest first): the cut state changes get their sequence numbers in that order.
  (declare (integer time))
  (let ((running '()) (macros nil))
    (dolist (item (run-items run) (values running macros))
      (case (agenda-item-kind item)
        (:macro-end (setf macros t))
        (:op (when (and (item-status-p item :done) (micros< time (agenda-item-end item)))
               (setf running (spare-cons agenda item running))))))))

(defun cut-run (timeline run time by footprint)
  "Interrupt RUN at TIME for event BY: cut its running ops at their next
interruption points, cancel the rest of it.  The time the new event can start
is brought up to TIMELINE's CUTS-END (a double returned would be boxed).
Returns the top-level directive RUN would resume from (NIL when nothing of it
was left to do)."
  ;; Its footprint stays needed (SETTLED-TIME) after its items are trimmed.
  (run-footprint* timeline run)
  (let ((presenter (timeline-presenter timeline))
        (agenda (timeline-agenda timeline))
        (cut-time (settled-time timeline run time footprint))
        (resume nil)
        (keep '())
        (shown nil)
        (finishing nil)
        (running '())
        (macros nil))
    ;; RESUME typed, and RESUME-AT inline: the steps compare as fixnums, not
    ;; by a generic MIN in a local call, for each item the cut cancels.
    (declare (integer time cut-time) (type (or null fixnum) resume))
    (flet ((resume-at (item)
             (let ((step (agenda-item-step item)))
               (when (or (null resume) (< step resume))
                 (setf resume step)))))
      (declare (inline resume-at))
      ;; Running ops: cut short, or let finish, newest first.
      (multiple-value-setq (running macros) (running-ops agenda run time))
      (dolist (item running)
        (let ((at (op-cut-time timeline item time)))
          (when (micros< cut-time at) (setf cut-time at))
          (if (micros< at (agenda-item-end item))
              (multiple-value-bind (mask bits) (cut-effect-fields (agenda-item-op item))
                (setf (agenda-item-end item) at)
                (resume-at item)
                (unless (eql mask 0)
                  (let ((change (fresh-agenda-item agenda :delta at run)))
                    (setf (agenda-item-a change) mask (agenda-item-b change) bits
                          (agenda-item-step change) (agenda-item-step item))
                    (setf keep (spare-cons agenda change keep))
                    (agenda-push agenda change)))
                (setf shown (spare-cons agenda item shown)))
              (progn (setf finishing item)
                     (dolist (other (run-items run))
                       (when (eq (agenda-item-owner other) item)
                         (setf keep (spare-cons agenda other keep))))))
          ;; Cut short or not, it plays out after RUN is over.
          (setf (timeline-live-ops-end timeline) (if (timeline-live-ops timeline)
                                                      (min (timeline-live-ops-end timeline) (agenda-item-end item))
                                                      (agenda-item-end item))
                (timeline-live-ops timeline) (spare-cons agenda item (timeline-live-ops timeline)))))
      ;; A macro whose sub-ops all finish by the cut ends as it would have.
      (when macros
        (setf keep (keep-finished-macros agenda run keep cut-time shown)))
      ;; Everything else still pending is cancelled, its :FINISH too if the
      ;; run has got that far.
      (dolist (item (run-items run))
        (when (and (item-status-p item :pending) (not (memq item keep)))
          (resume-at item)
          (setf (agenda-item-status item) :cancelled)))
      (let ((finish (run-finish run)))
        (when finish
          (setf (agenda-item-status finish) :cancelled))))
    ;; Close the macros the cut falls in, innermost first.
    (unless (timeline-quiet timeline)
      (dolist (item (and macros (cut-macro-starts run)))
        (present-macro-end presenter (agenda-item-op item) (micros->seconds (agenda-item-start item))
                           (micros->seconds cut-time))))
    (cond ((timeline-quiet timeline))
          (shown
           (dolist (item (reverse shown))
             (present-cut presenter (agenda-item-op item) (micros->seconds (agenda-item-start item))
                          (micros->seconds (agenda-item-end item)) by)))
          (t (present-cut presenter (and finishing (agenda-item-op finishing))
                          (micros->seconds (if finishing (agenda-item-start finishing) time))
                          (micros->seconds cut-time) by)))
    (retire-played-items agenda run running keep)
    ;; Lists of this cut alone (the live ops have their own conses).
    (give-back-list agenda running)
    (give-back-list agenda shown)
    (give-back-list agenda keep)
    (setf (run-finished run) t
          (run-items run) '())
    (drop-run timeline run)
    (setf (timeline-cuts-end timeline) (max (timeline-cuts-end timeline) cut-time))
    resume))

(defun retire-cancelled-items (timeline run)
  "Take the items of RUN, just cut, that the cut cancelled off its pending
list (and its first off TIMELINE's agenda, if that is one) and retire them
at once: nothing else reaches them.  The items the cut kept stay pending,
the first of them on the agenda in place of the one cancelled.  Call it once
nothing reads RUN's policy any more: the last of its items retired may
retire RUN too."
  ;; At once, not as the agenda would have passed them one by one (AGENDA-NEXT
  ;; discarding the cancelled first, FEED-NEXT-ITEM the rest): the pool takes
  ;; them in one splice, and nothing cancelled is left on the agenda.
  (let* ((agenda (timeline-agenda timeline))
         (pending (run-pending run))
         (first (first pending))
         (kept '()) (kept-last nil)
         (cancelled '()) (cancelled-last nil))
    (if (loop for item in pending always (item-status-p item :cancelled))
        ;; The usual case: the cut kept none of them.
        (setf cancelled pending)
        ;; Split the pending conses (RUN's own since the cut) in two lists, in order.
        (loop while pending
              do (let ((cell pending))
                   (setf pending (rest cell)
                         (rest cell) '())
                   (if (item-status-p (first cell) :cancelled)
                       (if cancelled-last
                           (setf (rest cancelled-last) cell cancelled-last cell)
                           (setf cancelled cell cancelled-last cell))
                       (if kept-last
                           (setf (rest kept-last) cell kept-last cell)
                           (setf kept cell kept-last cell))))))
    (when (and first (item-status-p first :cancelled))
      (agenda-swap-out agenda first (first kept)))
    (setf (run-pending run) kept)
    (retire-item-list agenda cancelled run)))

(defun retire-played-items (agenda run running keep)
  "Retire the items of RUN, being cut, that have been played and neither play
on (RUNNING, which become live ops) nor are KEPT: nothing will reach them.
Its cancelled items are retired once the cut is made (RETIRE-CANCELLED-ITEMS).
Give back the conses of RUN's items list that its pending list does not share
(all of them when that is a sorted copy): the run keeps only its pending list."
  (let ((pending (let ((pending (run-pending run)))
                   ;; A :FINISH made ahead of later items has a cons of its own.
                   (if (and pending (eq (first pending) (run-finish run)))
                       (rest pending)
                       pending)))
        (cell (run-items run))
        (last nil))
    ;; Up to the pending list: the items after it are pending still, none
    ;; played (an item leaves the pending list before it is played).
    (loop until (or (null cell) (eq cell pending))
          do (let ((item (first cell)))
               (when (and (item-status-p item :done)
                          (not (memq item running))
                          (not (memq item keep)))
                 (retire-item agenda item)))
             (setf last cell
                   cell (rest cell)))
    ;; The conses passed, RUN's own, go back in one splice.
    (when (and last (agenda-recycle agenda))
      (setf (rest last) (agenda-free-conses agenda)
            (agenda-free-conses agenda) (run-items run)))))

;; RUN's items are in SEQ order (the order they were recorded), so pushing
;; them as they come leaves the newest, innermost macro first without a sort.
(defun cut-macro-starts (run)
  "The :MACRO-START items of RUN presented whose :MACRO-END the cut cancelled,
innermost (newest) first."
  (let ((starts '()))
    (dolist (item (run-items run) starts)
      (when (and (eq (agenda-item-kind item) :macro-start)
                 (item-status-p item :done)
                 (agenda-item-owner item)
                 (item-status-p (agenda-item-owner item) :cancelled))
        (push item starts)))))

(defun keep-finished-macros (agenda run keep cut-time cut-ops)
  "KEEP, plus the end (and end state change) of each macro of RUN that ends by
CUT-TIME with every pending item inside it kept and none of its sub-ops in
CUT-OPS (the :OP items cut short): its last sub-op runs to its end through the
cut, so the macro ends then, declared effects and all."
  ;; A run's items are in SEQ order (the order they were recorded).
  (let ((items (run-items run)))
    (dolist (item items keep)
      (when (and (eq (agenda-item-kind item) :macro-end) (item-status-p item :pending)
                 (micros<= (agenda-item-time item) cut-time))
        (let ((opening (find item items :key #'agenda-item-owner)))
          (when (and opening
                     (every (lambda (inner)
                              (or (<= (agenda-item-seq inner) (agenda-item-seq opening))
                                  (>= (agenda-item-seq inner) (agenda-item-seq item))
                                  (and (not (member inner cut-ops))
                                       (or (not (item-status-p inner :pending))
                                           (member inner keep)))))
                            items))
            (setf keep (spare-cons agenda item keep))
            (dolist (other items)
              (when (eq (agenda-item-owner other) item)
                (setf keep (spare-cons agenda other keep))))))))))
