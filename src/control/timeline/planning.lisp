;;;; planning.lisp -- an event planned ahead: its compiled closures run at
;;;; once, from the state due when it would start, with the recorder
;;;; (RECORDER.LISP) in the controller, so what they play becomes agenda items;
;;;; then the controller's state is put back.  A plan made on trial tells the
;;;; event's footprint (FOOTPRINTS.LISP) before it is let start.

(in-package #:player.control)

(declaim #.*timeline-optimize*)                 ; the engine's policy (agenda.lisp)

(defun project-state (timeline time)
  "Put into the controller the state it will have at TIME (after NOW): the
pending state changes due by then, applied without telling anyone."
  (declare (integer time))
  (let ((controller (timeline-controller timeline))
        (agenda (timeline-agenda timeline))
        (due '()))
    (map-agenda (lambda (item)
                  (when (and (member (agenda-item-kind item) '(:delta :value))
                             (micros<= (agenda-item-time item) time))
                    (setf due (spare-cons agenda item due))))
                agenda)
    (setf due (if (rest due) (sort due #'item-before-p) due))
    (dolist (item due)
      (apply-change controller item))
    ;; SORT reuses the conses it was given: all of them are the list's.
    (give-back-list agenda due)))

(defun apply-change (controller item)
  "Apply state change ITEM to CONTROLLER's state, silently."
  (if (eq (agenda-item-kind item) :delta)
      (setf (controller-bits controller)
            (state-with-fields (controller-bits controller) (agenda-item-a item) (agenda-item-b item)))
      (setf (svref (controller-values controller) (var-slot (agenda-item-a item))) (agenda-item-b item))))

(defun plan-run-ahead (timeline run time &optional all-due)
  "Run RUN's compiled event on the controller with the recorder as presenter,
from the state due at TIME, then put the controller's state back.  The
recorded items end with a :FAIL (if the plan failed) and the :FINISH.  With
ALL-DUE, the changes due at TIME = NOW not applied yet count too (a run
starting while the items of the instant are being applied)."
  (declare (integer time))
  (let* ((controller (timeline-controller timeline))
         (recorder (timeline-recorder timeline))
         (bits (controller-bits controller))
         (values (controller-values controller))
         (result nil))
    (unwind-protect
         (progn
           (when (plusp (length values))
             (setf (controller-values controller)
                   (replace (the simple-vector (timeline-scratch-values timeline))
                            (the simple-vector values))))
           (when (or all-due (micros< (timeline-now timeline) time))
             (project-state timeline time))
           (start-recording recorder run)
           (setf (controller-presenter controller) (timeline-recording-presenter timeline)
                 (controller-recorder controller) recorder
                 (controller-step controller) (run-first-step run)
                 (controller-schedule controller) time
                 (controller-span-start controller) time
                 (controller-span-end controller) time)
           (dolist (var (event-time-variables (run-event run)))
             (set-runtime-value controller var (micros->double time) time))
           (setf result (run-event-plan timeline run controller))
           (unless (eq result t)
             (record-failure recorder (failure-goal-form result) (controller-schedule controller)))
           ;; Its :FINISH is made when the run gets there (FINISH-ITEM).
           (setf (run-finish-time run) (controller-span-end controller)
                 (run-finish-seq run) (agenda-next-seq (timeline-agenda timeline))
                 (run-finish run) nil)
           (finish-recording recorder))
      (setf (recorder-taping recorder) nil
            (controller-presenter controller) (timeline-presenter timeline)
            (controller-recorder controller) nil
            ;; No macro-op is open once planning is over, even one an error left.
            (controller-active-macros controller) 0
            (controller-bits controller) bits
            (controller-values controller) values))
    result))

(defun planned-footprint (timeline run)
  "The footprint of RUN, planned ahead."
  (run-footprint-from-items timeline run))

(defun run-footprint* (timeline run)
  "RUN's footprint, worked out from its items when first asked (before a cut
trims them)."
  (or (run-footprint run)
      (setf (run-footprint run) (planned-footprint timeline run))))

;; Inline: it runs for every event arriving while others play.
(declaim (inline untried-p))
(defun untried-p (timeline run)
  "Is RUN taken to meet everything without being planned: its event runs code
(planning it would run the code), or a running event meets everything anyway?"
  (or (compiled-event-runs-code-p (run-compiled run))
      (some (lambda (other) (meets-everything-p (run-footprint* timeline other))) (timeline-runs timeline))))

(defun plan-on-trial (timeline run time)
  "Plan RUN ahead from TIME to learn its footprint, unless it is UNTRIED-P.
Returns the planning result, or :UNTRIED; RUN keeps its items and footprint."
  (if (untried-p timeline run)
      :untried
      (plan-footprint timeline run time)))

(defun plan-footprint (timeline run time &optional all-due)
  "Plan RUN ahead from TIME (ALL-DUE: see PLAN-RUN-AHEAD) and note its
footprint; return the planning result."
  (prog1 (plan-run-ahead timeline run time all-due)
    (setf (run-footprint run) (planned-footprint timeline run))))

(defun meets-running-p (timeline run)
  "Does planned RUN (its footprint known) meet a running event?"
  (some (lambda (other) (footprints-meet-p (run-footprint run) (run-footprint* timeline other)))
        (timeline-runs timeline)))

(defun forget-plan (timeline run)
  "Drop what RUN planned on trial (it will be planned again when it starts):
its items were never on the agenda, so they are retired."
  (retire-item-list (timeline-agenda timeline) (shiftf (run-items run) '()))
  (setf (run-pending run) '()
        (run-footprint run) nil))
