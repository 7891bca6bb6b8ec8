;;;; timeline-streams.lisp -- random specs with timing (durations, :interrupt,
;;;; :if-cut, :channels, :when-busy, timers and triggers) and random timed
;;;; event streams for the timed controller's model-based test
;;;; (test-timeline-model.lisp), and playing a stream on the controller.

(in-package #:player-tests)

;;;# Random specs with timing

(defparameter *tm-durations* '(0 1 2 4 8 8 8 12 16 24)
  "Op durations, in eighths of a second (0 to 3 s; 1 s most often).")

(defparameter *tm-policies* '(:queue :preempt :override :interleave))

(defparameter *tm-spec-seeds* (loop for seed from 1 to 300 collect seed)
  "The seeds of the random specs of the property test.")

(defparameter *tm-streams-per-spec* 4
  "How many random event streams each spec plays.")

(defvar *tm-macro-completes-on-its-last-sub-op* t
  "The model's reading of a cut that falls in a macro-op's last sub-op when that
sub-op runs to its end: the macro-op has then run its whole :seq, so it ends
normally (its declared effects apply).  NIL: it ends as a cut macro (the
sub-ops' changes stay, its declared effects never apply).")

(defvar *tm-statistics* nil
  "A plist describing the last property run: streams, sends, busy sends, cuts...")

(defparameter *tm-channel-sets* '(("head") ("wings") ("legs") ("head" "wings") ("wings" "legs"))
  "The :channels a plain op of an unpartitioned spec may declare.")

(defstruct (tm-timer (:conc-name tmt-))
  "A (timer NAME :after AFTER :event EVENT [:repeat t] [:restart-on R]) of a spec;
RESTART-ON :ANY or a list of event names."
  name after event repeat restart-on)

(defstruct (tm-trigger (:conc-name tmg-))
  "A (trigger NAME :when CONDITION :event EVENT) of a spec; CONDITION a model AST."
  name condition event)

(defstruct (tm-spec (:conc-name tms-))
  "A random spec with timing: its forms, its RANDOM-SPEC model, and what the
model adds (durations, interruption, policies, channels, timers, triggers)."
  seed forms model
  ;; Plain op name -> duration in seconds (a rational).
  (durations (make-hash-table))
  ;; Plain op name -> :NEVER, :ANYTIME or a sorted list of points in seconds.
  (interrupts (make-hash-table))
  ;; Plain op name -> :if-cut effects ((VAR-INDEX . VALUE-INDEX) ...).
  (cut-effects (make-hash-table))
  ;; Event name -> its (:when-busy POLICY), when it has one.
  (event-policies (make-hash-table))
  ;; The spec's (:when-busy POLICY), or NIL.
  (default-policy nil)
  ;; Plain op name -> its declared :channels (lower-case strings); absent: none.
  (channels (make-hash-table))
  ;; True when variables, ops and events were split into two disjoint groups.
  (partitioned nil)
  (timers '())
  (triggers '())
  ;; Filled once the spec is compiled (TM-COMPUTE-FOOTPRINTS): the machine,
  ;; op name -> its variables (indices), and the plans TM-PLAN worked out.
  machine
  (op-variables (make-hash-table))
  (plans (make-hash-table :test 'equal)))

(defun tm-event-generator (prng model)
  "An :EVENT-GENERATOR for RANDOM-SPEC: events Q0... of 2 or 3 top-level
directives, each a (:state GOAL) or an (:op X), so :interleave has directives to
resume from."
  (loop for i below (rs-between prng 2 3)
        collect (make-model-event
                 :name (rs-symbol "q~D" i)
                 :directives (loop repeat (rs-between prng 2 4)
                                   collect (if (rs-chance prng 0.5)
                                               `(:state ,(random-condition prng model))
                                               `(:op ,(mop-name (rs-pick prng (model-ops model)))))))))

;;; Partitioned specs: two groups of variables, ops and events that never meet

(defun tm-group-condition (prng model vars)
  "A conjunction of 1 or 2 literals on distinct variables of VARS (indices)."
  (let ((literals (loop for i in (rs-sample prng vars (rs-between prng 1 (min 2 (length vars))))
                        for var = (svref (model-variables model) i)
                        collect (if (and (eq (mvar-kind var) :enumerated) (rs-chance prng 0.2))
                                    `(:not (:is ,i ,(rs-below prng (length (mvar-domain var)))))
                                    `(:is ,i ,(rs-below prng (length (mvar-domain var))))))))
    (if (rest literals) `(:and ,@literals) (first literals))))

(defun tm-group-effects (prng model vars)
  "1 or 2 effects on distinct variables of VARS."
  (loop for i in (rs-sample prng vars (rs-between prng 1 (min 2 (length vars))))
        collect (cons i (rs-below prng (length (mvar-domain (svref (model-variables model) i)))))))

(defun tm-partition-model (prng model groups)
  "Rewrite MODEL's ops and events so that each belongs to one of two groups of
variables (variable I in group I mod 2): its preconditions, effects and goals
mention only its group's.  Fills GROUPS (op name -> 0 or 1)."
  (let ((vars (vector (loop for i below (model-variable-count model) when (evenp i) collect i)
                      (loop for i below (model-variable-count model) when (oddp i) collect i))))
    ;; Plain ops and helpers first, then the macros, in the group of their first helper.
    (dolist (op (model-ops model))
      (unless (eq (mop-kind op) :macro)
        (let ((group (rs-below prng 2)))
          (setf (gethash (mop-name op) groups) group)
          (when (mop-precond op)
            (setf (mop-precond op) (tm-group-condition prng model (svref vars group))))
          (when (mop-effects op)
            (setf (mop-effects op) (tm-group-effects prng model (svref vars group)))))))
    (dolist (op (model-ops model))
      (when (eq (mop-kind op) :macro)
        (let ((group (gethash (first (mop-seq op)) groups)))
          (setf (gethash (mop-name op) groups) group
                (mop-seq op) (remove-if-not (lambda (name) (eql (gethash name groups) group)) (mop-seq op))
                (mop-precond op) (if (equal (mop-precond op) '(:const t))
                                     '(:const t)
                                     (tm-group-condition prng model (svref vars group)))
                (mop-effects op) (tm-group-effects prng model (svref vars group))))))
    (dolist (event (model-events model))
      (let* ((named (find :op (mevent-directives event) :key #'first))
             (group (if named (gethash (second named) groups) (rs-below prng 2)))
             (choices (remove-if-not (lambda (op) (eql (gethash (mop-name op) groups) group))
                                     (model-ops model))))
        (setf (mevent-directives event)
              (loop for directive in (mevent-directives event)
                    collect (ecase (first directive)
                              (:state `(:state ,(tm-group-condition prng model (svref vars group))))
                              (:op (if (eql (gethash (second directive) groups) group)
                                       directive
                                       `(:op ,(mop-name (rs-pick prng choices))))))))))))

(defun tm-random-timers (prng spec)
  "Sometimes one or two timers and sometimes a trigger for SPEC."
  (let* ((model (tms-model spec))
         (names (mapcar #'mevent-name (model-events model))))
    (when (rs-chance prng 0.4)
      (setf (tms-timers spec)
            (loop for i below (rs-between prng 1 2)
                  collect (let ((repeat (rs-chance prng 0.3)))
                            (make-tm-timer :name (rs-symbol "t~D" i)
                                           :after (if repeat
                                                      (rs-pick prng '(24 32 40))
                                                      (/ (rs-pick prng '(4 8 12 16 20 24 40 64)) 8))
                                           :event (rs-pick prng names)
                                           :repeat repeat)))))
    (when (rs-chance prng 0.35)
      (setf (tms-triggers spec)
            (list (make-tm-trigger :name (rs-symbol "r0") :condition (random-condition prng model)
                                   :event (rs-pick prng names)))))
    ;; :restart-on lists only events no timer sends, so timers never re-arm each other for ever.
    (let ((free (set-difference names (mapcar #'tmt-event (tms-timers spec)))))
      (dolist (timer (tms-timers spec))
        (setf (tmt-restart-on timer)
              (case (rs-below prng 3)
                (0 nil)
                (1 :any)
                (t (and free (rs-sample prng free (rs-between prng 1 2))))))))))

(defun tm-random-spec (seed)
  "The TM-SPEC for SEED: RANDOM-SPEC's spec and events plus TM-EVENT-GENERATOR's,
then (from a PRNG of its own) sometimes a partition of it into two groups that
never meet, every plain op's :duration, :interrupt, sometimes :if-cut and
:channels, some events' (:when-busy P), sometimes the spec's, timers and a trigger."
  (multiple-value-bind (forms model)
      (random-spec seed :name (rs-symbol "timeline-model-~D" seed)
                        :max-variables 5 :max-states 256 :op-event-count 3
                        :event-generator #'tm-event-generator)
    (declare (ignore forms))
    (let ((prng (make-rs-prng (+ 104729 seed)))
          (spec (make-tm-spec :seed seed :model model))
          (groups (make-hash-table)))
      (when (and (>= (model-variable-count model) 2) (rs-chance prng 0.45))
        (setf (tms-partitioned spec) t)
        (tm-partition-model prng model groups))
      (dolist (op (model-ops model))
        (unless (eq (mop-kind op) :macro)
          (let* ((name (mop-name op))
                 (eighths (rs-pick prng *tm-durations*))
                 (interrupt (case (rs-below prng 10)
                              ((0 1 2 3) :never)
                              ((4 5 6) :anytime)
                              (t (sort (remove-duplicates
                                        (loop repeat (rs-between prng 1 3)
                                              collect (/ (rs-between prng 0 eighths) 8)))
                                       #'<)))))
            (setf (gethash name (tms-durations spec)) (/ eighths 8)
                  (gethash name (tms-interrupts spec)) interrupt)
            (when (and (not (eq interrupt :never)) (not (mop-must-ask op)) (rs-chance prng 0.6))
              (setf (gethash name (tms-cut-effects spec))
                    (if (tms-partitioned spec)
                        ;; Within the op's own group, so the groups stay apart.
                        (let ((mine (loop for i below (model-variable-count model)
                                          when (= (mod i 2) (gethash name groups)) collect i)))
                          (tm-group-effects prng model mine))
                        (random-effects prng model)))))))
      ;; Channels: a partitioned spec's group 0 drives the head, group 1 the
      ;; wings and legs; elsewhere some ops declare some.
      (let ((declaring (if (tms-partitioned spec) 0.9 (if (rs-chance prng 0.5) 0.7 0))))
        (dolist (op (model-ops model))
          (when (and (not (eq (mop-kind op) :macro)) (rs-chance prng declaring))
            (setf (gethash (mop-name op) (tms-channels spec))
                  (cond ((not (tms-partitioned spec)) (rs-pick prng *tm-channel-sets*))
                        ((zerop (gethash (mop-name op) groups)) '("head"))
                        (t (rs-pick prng '(("wings") ("legs") ("wings" "legs")))))))))
      (dolist (event (model-events model))
        (when (rs-chance prng 0.5)
          (setf (gethash (mevent-name event) (tms-event-policies spec)) (rs-pick prng *tm-policies*))))
      (when (rs-chance prng 0.5)
        (setf (tms-default-policy spec) (rs-pick prng *tm-policies*)))
      (tm-random-timers prng spec)
      (setf (tms-forms spec) (tm-decorate-forms spec (model-spec-forms model)))
      spec)))

(defun tm-form-kind-p (form kind)
  "Is FORM a spec form whose head is named KIND (a string)?"
  (and (consp form) (symbolp (first form)) (string= (symbol-name (first form)) kind)))

(defun tm-decorate-forms (spec forms)
  "FORMS with SPEC's timing: :duration, :interrupt, :if-cut, :channels on the
ops, (:when-busy P) on events and, when SPEC has a default, as a spec option;
then its timers and triggers."
  (let ((model (tms-model spec)))
    (append
     (when (tms-default-policy spec)
       (list (list :when-busy (tms-default-policy spec))))
     (loop for form in forms
           collect (cond ((tm-form-kind-p form "OP")
                          (let* ((name (second form))
                                 (interrupt (gethash name (tms-interrupts spec)))
                                 (cut (gethash name (tms-cut-effects spec)))
                                 (channels (gethash name (tms-channels spec))))
                            (append form
                                    (list :duration (float (gethash name (tms-durations spec))))
                                    (cond ((eq interrupt :never) '())
                                          ((eq interrupt :anytime) (list :interrupt :anytime))
                                          (t (list :interrupt (cons :at (mapcar #'float interrupt)))))
                                    (when cut
                                      (list :if-cut (render-effect-options model cut)))
                                    (when channels
                                      (list :channels channels)))))
                         ((and (tm-form-kind-p form "EVENT")
                               (gethash (second form) (tms-event-policies spec)))
                          (list* (first form) (second form)
                                 (list :when-busy (gethash (second form) (tms-event-policies spec)))
                                 (cddr form)))
                         (t form)))
     (loop for timer in (tms-timers spec)
           collect `(,(rs-symbol "timer") ,(tmt-name timer) :after ,(float (tmt-after timer))
                     :event ,(tmt-event timer)
                     ,@(when (tmt-repeat timer) (list :repeat (rs-symbol "true")))
                     ,@(when (tmt-restart-on timer) (list :restart-on (tmt-restart-on timer)))))
     (loop for trigger in (tms-triggers spec)
           collect `(,(rs-symbol "trigger") ,(tmg-name trigger)
                     :when ,(render-expression model (tmg-condition trigger))
                     :event ,(tmg-event trigger))))))

(defun tm-op-duration (spec op)
  "OP's (a MODEL-OP) duration in seconds: a macro's is its :seq ops' sum."
  (if (eq (mop-kind op) :macro)
      (loop for name in (mop-seq op)
            sum (tm-op-duration spec (model-find-op (tms-model spec) name)))
      (gethash (mop-name op) (tms-durations spec))))

;;;# Random streams

(defun tm-random-stream (spec seed stream)
  "Stream number STREAM of SPEC: (VALUES ACTIONS INITIAL-STATE).  ACTIONS are
(:send EVENT TIME POLICY-OR-NIL) and (:check TIME), in time order; half the gaps
between sends are short (0 to 3 s), half long (40 s and more).  With timers
or triggers, a last (:check T) 12 s after the last send and a (:settle) (see TM-PLAY-STREAM)."
  (let* ((prng (make-rs-prng (+ (* 1000 seed) stream 7)))
         (model (tms-model spec))
         (events (model-events model))
         (initial (model-index-state model (rs-below prng (model-state-count model))))
         (time 0)
         (last 0)
         (actions '()))
    (loop repeat (rs-between prng 6 14)
          do (push (list :send (mevent-name (rs-pick prng events)) time
                         (if (rs-chance prng 0.35) nil (rs-pick prng *tm-policies*)))
                   actions)
             (setf last time)
             (let ((gap (if (rs-chance prng 0.85)
                            (/ (rs-pick prng '(0 0 1 1 2 2 3 4 6 8)) 8)
                            (+ 40 (rs-below prng 20)))))
               (when (and (plusp gap) (rs-chance prng 0.4))
                 (push (list :check (+ time (* gap (/ (rs-between prng 1 4) 4)))) actions))
               (incf time gap)))
    (when (or (tms-timers spec) (tms-triggers spec))
      (setf actions (remove-if (lambda (action) (and (eq (first action) :check) (> (second action) last)))
                               actions))
      (push (list :check (+ last 12)) actions)
      (push (list :settle (+ last 12)) actions))
    (values (nreverse actions) initial)))

;;;# Playing a stream on the timed controller

(defparameter *tm-settle-steps* 12
  "How many 50 s steps a :settle action advances at most while the controller
stays busy (a repeating timer or triggers may keep it busy for ever).")

(defstruct (tm-play (:conc-name tmp-))
  "What the controller did with a stream."
  lines
  ;; Per send, the list of values SEND-EVENT returned.
  results
  ;; Per :check (and per step of a :settle), (STATE-ALIST BUSY-P).
  checks
  ;; The times a :settle advanced to.
  settle-times
  final-state final-busy
  ;; :LIVELOCK (still busy after settling) or :ZERO-TIME-LOOP (a TIMELINE-ERROR).
  abandoned)

(defun call-with-random-stream (seed stream function)
  "Call FUNCTION with the machine, the TM-SPEC, the actions and the initial
state of stream STREAM of random spec SEED (in package PLAYER-USER), then
remove the spec; return what FUNCTION returns."
  (let* ((spec (tm-random-spec seed))
         (name (model-name (tms-model spec)))
         (*package* (find-package '#:player-user)))
    (unwind-protect
         (let ((machine (tm-compile-spec spec)))
           (multiple-value-bind (actions initial) (tm-random-stream spec seed stream)
             (funcall function machine spec actions initial)))
      (remove-spec name))))

(defun tm-play-stream (machine spec actions initial &key (presenter (make-trace-presenter)))
  "Play ACTIONS on a fresh timed controller of MACHINE from INITIAL, then FINISH-EVENTS.
A (:settle T) advances by 50 s steps from T while the controller is busy.  The
play's lines are PRESENTER's trace lines (none unless it is a trace presenter)."
  (let* ((model (tms-model spec))
         (controller (make-controller machine :timed t :presenter presenter
                                              :initial-state (model-state-alist model initial)))
         (results '()) (checks '()) (settle-times '()) (abandoned nil))
    (flet ((check (time)
             (advance controller (float time 1d0))
             (push (list (controller-state controller) (controller-busy-p controller)) checks)))
      (handler-case
          (progn
            (dolist (action actions)
              (ecase (first action)
                (:send (destructuring-bind (event time policy) (rest action)
                         (push (multiple-value-list
                                (if policy
                                    (send-event controller event :at (float time 1d0) :when-busy policy)
                                    (send-event controller event :at (float time 1d0))))
                               results)))
                (:check (check (second action)))
                (:settle (loop for step from 1 to *tm-settle-steps*
                               while (controller-busy-p controller)
                               do (let ((time (+ (second action) (* 50 step))))
                                    (push time settle-times)
                                    (check time)))
                 (when (controller-busy-p controller)
                   (setf abandoned :livelock)))))
            (unless abandoned
              (finish-events controller)))
        (player::timeline-error () (setf abandoned :zero-time-loop))))
    (make-tm-play :lines (and (player.control::trace-presenter-p presenter) (trace-lines presenter)) :results (nreverse results) :checks (nreverse checks)
                  :settle-times (nreverse settle-times)
                  :final-state (controller-state controller)
                  :final-busy (controller-busy-p controller)
                  :abandoned abandoned)))

(defun tm-stream-problems (function &key (specs 100) (streams 2))
  "Call FUNCTION on (SEED STREAM) for the first SPECS spec seeds and STREAMS
streams each; FUNCTION returns a problem (a string) or NIL, and a count.
Returns the problems, each naming its seed and stream (an error is one), and
the sum of the counts."
  (let ((problems '()) (total 0))
    (dolist (seed (subseq *tm-spec-seeds* 0 specs))
      (loop for stream from 1 to streams
            do (multiple-value-bind (problem count)
                   (handler-case (funcall function seed stream)
                     (error (e) (format nil "error: ~A" e)))
                 (incf total (or count 0))
                 (when problem
                   (push (format nil "spec seed ~D, stream ~D: ~A" seed stream problem) problems)))))
    (values (reverse problems) total)))
