;;;; agenda.lisp -- what a timed controller has yet to do, in time order: a
;;;; binary heap of items ordered by (TIME, SEQ), so equal times keep the
;;;; order in which the event planning ahead produced them (an op's end, then
;;;; the next op's start, as the whole-event trace shows them).

(in-package #:player.control)

(eval-when (:compile-toplevel :load-toplevel :execute)
  (defparameter *timeline-optimize*
    #-player-unchecked-engine '(optimize (speed 1) (safety 1) (debug 1))
    #+player-unchecked-engine '(optimize (speed 1) (safety 0) (debug 0))
    "The optimize form declaimed at the top of each file of the timeline's
engine (agenda.lisp to cuts.lisp).  By default it is the project's checked
policy, SBCL's own (safety 1): every structure access and declared type is
checked, so an engine bug is an error where it happens, not a wrong state
later.  A build with :PLAYER-UNCHECKED-ENGINE in *FEATURES* when it compiles
takes (safety 0) (debug 0) instead: the engine only ever handles the items,
runs and lists it made itself, from arguments the API (api.lisp, compiled
checked either way) has checked, and unchecked, the code that plays one
event fits the instruction cache (a timed Peedy event: about 2,960
instructions and 12 level-1 instruction-cache misses, against 4,090 and
45 to 60 checked; `make bench-instructions' counts both builds).  Only
benchmarks turn it on; `make test' runs the engine's suites against such a
build too (`make test-unchecked-engine'), so both ways stay tested.  The
checked build also signals a RETIRED-ITEM-ERROR for an agenda item retired
twice or applied once retired (ITEM-POOL.LISP).  doc/internals/timeline.md
says more."))

(declaim #.*timeline-optimize*)

;; Twelve words with the header: an item is made for every op, state change,
;; macro span and end an event plans, and a third of them a cut cancels
;; unplayed, so the slots a kind seldom needs share A and B (a :FAIL's goal,
;; a :MACRO-END's start) and an :OP or :MACRO-START item's start is its TIME.
;; Inline: the recorder makes several items for every event a timed
;; controller plans.
(declaim (inline make-agenda-item))
(defstruct (agenda-item (:constructor make-agenda-item (kind time seq run)))
  "One thing due on a timeline.  KIND says what:
  :OP          play OP from TIME (its start) to END, which a cut may bring forward
  :DELTA       set the plannable fields of mask A to the bits B
  :VALUE       set runtime variable A to B
  :MACRO-START macro-op OP's span begins at TIME (and ends at END)
  :MACRO-END   macro-op OP's span, begun at A, ends at TIME (times in microseconds)
  :FAIL        the event could not achieve goal B
  :FINISH      the event RUN is over: show the state, start the next one
  :TIMER       timer state A goes off
  :FREE        none: the item is retired, in its agenda's pool (ITEM-POOL.LISP)
AGENDA-ITEM-START is where an :OP or a macro span starts."
  (kind :op :type keyword)
  (time 0 :type integer)
  (seq 0 :type fixnum)
  ;; The EVENT-RUN the item belongs to (NIL for a timer).
  (run nil)
  (op nil)
  (end 0 :type integer)
  (a nil)
  (b nil)
  ;; An op's end :DELTA -> that op's :OP item; a :MACRO-START -> its :MACRO-END.
  (owner nil)
  ;; The top-level directive of the event that produced the item.
  (step 0 :type fixnum)
  ;; Its AGENDA-ITEM-STATUS, as a number (ITEM-STATUS-CODE).
  (status-code 0 :type (integer 0 3)))

;;; An item's status is a keyword to its readers, a small integer in the
;;; item: a keyword stored in a structure is a pointer store, marked for the
;;; garbage collector (three instructions more), and the status is set two
;;; or three times in every item's life.

(declaim (inline item-status-code))
(defun item-status-code (status)
  "The number an item holds for STATUS, one of :PENDING (not yet applied),
:DONE (applied), :CANCELLED (by a cut) and :FREE (retired, ITEM-POOL.LISP)."
  ;; Inline, so a constant STATUS folds to its number.
  (ecase status (:pending 0) (:done 1) (:cancelled 2) (:free 3)))

(declaim (inline agenda-item-status (setf agenda-item-status) item-status-p))
(defun agenda-item-status (item)
  "ITEM's status: :PENDING, :DONE, :CANCELLED or :FREE (ITEM-STATUS-CODE)."
  (svref #(:pending :done :cancelled :free) (agenda-item-status-code item)))

(defun (setf agenda-item-status) (status item)
  "Make STATUS ITEM's status."
  (setf (agenda-item-status-code item) (item-status-code status))
  status)

(defun item-status-p (item status)
  "Is STATUS (a constant, in the engine) ITEM's status?"
  (= (agenda-item-status-code item) (item-status-code status)))

(declaim (inline agenda-item-start))
(defun agenda-item-start (item)
  "When the op or macro span of ITEM (:OP, :MACRO-START or :MACRO-END) starts."
  (declare (agenda-item item))
  (if (eq (agenda-item-kind item) :macro-end)
      (the integer (agenda-item-a item))
      (agenda-item-time item)))

(declaim (inline item-before-p))
(defun item-before-p (a b)
  "Is item A due before item B: an earlier time, or the same time and made earlier?"
  (declare (agenda-item a b))
  (let ((ta (agenda-item-time a)) (tb (agenda-item-time b)))
    (if (and (typep ta 'fixnum) (typep tb 'fixnum))   ; the usual times: machine compares
        (or (< ta tb) (and (= ta tb) (< (agenda-item-seq a) (agenda-item-seq b))))
        (or (< ta tb) (and (= ta tb) (< (agenda-item-seq a) (agenda-item-seq b)))))))

(defvar *recycle-agenda-items* t
  "Do the agendas made while it is true use retired agenda items, conses and
runs again?  When false, retired items and runs are only marked :FREE (and
never used again), so a test can look for one that something still reaches
(test-item-pool.lisp).")

(defstruct (agenda (:constructor make-agenda ()))
  "A binary min-heap of AGENDA-ITEMs by ITEM-BEFORE-P.  An event's items are
not all on it: each run feeds it its next item only (FEEDING.LISP).  A
cancelled timer item stays until it reaches the top, where AGENDA-NEXT skips
it (cancelling is O(1)); a cut takes its run's cancelled items off at once
(RETIRE-CANCELLED-ITEMS)."
  (items (make-array 64) :type simple-vector)
  (count 0 :type fixnum)
  ;; The last sequence number given to an item made for it (AGENDA-NEXT-SEQ).
  (seq 0 :type fixnum)
  ;; Does nobody need told when an op starts (the timeline's presenter is
  ;; quiet)?  Then an :OP item is played when its run reaches it, if it is due
  ;; then, without going on the heap (SKIP-PENDING).
  (silent-ops nil :type boolean)
  ;; Does it use retired items, conses and runs again (*RECYCLE-AGENDA-ITEMS*
  ;; when it was made)?
  (recycle *recycle-agenda-items* :type boolean)
  ;; Retired items to use again, chained through their OWNER, and conses of
  ;; runs' item lists to use again (ITEM-POOL.LISP).
  (free nil :type (or null agenda-item))
  (free-conses '() :type list)
  ;; Runs that are over and reached by nothing, to use again, chained
  ;; through their FOOTPRINT (RUNS.LISP).
  (free-runs nil))

;; Inline: the recorder numbers every item it makes.
(declaim (inline agenda-next-seq))
(defun agenda-next-seq (agenda)
  "A fresh sequence number for an item of AGENDA: items made later sort later
at equal times."
  (declare (agenda agenda))
  (incf (agenda-seq agenda)))

(defun agenda-push (agenda item)
  "Add ITEM to AGENDA."
  (declare (agenda agenda) (agenda-item item))
  (let ((items (agenda-items agenda))
        (i (agenda-count agenda)))
    (when (= i (length items))
      (setf items (replace (make-array (* 2 i)) items)
            (agenda-items agenda) items))
    (loop while (plusp i)
          do (let ((parent (ash (1- i) -1)))
               (if (item-before-p item (svref items parent))
                   (setf (svref items i) (svref items parent) i parent)
                   (return))))
    (setf (svref items i) item)
    (incf (agenda-count agenda))
    item))

(declaim (inline sift-down))
(defun sift-down (items count i item)
  "Put ITEM at hole I of heap ITEMS (COUNT long), moving earlier children up."
  (declare (simple-vector items) (fixnum count i) (agenda-item item))
  (loop (let* ((left (1+ (* 2 i))) (right (1+ left)) (least i) (least-item item))
          (declare (fixnum left right least))
          (when (and (< left count) (item-before-p (svref items left) least-item))
            (setf least left least-item (svref items left)))
          (when (and (< right count) (item-before-p (svref items right) least-item))
            (setf least right least-item (svref items right)))
          (when (= least i) (return))
          (setf (svref items i) least-item i least)))
  (setf (svref items i) item))

;; Inline: it runs for every event a timed controller plays.
(declaim (inline agenda-remove-top))
(defun agenda-remove-top (agenda)
  "Remove AGENDA's first item."
  (declare (agenda agenda))
  (let* ((items (agenda-items agenda))
         (count (decf (agenda-count agenda)))
         (last (svref items count)))
    (declare (fixnum count))
    (setf (svref items count) nil)
    (when (plusp count)
      (sift-down items count 0 last))))

;; Inline: it runs for every event a timed controller plays.
(declaim (inline agenda-replace-top))
(defun agenda-replace-top (agenda item)
  "Put ITEM in place of AGENDA's first item: one sift down, where removing the
first and pushing ITEM would take two."
  (declare (agenda agenda) (agenda-item item))
  (sift-down (agenda-items agenda) (agenda-count agenda) 0 item))

(defun agenda-swap-out (agenda item next)
  "Take ITEM off AGENDA, putting NEXT, when not NIL, in its place: NEXT must
not be due before ITEM (the next item of ITEM's run, say)."
  (declare (agenda agenda) (agenda-item item))
  (let* ((items (agenda-items agenda))
         (i (loop for i of-type fixnum below (agenda-count agenda)
                  when (eq (svref items i) item) return i)))
    (cond (next (sift-down items (agenda-count agenda) i next))
          (t (let* ((count (decf (agenda-count agenda)))
                    (last (svref items count)))
               (declare (fixnum count))
               (setf (svref items count) nil)
               (when (< i count)
                 ;; LAST, from the bottom, may belong above I or below it.
                 (loop while (plusp i)
                       do (let ((parent (ash (1- i) -1)))
                            (if (item-before-p last (svref items parent))
                                (setf (svref items i) (svref items parent) i parent)
                                (return))))
                 (sift-down items count i last)))))
    nil))

(defun agenda-clear (agenda)
  "Forget every item of AGENDA."
  (fill (agenda-items agenda) nil)
  (setf (agenda-count agenda) 0))
