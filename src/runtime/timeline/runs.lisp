;;;; runs.lisp -- one event played on a timeline: what it was, under which
;;;; policy it came, and the items it planned ahead.  A run feeds the agenda
;;;; its items one at a time, in time order: only its next item is on the
;;;; heap, and the one after takes its place when it comes up.  So the heap
;;;; stays a few items deep, and the items a cut cancels are mostly never
;;;; pushed or popped at all.

(in-package #:player)

;; Twelve words with the header, one taken for every event (ITEM-POOL.LISP):
;; its name is its compiled event's (RUN-NAME), not a slot of its own.
(defstruct (event-run (:conc-name run-) (:constructor make-event-run (compiled policy source)))
  "An event (its COMPILED-EVENT) on a timed controller, from its start to its
end or cut.  SOURCE is :USER, :TIMER or :TRIGGER.  FIRST-STEP is the top-level
directive it starts from (above 0 when it resumes an interrupted run)."
  (compiled nil :type compiled-event)
  (policy :queue :type keyword)
  (source :user :type keyword)
  (first-step 0 :type fixnum)
  (resumed nil :type boolean)
  ;; The run's AGENDA-ITEMs in the order they were planned (SEQ order); none
  ;; once it is over (its items are retired, or, if cut, retired as they go).
  (items '() :type list)
  ;; Its items not yet taken off the agenda, in (TIME, SEQ) order
  ;; (FINISH-RECORDING); once it is installed, the first is on the agenda and
  ;; the others wait their turn (FEED-NEXT-ITEM).
  (pending '() :type list)
  ;; What the event may touch (FOOTPRINTS.LISP).
  (footprint nil)
  (finished nil :type boolean)
  ;; How many of its items are not retired: when none is left of a run that
  ;; is over, nothing reaches it and it is used again (ITEM-POOL.LISP).
  (live-items 0 :type fixnum))

;; Inline: a run is taken for every event a timed controller plays.
(declaim (inline fresh-event-run))
(defun fresh-event-run (agenda compiled policy source)
  "A run of COMPILED by POLICY from SOURCE: one from AGENDA's spare runs, every
slot set again, or a new one."
  (declare (agenda agenda))
  (let ((run (agenda-free-runs agenda)))
    (if (null run)
        (make-event-run compiled policy source)
        (progn
          (setf (agenda-free-runs agenda) (run-footprint run)
                (run-compiled run) compiled
                (run-policy run) policy
                (run-source run) source
                (run-first-step run) 0
                (run-resumed run) nil
                (run-items run) '()
                (run-pending run) '()
                (run-footprint run) nil
                (run-finished run) nil
                (run-live-items run) 0)
          run))))

(defun retire-run (agenda run)
  "RUN is over and nothing reaches it any more (its last item is retired):
keep it for FRESH-EVENT-RUN, chained through its FOOTPRINT."
  (declare (agenda agenda))
  ;; POLICY :FREE, so a test can see a retired run something still reaches
  ;; (test-item-pool.lisp).
  (setf (run-policy run) :free
        (run-items run) '()
        (run-pending run) '())
  (when *recycle-agenda-items*
    (setf (run-footprint run) (agenda-free-runs agenda)
          (agenda-free-runs agenda) run)))

(declaim (ftype (function (t t) (values null &optional)) retire-item))

;; Inline: a cut run gives back a cons for every item the agenda passes.
(declaim (inline give-back-cons))
(defun give-back-cons (agenda cell)
  "Keep CELL, a cons nothing else holds, for FRESH-ITEM-CONS."
  (declare (agenda agenda) (cons cell))
  (when *recycle-agenda-items*
    (setf (first cell) nil
          (rest cell) (agenda-free-conses agenda)
          (agenda-free-conses agenda) cell)))

;; Inline: it runs for every event a timed controller plays.
(declaim (inline run-event run-name))
(defun run-event (run)
  "The EVENT-DEF RUN plays."
  (compiled-event-event (run-compiled run)))

(defun run-name (run)
  "The name of the event RUN plays."
  (event-name (run-event run)))

(defmethod print-object ((run event-run) stream)
  (print-unreadable-object (run stream :type t)
    (format stream "~A ~(~A~) from step ~D~:[~; (finished)~]" (lisp-text (run-name run)) (run-policy run)
            (run-first-step run) (run-finished run))))

;;;# Feeding the agenda one item per run

;; Inline: it runs for every item a timed controller plays.
(declaim (inline skip-pending))
(defun skip-pending (agenda pending time skip-ops)
  "PENDING (a run's pending items) from the first item the agenda must still
take.  Cancelled items are retired (nothing else reaches them).  With SKIP-OPS,
when AGENDA's ops are silent, an :OP item due at TIME, the instant the run
reaches it, is played there and then (marked :DONE): telling nobody, it need
not wait its turn on the agenda, and no cut can fall before it (a cut comes
once everything due at its instant has happened)."
  (declare (agenda agenda) (list pending) (double-float time))
  (loop (let ((item (first pending)))
          (cond ((null item) (return pending))
                ((eq (agenda-item-status item) :cancelled)
                 ;; Only a cut cancels, and a cut run's pending list is its own.
                 (retire-item agenda item)
                 (give-back-cons agenda (shiftf pending (rest pending))))
                ((and skip-ops (agenda-silent-ops agenda) (eq (agenda-item-kind item) :op)
                      (= (agenda-item-time item) time))
                 (setf (agenda-item-status item) :done
                       pending (rest pending)))
                (t (return pending))))))

;; Inline: it runs for every item a timed controller plays.
(declaim (inline feed-next-item))
(defun feed-next-item (agenda run skip-ops)
  "RUN's first pending item comes off AGENDA: drop it, and the items after it
SKIP-PENDING passes, from RUN's pending items; return the next pending one or NIL."
  (let* ((pending (run-pending run))
         (rest (skip-pending agenda (rest pending) (agenda-item-time (first pending)) skip-ops)))
    ;; A run that is over (cut) owns its pending list: its items list is
    ;; empty.  Otherwise the list is shared with its items.
    (when (run-finished run)
      (give-back-cons agenda pending))
    (setf (run-pending run) rest)
    (first rest)))

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

(declaim (inline agenda-next))
(defun agenda-next (agenda)
  "AGENDA's first pending item, or NIL; cancelled items on top are discarded
(and a cut run's retired: a cancelled timer item is still its timer's)."
  (declare (agenda agenda))
  (loop while (plusp (agenda-count agenda))
        do (let ((top (svref (agenda-items agenda) 0)))
             (if (eq (agenda-item-status top) :cancelled)
                 (progn (agenda-pop agenda top nil)
                        (when (agenda-item-run top)
                          (retire-item agenda top)))
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
            (when (eq (agenda-item-status pending) :pending) (funcall function pending)))
          (when (eq (agenda-item-status item) :pending) (funcall function item))))))
