;;;; controller-state.lisp -- a controller instance and the primitive changes
;;;; compiled events make to it. Every change of a watched variable goes
;;;; through here, so autoscripts start and stop exactly when values change.

(in-package #:player.control)

(defvar *controller* nil
  "The controller whose event is running, for :code forms and presenters.
Bound while a controller runs an event's closures (SEND-EVENT, or a timed
controller planning one ahead): a SEND-EVENT to it then is deferred
(DEFERRED-SENDS.LISP), and a redefinition waits (SAFE-POINT-P).")

(defstruct (controller (:constructor %make-controller))
  "One running agent: a machine (shared, read-only) plus this agent's state."
  (machine nil :type machine)
  ;; One-hot plannable state.
  (bits 0 :type integer)
  ;; Runtime numbers and times, by slot.
  (values #() :type simple-vector)
  ;; Times, like every time below, in whole microseconds (EXACT-TIMES.LISP).
  (labels (vector) :type simple-vector)
  ;; When the next event starts: the end of the last one.
  (clock-micros 0 :type integer)
  ;; The scheduling clock of the running event.
  (schedule 0 :type integer)
  ;; Start of the running event or macro.
  (span-start 0 :type integer)
  ;; Latest end of an op in the running event or macro.
  (span-end 0 :type integer)
  ;; Bit per macro-op now running, against re-entry.
  (active-macros 0 :type integer)
  (presenter nil)
  ;; A timed controller's TIMELINE (see src/control/timeline/), else NIL.
  (timeline nil)
  ;; While a timed controller plans an event ahead: the recorder its state
  ;; changes go to, instead of happening now.
  (recorder nil)
  ;; The top-level directive of the event running ahead, so an interrupted
  ;; event can be resumed from it.
  (step 0 :type fixnum)
  ;; A compiled machine to switch to at the next safe point: a redefinition
  ;; that came while an event ran (see REDEFINE-CONTROLLER).
  (pending nil)
  ;; The presenter when it is silent (SILENT-PRESENTER-P: it does nothing
  ;; with anything a whole-event controller tells it, and its ops take their
  ;; declared durations), else :NONE.  The compiled closures then skip the
  ;; protocol's calls; they compare it with the presenter slot (SILENT-P), so
  ;; a presenter set since is never taken for silent.  SEND-EVENT refreshes it
  ;; (NOTE-PRESENTER-SILENCE) when the presenter or the protocol's methods
  ;; changed since CHECKED-PRESENTER and CHECKED-GENERATION.
  (silent-presenter :none)
  (checked-presenter :none)
  (checked-generation -1 :type fixnum)
  ;; The sends to it from inside its own running event, deferred till that
  ;; is over (DEFERRED-SENDS.LISP), oldest first: (EVENT . AT) pairs.
  (deferred-sends '() :type list))

(declaim (inline micros->seconds-double))
(defun micros->seconds-double (micros)
  "MICROS as the double nearest its seconds, what the API's functions answer."
  (if (typep micros '(integer -9007199254740992 9007199254740992))
      (/ (coerce micros 'double-float) 1d6)
      (coerce (micros->seconds micros) 'double-float)))

(defun controller-clock (controller)
  "When CONTROLLER's next event starts (a timed controller: its clock), in
seconds as a double; CONTROLLER-MICROSECONDS is the exact value."
  (micros->seconds-double (controller-clock-micros controller)))

(defun (setf controller-clock) (seconds controller)
  "Move CONTROLLER's clock to SECONDS (converted to the nearest microsecond)."
  (setf (controller-clock-micros controller) (seconds->micros seconds))
  seconds)

(declaim (inline silent-p))
(defun silent-p (controller)
  "May CONTROLLER's closures skip telling its presenter what they do: is the
presenter the one found silent when the running event started?"
  (eq (controller-presenter controller) (controller-silent-presenter controller)))

;;; The one-hot state is an integer; where a machine's states fit a fixnum
;;; (62 bits: every spec but those with hundreds of values), the closures that
;;; test cubes and change fields are compiled with the state declared a fixnum,
;;; so each test is a couple of machine instructions instead of calls of
;;; generic LOGAND and LOGIOR.  Wider states (bignums) take the general path.

(defun fixnum-state-p (machine)
  "Do all of MACHINE's one-hot states (and so its cubes and masks) fit a fixnum?"
  (typep (top-cube (machine-spec machine)) 'fixnum))

(defmacro with-state-bits ((machine) &body body)
  "BODY, compiled twice: run where MACHINE's states fit a fixnum with
(STATE-BITS FORM) declaring FORM a fixnum, else with (STATE-BITS FORM) = FORM,
any integer.  Bind masks and cubes with STATE-BITS outside the closures BODY
makes, so the closures see them typed."
  `(if (fixnum-state-p ,machine)
       (macrolet ((state-bits (form) `(the fixnum ,form))) ,@body)
       (macrolet ((state-bits (form) form)) ,@body)))

;;; While a timed controller plans an event ahead, the compiled closures hand
;;; what they do to its recorder, by plain calls (they run for every op) of
;;; functions the timeline defines (src/control/timeline/recorder.lisp):
;;;   (RECORD-CHANGE RECORDER KIND CONTROLLER TIME A B OP) a state change due
;;;     at TIME: KIND :DELTA sets the plannable fields of mask A to the bits B,
;;;     KIND :VALUE sets runtime variable A to B; OP is the op whose end this
;;;     is, or NIL.
;;;   (RECORD-OP-PLAYED RECORDER CONTROLLER OP MASK BITS) OP plays from the
;;;     scheduling clock, which moves to its end, where the plannable fields
;;;     of MASK become BITS: what an op's procedure does, recorded.
;;;   (RECORD-MACRO-START RECORDER OP START), (RECORD-MACRO-END RECORDER OP START END)
;;;   (RECORD-STATE-CHANGE RECORDER CONTROLLER TIME MASK BITS OP) a :DELTA
;;;     change a step or a macro's end makes (not an op's own end).
;;;   (RECORD-VALUE-CHANGE RECORDER CONTROLLER TIME VAR VALUE) a :VALUE change.
(declaim (ftype (function (t keyword t t t t t) t) record-change)
         (ftype (function (t t t t t t) t) record-state-change)
         (ftype (function (t t t t t) t) record-value-change)
         (ftype (function (t t t t t) t) record-op-played)
         (ftype (function (t t t) t) record-macro-start)
         (ftype (function (t t t t) t) record-macro-end))

(defun spec-of (controller)
  "CONTROLLER's spec."
  (machine-spec (controller-machine controller)))

(defun variable-value (controller var)
  "The current value of VAR in CONTROLLER, as the user sees it."
  (if (plannable-p var)
      (let ((field (ldb (byte (var-domain-size var) (var-bit-offset var))
                        (controller-bits controller))))
        (aref (var-domain var) (1- (integer-length field))))
      (svref (controller-values controller) (var-slot var))))

(defun value-index-of (controller var)
  "The domain index of plannable VAR's current value in CONTROLLER."
  (1- (integer-length (ldb (byte (var-domain-size var) (var-bit-offset var))
                           (controller-bits controller)))))

(defun notify-autoscripts (controller var old new time)
  "Stop the autoscripts of VAR = OLD, then start those of VAR = NEW, at TIME.
OLD and NEW are value indices (plannable) or numbers."
  (let ((presenter (controller-presenter controller)))
    (dolist (auto (spec-autoscripts (spec-of controller)))
      (when (and (eq (autoscript-variable auto) var) (eql (autoscript-value-index auto) old))
        (dolist (proc (autoscript-procs auto))
          (stop-autoscript presenter proc (var-name var) (autoscript-value auto) (micros->seconds time)))))
    (dolist (auto (spec-autoscripts (spec-of controller)))
      (when (and (eq (autoscript-variable auto) var) (eql (autoscript-value-index auto) new))
        (dolist (proc (autoscript-procs auto))
          (start-autoscript presenter proc (var-name var) (autoscript-value auto) (micros->seconds time)))))))

(defstruct (watch (:constructor %make-watch (variable mask offset size by-value)))
  "A plannable VARIABLE some autoscript watches, as TRANSITION-STATE needs it:
its one-hot field (MASK, from bit OFFSET, SIZE bits) and, for each value
index, the autoscripts of that value in spec order (BY-VALUE)."
  (variable nil)
  (mask 0 :type integer)
  (offset 0 :type fixnum)
  (size 0 :type fixnum)
  (by-value #() :type simple-vector))

(defun make-watches (machine)
  "The WATCHes of MACHINE's watched plannable variables, in its order."
  (let ((autoscripts (spec-autoscripts (machine-spec machine))))
    (loop for var in (machine-watched-variables machine)
          collect (let ((by-value (make-array (var-domain-size var) :initial-element '())))
                    (dolist (auto (reverse autoscripts))
                      (when (eq (autoscript-variable auto) var)
                        (push auto (svref by-value (autoscript-value-index auto)))))
                    (%make-watch var (var-field-mask var) (var-bit-offset var) (var-domain-size var)
                                 by-value)))))

(defun watch-value-index (watch bits)
  "The value index WATCH's variable has in state BITS (-1 if its field is empty)."
  (1- (integer-length (ldb (byte (watch-size watch) (watch-offset watch)) bits))))

(defun notify-watch (controller watch old-bits new-bits time)
  "WATCH's variable went from its value in OLD-BITS to that in NEW-BITS at
TIME: stop the old value's autoscripts, then start the new one's (as
NOTIFY-AUTOSCRIPTS does, from the table)."
  (let ((presenter (controller-presenter controller))
        (var (watch-variable watch))
        (old (watch-value-index watch old-bits))
        (new (watch-value-index watch new-bits)))
    (when (>= old 0)
      (dolist (auto (svref (watch-by-value watch) old))
        (dolist (proc (autoscript-procs auto))
          (stop-autoscript presenter proc (var-name var) (autoscript-value auto) (micros->seconds time)))))
    (when (>= new 0)
      (dolist (auto (svref (watch-by-value watch) new))
        (dolist (proc (autoscript-procs auto))
          (start-autoscript presenter proc (var-name var) (autoscript-value auto) (micros->seconds time)))))))

(defun transition-state (controller new-bits time)
  "Make NEW-BITS CONTROLLER's plannable state at TIME, telling autoscripts."
  (when (silent-p controller)
    (return-from transition-state (setf (controller-bits controller) new-bits)))
  (let* ((machine (controller-machine controller))
         (old-bits (controller-bits controller))
         (watched (logand (logxor old-bits new-bits) (machine-autoscript-mask machine))))
    (setf (controller-bits controller) new-bits)
    (unless (zerop watched)
      (dolist (watch (machine-watches machine))
        (when (logtest watched (watch-mask watch))
          (notify-watch controller watch old-bits new-bits time))))
    (unless (eql old-bits new-bits)
      (present-state-change (controller-presenter controller) controller (micros->seconds time)))
    new-bits))

(declaim (inline state-with-fields))
(defun state-with-fields (state mask bits)
  "STATE with the fields of MASK set to BITS.  Fixnums (the usual states) take
machine instructions; any other integers, generic arithmetic."
  (if (and (typep state 'fixnum) (typep mask 'fixnum) (typep bits 'fixnum))
      (logior (logandc2 state mask) bits)
      (logior (logandc2 state mask) bits)))

(declaim (inline set-state))
(defun set-state (controller new mask bits time op)
  "Make NEW, CONTROLLER's plannable state with the fields of MASK set to BITS,
its state at TIME (at the end of OP, or NIL).  A controller planning ahead
records the change for its timeline instead of telling autoscripts now; one
whose presenter is silent tells nobody."
  (let ((recorder (controller-recorder controller)))
    (cond (recorder
           (record-state-change recorder controller time mask bits op)
           (setf (controller-bits controller) new))
          ((silent-p controller) (setf (controller-bits controller) new))
          (t (transition-state controller new time)))))

(declaim (inline change-state))
(defun change-state (controller mask bits time &optional op)
  "Set the plannable fields of MASK to BITS at TIME (at the end of OP, if given),
as SET-STATE does."
  (set-state controller (state-with-fields (controller-bits controller) mask bits) mask bits time op))

(defun plannable-field-masks (spec)
  "The one-hot fields of SPEC's plannable variables, as masks, in declaration
order (worked out once per compiled macro-op: CHANGED-FIELDS runs at every
macro end a timed controller plans)."
  (mapcar #'var-field-mask (plannable-variables spec)))

(defun changed-fields (field-masks old new)
  "Those of FIELD-MASKS (PLANNABLE-FIELD-MASKS) whose bits differ between
plannable states OLD and NEW, together as one mask."
  (let ((diff (logxor old new)) (mask 0))
    (unless (zerop diff)
      (dolist (field field-masks)
        (when (logtest diff field)
          (setf mask (logior mask field)))))
    mask))

(defun change-state-to (controller new time field-masks &optional op)
  "Make NEW CONTROLLER's plannable state at TIME (at the end of OP, if given),
as CHANGE-STATE does.  FIELD-MASKS are the spec's PLANNABLE-FIELD-MASKS."
  (if (controller-recorder controller)
      (let ((mask (changed-fields field-masks (controller-bits controller) new)))
        (change-state controller mask (logand new mask) time op))
      (transition-state controller new time)))

(defun set-runtime-value (controller var value time)
  "Set runtime variable VAR to VALUE at TIME, telling autoscripts that watch it
(a controller planning ahead records the change instead)."
  (when (or (controller-recorder controller) (silent-p controller))
    (when (controller-recorder controller)
      (record-value-change (controller-recorder controller) controller time var value))
    (setf (svref (controller-values controller) (var-slot var)) value)
    (return-from set-runtime-value value))
  (let ((old (svref (controller-values controller) (var-slot var))))
    (setf (svref (controller-values controller) (var-slot var)) value)
    (unless (eql old value)
      (when (find var (spec-autoscripts (spec-of controller)) :key #'autoscript-variable)
        (notify-autoscripts controller var old value time)))
    value))

(defun start-initial-autoscripts (controller time)
  "Start, at TIME, the autoscripts whose values CONTROLLER holds now."
  (dolist (auto (spec-autoscripts (spec-of controller)))
    (let ((var (autoscript-variable auto)))
      (when (eql (autoscript-value-index auto)
                 (if (plannable-p var)
                     (value-index-of controller var)
                     (svref (controller-values controller) (var-slot var))))
        (dolist (proc (autoscript-procs auto))
          (start-autoscript (controller-presenter controller) proc (var-name var)
                            (autoscript-value auto) (micros->seconds time)))))))

;; Inline: every op of every event runs it, and a call would box END.
(declaim (inline note-op-end))
(defun note-op-end (controller end)
  "Advance the scheduling clock to END and extend the running span."
  (setf (controller-schedule controller) end)
  (when (micros< (controller-span-end controller) end)
    (setf (controller-span-end controller) end)))

(defmethod print-object ((controller controller) stream)
  ;; One line at the REPL: #<CONTROLLER PEEDY t=12.25 alert=awake posture=sit ...>
  (print-unreadable-object (controller stream :type t)
    (let* ((spec (spec-of controller))
           (text (format nil "~A t=~A~{ ~A~}" (lisp-text (spec-name spec))
                         (format-micros (controller-clock-micros controller))
                         (loop for var in (spec-variables spec)
                               collect (format nil "~A=~A" (lisp-text (var-name var))
                                               (let ((value (variable-value controller var)))
                                                 (cond ((eq (var-kind var) :boolean)
                                                        (if (= 1 (value-index-of controller var)) "true" "false"))
                                                       ((null value) "-")
                                                       (t (lisp-text value)))))))))
      (write-string (truncate-text text 120) stream))))
