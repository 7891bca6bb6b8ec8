;;;; recorder.lisp -- planning an event ahead.  A timed controller runs an
;;;; event's compiled closures at once, as the whole-event API does, but with
;;;; a RECORDER in the controller: every op, macro span, failure and state
;;;; change becomes an agenda item due at its time, and nothing reaches the
;;;; real presenter or the autoscripts until the timeline gets there.
;;;;
;;;; The compiled closures call RECORD-OP-PLAYED, RECORD-MACRO-START,
;;;; RECORD-MACRO-END and RECORD-CHANGE directly (plain calls, no generic
;;;; dispatch: they run for every op of every event a timed controller plans).  While an
;;;; event is planned, the controller's presenter is a RECORDING-PRESENTER
;;;; that forwards to the recorder, so nothing else that presents then can
;;;; reach the real presenter either.

(in-package #:player.control)

(declaim #.*timeline-optimize*)                 ; the engine's policy (agenda.lisp)

(defstruct (recorder (:constructor make-recorder (timeline controller)))
  "What a timeline's planning ahead keeps between the closures' calls."
  ;; The TIMELINE (defined after this file), its controller, and its AGENDA,
  ;; which numbers the items (the timeline's accessors are not known here).
  (timeline nil)
  (controller nil :type controller)
  (agenda nil :type (or null agenda))
  ;; The EVENT-RUN being planned, and the last cons of its items (they are
  ;; kept in the order recorded, which is SEQ order).
  (run nil)
  (items-tail '() :type list)
  ;; Is each item recorded so far due no earlier than the one before?  Then
  ;; SEQ order is (TIME, SEQ) order too, and the run's items need no sort.
  (in-order t :type boolean)
  ;; The :OP item recorded last, whose end delta comes next.
  (last-op nil)
  ;; The :MACRO-END item recorded last, whose end delta comes next.
  (last-macro-end nil)
  ;; The :MACRO-START items of the macros still running, innermost first.
  (open-macros '() :type list)
  ;; Does the real presenter answer PLANNED-OP-DURATION with the declared
  ;; :duration (the default method)?  Then it is not asked for every op.
  (declared-durations nil :type boolean)
  ;; Does it give an op its declared channels, :ALL when it has none
  ;; (DECLARED-CHANNELS-P)?  Then a run that plays an op without :channels
  ;; meets everything, and is marked so as the op is recorded.
  (declared-channels nil :type boolean)
  ;; Is the plan being recorded also taped (TAPES.LISP)?  Then TAPE holds
  ;; what the closures did so far, newest first, or :SPOILED when they did
  ;; something a tape cannot replay.
  (taping nil :type boolean)
  (tape '() :type (or list (eql :spoiled)))
  ;; Where a replay keeps the spans of the MACRO-DEPTH macros open (three
  ;; doubles a macro, grown as macros nest deeper), so it conses none
  ;; (REPLAY-MACRO-START).
  (macro-spans (make-array 12 :initial-element 0)
   :type simple-vector)
  (macro-depth 0 :type fixnum))

;;; What a tape says the closures did, one code per call they made to the
;;; recorder (REPLAY-TAPE does each again).  Small integers: the tape is read
;;; once for every event replayed, and a code compares in one instruction.
(defconstant +taped-op+ 0
  "Tape code: an op played (RECORD-OP-PLAYED), its end's change MASK BITS.")
(defconstant +taped-macro-start+ 1
  "Tape code: a macro-op began, its span opening at the clock (RECORD-MACRO-START).")
(defconstant +taped-macro-end+ 2
  "Tape code: the innermost macro-op open ended, the clock moving to its end (RECORD-MACRO-END).")
(defconstant +taped-state-change+ 3
  "Tape code: the fields of MASK became BITS at the clock, at the end of the op or NIL (RECORD-STATE-CHANGE).")

(defun note-taped (recorder code op mask bits)
  "Put on RECORDER's tape what the closures just did: CODE (+TAPED-OP+ and the rest, above)
with OP, MASK and BITS, at the controller's current step."
  (let ((tape (recorder-tape recorder)))
    (unless (eq tape :spoiled)
      (setf (recorder-tape recorder)
            (list* (controller-step (recorder-controller recorder)) bits mask op code tape)))))

;; Inline: it runs for every event a timed controller plays.
(declaim (inline start-recording))
(defun start-recording (recorder run)
  "Make RECORDER record RUN's items from scratch."
  (setf (run-items run) '()
        (recorder-run recorder) run
        (recorder-items-tail recorder) '()
        (recorder-in-order recorder) t
        (recorder-last-op recorder) nil
        (recorder-last-macro-end recorder) nil
        (recorder-open-macros recorder) '()))

;; Inline: it runs for every event a timed controller plays.
(declaim (inline finish-recording))
(defun finish-recording (recorder)
  "The run RECORDER planned is recorded: its pending items are its items in
(TIME, SEQ) order.  That is the order they were recorded in unless a :time
directive moved the clock back."
  (let* ((run (recorder-run recorder))
         (items (run-items run)))
    (setf (run-pending run)
          (if (recorder-in-order recorder)
              items
              ;; A copy of spare conses: a cut run gives its pending
              ;; conses back (SPARE-CONS).
              (let ((copy '())
                    (agenda (recorder-agenda recorder)))
                (dolist (item items)
                  (setf copy (spare-cons agenda item copy)))
                (stable-sort copy #'item-before-p))))))

(declaim (inline record-item))
(defun record-item (recorder kind time)
  "A new pending item of KIND at TIME for the run RECORDER is planning, added
last to its items."
  (let* ((run (recorder-run recorder))
         (item (fresh-agenda-item (recorder-agenda recorder) kind time run))
         (cell (fresh-item-cons (recorder-agenda recorder) item))
         (tail (recorder-items-tail recorder)))
    (setf (agenda-item-step item) (controller-step (recorder-controller recorder)))
    (if tail
        (progn (when (micros< time (agenda-item-time (first tail)))
                 (setf (recorder-in-order recorder) nil))
               (setf (rest tail) cell))
        (setf (run-items run) cell))
    (setf (recorder-items-tail recorder) cell)
    item))

(declaim (inline planned-duration))
(defun planned-duration (recorder op start)
  "How long OP played from START will take, as the real presenter says, in
microseconds (START is too)."
  (if (recorder-declared-durations recorder)
      (seconds->micros (op-duration op))
      (let ((presenter (controller-presenter* (recorder-timeline recorder))))
        (seconds->micros (presenter-seconds (planned-op-duration presenter op (micros->seconds start))
                                            presenter 'planned-op-duration op)))))

(declaim (inline record-op))
(defun record-op (recorder op start)
  "Record OP playing from START; return its duration (what PRESENT-OP would)."
  (declare (integer start))
  (let ((duration (planned-duration recorder op start))
        (item (record-item recorder :op start)))
    (declare (integer duration))
    (setf (agenda-item-op item) op
          (agenda-item-end item) (micros+ start duration)
          (recorder-last-op recorder) item)
    ;; What RUN-FOOTPRINT-FROM-ITEMS would find, known now: an event arriving
    ;; while this run plays asks, and need not walk its items.
    (when (and (recorder-declared-channels recorder) (null (op-channels op)))
      (setf (run-footprint (recorder-run recorder)) *everything-footprint*))
    duration))

(defun record-macro-start (recorder op start)
  "Record macro-op OP beginning at START."
  (when (recorder-taping recorder)
    (note-taped recorder +taped-macro-start+ op 0 0))
  (let ((item (record-item recorder :macro-start start)))
    (setf (agenda-item-op item) op)
    (push item (recorder-open-macros recorder))
    item))

(defun record-macro-end (recorder op start end)
  "Record macro-op OP, begun at START, ending at END."
  (when (recorder-taping recorder)
    (note-taped recorder +taped-macro-end+ op 0 0))
  (let ((opening (pop (recorder-open-macros recorder)))
        (item (record-item recorder :macro-end end)))
    (setf (agenda-item-op item) op (agenda-item-a item) start
          (agenda-item-end item) end
          (agenda-item-end opening) end
          (agenda-item-owner opening) item
          (recorder-last-macro-end recorder) item)
    item))

(defun record-failure (recorder goal time)
  "Record that the event could not achieve GOAL at TIME."
  (setf (agenda-item-b (record-item recorder :fail time)) goal))

(declaim (inline record-change))
(defun record-change (recorder kind controller time a b op)
  "Note a state change due at TIME: KIND :DELTA sets the plannable fields of
mask A to the bits B, KIND :VALUE sets runtime variable A to B.  OP is the op
whose end this is, or NIL (see CONTROLLER-STATE.LISP)."
  (declare (ignore controller))
  (let ((item (record-item recorder kind time)))
    (setf (agenda-item-a item) a (agenda-item-b item) b)
    (let ((last-op (recorder-last-op recorder))
          (last-macro-end (recorder-last-macro-end recorder)))
      (cond ((null op))
            ((and last-op (eq op (agenda-item-op last-op)))
             (setf (agenda-item-owner item) last-op))
            ((and last-macro-end (eq op (agenda-item-op last-macro-end)))
             (setf (agenda-item-owner item) last-macro-end))))
    item))

(defun record-op-played (recorder controller op mask bits)
  "What an op's procedure does (COMPILE-EXECUTOR), recorded: OP plays from
CONTROLLER's scheduling clock, the clock moves to its end, and there the
plannable fields of MASK (unless 0) become BITS.  In one function, so no time
is boxed between the steps."
  (when (recorder-taping recorder)
    (note-taped recorder +taped-op+ op mask bits))
  (let* ((start (controller-schedule controller))
         (end (micros+ start (record-op recorder op start))))
    (note-op-end controller end)
    (unless (eql mask 0)
      (record-change recorder :delta controller end mask bits op)
      (setf (controller-bits controller)
            (state-with-fields (controller-bits controller) mask bits)))))

(defun record-state-change (recorder controller time mask bits op)
  "Record a :DELTA change of a step or a macro's end (SET-STATE): the fields
of MASK become BITS at TIME (the scheduling clock), at the end of OP or NIL."
  (when (recorder-taping recorder)
    ;; A replay records it at the clock: a change due at any other time spoils the tape.
    (if (eql time (controller-schedule controller))
        (note-taped recorder +taped-state-change+ op mask bits)
        (setf (recorder-tape recorder) :spoiled)))
  (record-change recorder :delta controller time mask bits op))

(defun record-value-change (recorder controller time var value)
  "Record runtime variable VAR becoming VALUE at TIME.  A value depends on
more than the plannable state, so a plan that sets one is not taped."
  (when (recorder-taping recorder)
    (setf (recorder-tape recorder) :spoiled))
  (record-change recorder :value controller time var value nil))

(defun default-method-only-p (function presenter &rest more-arguments)
  "Does only FUNCTION's default method (on PRESENTER) apply to PRESENTER, with
MORE-ARGUMENTS arguments of any class after it?  (Asked when a timeline is
made: a method defined later is not seen by timelines made before.)"
  (multiple-value-bind (methods known)
      (sb-mop:compute-applicable-methods-using-classes
       function (list* (class-of presenter) (mapcar (lambda (x) (declare (ignore x)) (find-class t))
                                                   more-arguments)))
    (and known methods (null (rest methods))
         (eq (first (sb-mop:method-specializers (first methods))) (find-class 'presenter)))))

(defun declared-durations-p (presenter)
  "Does PRESENTER answer PLANNED-OP-DURATION with the op's declared :duration
(only the default method applies to it)?"
  (default-method-only-p #'planned-op-duration presenter 'op 'start))

(defun declared-channels-p (presenter)
  "Does PRESENTER answer OP-CHANNEL-SET with the op's declared :channels, or
:ALL when it declares none (only the default method applies to it)?"
  (default-method-only-p #'op-channel-set presenter 'op))

;;;# The presenter while an event is planned

(defclass recording-presenter (presenter)
  ((recorder :initarg :recorder :reader presenter-recorder))
  (:documentation "The presenter of a controller while it plans an event ahead:
it forwards to its RECORDER, so what is presented then becomes agenda items."))

;; Presenters are handed seconds; the recorder keeps microseconds.
(defmethod present-op ((presenter recording-presenter) op start)
  (micros->seconds (record-op (presenter-recorder presenter) op (seconds->micros start))))

(defmethod present-macro-start ((presenter recording-presenter) op start)
  (record-macro-start (presenter-recorder presenter) op (seconds->micros start)))

(defmethod present-macro-end ((presenter recording-presenter) op start end)
  (record-macro-end (presenter-recorder presenter) op (seconds->micros start) (seconds->micros end)))

(defmethod present-failure ((presenter recording-presenter) event goal time)
  (declare (ignore event))
  (record-failure (presenter-recorder presenter) goal (seconds->micros time)))
