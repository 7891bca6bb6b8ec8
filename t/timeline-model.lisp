;;;; timeline-model.lisp -- an independent reference model of the timed
;;;; controller (src/runtime/timeline/), which test-timeline-model.lisp checks
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
;;;;  * known presenter bug, tolerated while *TM-TOLERATE-CROSSING-MACRO-LINES*:
;;;;    macro lines of runs side by side whose spans cross get each other's :end.
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
        (let ((compiled (player::find-compiled-event controller name))
              (player::*controller* controller))
          (setf (player::controller-schedule controller) 0d0
                (player::controller-span-start controller) 0d0
                (player::controller-span-end controller) 0d0)
          (funcall (svref (player::event-suffixes compiled machine) step) controller)))
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
                         (if (and (realp e) (realp a)) (= e a) (equal e a)))
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

;;; Runs

(defun tm-start-run (context name kind first-step time result)
  "Start NAME's run (KIND :EVENT or :RESUME, from directive FIRST-STEP) at TIME."
  (let* ((index (tm-expect context (list kind name :time time)
                           (format nil "~(~A~) ~A starting at ~A" kind name (float time 1d0))))
         (event (find name (model-events (tmx-model context)) :key #'mevent-name))
         ;; It plans from the state due then (TM-GATE's).
         (base (tm-state-at context time))
         (run (multiple-value-bind (footprint names) (tm-plan context name first-step base)
                (make-tm-run :name name :kind kind :start time :at time
                             :directives (mevent-directives event)
                             :pos first-step
                             :line index :base base :plan-names names
                             :result result
                             :block (tm-new-block context)
                             :footprint footprint))))
    (setf (tmr-next-key run) (tm-fresh-key run))
    (when (tmx-active context)
      (tm-count context :beside))
    (push run (tmx-runs context))
    (setf (tmx-active context) (append (tmx-active context) (list run)))
    (when (eq kind :resume) (tm-count context :resumed))
    run))

(defun tm-run-state (context run)
  "The state RUN plans its next step in: the one it started from with its own
changes so far (the controller plans an event ahead when it starts; the events
playing beside it touch none of its variables)."
  (let ((state (copy-seq (tmr-base run))))
    (dolist (change (sort (remove-if-not (lambda (change)
                                           (and (eq (tmc-run change) run) (<= (tmc-time change) (tmr-at run))))
                                         (copy-list (tmx-changes context)))
                          (lambda (a b) (tm-key< (tmc-time a) (tmc-key a) (tmc-time b) (tmc-key b)))))
      (loop for (i . k) in (tmc-data change) do (setf (svref state i) k)))
    state))

(defun tm-step (context run)
  "Play RUN's next thing at its schedule: begin its directives due then until
it consumes an op line, or is complete."
  (loop
    (when (or (tmr-complete run) (tmr-cut run))
      (return))
    (cond ((tmr-macro run) (tm-consume-sub-op context run) (return))
          ((plusp (tmr-remaining run)) (tm-consume-op context run) (return))
          ((>= (tmr-pos run) (length (tmr-directives run)))
           (setf (tmr-complete run) t (tmr-end run) (tmr-at run)))
          (t (tm-begin-directive context run)))))

(defun tm-begin-directive (context run)
  "Work out how many ops RUN's next directive takes, from the state at its start."
  (let* ((directive (nth (tmr-pos run) (tmr-directives run)))
         (state (tm-run-state context run))
         (distance (tm-distance context (tm-directive-goal context directive) state)))
    (cond ((null distance)
           (setf (tmr-failed run) t
                 (tmr-fail-goal run) (tm-directive-goal-form context directive)
                 (tmr-complete run) t
                 (tmr-end run) (tmr-at run)))
          ((eq (first directive) :op) (setf (tmr-remaining run) (1+ distance)))
          ((zerop distance) (incf (tmr-pos run)))
          (t (setf (tmr-remaining run) distance)))))

(defun tm-next-line (context run what)
  "RUN's next op line, which the model expects to be WHAT: the first op line
after RUN's :event or :resume line that no run has taken and that RUN's plan
plays (the ops of runs playing side by side are disjoint)."
  (or (let ((line (find-if (lambda (line)
                             (and (not (tmo-claimed line)) (> (tmo-index line) (tmr-line run))
                                  (member (tmo-name line) (tmr-plan-names run))))
                           (tmx-op-lines context))))
        (when line
          (setf (tmo-claimed line) t)
          line))
      (tm-fail "~A ~A (from ~A): the model expects ~A at ~A, but the trace shows no more ops of it"
               (tmr-kind run) (tmr-name run) (float (tmr-start run) 1d0) what (float (tmr-at run) 1d0))))

(defun tm-check-op-line (run line duration)
  "LINE must start at RUN's schedule and last DURATION."
  (unless (= (tmo-start line) (tmr-at run))
    (tm-fail "~A ~A: op ~A (line ~D) starts at ~A; the previous one ended at ~A"
             (tmr-kind run) (tmr-name run) (tmo-name line) (tmo-index line)
             (float (tmo-start line) 1d0) (float (tmr-at run) 1d0)))
  (unless (or (eq (mop-kind (tmo-mop line)) :macro) (= (tmo-end line) (+ (tmo-start line) duration)))
    (tm-fail "op ~A (line ~D) is shown ending at ~A; it starts at ~A and lasts ~A"
             (tmo-name line) (tmo-index line) (float (tmo-end line) 1d0) (float (tmo-start line) 1d0)
             (float duration 1d0)))
  (setf (tmo-run line) run
        (tmo-directive line) (tmr-pos run)
        (tmo-effective-end line) (+ (tmr-at run) duration)))

(defun tm-consume-op (context run)
  "RUN's next plan op (or the requested op of an (:op X) directive)."
  (let* ((line (tm-next-line context run "a plan op"))
         (model (tmx-model context))
         (op (tmo-mop line))
         (directive (nth (tmr-pos run) (tmr-directives run)))
         (requested (and (eq (first directive) :op) (= 1 (tmr-remaining run))))
         (state (tm-run-state context run))
         (real (tm-state-at context (tmr-at run)))
         (duration (tm-op-duration (tmx-spec context) op)))
    (tm-check-op-line run line duration)
    (cond ((and requested (not (eq (tmo-name line) (second directive))))
           (tm-fail "~A ~A: op ~A (line ~D) where the requested op ~A should run"
                    (tmr-kind run) (tmr-name run) (tmo-name line) (tmo-index line) (second directive)))
          ((and (not requested) (not (member op (model-plan-operators model))))
           (tm-fail "~A ~A: op ~A (line ~D) is must-ask, yet inside a plan"
                    (tmr-kind run) (tmr-name run) (tmo-name line) (tmo-index line))))
    (unless (and (model-op-applicable-p op state) (model-op-applicable-p op real))
      (tm-fail "op ~A (line ~D) starts at ~A, but its precondition is false in the state then, ~A (as planned: ~A)"
               (tmo-name line) (tmo-index line) (float (tmo-start line) 1d0) (tm-state-text context real)
               (tm-state-text context state)))
    (tm-count context :ops)
    (if (eq (mop-kind op) :macro)
        (progn (push line (tmx-macros context))
               (setf (tmr-macro run) line
                     (tmr-macro-before run) state
                     (tmr-macro-seq run) (mop-seq op)
                     (tmr-next-key run) (tm-fresh-key run)))
        (progn (push line (tmx-ops context))
               (tm-add-change context (+ (tmr-at run) duration) (mop-effects op) run line (tm-fresh-key run))
               (incf (tmr-at run) duration)
               (setf (tmr-next-key run) (tm-fresh-key run))
               (tm-op-done context run)))))

(defun tm-consume-sub-op (context run)
  "The next sub-op of RUN's macro under way; after its last, the macro's end."
  (let* ((name (first (tmr-macro-seq run)))
         (line (tm-next-line context run (format nil "sub-op ~A of macro ~A" name (tmo-name (tmr-macro run)))))
         (op (tmo-mop line))
         (duration (tm-op-duration (tmx-spec context) op)))
    (unless (eq (tmo-name line) name)
      (tm-fail "macro ~A: sub-op ~A (line ~D) where its :seq has ~A"
               (tmo-name (tmr-macro run)) (tmo-name line) (tmo-index line) name))
    (tm-check-op-line run line duration)
    (setf (tmo-macro line) (tmr-macro run))
    (push line (tmx-ops context))
    (tm-add-change context (+ (tmr-at run) duration) (mop-effects op) run line (tm-fresh-key run))
    (incf (tmr-at run) duration)
    (pop (tmr-macro-seq run))
    (if (tmr-macro-seq run)
        (setf (tmr-next-key run) (tm-fresh-key run))
        (let* ((macro (tmr-macro run))
               (mop (tmo-mop macro))
               (after (model-apply-effects mop (tmr-macro-before run)))
               ;; The variables its sub-ops or its effects touch take their
               ;; values in the state it started from with its effects.
               (touched (remove-duplicates
                         (append (mapcar #'car (mop-effects mop))
                                 (loop for sub in (mop-seq mop)
                                       append (mapcar #'car (mop-effects (model-find-op (tmx-model context) sub))))))))
          (setf (tmo-expected-end macro) (tmr-at run)
                (tmo-effective-end macro) (tmr-at run))
          ;; Tagged with the last sub-op: the macro's end goes with it.
          (setf (tmc-macro-end (tm-add-change context (tmr-at run)
                                              (loop for i in touched collect (cons i (svref after i)))
                                              run line (tm-fresh-key run)))
                t)
          (setf (tmr-macro run) nil
                (tmr-next-key run) (tm-fresh-key run))
          (tm-op-done context run)))))

(defun tm-op-done (context run)
  "A top-level op of RUN's directive is over: when it was the directive's last,
its goal must hold, and the next directive follows."
  (when (zerop (decf (tmr-remaining run)))
    (let ((directive (nth (tmr-pos run) (tmr-directives run))))
      (when (eq (first directive) :state)
        (let ((state (tm-run-state context run)))
          (unless (model-eval (second directive) state)
            (tm-fail "~A ~A: after its plan for directive ~D the goal does not hold in ~A"
                     (tmr-kind run) (tmr-name run) (tmr-pos run) (tm-state-text context state))))))
    (incf (tmr-pos run))))

(defun tm-check-result (run)
  "What SEND-EVENT returned for RUN, now that the model knows how it ended."
  (let ((result (tmr-result run)))
    (unless (eq result :none)
      (let ((expected (if (tmr-failed run) (list nil (tmr-fail-goal run)) (list t))))
        (unless (equal result expected)
          (tm-fail "send-event of ~A returned ~S; its run ~:[succeeded~;failed~] so the model expects ~S"
                   (tmr-name run) result (tmr-failed run) expected))))))

;;; The clock

(defun tm-key< (time-a key-a time-b key-b)
  (or (< time-a time-b) (and (= time-a time-b) (< key-a key-b))))

(defun tm-next-happening (context limit)
  "The first thing due by LIMIT: (TIME KEY KIND THING), KIND :STEP (a run's next
op or end), :CHANGE or :TIMER; or NIL."
  (let ((best nil))
    (flet ((consider (time key kind thing)
             (when (and (<= time limit) (or (null best) (tm-key< time key (first best) (second best))))
               (setf best (list time key kind thing)))))
      (dolist (run (tmx-active context))
        (consider (tmr-at run) (tmr-next-key run) :step run))
      (dolist (change (tmx-changes context))
        (unless (tmc-applied change)
          (consider (tmc-time change) (tmc-key change) :change change)))
      (dolist (timer (tmx-timers context))
        (when (tmts-time timer)
          (consider (tmts-time timer) (tmts-key timer) :timer timer))))
    best))

(defun tm-busy-p (context)
  "Is an event running or waiting?"
  (or (tmx-active context) (tmx-queue context)))

(defun tm-advance (context limit &key (dispatch t))
  "Play everything due by LIMIT, in time order (equal times by key): runs'
ops and ends, state changes (and the triggers they fire), timers.  The events
timers and triggers send at an instant are dispatched, in the order they went
off, once everything else due then has happened (unless DISPATCH is false:
then they wait for the advance under way)."
  (loop
    (let ((next (tm-next-happening context limit)))
      (cond ((and next (not (and dispatch (tmx-deferred context) (> (first next) (tmx-now context)))))
             (destructuring-bind (time key kind thing) next
               (declare (ignore key))
               (if (eql time (tmx-instant context))
                   (when (> (incf (tmx-instant-count context)) 20000)
                     (tm-fail "the model does not move on at time ~A" (float time 1d0)))
                   (setf (tmx-instant context) time (tmx-instant-count context) 0))
               (setf (tmx-now context) time)
               (ecase kind
                 (:change (tm-apply-change context thing))
                 (:timer (tm-fire-timer context thing))
                 (:step (tm-step context thing)
                  (when (tmr-complete thing)
                    (tm-finish-run context thing))))))
            ((and dispatch (tmx-deferred context))
             (let ((sends (tmx-deferred context)))
               (setf (tmx-deferred context) '())
               (loop for (name source) in sends
                     do (tm-dispatch context name (tmx-now context) nil :none source))))
            (t (return)))))
  (setf (tmx-now context) (max limit (tmx-now context))))

(defun tm-finish (context)
  "FINISH-EVENTS: while an event runs or waits, play everything up to the next thing due."
  (loop while (tm-busy-p context)
        do (let ((next (tm-next-happening context (expt 10 9))))
             (tm-advance context (if next (first next) (tmx-now context)))
             (unless next (return)))))

(defun tm-apply-change (context change)
  "CHANGE falls due: the state takes it, then the triggers look."
  (setf (tmc-applied change) t)
  (loop for (i . k) in (tmc-data change) do (setf (svref (tmx-state context) i) k))
  (tm-check-triggers context (tmc-time change)))

(defun tm-check-triggers (context time)
  "After a state change at TIME, each trigger whose condition went from false
to true shows (:trigger NAME :time TIME) and sends its event."
  (dolist (entry (tmx-triggers context))
    (let* ((trigger (car entry))
           (holds (model-eval (tmg-condition trigger) (tmx-state context))))
      (when (and holds (not (cdr entry)))
        (setf (cdr entry) t)
        (tm-count context :triggers)
        (tm-expect context (list :trigger (tmg-name trigger) :time time)
                   (format nil "trigger ~A's condition becoming true at ~A" (tmg-name trigger) (float time 1d0)))
        (tm-defer context (tmg-event trigger) :trigger))
      (setf (cdr entry) holds))))

(defun tm-arm-timer (context timer-state time)
  "Make TIMER-STATE go off its :after after TIME."
  (setf (tmts-time timer-state) (+ time (tmt-after (tmts-timer timer-state)))
        (tmts-key timer-state) (* (tm-new-block context) +tm-block+)))

(defun tm-fire-timer (context timer-state)
  "A timer goes off: its line, its re-arming if it repeats, its event."
  (let ((timer (tmts-timer timer-state))
        (time (tmts-time timer-state)))
    (tm-count context :timers)
    (setf (tmts-time timer-state) nil)
    (tm-expect context (list :timer (tmt-name timer) :time time)
               (format nil "timer ~A going off at ~A" (tmt-name timer) (float time 1d0)))
    (when (tmt-repeat timer)
      (tm-count context :repeats)
      (tm-arm-timer context timer-state time))
    (tm-defer context (tmt-event timer) :timer)))

(defun tm-defer (context name source)
  "Event NAME, sent now by a timer or trigger (SOURCE), waits until everything
else due now has happened."
  (setf (tmx-deferred context) (append (tmx-deferred context) (list (list name source)))))

(defun tm-finish-run (context run)
  "RUN is complete: its :fail and :state lines, then the waiting events no
running event meets start."
  (let ((end (tmr-end run)))
    (when (tmr-failed run)
      (tm-count context :fails)
      (tm-expect context (list :fail (tmr-name run) :goal (tmr-fail-goal run) :time end)
                 (format nil "~(~A~) ~A failing at ~A" (tmr-kind run) (tmr-name run) (float end 1d0))))
    (tm-expect context (list :state (copy-seq (tmx-state context)))
               (format nil "~(~A~) ~A ending at ~A" (tmr-kind run) (tmr-name run) (float end 1d0)))
    (tm-check-result run)
    (setf (tmx-active context) (remove run (tmx-active context)))
    (tm-start-waiting context end)))

(defun tm-untried-p (context)
  "Does a running event meet everything (no op on a known channel)?  Then an
event arriving is not planned on trial: it meets every running one."
  (some (lambda (run) (member (car (tmr-footprint run)) '(:all nil))) (tmx-active context)))

(defun tm-finishing-ops (context footprint &optional (time (tmx-now context)))
  "The ops of interrupted (or finished) runs, begun by NOW and still playing
after TIME, whose run's footprint meets FOOTPRINT."
  (remove-if-not (lambda (op)
                   (let ((run (tmo-run op)))
                     (and (not (member run (tmx-active context)))
                          (<= (tmo-start op) (tmx-now context))
                          (> (tmo-effective-end op) time)
                          (tm-meet-p footprint (tmr-footprint run)))))
                 (tmx-ops context)))

(defun tm-gate (context name first-step time)
  "The start gate for event NAME's run from its top-level directive FIRST-STEP
at TIME: planned from the state due then, it starts then only if its plan's
footprint meets no active run and no op of an interrupted run still playing
after TIME; with only such ops in the way, TIME becomes the latest of their
ends and it is planned again.  Returns its start time, or NIL when an active
run is in its way (every plan meets an active run that meets everything)."
  (loop
    (when (tm-untried-p context)
      (return nil))
    ;; Every change due by TIME: a run leaving the queue when another ends
    ;; starts in the middle of an instant, before the changes due then that
    ;; come after that end are applied.
    (let* ((state (tm-state-at context time))
           (footprint (tm-plan context name first-step state)))
      (when (some (lambda (run) (tm-meet-p footprint (tmr-footprint run))) (tmx-active context))
        (return nil))
      (let ((finishing (tm-finishing-ops context footprint time)))
        (unless finishing
          (return time))
        (tm-count context :after-finishing)
        (setf time (reduce #'max finishing :key #'tmo-effective-end))))))

(defun tm-start-or-wait (context name time result)
  "Event NAME's run, arriving at TIME, starts when the start gate lets it, or
waits first in the queue (SEND-EVENT then answers T) when an active run is in
its way."
  (let ((start (tm-gate context name 0 time)))
    (cond (start (tm-start-run context name :event 0 start result))
          (t (unless (member result '(:none (t)) :test #'equal)
               (tm-fail "send-event of ~A at ~A (waiting at the start gate) returned ~S, not T"
                        name (float time 1d0) result))
             (tm-count context :gate-waits)
             (push (list name :event 0 :none) (tmx-queue context))))))

(defun tm-start-waiting (context time)
  "Start the waiting runs, first first, each at TIME or when the start gate
lets it (TM-GATE), until one finds an active run in its way."
  (loop for next = (first (tmx-queue context))
        while next
        do (destructuring-bind (name kind first-step result) next
             (let ((start (tm-gate context name first-step time)))
               (unless start
                 (return))
               (when (tmx-active context)
                 (tm-count context :queue-beside))
               (pop (tmx-queue context))
               (tm-start-run context name kind first-step start result)))))

(defun tm-stop-time (context line time)
  "When op LINE, running at TIME, stops: its next interruption point."
  (let ((interrupt (gethash (tmo-name line) (tms-interrupts (tmx-spec context))))
        (start (tmo-start line))
        (end (tmo-effective-end line)))
    (cond ((eq interrupt :never) end)
          ((eq interrupt :anytime) time)
          (t (or (loop for point in interrupt
                       for at = (+ start point)
                       when (<= time at end) return at)
                 end)))))

(defun tm-first-directive-with-work (context run)
  "The first of RUN's directives from its position that would do anything from
the state at its schedule (an op, or a failure), or NIL."
  (let ((state (tm-run-state context run)))
    (loop for position from (tmr-pos run) below (length (tmr-directives run))
          for directive = (nth position (tmr-directives run))
          unless (and (eq (first directive) :state)
                      (eql 0 (tm-distance context (second directive) state)))
            return position)))

(defun tm-cut (context run time by footprint)
  "Event BY (of FOOTPRINT) cuts RUN at TIME.  Returns (VALUES START RESUME):
when BY can start as far as RUN and the runs cut before it are concerned, and
the directive RUN would resume from (NIL: nothing left of it)."
  (let* ((live (remove-if-not (lambda (op) (and (<= (tmo-start op) time) (> (tmo-effective-end op) time)))
                              (tmx-ops context)))
         (own (remove-if-not (lambda (op) (eq (tmo-run op) run)) live))
         ;; Ops of runs over (cut) that meet BY still finishing.
         (others (remove-if (lambda (op)
                              (let ((other (tmo-run op)))
                                (or (eq other run) (member other (tmx-active context))
                                    (not (tm-meet-p footprint (tmr-footprint other))))))
                            live))
         (start time)
         (shown '())
         (finishing nil)
         (macro-cut nil)
         (resume nil))
    (when (rest own)
      (tm-fail "~A ~A has ~D ops running at ~A" (tmr-kind run) (tmr-name run) (length own) (float time 1d0)))
    (dolist (op others) (setf start (max start (tmo-effective-end op))))
    (let ((op (first own)))
      (when op
        (let ((stop (tm-stop-time context op time)))
          (setf start (max start stop))
          (if (< stop (tmo-effective-end op))
              (let ((cut-effects (gethash (tmo-name op) (tms-cut-effects (tmx-spec context)))))
                (tm-count context :cut-short)
                (setf (tmo-effective-end op) stop
                      (tmo-cut op) t
                      resume (tmo-directive op)
                      macro-cut (tmo-macro op))
                (when cut-effects
                  (tm-count context :if-cut)
                  (when (= stop time) (tm-count context :if-cut-at-the-send-time))
                  ;; Made by the cut, not by RUN's plan: no run to cancel it with.
                  (tm-add-change context stop cut-effects nil op (* (tm-new-block context) +tm-block+)))
                (push op shown))
              (setf finishing op
                    macro-cut (and (tmo-macro op)
                                   (or (tmr-macro run) (not *tm-macro-completes-on-its-last-sub-op*))
                                   (tmo-macro op)))))))
    ;; Nothing of RUN due after TIME happens, but the finishing op's end.
    (setf (tmx-changes context)
          (remove-if (lambda (change)
                       (and (eq (tmc-run change) run) (> (tmc-time change) time)
                            (not (and finishing (eq (tmc-op change) finishing)
                                      (or (not (tmc-macro-end change)) (not macro-cut))))))
                     (tmx-changes context)))
    (when macro-cut
      (tm-count context :macro-cuts)
      (setf (tmo-expected-end macro-cut) start
            (tmo-effective-end macro-cut) start))
    (unless resume
      (setf resume (cond (macro-cut (tmo-directive macro-cut))
                         ((plusp (tmr-remaining run)) (tmr-pos run))
                         (t (tm-first-directive-with-work context run)))))
    (setf (tmr-cut run) t (tmr-macro run) nil
          ;; RUN is over when its own op is (not when BY may start: that
          ;; waits for earlier runs' ops too).
          (tmr-end run) (reduce #'max own :key #'tmo-effective-end :initial-value time)
          (tmx-active context) (remove run (tmx-active context)))
    (if shown
        (dolist (op shown)
          (tm-expect context (list :cut (tmo-name op) :time (tmo-effective-end op) :by by)
                     (format nil "~A cutting op ~A of ~A at ~A" by (tmo-name op) (tmr-name run) (float time 1d0))))
        (tm-expect context (list :cut (and finishing (tmo-name finishing)) :time start :by by)
                   (format nil "~A cutting ~A at ~A (no op stopped short)" by (tmr-name run) (float time 1d0))))
    (values start resume)))

(defun tm-dispatch (context name time given-policy result source)
  "Event NAME arrives at TIME from SOURCE (:USER, :TIMER or :TRIGGER) with
:when-busy GIVEN-POLICY (or none); RESULT is what SEND-EVENT returned (:NONE
when no one asked)."
  (let* ((spec (tmx-spec context))
         (policy (or given-policy
                     (gethash name (tms-event-policies spec))
                     (tms-default-policy spec)
                     :queue))
         ;; Its trial plan, from the state now (none when a running event
         ;; meets everything anyway): what it would do if it started now.
         (untried (tm-untried-p context))
         (trial (and (tmx-active context) (not untried)
                     (tm-plan context name 0 (tmx-state context))))
         (footprint (or trial '(:all)))
         (met (if untried
                  (tmx-active context)
                  (remove-if-not (lambda (run) (tm-meet-p footprint (tmr-footprint run))) (tmx-active context)))))
    ;; Timers it restarts.
    (dolist (timer (tmx-timers context))
      (let ((restart-on (tmt-restart-on (tmts-timer timer))))
        (when (if (eq restart-on :any) (eq source :user) (member name restart-on))
          (tm-count context :timer-restarts)
          (tm-arm-timer context timer time))))
    (cond ((null (tmx-active context))
           (tm-count context :idle)
           (tm-start-or-wait context name time result))
          ((null met)
           (tm-count context :parallel)
           (tm-start-or-wait context name time result))
          (t
           (when (eq source :user) (tm-count context :busy))
           (tm-count context policy)
           (ecase policy
             (:queue
              (unless (member result '(:none (t)) :test #'equal)
                (tm-fail "send-event of ~A at ~A (queued) returned ~S, not T" name (float time 1d0) result))
              (setf (tmx-queue context) (append (tmx-queue context) (list (list name :event 0 :none)))))
             (:override
              (unless (member result '(:none (nil :dropped)) :test #'equal)
                (tm-fail "send-event of ~A at ~A (dropped) returned ~S, not NIL :DROPPED" name (float time 1d0) result))
              (tm-expect context (list :dropped name :time time :busy-with (tmr-name (first met)))
                         (format nil "~A sent at ~A while ~A runs, :override" name (float time 1d0) (tmr-name (first met)))))
             ((:preempt :interleave)
              (when (rest met) (tm-count context :multi-cuts))
              (let ((start time) (resumptions '()))
                (dolist (run met)
                  (multiple-value-bind (at resume) (tm-cut context run time name footprint)
                    (setf start (max start at))
                    (when (and (eq policy :interleave) resume)
                      (push (list (tmr-name run) :resume resume :none) resumptions))))
                ;; What falls due now happens before the newcomer plans (the
                ;; events timers and triggers send then wait for the
                ;; dispatching that is under way).
                (tm-advance context time :dispatch nil)
                (setf (tmx-queue context) (append (nreverse resumptions) (tmx-queue context)))
                ;; Its plan from the state the cuts leave passes the start
                ;; gate: it may wait, first, ahead of the runs it interrupted.
                (tm-start-or-wait context name start result))))))))

(defun tm-send (context name time given-policy result)
  "Event NAME sent at TIME with :when-busy GIVEN-POLICY (or none); RESULT is
what SEND-EVENT returned."
  (tm-advance context time)
  (tm-count context :sends)
  (tm-dispatch context name time given-policy result :user))

(defun tm-attribute (context lines)
  "Read LINES: the control lines in order, and the op lines (which the runs of
the model take as they play, see TM-NEXT-LINE)."
  (let ((model (tmx-model context))
        (control '())
        (ops '()))
    (loop for line in lines
          for index from 0
          do (case (first line)
               ((:event :resume :dropped :cut :fail :state :timer :trigger)
                (push (cons index line) control))
               (:op
                (let ((op (model-find-op model (second line))))
                  (unless op (tm-fail "line ~D: ~S is not an op of the spec" index line))
                  (push (make-tm-op :name (second line) :mop op :index index
                                    :start (rational (getf (cddr line) :start))
                                    :end (rational (getf (cddr line) :end)))
                        ops)))
               ((:autoscript-start :autoscript-stop))
               (t (tm-fail "line ~D: unexpected trace line ~S" index line))))
    (setf (tmx-op-lines context) (nreverse ops)
          (tmx-control context) (nreverse control))))

(defun tm-check-overlaps (context)
  "Ops that share a channel (one with none shares every one) never overlap in
time; two runs overlap only when their footprints do not meet."
  (let ((ops (sort (copy-list (tmx-ops context)) #'< :key #'tmo-index)))
    (loop for (a . rest) on ops
          for channels-a = (tm-op-channels context (tmo-name a))
          do (dolist (b rest)
               (let ((channels-b (tm-op-channels context (tmo-name b))))
                 (when (and (or (eq channels-a :all) (eq channels-b :all)
                                (intersection channels-a channels-b :test #'string=))
                            (< (tmo-start a) (tmo-effective-end b))
                            (< (tmo-start b) (tmo-effective-end a)))
                   (tm-fail "op ~A (line ~D, ~A to ~A) and op ~A (line ~D, ~A to ~A) overlap on channels ~A and ~A"
                            (tmo-name a) (tmo-index a) (float (tmo-start a) 1d0) (float (tmo-effective-end a) 1d0)
                            (tmo-name b) (tmo-index b) (float (tmo-start b) 1d0) (float (tmo-effective-end b) 1d0)
                            channels-a channels-b))))))
  (let ((runs (reverse (tmx-runs context))))
    (loop for (a . rest) on runs
          do (dolist (b rest)
               (when (and (tmr-end a) (tmr-end b)
                          (< (max (tmr-start a) (tmr-start b)) (min (tmr-end a) (tmr-end b))))
                 (tm-count context :overlapping-runs)
                 (when (tm-meet-p (tmr-footprint a) (tmr-footprint b))
                   (tm-fail "~(~A~) ~A (~A to ~A) and ~(~A~) ~A (~A to ~A) overlap, but their footprints meet"
                            (tmr-kind a) (tmr-name a) (float (tmr-start a) 1d0) (float (tmr-end a) 1d0)
                            (tmr-kind b) (tmr-name b) (float (tmr-start b) 1d0) (float (tmr-end b) 1d0))))))))

(defvar *tm-tolerate-crossing-macro-lines* nil
  "When true, the model does not check the :end of macro lines whose spans
cross a macro of another event playing beside them.  NIL: they are checked (the
trace presenter once closed macro lines last-opened-first and gave each the
other's :end; it now closes the line of the macro that ended).")

(defun tm-crossing-macro-p (context macro)
  "Does MACRO's span overlap that of a macro of another run?"
  (let ((end (or (tmo-expected-end macro) (tmo-end macro))))
    (some (lambda (other)
            (let ((other-end (or (tmo-expected-end other) (tmo-end other))))
              (and (not (eq other macro)) (not (eq (tmo-run other) (tmo-run macro)))
                   (< (max (tmo-start macro) (tmo-start other)) (min end other-end)))))
          (tmx-macros context))))

(defun tm-replay (spec actions initial play &key predecessors)
  "Check PLAY (what the controller did with ACTIONS from INITIAL) against the
model.  Returns (VALUES PROBLEM STATISTICS): PROBLEM NIL or a string."
  (when (tmp-abandoned play)
    (return-from tm-replay (values nil (list (tmp-abandoned play) 1))))
  (let* ((model (tms-model spec))
         (context (make-tm-context :spec spec :model model :initial initial
                                   :state (copy-seq initial)
                                   :predecessors (or predecessors (reference-predecessors model)))))
    (setf (tmx-timers context) (loop for timer in (tms-timers spec)
                                     collect (make-tm-timer-state :timer timer))
          (tmx-triggers context) (loop for trigger in (tms-triggers spec)
                                       collect (cons trigger (model-eval (tmg-condition trigger) initial))))
    (dolist (timer (tmx-timers context))
      (tm-arm-timer context timer 0))
    (values
     (catch 'tm-problem
       (tm-attribute context (tmp-lines play))
       (let ((results (tmp-results play))
             (checks (tmp-checks play)))
         (flet ((check (time)
                  (destructuring-bind (alist busy) (pop checks)
                    (tm-advance context time)
                    (tm-count context :checks)
                    (let ((state (tmx-state context)))
                      (unless (equalp state (model-state-from-alist model alist))
                        (tm-fail "at the checkpoint ~A the controller's state is ~A; the model's ~A"
                                 (float time 1d0) (tm-state-text context (model-state-from-alist model alist))
                                 (tm-state-text context state))))
                    (unless (eq (and busy t) (and (tm-busy-p context) t))
                      (tm-fail "at the checkpoint ~A controller-busy-p says ~S; the model says ~:[idle~;busy~]"
                               (float time 1d0) busy (tm-busy-p context))))))
           (dolist (action actions)
             (ecase (first action)
               (:send (destructuring-bind (name time policy) (rest action)
                        (tm-send context name time policy (pop results))))
               (:check (check (second action)))
               (:settle (dolist (time (tmp-settle-times play))
                          (tm-count context :settles)
                          (check time))))))
         (tm-finish context)
         (when (tm-busy-p context)
           (tm-fail "after finish-events the model still runs ~A"
                    (mapcar #'tmr-name (tmx-active context))))
         (when (tmp-final-busy play)
           (tm-fail "controller-busy-p is true after finish-events"))
         (let ((extra (nth (tmx-cursor context) (tmx-control context))))
           (when extra
             (tm-fail "the trace goes on with ~A (line ~D), which the model does not expect"
                      (tm-show-line context (cdr extra)) (car extra))))
         (let ((stray (find-if-not #'tmo-claimed (tmx-op-lines context))))
           (when stray
             (tm-fail "the trace shows op ~A (line ~D, from ~A), which no run of the model plays"
                      (tmo-name stray) (tmo-index stray) (float (tmo-start stray) 1d0))))
         (let ((final (tmx-state context)))
           (unless (equalp final (model-state-from-alist model (tmp-final-state play)))
             (tm-fail "the final state is ~A; the model's ~A"
                      (tm-state-text context (model-state-from-alist model (tmp-final-state play)))
                      (tm-state-text context final))))
         (tm-check-overlaps context)
         ;; A macro's line ends when its :seq did, or where it was cut.
         (dolist (macro (tmx-macros context))
           (let ((line (nth (tmo-index macro) (tmp-lines play))))
             (unless (or (and (tmo-expected-end macro) (= (getf (cddr line) :end) (tmo-expected-end macro)))
                         (and *tm-tolerate-crossing-macro-lines*
                              (tm-crossing-macro-p context macro)
                              (tm-count context :crossing-macro-lines)))
               (tm-fail "macro ~A (line ~D) is shown ending at ~A; the model says ~A"
                        (tmo-name macro) (tmo-index macro) (getf (cddr line) :end)
                        (and (tmo-expected-end macro) (float (tmo-expected-end macro) 1d0))))))
         nil))
     (tmx-statistics context))))
