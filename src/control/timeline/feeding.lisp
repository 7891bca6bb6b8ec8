;;;; feeding.lisp -- a run feeds the agenda its items one at a time, in time
;;;; order: only its next item is on the heap, and the one after takes its
;;;; place when it comes up.  So the heap stays a few items deep, and the
;;;; items a cut cancels are mostly never pushed or popped at all.

(in-package #:player.control)

(declaim #.*timeline-optimize*)                 ; the engine's policy (agenda.lisp)

;; Inline: it runs for every item a timed controller plays.
(declaim (inline skip-pending))
(defun skip-pending (agenda pending time skip-ops)
  "PENDING (a run's pending items) from the first item the agenda must still
take.  (A cut's cancelled items are never among them: RETIRE-CANCELLED-ITEMS
takes them off at the cut.)  With SKIP-OPS, when AGENDA's ops are silent, an
:OP item due at TIME, the instant the run reaches it, is played there and
then (marked :DONE): telling nobody, it need not wait its turn on the agenda,
and no cut can fall before it (a cut comes once everything due at its instant
has happened)."
  (declare (agenda agenda) (list pending) (integer time))
  (loop (let ((item (first pending)))
          (cond ((null item) (return pending))
                ((and skip-ops (agenda-silent-ops agenda) (eq (agenda-item-kind item) :op)
                      (= (agenda-item-time item) time))
                 (setf (agenda-item-status item) :done
                       pending (rest pending)))
                (t (return pending))))))

;; Inline: it runs for every item a timed controller plays.
(declaim (inline with-finish))
(defun with-finish (agenda run pending)
  "PENDING, RUN's pending items, with its :FINISH first if that is due before
them (or they are none) and not made yet: a :time directive may leave
changes due after the event's end, and they stay after it."
  (if (and (null (run-finish run)) (not (run-finished run))
           (or (null pending) (micros< (run-finish-time run) (agenda-item-time (first pending)))))
      (spare-cons agenda (finish-item agenda run) pending)
      pending))

;; Inline: it runs for every item a timed controller plays.
(declaim (inline feed-next-item))
(defun feed-next-item (agenda run skip-ops)
  "RUN's first pending item comes off AGENDA: drop it, and the items after it
SKIP-PENDING passes, from RUN's pending items; return the next pending one or
NIL.  After its last item, a run that is not over gets its :FINISH."
  (let* ((pending (run-pending run))
         (rest (skip-pending agenda (rest pending) (agenda-item-time (first pending)) skip-ops)))
    ;; A cut run owns its pending list (its items list is empty then);
    ;; otherwise the list is shared with its items, but for the :FINISH's
    ;; own cons.
    (when (or (null (run-items run)) (eq (first pending) (run-finish run)))
      (give-back-cons agenda pending))
    (setf (run-pending run) (with-finish agenda run rest))
    (first (run-pending run))))

(declaim (inline run-head-p))
(defun run-head-p (item)
  "Is ITEM the one its run has on the agenda (not an item pushed on its own:
a timer, a cut's state change)?"
  (let ((run (agenda-item-run item)))
    (and run (eq (first (run-pending run)) item))))

;; Inline: ADVANCE-TIMELINE takes every item off the agenda with it.
(declaim (inline agenda-pop))
(defun agenda-pop (agenda item &optional (skip-ops t))
  "Take ITEM, AGENDA's first, off it; its run's next pending item, if it has
one, takes its place (past silent ops due now, unless SKIP-OPS is false)."
  (declare (agenda agenda) (agenda-item item))
  (let ((next (and (run-head-p item) (feed-next-item agenda (agenda-item-run item) skip-ops))))
    (if next
        (agenda-replace-top agenda next)
        (agenda-remove-top agenda))))

(defun discard-top (agenda top)
  "Take TOP, AGENDA's first item and a cancelled one, off it; retire it if it
is a cut run's (a cancelled timer item is still its timer's)."
  (declare (agenda agenda) (agenda-item top))
  (agenda-pop agenda top nil)
  (when (agenda-item-run top)
    (retire-item agenda top)))

;; Inline: ADVANCE-TIMELINE asks for every item.  Discarding is out of line:
;; it is the rare case, and a second copy of AGENDA-POP here would make the
;; loop that runs for every item twice as long.
(declaim (inline agenda-next))
(defun agenda-next (agenda)
  "AGENDA's first pending item, or NIL; cancelled items on top are discarded."
  (declare (agenda agenda))
  (loop while (plusp (agenda-count agenda))
        do (let ((top (svref (agenda-items agenda) 0)))
             (if (item-status-p top :cancelled)
                 (discard-top agenda top)
                 (return top)))))

;; Inline, so PROJECT-STATE's function is not made as a closure on the heap.
(declaim (inline map-agenda))
(defun map-agenda (function agenda)
  "Call FUNCTION on each pending item due on AGENDA (those its runs have not
fed it yet included), in no particular order."
  (dotimes (i (agenda-count agenda))
    (let ((item (svref (agenda-items agenda) i)))
      (if (run-head-p item)
          (dolist (pending (run-pending (agenda-item-run item)))
            (when (item-status-p pending :pending) (funcall function pending)))
          (when (item-status-p item :pending) (funcall function item))))))
