;;;; runs.lisp -- one event played on a timeline: what it was, under which
;;;; policy it came, and the items it planned ahead (FEEDING.LISP gives them
;;;; to the agenda one at a time).

(in-package #:player.control)

(declaim #.*timeline-optimize*)                 ; the engine's policy (agenda.lisp)

;; Fourteen words with the header, one taken for every event (ITEM-POOL.LISP):
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
  (live-items 0 :type fixnum)
  ;; When it ends and the sequence number its :FINISH item gets: that item is
  ;; made only when the run gets there (FINISH-ITEM), so a run that is cut
  ;; short, or planned on trial and dropped, never makes one.
  (finish-time 0 :type integer)
  (finish-seq 0 :type fixnum)
  (finish nil))

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
                (run-live-items run) 0
                (run-finish run) nil)
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
  (when (agenda-recycle agenda)
    (setf (run-footprint run) (agenda-free-runs agenda)
          (agenda-free-runs agenda) run)))

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
