;;;; timeline-model.lisp -- an independent reference model of the timed
;;;; controller (src/control/timeline/), which test-timeline-model.lisp checks
;;;; on random specs and random timed event streams (timeline-streams.lisp).
;;;;
;;;; Each case is a random spec (RANDOM-SPEC, plus multi-directive events, op
;;;; :duration, :interrupt and :if-cut, event and spec :when-busy policies), a
;;;; random initial state and a random stream of sends at increasing times
;;;; (about half of them while the character is busy), each with a random
;;;; :when-busy or none, and between them some ADVANCE checkpoints.  A timed
;;;; controller with a trace presenter plays the stream and FINISH-EVENTS; then
;;;; the reference model replays the trace lines, knowing only the spec's op
;;;; definitions (preconditions, effects, durations, interruption points,
;;;; :if-cut effects) and the reference BFS (reference-bfs.lisp), never the
;;;; timeline code.  It encodes the timed semantics restated:
;;;;
;;;;  * an event sent at T while no event runs starts at T: (:event EV :time T);
;;;;    each of its top-level directives takes as many plan operators as the
;;;;    reference BFS's shortest distance from the state then (an (:op X)
;;;;    directive: the distance to X's precondition, then X), each op starting
;;;;    when the previous one ends, with its precondition holding, lasting its
;;;;    declared :duration (a macro: its :seq ops one after another), its
;;;;    effects applying at its end (a macro's: the state it started from with
;;;;    its declared effects); a directive with no plan gives (:fail EV :goal G
;;;;    :time T); the event ends with (:state ...) when its last op ends;
;;;;  * busy means an event's run has not finished at T.  :queue waits (FIFO)
;;;;    and starts when the running event ends (if the start gate, below,
;;;;    lets it); :override gives (:dropped EV :time T :busy-with RUNNING);
;;;;    :preempt and :interleave stop the op running at T at its next
;;;;    interruption point (:never its end, :anytime T, (:at P...) the first
;;;;    start+P in [T, end], else its end), with
;;;;    (:cut OP :time STOP :by EV) for an op stopped short -- which then has
;;;;    its :if-cut effects at STOP instead of its own -- or one (:cut OP-OR-NIL
;;;;    :time TC :by EV) when none is; the rest of the interrupted event never
;;;;    happens (the interrupted run is over when its own op is); EV starts at
;;;;    TC, the latest of T, those stops and the ends of ops of earlier events
;;;;    still finishing (if the start gate lets it); :interleave then resumes the
;;;;    interrupted event, (:resume EV0 :time T3), once EV has finished, from
;;;;    the top-level directive it was cut in (the first with work left);
;;;;  * a cut that falls in a macro-op's sub-op ends the macro-op at TC (its
;;;;    line's :end), its sub-ops' changes so far standing and its declared
;;;;    effects never applying -- unless the cut lets its last sub-op run to
;;;;    its end, when the macro-op ends as it would have (see
;;;;    *TM-MACRO-COMPLETES-ON-ITS-LAST-SUB-OP*);
;;;;  * the state at every checkpoint and every (:state ...) line is the
;;;;    initial state with every completed op's effects and every cut op's
;;;;    :if-cut effects applied in time order; ops never overlap.
;;;;
;;;;  * events play side by side: an event arriving while others run is
;;;;    planned on trial from the state then (the model asks an untimed
;;;;    controller, whose whole-event path is checked against the reference BFS
;;;;    elsewhere, for that plan: TM-PLAN); its footprint is the channels of the
;;;;    plain ops it plays (:ALL for one declaring none, NIL for no op) and the
;;;;    variables of its ops' (macros' too) preconditions, effects and :if-cut
;;;;    effects.  Footprints meet when either has channels :ALL or NIL or they
;;;;    share a channel or a variable.  Meeting no running run it starts
;;;;    beside them; else its policy applies against the runs it meets
;;;;    (:busy-with the first);
;;;;  * the start gate (TM-GATE): every run about to start at S -- arriving
;;;;    idle or beside others, a preemptor after its cuts, a queued event or a
;;;;    resumption when a run ends -- is planned from the state due at S and
;;;;    starts at S only if that plan meets no running run and no op of an
;;;;    interrupted run still playing after S; with only such ops in the way,
;;;;    S becomes the latest of their ends and it is planned again; with a
;;;;    running run in the way it waits first in the queue (a preemptor ahead
;;;;    of the runs it interrupted), looked at again when a run ends.  A run
;;;;    plans all of itself when it starts, so its later directives see its
;;;;    own changes only (TM-RUN-STATE);
;;;;  * a timer's or trigger's line shows when it goes off; its event is
;;;;    dispatched once everything else due then has happened, in the order
;;;;    they went off.  The generator gives a trigger only an event that cannot
;;;;    raise its condition again by itself (TM-COMPILE-SPEC), so streams do not
;;;;    livelock;
;;;;  * macro lines of runs side by side whose spans cross each get their own
;;;;    :end (*TM-TOLERATE-CROSSING-MACRO-LINES*, off, once let a presenter
;;;;    that swapped them pass).
;;;;
;;;; The model takes from the trace only which ops the planner chose (any
;;;; shortest plan will do); everything else -- when each event starts, whether
;;;; the controller is busy at each send, every :event, :resume, :dropped, :cut,
;;;; :fail and :state line in order, each op's start and end, the state -- it
;;;; works out itself and compares.  Times are multiples of 1/8 s (durations,
;;;; interruption points, send times), so it counts in exact rationals.
;;;;
;;;; A failure names the spec seed and stream number: (tm-check-stream SEED
;;;; STREAM) reproduces it and returns the problem; (tm-show-stream SEED STREAM)
;;;; prints the spec, the stream and the trace.
;;;;
;;;; The model is in four files: this one (its records, footprints, matching
;;;; the control lines), timeline-model-runs.lisp (runs taking their op lines,
;;;; the clock), timeline-model-arrivals.lisp (policies, cuts, the start gate)
;;;; and timeline-model-replay.lisp (reading a trace, replaying, the
;;;; invariants).

(in-package #:player-tests)

;;;# The reference model

(defstruct (tm-op (:conc-name tmo-))
  "An op line of the trace as the model reads it."
  name mop index start end
  ;; The end it really had (its cut time when cut short).
  effective-end
  run
  ;; The absolute index of the top-level directive it serves.
  directive
  ;; For a macro's sub-op, the macro's TM-OP.
  macro
  ;; For a macro: the :end its trace line should show in the end.
  expected-end
  (cut nil)
  ;; Set once a run of the model has taken it as one of its ops.
  (claimed nil))

(defstruct (tm-change (:conc-name tmc-))
  "A state change at TIME: DATA an effects alist ((VAR-INDEX . VALUE-INDEX)...);
RUN and OP that made it; KEY its place among things due at the same time (see
TM-KEY); APPLIED once the model's clock has passed it; MACRO-END for a macro's
end (the state it started from with its declared effects)."
  time data run op key applied macro-end)

(defstruct (tm-run (:conc-name tmr-))
  "An event's run as the model plays it: the directives still to do and the
op lines the trace attributes to it."
  name kind start directives
  ;; Absolute index of the directive under way, ops it still needs.
  (pos 0) (remaining 0)
  ;; When its next op starts (its schedule).
  at
  ;; The index of its :event or :resume line, the state it was planned from
  ;; (the controller plans an event ahead, all of it, when it starts) and the
  ;; ops of that plan (names).
  line base plan-names
  ;; The macro under way: its TM-OP, the state it started from, its sub-ops to come.
  macro macro-before macro-seq
  complete end failed fail-goal cut
  ;; What SEND-EVENT returned when this run started from a send, or :NONE.
  (result :none)
  ;; Where its things fall among those due at the same time (TM-KEY).
  block (sub 0) next-key
  footprint)

(defstruct (tm-timer-state (:conc-name tmts-))
  "A timer as the model plays it: when it goes off next (NIL: disarmed)."
  timer time key)

(defstruct (tm-context (:conc-name tmx-))
  "The model's replay of one stream."
  spec model initial predecessors
  (distances (make-hash-table :test 'equal))
  ;; The state as the controller has it: the initial one with the changes applied so far.
  state
  ;; TM-CHANGEs, newest first.
  (changes '())
  ;; Every plain op and sub-op consumed, newest first.
  (ops '())
  ;; Every macro consumed.
  (macros '())
  ;; The control lines of the trace (:event :resume :dropped :cut :fail :state
  ;; :timer :trigger) as (INDEX . LINE), and the next to match.
  control (cursor 0)
  ;; The op lines of the trace (TM-OPs), in order.
  (op-lines '())
  ;; The model's clock: the time of what it plays, then the time it advanced to.
  (now 0)
  ;; Events timers and triggers sent at NOW, first first, to be dispatched once
  ;; everything else due then has happened: (NAME SOURCE).
  (deferred '())
  ;; Every run, newest first; those playing, oldest first.
  (runs '())
  (active '())
  ;; Waiting runs, first first: (NAME KIND FIRST-STEP RESULT).
  (queue '())
  ;; The counter of TM-KEY blocks.
  (blocks 0)
  timers
  ;; (TM-TRIGGER . HELD) per trigger.
  triggers
  ;; Against loops at one instant.
  instant (instant-count 0)
  statistics)

(defun tm-fail (control &rest arguments)
  "Stop the replay: the trace disagrees with the model."
  (throw 'tm-problem (apply #'format nil control arguments)))

(defun tm-count (context key &optional (n 1))
  "Count N more cases of KEY in CONTEXT's statistics."
  (incf (getf (tmx-statistics context) key 0) n))

;;; Order at equal times.  The controller's agenda orders things due at the
;;; same time by when they were made: a run's things when it starts (in its
;;; own order), a timer's going off when it is armed, a cut's :if-cut change
;;; at the cut.  The model numbers those makings: a KEY is BLOCK * 10^6 + SUB.

(defconstant +tm-block+ 1000000)

(defun tm-new-block (context)
  "A new block of keys, after every block made so far."
  (incf (tmx-blocks context)))

(defun tm-fresh-key (run)
  "RUN's next key, after every one it has had."
  (+ (* (tmr-block run) +tm-block+) (incf (tmr-sub run))))

(defun tm-finish-key (run)
  "The key of RUN's end: after all its things."
  (+ (* (tmr-block run) +tm-block+) (1- +tm-block+)))

(defun tm-state-at (context time)
  "The model's state at TIME as a run starting then sees it: the initial state
with every change due by TIME applied in time order."
  (let ((state (copy-seq (tmx-initial context))))
    (dolist (change (sort (remove-if (lambda (change) (> (tmc-time change) time))
                                     (copy-list (tmx-changes context)))
                          (lambda (a b) (or (< (tmc-time a) (tmc-time b))
                                            (and (= (tmc-time a) (tmc-time b)) (< (tmc-key a) (tmc-key b)))))))
      (loop for (i . k) in (tmc-data change) do (setf (svref state i) k)))
    state))

(defun tm-add-change (context time data run op key)
  "Note a TM-CHANGE (see there) in CONTEXT; return it."
  (let ((change (make-tm-change :time time :data data :run run :op op :key key)))
    (push change (tmx-changes context))
    change))

(defun tm-distance (context goal state)
  "The reference BFS's shortest plan length from STATE to GOAL, or NIL."
  (let ((distances (or (gethash goal (tmx-distances context))
                       (setf (gethash goal (tmx-distances context))
                             (reference-distances (tmx-model context) goal
                                                  :predecessors (tmx-predecessors context))))))
    (svref distances (model-state-index (tmx-model context) state))))

(defun tm-directive-goal (context directive)
  "The goal a top-level directive plans for."
  (ecase (first directive)
    (:state (second directive))
    (:op (or (mop-precond (model-find-op (tmx-model context) (second directive))) '(:const t)))))

(defun tm-directive-goal-form (context directive)
  "The goal, as written, a failing directive reports."
  (let ((model (tmx-model context)))
    (ecase (first directive)
      (:state (render-expression model (second directive)))
      (:op (render-expression model (mop-precond (model-find-op model (second directive))))))))

(defun tm-state-text (context state)
  "STATE (a model state vector) as readable text."
  (state-text (tmx-model context) state))

;;; Footprints

(defun tm-support (model ast)
  "The variables (indices) whose value AST's truth depends on."
  (when ast
    (let ((count (model-state-count model)))
      (loop for i below (model-variable-count model)
            when (loop for n below count
                       for state = (model-index-state model n)
                       for truth = (model-eval ast state)
                         thereis (loop for k below (length (mvar-domain (svref (model-variables model) i)))
                                       thereis (let ((other (copy-seq state)))
                                                 (setf (svref other i) k)
                                                 (not (eq truth (model-eval ast other))))))
              collect i))))

(defun tm-compute-footprints (spec machine)
  "Note MACHINE (SPEC compiled) in SPEC, for the untimed controllers that give
the model an event's plan (TM-PLAN), and each op's variables: those its
precondition's truth depends on, its effects' and its :if-cut effects'."
  (let ((model (tms-model spec)))
    (setf (tms-machine spec) machine)
    (dolist (op (model-ops model))
      (setf (gethash (mop-name op) (tms-op-variables spec))
            (union (tm-support model (mop-precond op))
                   (union (mapcar #'car (mop-effects op))
                          (mapcar #'car (gethash (mop-name op) (tms-cut-effects spec)))))))))

(defun tm-untimed-ops (machine model name step state)
  "The names of the ops (macros and their sub-ops too) an untimed controller of
MACHINE plays for event NAME from its top-level directive STEP in STATE."
  (let* ((presenter (make-trace-presenter))
         (controller (make-controller machine :presenter presenter
                                              :initial-state (model-state-alist model state))))
    (if (zerop step)
        (send-event controller name)
        ;; A resumption plans the event from directive STEP on.
        (let ((compiled (player.control::find-compiled-event controller name))
              (player::*controller* controller))
          (setf (player.control::controller-schedule controller) 0
                (player.control::controller-span-start controller) 0
                (player.control::controller-span-end controller) 0)
          (funcall (svref (player.control::event-suffixes compiled machine) step) controller)))
    (loop for line in (trace-lines presenter)
          when (eq (first line) :op) collect (second line))))

(defun tm-trigger-safe-p (spec machine condition event)
  "Can a trigger on CONDITION send EVENT without firing itself for ever?  From
every state where CONDITION holds, EVENT's plan never makes it false, neither
by an op's effects nor by its :if-cut effects (so only other events can give it
a new rising edge)."
  (let ((model (tms-model spec)))
    (loop for n below (model-state-count model)
          for start = (model-index-state model n)
          always (or (not (model-eval condition start))
                     (let ((state (copy-seq start))
                           ;; A macro under way: its sub-ops to come, its end state.
                           (subs 0) (macro-end nil))
                       (loop for name in (tm-untimed-ops machine model event 0 start)
                             for op = (model-find-op model name)
                             always (and (model-eval condition
                                                     (let ((cut (copy-seq state)))
                                                       (loop for (i . k) in (gethash name (tms-cut-effects spec))
                                                             do (setf (svref cut i) k))
                                                       cut))
                                         (progn
                                           (cond ((eq (mop-kind op) :macro)
                                                  (setf subs (length (mop-seq op))
                                                        macro-end (model-apply-effects op state)))
                                                 (t (setf state (model-apply-effects op state))
                                                    (when (and macro-end (zerop (decf subs)))
                                                      (setf state macro-end macro-end nil))))
                                           (model-eval condition state))
                                         (or (null macro-end) (model-eval condition macro-end)))))))))

(defun tm-compile-spec (spec)
  "Define and compile SPEC; returns its machine.  A trigger whose event could
fire it again for ever (see TM-TRIGGER-SAFE-P; or one sent by :interleave, as
an interrupted event resuming may raise its condition again) sends instead the first event
after it (in the model's order) that cannot, or is dropped."
  (flet ((compile-it ()
           (setf (tms-forms spec) (tm-decorate-forms spec (model-spec-forms (tms-model spec))))
           (compile-spec (define-spec (model-name (tms-model spec)) (tms-forms spec)
                                      :package (find-package '#:player-user)))))
    (let ((machine (compile-it))
          (names (mapcar #'mevent-name (model-events (tms-model spec))))
          (changed nil))
      (setf (tms-triggers spec)
            (loop for trigger in (tms-triggers spec)
                  for chosen = (find-if (lambda (event)
                                          ;; Nor does it interleave: an interrupted
                                          ;; event resuming could raise it again.
                                          (and (not (eq :interleave
                                                        (or (gethash event (tms-event-policies spec))
                                                            (tms-default-policy spec))))
                                               (tm-trigger-safe-p spec machine (tmg-condition trigger) event)))
                                        (let ((tail (member (tmg-event trigger) names)))
                                          (append tail (ldiff names tail))))
                  unless (eq chosen (tmg-event trigger)) do (setf changed t)
                  when chosen collect (progn (setf (tmg-event trigger) chosen) trigger)))
      (when changed
        (remove-spec (model-name (tms-model spec)))
        (setf machine (compile-it)))
      machine)))

(defun tm-plan (context name step state)
  "Event NAME's plan from its top-level directive STEP in STATE, as an untimed
controller (whose whole-event path is checked against the reference BFS
elsewhere) plays it: (VALUES FOOTPRINT OP-NAMES).  FOOTPRINT is (CHANNELS .
VARIABLES): the union of the declared channels of the plain ops it plays (:ALL
if one declares none, NIL if it plays none) and of its ops' (macros too)
variables."
  (let* ((spec (tmx-spec context))
         (model (tmx-model context))
         (key (list name step (model-state-index model state)))
         (cached (gethash key (tms-plans spec))))
    (unless cached
      (let ((names (tm-untimed-ops (tms-machine spec) model name step state)))
        (let ((channels '())
              (variables '()))
          (dolist (op-name names)
            (let ((op (model-find-op model op-name)))
              (unless op (tm-fail "the untimed controller plays ~S, not an op of the spec" op-name))
              (unless (eq (mop-kind op) :macro)
                (let ((declared (gethash op-name (tms-channels spec))))
                  (setf channels (if (or (null declared) (eq channels :all))
                                     :all
                                     (union channels declared :test #'string=)))))
              (setf variables (union variables (gethash op-name (tms-op-variables spec))))))
          (setf cached (list (cons channels variables) names)
                (gethash key (tms-plans spec)) cached))))
    (values (first cached) (second cached))))

(defun tm-meet-p (a b)
  "Do footprints A and B ((CHANNELS . VARIABLES)) meet?"
  (or (member (car a) '(:all nil)) (member (car b) '(:all nil))
      (intersection (car a) (car b) :test #'string=)
      (intersection (cdr a) (cdr b))))

(defun tm-op-channels (context name)
  "Op NAME's declared channels, or :ALL."
  (or (gethash name (tms-channels (tmx-spec context))) :all))

;;; Matching the control lines

(defun tm-same-line-p (context expected actual)
  "Does trace line ACTUAL say what EXPECTED does?  Numbers compare with =, a
:state line by the model state it names."
  (cond ((eq (first expected) :state)
        (and (eq (first actual) :state)
             (equalp (second expected) (model-state-from-alist (tmx-model context) (rest actual)))))
        (t (and (= (length expected) (length actual))
                (every (lambda (e a)
                         (cond ((and (realp e) (realp a)) (= e a))
                               ;; A :clash list, in the order the model does not know.
                               ((and (consp e) (consp a)) (null (set-exclusive-or e a :test #'equal)))
                               (t (equal e a))))
                       expected actual)))))

(defun tm-show-line (context line)
  "LINE (a trace line, or an expected one with a model state) as readable text."
  (if (eq (first line) :state)
      (if (simple-vector-p (second line))
          (format nil "(:state ~A)" (tm-state-text context (second line)))
          (trace-line-string line))
      (let ((*package* (find-package '#:player-user)))
        (format nil "~S" (mapcar (lambda (x) (if (rationalp x) (float x 1d0) x)) line)))))

(defun tm-expect (context expected why)
  "The next control line must be EXPECTED (WHY says what the model is doing);
returns its index in the trace."
  (let ((entry (nth (tmx-cursor context) (tmx-control context))))
    (unless (and entry (tm-same-line-p context expected (cdr entry)))
      (tm-fail "~A: the model expects ~A, the trace has ~:[no more control lines~;~:*~A (line ~D)~]"
               why (tm-show-line context expected)
               (and entry (tm-show-line context (cdr entry))) (and entry (car entry))))
    (incf (tmx-cursor context))
    (car entry)))
