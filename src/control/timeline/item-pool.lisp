;;;; item-pool.lisp -- agenda items used again.  A timed controller makes three
;;;; to five items for every event it plans.  Made fresh, they were two thirds
;;;; of what it allocated (about 450 of 675 bytes an event); at a million
;;;; events a second that is half a gigabyte a second, and once a garbage
;;;; collection has handed pages back to the system, touching fresh ones cost
;;;; more than the work (a page fault every 25 events, the rate halved).  So
;;;; an item nothing can reach any more goes back to its agenda's pool, and the
;;;; recorder takes the next item from there.
;;;;
;;;; An item is retired (RETIRE-ITEM) only where nothing can reach it again:
;;;;  - every item of a run that played to its end, at its :FINISH (FINISH-RUN):
;;;;    all of them have come off the agenda by then (unless a :time directive
;;;;    left changes due after the end: each of those once it is applied);
;;;;  - the items of a run planned on trial and not started (FORGET-PLAN);
;;;;  - at a cut, the items of the cut run already played that neither play on
;;;;    (as live ops) nor are kept (CUT-RUN);
;;;;  - the items a cut cancelled, all at once once the cut is made
;;;;    (RETIRE-CANCELLED-ITEMS), and a cancelled timer's item when the agenda
;;;;    discards it (AGENDA-NEXT);
;;;;  - an item of a run already over (cut) once it is applied (ADVANCE-TIMELINE);
;;;;  - a live op when it leaves the live ops (FORGET-ENDED-OPS).
;;;; A run counts its items not retired; the last one of a run that is over
;;;; retires the run.  The conses of a run's item list go back when the run
;;;; is over: all at once at its end, or, when it is cut, as the agenda passes
;;;; them (the list is then the run's alone).  An item never retired is left
;;;; to the garbage collector: a case missed costs memory, never correctness.

(in-package #:player.control)

(declaim #.*timeline-optimize*)                 ; the engine's policy (agenda.lisp)

;; Inline: the recorder takes an item for every op, state change and macro
;; span of every event a timed controller plans.
(declaim (inline fresh-agenda-item))
(defun fresh-agenda-item (agenda kind time run &optional (seq (agenda-next-seq agenda)))
  "A pending item of KIND due at TIME for RUN, with sequence number SEQ
(AGENDA's next): one from AGENDA's pool, every slot set again, or a new one."
  (declare (agenda agenda) (integer time) (fixnum seq))
  (let ((item (agenda-free agenda)))
    (when run
      (incf (run-live-items run)))
    (if (null item)
        (make-agenda-item kind time seq run)
        (progn
          (setf (agenda-free agenda) (agenda-item-owner item)
                (agenda-item-kind item) kind
                (agenda-item-time item) time
                (agenda-item-seq item) seq
                (agenda-item-run item) run
                (agenda-item-op item) nil
                (agenda-item-a item) nil
                (agenda-item-b item) nil
                (agenda-item-owner item) nil
                (agenda-item-end item) 0
                (agenda-item-step item) 0
                (agenda-item-status item) :pending)
          item))))

;; An item retired twice would be in the pool twice, and handed out for two
;; things at once; one applied after it was retired may be another thing's
;; already.  The checked engine says so where it happens.
(define-condition retired-item-error (timeline-error) ()
  (:documentation "The timed engine retired an agenda item already retired, or
applied one it had retired: a bug in the engine (its pool would hand the item
out twice).  Only the checked engine (the default build) looks."))

(defun retired-item-error (item what)
  "Signal a RETIRED-ITEM-ERROR: ITEM, already retired, was WHAT (a phrase)."
  (error 'retired-item-error
         :message (format nil "the timed engine ~A agenda item ~A (seq ~D), already retired: its pool would hand it out twice"
                          what (agenda-item-kind item) (agenda-item-seq item))))

;; Inline: every item a timed controller records is retired through it.
(declaim (inline pool-item))
(defun pool-item (item free recycle)
  "Mark ITEM :FREE and chain it before FREE, the head of its agenda's pool
(kept in a variable by a loop); return the new head.  Unless RECYCLE (the
agenda's: *RECYCLE-AGENDA-ITEMS*), poison ITEM instead, KIND :FREE and
nothing referred to, and keep FREE.  In the checked engine, an item already
retired is a RETIRED-ITEM-ERROR."
  (declare (agenda-item item))
  #-player-unchecked-engine
  (when (item-status-p item :free)
    (retired-item-error item "retired"))
  (setf (agenda-item-status item) :free)
  (cond (recycle
         ;; The pool is chained through OWNER: no cons per item.  The other
         ;; slots are set when the item is taken again (FRESH-AGENDA-ITEM).
         (setf (agenda-item-owner item) free)
         item)
        ;; KIND :FREE, so applying a retired item is an ECASE error, not a
        ;; silent wrong state.
        (t (setf (agenda-item-kind item) :free
                 (agenda-item-run item) nil
                 (agenda-item-op item) nil
                 (agenda-item-a item) nil
                 (agenda-item-b item) nil
                 (agenda-item-owner item) nil)
           free)))

(declaim (inline count-off-items))
(defun count-off-items (agenda run count)
  "COUNT items of RUN were retired: the last of a run that is over retires the run."
  (declare (fixnum count))
  (when (and run (zerop (decf (run-live-items run) count)) (run-finished run))
    (retire-run agenda run)))

;; Inline: an item is retired for every one a timed controller records.
(declaim (inline retire-item))
(defun retire-item (agenda item)
  "Nothing reaches ITEM any more: put it in AGENDA's pool (POOL-ITEM).  The
last item of a run that is over retires the run too."
  (declare (agenda agenda) (agenda-item item))
  (let ((run (agenda-item-run item)))
    (setf (agenda-free agenda) (pool-item item (agenda-free agenda) (agenda-recycle agenda)))
    (count-off-items agenda run 1))
  nil)

(defun retire-item-list (agenda items &optional run)
  "Retire each item of ITEMS, a list that nothing else shares any more, and
keep its conses for FRESH-ITEM-CONS.  RUN, when given, owns every item of
ITEMS: they are counted off it at once."
  (declare (agenda agenda) (list items))
  (when items
    ;; The pool's head kept in a variable and stored once: the same chain as
    ;; RETIRE-ITEM's, one pointer store less per item.
    (let ((free (agenda-free agenda))
          (recycle (agenda-recycle agenda))
          (last items)
          (count 0))
      (declare (fixnum count))
      (loop (let ((item (first last)))
              (if run
                  (incf count)
                  (count-off-items agenda (agenda-item-run item) 1))
              (setf free (pool-item item free recycle)))
            (if (rest last)
                (setf last (rest last))
                (return)))
      (setf (agenda-free agenda) free)
      (when recycle
        (setf (rest last) (agenda-free-conses agenda)
              (agenda-free-conses agenda) items))
      (count-off-items agenda run count))))

(defun new-cons (first rest)
  "(CONS FIRST REST), out of line: SPARE-CONS is inline in many places and
seldom needs a new cons once the spares are warm, so each copy of it calls
this instead of carrying the allocation itself."
  (cons first rest))

;; Inline: the recorder takes a cons for every item it records.
(declaim (inline spare-cons))
(defun spare-cons (agenda first rest)
  "(CONS FIRST REST), with a cons from AGENDA's spares when it has one.  Every
cons given back (GIVE-BACK-CONS) must have come from here, or the spares
would grow without end."
  (declare (agenda agenda))
  (let ((cell (agenda-free-conses agenda)))
    (if (null cell)
        (new-cons first rest)
        (progn (setf (agenda-free-conses agenda) (rest cell)
                     (first cell) first
                     (rest cell) rest)
               cell))))

(declaim (inline fresh-item-cons))
(defun fresh-item-cons (agenda item)
  "A list of ITEM alone, with a cons from AGENDA's spares when it has one."
  (spare-cons agenda item '()))

;; Inline: a cut run gives back a cons for every item the agenda passes.
(declaim (inline give-back-cons))
(defun give-back-cons (agenda cell)
  "Keep CELL, a cons nothing else holds and SPARE-CONS made, for SPARE-CONS."
  (declare (agenda agenda) (cons cell))
  (when (agenda-recycle agenda)
    (setf (rest cell) (agenda-free-conses agenda)
          (agenda-free-conses agenda) cell)))

;; Inline: a cut gives back three lists, mostly empty.
(declaim (inline give-back-list))
(defun give-back-list (agenda list)
  "Keep the conses of LIST, which nothing else holds and SPARE-CONS made, for SPARE-CONS."
  (declare (agenda agenda) (list list))
  ;; Spliced in whole, in their order: one store for the list, not two a cons.
  (when (and list (agenda-recycle agenda))
    (let ((last list))
      (loop while (rest last)
            do (setf last (rest last)))
      (setf (rest last) (agenda-free-conses agenda)
            (agenda-free-conses agenda) list))))

;; Inline: a run that plays to its end makes one, as its last item comes up.
(declaim (inline finish-item))
(defun finish-item (agenda run)
  "RUN's :FINISH item, made now that the run has played every item due before
its end (WITH-FINISH): due then, with the sequence number it was given when it
was planned, so it sorts exactly where a :FINISH recorded then would have.  A
run cut short, or planned on trial and dropped, never makes one."
  (setf (run-finish run)
        (fresh-agenda-item agenda :finish (run-finish-time run) run (run-finish-seq run))))
