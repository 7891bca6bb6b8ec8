;;;; runs.lisp -- one event played on a timeline: what it was, under which
;;;; policy it came, and the items it planned ahead.

(in-package #:player)

(defstruct (event-run (:conc-name run-) (:constructor make-event-run (compiled name policy source)))
  "Event NAME (its COMPILED-EVENT) on a timed controller, from its start to its
end or cut.  SOURCE is :USER, :TIMER or :TRIGGER.  FIRST-STEP is the top-level
directive it starts from (above 0 when it resumes an interrupted run)."
  (compiled nil :type compiled-event)
  (name nil)
  (policy :queue :type keyword)
  (source :user :type keyword)
  (first-step 0 :type fixnum)
  (resumed nil :type boolean)
  (start 0d0 :type double-float)
  ;; The run's AGENDA-ITEMs, newest first.
  (items '() :type list)
  ;; What the event may touch (FOOTPRINTS.LISP).
  (footprint nil)
  (finished nil :type boolean))

(defmethod print-object ((run event-run) stream)
  (print-unreadable-object (run stream :type t)
    (format stream "~A ~(~A~) from ~A~:[~; (finished)~]" (lisp-text (run-name run)) (run-policy run)
            (format-number (run-start run)) (run-finished run))))

(defun run-event (run)
  "The EVENT-DEF RUN plays."
  (compiled-event-event (run-compiled run)))
