;;;; test-timeline-model.lisp -- the timed controller (src/runtime/timeline/)
;;;; against an independent reference model, on random specs and random timed
;;;; event streams.
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
;;;;    and starts the moment the running event ends; :override gives
;;;;    (:dropped EV :time T :busy-with RUNNING); :preempt and :interleave stop
;;;;    the op running at T at its next interruption point (:never its end,
;;;;    :anytime T, (:at P...) the first start+P in [T, end], else its end), with
;;;;    (:cut OP :time STOP :by EV) for an op stopped short -- which then has
;;;;    its :if-cut effects at STOP instead of its own -- or one (:cut OP-OR-NIL
;;;;    :time TC :by EV) when none is; the rest of the interrupted event never
;;;;    happens; EV starts at TC, the latest of T, those stops and the ends of
;;;;    ops of earlier events still finishing; :interleave then resumes the
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

(def-suite* timeline-model :in player-tests)

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

(defstruct (tm-spec (:conc-name tms-))
  "A random spec with timing: its forms, its RANDOM-SPEC model, and what the
model adds (durations, interruption, policies)."
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
  (default-policy nil))

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

(defun tm-random-spec (seed)
  "The TM-SPEC for SEED: RANDOM-SPEC's spec and events plus TM-EVENT-GENERATOR's,
then (from a PRNG of its own) every plain op's :duration, :interrupt and
sometimes :if-cut, some events' (:when-busy P) and sometimes the spec's."
  (multiple-value-bind (forms model)
      (random-spec seed :name (rs-symbol "timeline-model-~D" seed)
                        :max-variables 5 :max-states 256 :op-event-count 3
                        :event-generator #'tm-event-generator)
    (let ((prng (make-rs-prng (+ 104729 seed)))
          (spec (make-tm-spec :seed seed :model model)))
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
              (setf (gethash name (tms-cut-effects spec)) (random-effects prng model))))))
      (dolist (event (model-events model))
        (when (rs-chance prng 0.5)
          (setf (gethash (mevent-name event) (tms-event-policies spec)) (rs-pick prng *tm-policies*))))
      (when (rs-chance prng 0.5)
        (setf (tms-default-policy spec) (rs-pick prng *tm-policies*)))
      (setf (tms-forms spec) (tm-decorate-forms spec forms))
      spec)))

(defun tm-form-kind-p (form kind)
  "Is FORM a spec form whose head is named KIND (a string)?"
  (and (consp form) (symbolp (first form)) (string= (symbol-name (first form)) kind)))

(defun tm-decorate-forms (spec forms)
  "FORMS with SPEC's timing: :duration, :interrupt, :if-cut on the ops,
(:when-busy P) on events and, when SPEC has a default, as a spec option."
  (let ((model (tms-model spec)))
    (append
     (when (tms-default-policy spec)
       (list (list :when-busy (tms-default-policy spec))))
     (loop for form in forms
           collect (cond ((tm-form-kind-p form "OP")
                          (let* ((name (second form))
                                 (interrupt (gethash name (tms-interrupts spec)))
                                 (cut (gethash name (tms-cut-effects spec))))
                            (append form
                                    (list :duration (float (gethash name (tms-durations spec))))
                                    (cond ((eq interrupt :never) '())
                                          ((eq interrupt :anytime) (list :interrupt :anytime))
                                          (t (list :interrupt (cons :at (mapcar #'float interrupt)))))
                                    (when cut
                                      (list :if-cut (render-effect-options model cut))))))
                         ((and (tm-form-kind-p form "EVENT")
                               (gethash (second form) (tms-event-policies spec)))
                          (list* (first form) (second form)
                                 (list :when-busy (gethash (second form) (tms-event-policies spec)))
                                 (cddr form)))
                         (t form))))))

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
between sends are short (0 to 3 s), half long (40 s and more)."
  (let* ((prng (make-rs-prng (+ (* 1000 seed) stream 7)))
         (model (tms-model spec))
         (events (model-events model))
         (initial (model-index-state model (rs-below prng (model-state-count model))))
         (time 0)
         (actions '()))
    (loop repeat (rs-between prng 6 14)
          do (push (list :send (mevent-name (rs-pick prng events)) time
                         (if (rs-chance prng 0.35) nil (rs-pick prng *tm-policies*)))
                   actions)
             (let ((gap (if (rs-chance prng 0.85)
                            (/ (rs-pick prng '(0 0 1 1 2 2 3 4 6 8)) 8)
                            (+ 40 (rs-below prng 20)))))
               (when (and (plusp gap) (rs-chance prng 0.4))
                 (push (list :check (+ time (* gap (/ (rs-between prng 1 4) 4)))) actions))
               (incf time gap)))
    (values (nreverse actions) initial)))

;;;# Playing a stream on the timed controller

(defstruct (tm-play (:conc-name tmp-))
  "What the controller did with a stream."
  lines
  ;; Per send, the list of values SEND-EVENT returned.
  results
  ;; Per :check, (STATE-ALIST BUSY-P).
  checks
  final-state final-busy)

(defun tm-play-stream (machine spec actions initial)
  "Play ACTIONS on a fresh timed controller of MACHINE from INITIAL, then FINISH-EVENTS."
  (let* ((model (tms-model spec))
         (presenter (make-trace-presenter))
         (controller (make-controller machine :timed t :presenter presenter
                                              :initial-state (model-state-alist model initial)))
         (results '()) (checks '()))
    (dolist (action actions)
      (ecase (first action)
        (:send (destructuring-bind (event time policy) (rest action)
                 (push (multiple-value-list
                        (if policy
                            (send-event controller event :at (float time 1d0) :when-busy policy)
                            (send-event controller event :at (float time 1d0))))
                       results)))
        (:check (advance controller (float (second action) 1d0))
         (push (list (controller-state controller) (controller-busy-p controller)) checks))))
    (finish-events controller)
    (make-tm-play :lines (trace-lines presenter) :results (nreverse results) :checks (nreverse checks)
                  :final-state (controller-state controller)
                  :final-busy (controller-busy-p controller))))

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
  (cut nil))

(defstruct (tm-change (:conc-name tmc-))
  "A state change at TIME: KIND :EFFECTS (DATA an effects alist) or :SET (DATA
a whole state vector); RUN and OP that made it."
  time kind data run op)

(defstruct (tm-run (:conc-name tmr-))
  "An event's run as the model plays it: the directives still to do and the
op lines the trace attributes to it."
  name kind start directives
  ;; Absolute index of the directive under way, ops it still needs.
  (pos 0) (remaining 0)
  ;; When its next op starts (its schedule).
  at
  ;; Its op lines not yet consumed, oldest first.
  ops
  ;; The macro under way: its TM-OP, the state it started from, its sub-ops to come.
  macro macro-before macro-seq
  complete end failed fail-goal cut
  ;; What SEND-EVENT returned when this run started from a send, or :NONE.
  (result :none))

(defstruct (tm-context (:conc-name tmx-))
  "The model's replay of one stream."
  spec model initial predecessors
  (distances (make-hash-table :test 'equal))
  ;; TM-CHANGEs, newest first.
  (changes '())
  ;; Every plain op and sub-op consumed, newest first.
  (ops '())
  ;; Every macro consumed.
  (macros '())
  ;; The control lines of the trace (:event :resume :dropped :cut :fail :state)
  ;; as (INDEX . LINE), and the next to match.
  control (cursor 0)
  ;; Event/resume line index -> its op lines (TM-OPs), oldest first.
  (attribution (make-hash-table))
  (runs '())
  current
  ;; Waiting runs: (NAME KIND FIRST-STEP RESULT).
  (queue '())
  statistics)

(defun tm-fail (control &rest arguments)
  "Stop the replay: the trace disagrees with the model."
  (throw 'tm-problem (apply #'format nil control arguments)))

(defun tm-count (context key &optional (n 1))
  "Count N more cases of KEY in CONTEXT's statistics."
  (incf (getf (tmx-statistics context) key 0) n))

(defun tm-state-at (context time)
  "The model's state at TIME: the initial state with every change due by TIME
applied in time order (equal times in the order the model made them)."
  (let ((state (copy-seq (tmx-initial context))))
    (dolist (change (stable-sort (remove-if (lambda (change) (> (tmc-time change) time))
                                            (reverse (tmx-changes context)))
                                 #'< :key #'tmc-time))
      (ecase (tmc-kind change)
        (:effects (loop for (i . k) in (tmc-data change) do (setf (svref state i) k)))
        (:set (replace state (tmc-data change)))))
    state))

(defun tm-add-change (context time kind data run op)
  "Note a TM-CHANGE (see there) in CONTEXT; return it."
  (let ((change (make-tm-change :time time :kind kind :data data :run run :op op)))
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
         (run (make-tm-run :name name :kind kind :start time :at time
                           :directives (mevent-directives event)
                           :pos first-step
                           :ops (gethash index (tmx-attribution context))
                           :result result)))
    (push run (tmx-runs context))
    (when (eq kind :resume) (tm-count context :resumed))
    (setf (tmx-current context) run)))

(defun tm-walk (context run limit)
  "Play RUN as far as LIMIT: consume its op lines starting by then, begin its
directives due by then, and note when it is complete."
  (loop
    (when (or (tmr-complete run) (tmr-cut run) (> (tmr-at run) limit))
      (return))
    (cond ((tmr-macro run) (tm-consume-sub-op context run))
          ((plusp (tmr-remaining run)) (tm-consume-op context run))
          ((>= (tmr-pos run) (length (tmr-directives run)))
           (setf (tmr-complete run) t (tmr-end run) (tmr-at run)))
          (t (tm-begin-directive context run)))))

(defun tm-begin-directive (context run)
  "Work out how many ops RUN's next directive takes, from the state at its start."
  (let* ((directive (nth (tmr-pos run) (tmr-directives run)))
         (state (tm-state-at context (tmr-at run)))
         (distance (tm-distance context (tm-directive-goal context directive) state)))
    (cond ((null distance)
           (setf (tmr-failed run) t
                 (tmr-fail-goal run) (tm-directive-goal-form context directive)
                 (tmr-complete run) t
                 (tmr-end run) (tmr-at run)))
          ((eq (first directive) :op) (setf (tmr-remaining run) (1+ distance)))
          ((zerop distance) (incf (tmr-pos run)))
          (t (setf (tmr-remaining run) distance)))))

(defun tm-next-line (run what)
  "RUN's next op line, which the model expects to be WHAT."
  (or (pop (tmr-ops run))
      (tm-fail "~A ~A (from ~A): the model expects ~A at ~A, but the trace shows no more ops of it"
               (tmr-kind run) (tmr-name run) (float (tmr-start run) 1d0) what (float (tmr-at run) 1d0))))

(defun tm-check-op-line (run line duration)
  "LINE must start at RUN's schedule and last DURATION."
  (unless (= (tmo-start line) (tmr-at run))
    (tm-fail "~A ~A: op ~A (line ~D) starts at ~A; the previous one ended at ~A"
             (tmr-kind run) (tmr-name run) (tmo-name line) (tmo-index line)
             (tmo-start line) (float (tmr-at run) 1d0)))
  (unless (or (eq (mop-kind (tmo-mop line)) :macro) (= (tmo-end line) (+ (tmo-start line) duration)))
    (tm-fail "op ~A (line ~D) is shown ending at ~A; it starts at ~A and lasts ~A"
             (tmo-name line) (tmo-index line) (tmo-end line) (tmo-start line) (float duration 1d0)))
  (setf (tmo-run line) run
        (tmo-directive line) (tmr-pos run)
        (tmo-effective-end line) (+ (tmr-at run) duration)))

(defun tm-consume-op (context run)
  "RUN's next plan op (or the requested op of an (:op X) directive)."
  (let* ((line (tm-next-line run "a plan op"))
         (model (tmx-model context))
         (op (tmo-mop line))
         (directive (nth (tmr-pos run) (tmr-directives run)))
         (requested (and (eq (first directive) :op) (= 1 (tmr-remaining run))))
         (state (tm-state-at context (tmr-at run)))
         (duration (tm-op-duration (tmx-spec context) op)))
    (tm-check-op-line run line duration)
    (cond ((and requested (not (eq (tmo-name line) (second directive))))
           (tm-fail "~A ~A: op ~A (line ~D) where the requested op ~A should run"
                    (tmr-kind run) (tmr-name run) (tmo-name line) (tmo-index line) (second directive)))
          ((and (not requested) (not (member op (model-plan-operators model))))
           (tm-fail "~A ~A: op ~A (line ~D) is must-ask, yet inside a plan"
                    (tmr-kind run) (tmr-name run) (tmo-name line) (tmo-index line))))
    (unless (model-op-applicable-p op state)
      (tm-fail "op ~A (line ~D) starts at ~A, but its precondition is false in the state then, ~A"
               (tmo-name line) (tmo-index line) (tmo-start line) (tm-state-text context state)))
    (tm-count context :ops)
    (if (eq (mop-kind op) :macro)
        (progn (push line (tmx-macros context))
               (setf (tmr-macro run) line
                     (tmr-macro-before run) state
                     (tmr-macro-seq run) (mop-seq op)))
        (progn (push line (tmx-ops context))
               (tm-add-change context (+ (tmr-at run) duration) :effects (mop-effects op) run line)
               (incf (tmr-at run) duration)
               (tm-op-done context run)))))

(defun tm-consume-sub-op (context run)
  "The next sub-op of RUN's macro under way; after its last, the macro's end."
  (let* ((name (first (tmr-macro-seq run)))
         (line (tm-next-line run (format nil "sub-op ~A of macro ~A" name (tmo-name (tmr-macro run)))))
         (op (tmo-mop line))
         (duration (tm-op-duration (tmx-spec context) op)))
    (unless (eq (tmo-name line) name)
      (tm-fail "macro ~A: sub-op ~A (line ~D) where its :seq has ~A"
               (tmo-name (tmr-macro run)) (tmo-name line) (tmo-index line) name))
    (tm-check-op-line run line duration)
    (setf (tmo-macro line) (tmr-macro run))
    (push line (tmx-ops context))
    (tm-add-change context (+ (tmr-at run) duration) :effects (mop-effects op) run line)
    (incf (tmr-at run) duration)
    (pop (tmr-macro-seq run))
    (unless (tmr-macro-seq run)
      (let ((macro (tmr-macro run)))
        (setf (tmo-expected-end macro) (tmr-at run)
              (tmo-effective-end macro) (tmr-at run))
        ;; Tagged with the last sub-op: the macro's end goes with it.
        (tm-add-change context (tmr-at run) :set
                       (model-apply-effects (tmo-mop macro) (tmr-macro-before run)) run line)
        (setf (tmr-macro run) nil)
        (tm-op-done context run)))))

(defun tm-op-done (context run)
  "A top-level op of RUN's directive is over: when it was the directive's last,
its goal must hold, and the next directive follows."
  (when (zerop (decf (tmr-remaining run)))
    (let ((directive (nth (tmr-pos run) (tmr-directives run))))
      (when (eq (first directive) :state)
        (let ((state (tm-state-at context (tmr-at run))))
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

(defun tm-advance (context time)
  "Play everything due by TIME: the running event's ops, its end (a :fail and
a :state line), the waiting events starting."
  (loop
    (let ((run (tmx-current context)))
      (unless run (return))
      (tm-walk context run time)
      (unless (tmr-complete run) (return))
      (let ((end (tmr-end run)))
        (when (tmr-failed run)
          (tm-count context :fails)
          (tm-expect context (list :fail (tmr-name run) :goal (tmr-fail-goal run) :time end)
                     (format nil "~(~A~) ~A failing at ~A" (tmr-kind run) (tmr-name run) (float end 1d0))))
        (tm-expect context (list :state (tm-state-at context end))
                   (format nil "~(~A~) ~A ending at ~A" (tmr-kind run) (tmr-name run) (float end 1d0)))
        (tm-check-result run)
        (setf (tmx-current context) nil)
        (when (tmx-queue context)
          (destructuring-bind (name kind first-step result) (pop (tmx-queue context))
            (tm-start-run context name kind first-step end result)))))))

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
  (let ((state (tm-state-at context (tmr-at run))))
    (loop for position from (tmr-pos run) below (length (tmr-directives run))
          for directive = (nth position (tmr-directives run))
          unless (and (eq (first directive) :state)
                      (eql 0 (tm-distance context (second directive) state)))
            return position)))

(defun tm-cut (context run time by)
  "Event BY cuts RUN at TIME.  Returns (VALUES START RESUME): when BY starts,
and the directive RUN would resume from (NIL: nothing left of it)."
  (let* ((live (remove-if-not (lambda (op) (and (<= (tmo-start op) time) (> (tmo-effective-end op) time)))
                              (tmx-ops context)))
         (own (remove-if-not (lambda (op) (eq (tmo-run op) run)) live))
         (others (remove run live :key #'tmo-run))
         (start time)
         (shown '())
         (finishing nil)
         (macro-cut nil)
         (resume nil))
    (when (rest own)
      (tm-fail "~A ~A has ~D ops running at ~A" (tmr-kind run) (tmr-name run) (length own) time))
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
                  (tm-add-change context stop :effects cut-effects nil op))
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
                                      (or (eq (tmc-kind change) :effects) (not macro-cut))))))
                     (tmx-changes context)))
    (when macro-cut
      (tm-count context :macro-cuts)
      (setf (tmo-expected-end macro-cut) start
            (tmo-effective-end macro-cut) start))
    (unless resume
      (setf resume (cond (macro-cut (tmo-directive macro-cut))
                         ((plusp (tmr-remaining run)) (tmr-pos run))
                         (t (tm-first-directive-with-work context run)))))
    (setf (tmr-cut run) t (tmr-macro run) nil)
    (when (tmr-ops run)
      (tm-fail "~A ~A, cut at ~A by ~A, still shows op ~A (line ~D) afterwards"
               (tmr-kind run) (tmr-name run) (float time 1d0) by
               (tmo-name (first (tmr-ops run))) (tmo-index (first (tmr-ops run)))))
    (if shown
        (dolist (op shown)
          (tm-expect context (list :cut (tmo-name op) :time (tmo-effective-end op) :by by)
                     (format nil "~A cutting op ~A of ~A at ~A" by (tmo-name op) (tmr-name run) (float time 1d0))))
        (tm-expect context (list :cut (and finishing (tmo-name finishing)) :time start :by by)
                   (format nil "~A cutting ~A at ~A (no op stopped short)" by (tmr-name run) (float time 1d0))))
    (values start resume)))

(defun tm-send (context name time given-policy result)
  "Event NAME sent at TIME with :when-busy GIVEN-POLICY (or none); RESULT is
what SEND-EVENT returned."
  (tm-advance context time)
  (tm-count context :sends)
  (let* ((spec (tmx-spec context))
         (policy (or given-policy
                     (gethash name (tms-event-policies spec))
                     (tms-default-policy spec)
                     :queue))
         (run (tmx-current context)))
    (cond ((null run)
           (tm-count context :idle)
           (tm-start-run context name :event 0 time result))
          (t
           (tm-count context :busy)
           (tm-count context policy)
           (ecase policy
             (:queue
              (unless (equal result '(t))
                (tm-fail "send-event of ~A at ~A (queued) returned ~S, not T" name (float time 1d0) result))
              (setf (tmx-queue context) (append (tmx-queue context) (list (list name :event 0 :none)))))
             (:override
              (unless (equal result '(nil :dropped))
                (tm-fail "send-event of ~A at ~A (dropped) returned ~S, not NIL :DROPPED" name (float time 1d0) result))
              (tm-expect context (list :dropped name :time time :busy-with (tmr-name run))
                         (format nil "~A sent at ~A while ~A runs, :override" name (float time 1d0) (tmr-name run))))
             ((:preempt :interleave)
              (multiple-value-bind (start resume) (tm-cut context run time name)
                (setf (tmx-current context) nil)
                (when (and (eq policy :interleave) resume)
                  (push (list (tmr-name run) :resume resume :none) (tmx-queue context)))
                (tm-start-run context name :event 0 start result))))))))

(defun tm-attribute (context lines)
  "Read LINES: the control lines in order, and each op line given to the
event or resume line before it."
  (let ((model (tmx-model context))
        (owner nil)
        (control '()))
    (loop for line in lines
          for index from 0
          do (case (first line)
               ((:event :resume :dropped :cut :fail :state)
                (push (cons index line) control)
                (when (member (first line) '(:event :resume))
                  (setf owner index)
                  (setf (gethash index (tmx-attribution context)) '())))
               (:op
                (let ((op (model-find-op model (second line))))
                  (unless op (tm-fail "line ~D: ~S is not an op of the spec" index line))
                  (unless owner (tm-fail "line ~D: op ~S before any event" index line))
                  (push (make-tm-op :name (second line) :mop op :index index
                                    :start (rational (getf (cddr line) :start))
                                    :end (rational (getf (cddr line) :end)))
                        (gethash owner (tmx-attribution context)))))
               ((:autoscript-start :autoscript-stop))
               (t (tm-fail "line ~D: unexpected trace line ~S" index line))))
    (maphash (lambda (key ops) (setf (gethash key (tmx-attribution context)) (reverse ops)))
             (tmx-attribution context))
    (setf (tmx-control context) (nreverse control))))

(defun tm-replay (spec actions initial play &key predecessors)
  "Check PLAY (what the controller did with ACTIONS from INITIAL) against the
model.  Returns (VALUES PROBLEM STATISTICS): PROBLEM NIL or a string."
  (let* ((model (tms-model spec))
         (context (make-tm-context :spec spec :model model :initial initial
                                   :predecessors (or predecessors (reference-predecessors model)))))
    (values
     (catch 'tm-problem
       (tm-attribute context (tmp-lines play))
       (let ((results (tmp-results play))
             (checks (tmp-checks play)))
         (dolist (action actions)
           (ecase (first action)
             (:send (destructuring-bind (name time policy) (rest action)
                      (tm-send context name time policy (pop results))))
             (:check (let ((time (second action)))
                       (destructuring-bind (alist busy) (pop checks)
                         (tm-advance context time)
                         (tm-count context :checks)
                         (let ((state (tm-state-at context time)))
                           (unless (equalp state (model-state-from-alist model alist))
                             (tm-fail "at the checkpoint ~A the controller's state is ~A; the model's ~A"
                                      (float time 1d0) (tm-state-text context (model-state-from-alist model alist))
                                      (tm-state-text context state))))
                         (unless (eq (and busy t) (and (tmx-current context) t))
                           (tm-fail "at the checkpoint ~A controller-busy-p says ~S; the model says ~:[idle~;busy~]"
                                    (float time 1d0) busy (tmx-current context))))))))
         (tm-advance context (expt 10 9))
         (when (tmx-current context)
           (tm-fail "after finish-events the model still runs ~A" (tmr-name (tmx-current context))))
         (when (tmp-final-busy play)
           (tm-fail "controller-busy-p is true after finish-events"))
         (let ((extra (nth (tmx-cursor context) (tmx-control context))))
           (when extra
             (tm-fail "the trace goes on with ~A (line ~D), which the model does not expect"
                      (tm-show-line context (cdr extra)) (car extra))))
         (dolist (run (tmx-runs context))
           (when (tmr-ops run)
             (tm-fail "~A ~A shows op ~A (line ~D), which the model does not expect"
                      (tmr-kind run) (tmr-name run) (tmo-name (first (tmr-ops run))) (tmo-index (first (tmr-ops run))))))
         (let ((final (tm-state-at context (expt 10 9))))
           (unless (equalp final (model-state-from-alist model (tmp-final-state play)))
             (tm-fail "the final state is ~A; the model's ~A"
                      (tm-state-text context (model-state-from-alist model (tmp-final-state play)))
                      (tm-state-text context final))))
         ;; One channel: no op starts before the one shown before it ended.
         (let ((previous nil))
           (dolist (op (sort (copy-list (tmx-ops context)) #'< :key #'tmo-index))
             (when (and previous (< (tmo-start op) (tmo-effective-end previous)))
               (tm-fail "op ~A (line ~D) starts at ~A, while op ~A (line ~D) runs until ~A"
                        (tmo-name op) (tmo-index op) (float (tmo-start op) 1d0)
                        (tmo-name previous) (tmo-index previous) (float (tmo-effective-end previous) 1d0)))
             (setf previous op)))
         ;; A macro's line ends when its :seq did, or where it was cut.
         (dolist (macro (tmx-macros context))
           (let ((line (nth (tmo-index macro) (tmp-lines play))))
             (unless (and (tmo-expected-end macro) (= (getf (cddr line) :end) (tmo-expected-end macro)))
               (tm-fail "macro ~A (line ~D) is shown ending at ~A; the model says ~A"
                        (tmo-name macro) (tmo-index macro) (getf (cddr line) :end)
                        (and (tmo-expected-end macro) (float (tmo-expected-end macro) 1d0))))))
         nil))
     (tmx-statistics context))))

;;;# Running the cases

(defun tm-describe-stream (spec stream actions initial play problem)
  "A failure message a human can reproduce from."
  (let ((*package* (find-package '#:player-user))
        (*print-pretty* nil)
        (model (tms-model spec)))
    (format nil "spec seed ~D, stream ~D: ~A~%  reproduce: (player-tests::tm-check-stream ~D ~D), or (player-tests::tm-show-stream ~D ~D)~%  initial state: ~A~%  stream:~{~%    ~S~}~%  trace:~:{~%    ~D ~A~}~%  spec:~{~%    ~S~}"
            (tms-seed spec) stream problem (tms-seed spec) stream (tms-seed spec) stream
            (state-text model initial)
            (mapcar (lambda (action) (mapcar (lambda (x) (if (rationalp x) (float x 1d0) x)) action)) actions)
            (and play (loop for line in (tmp-lines play) for i from 0
                            collect (list i (trace-line-string line))))
            (tms-forms spec))))

(defun tm-merge-statistics (totals statistics)
  "TOTALS (a plist of counts) with STATISTICS' counts added."
  (loop for (key value) on statistics by #'cddr
        do (incf (getf totals key 0) value))
  totals)

(defun tm-check-spec (seed &key (streams *tm-streams-per-spec*) only)
  "Play STREAMS random streams (or just stream ONLY) on the spec of SEED.
Returns (VALUES PROBLEMS STATISTICS)."
  (let* ((spec (tm-random-spec seed))
         (model (tms-model spec))
         (name (model-name model))
         (problems '())
         (totals '()))
    (handler-case
        (unwind-protect
             (let* ((machine (compile-spec (define-spec name (tms-forms spec)
                                                        :package (find-package '#:player-user))))
                    (predecessors (reference-predecessors model)))
               (dolist (stream (if only (list only) (loop for i from 1 to streams collect i)))
                 (multiple-value-bind (actions initial) (tm-random-stream spec seed stream)
                   (let ((play nil))
                     (multiple-value-bind (problem statistics)
                         (handler-case
                             (progn (setf play (let ((*package* (find-package '#:player-user)))
                                                 (tm-play-stream machine spec actions initial)))
                                    (tm-replay spec actions initial play :predecessors predecessors))
                           (error (e) (values (format nil "error: ~A" e) '())))
                       (setf totals (tm-merge-statistics totals statistics))
                       (incf (getf totals :streams 0))
                       (when problem
                         (push (tm-describe-stream spec stream actions initial play problem) problems)))))))
          (remove-spec name))
      (error (e)
        (push (let ((*package* (find-package '#:player-user)))
                (format nil "spec seed ~D: error defining or compiling the spec: ~A~%  spec: ~S"
                        seed e (tms-forms spec)))
              problems)))
    (values (nreverse problems) totals)))

(defun tm-check-stream (seed stream)
  "The problem the model finds with stream STREAM of spec SEED, or NIL."
  (first (tm-check-spec seed :only stream)))

(defun tm-show-stream (seed stream)
  "Print spec SEED's forms, stream STREAM and the trace the controller gives it."
  (let* ((spec (tm-random-spec seed))
         (name (model-name (tms-model spec))))
    (unwind-protect
         (let ((machine (compile-spec (define-spec name (tms-forms spec) :package (find-package '#:player-user)))))
           (multiple-value-bind (actions initial) (tm-random-stream spec seed stream)
             (let ((play (let ((*package* (find-package '#:player-user)))
                           (tm-play-stream machine spec actions initial))))
               (write-string (tm-describe-stream spec stream actions initial play
                                                 (or (tm-replay spec actions initial play) "agrees with the model")))
               (terpri))))
      (remove-spec name))
    (values)))

;;;# The tests

(test timeline-random-streams-match-the-model
  "Random specs x random timed event streams x random :when-busy policies: the
timed controller's trace, its state at checkpoints and SEND-EVENT's answers
agree with the reference model (see the top of this file)."
  (let ((start (get-internal-real-time))
        (problems '()) (failing 0) (totals '()))
    (dolist (seed *tm-spec-seeds*)
      (multiple-value-bind (found statistics) (tm-check-spec seed)
        (setf totals (tm-merge-statistics totals statistics))
        (when found
          (incf failing (length found))
          (when (< (length problems) 3)
            (setf problems (append problems (list (first found))))))))
    (setf *tm-statistics*
          (list* :seconds (/ (float (- (get-internal-real-time) start)) internal-time-units-per-second)
                 totals))
    (let ((streams (getf totals :streams 0))
          (sends (getf totals :sends 0))
          (busy (getf totals :busy 0)))
      (is (>= streams 1200) "only ~D streams" streams)
      ;; The generator must keep exercising every case.
      (is (<= 0.3 (/ busy (max sends 1)) 0.7) "~D of ~D sends arrived while busy" busy sends)
      (dolist (key '(:queue :override :preempt :interleave :resumed :cut-short :if-cut :fails :macro-cuts :checks))
        (is (>= (getf totals key 0) 20) "only ~D cases of ~(~A~)" (getf totals key 0) key))
      (is (zerop failing) "~D of ~D streams disagree with the model; the first:~{~%~%~A~}"
          failing streams problems))))

;;; Examples the model pinned down

(test timeline-cut-examples
  "Two cuts as the model reads them.  A preemption of an event that was itself
started later by a preemption (its op never began): (:cut nil ...) at the end of
the op still finishing, the newcomer starts there, and an event queued meanwhile
waits for it.  An :interleave cut at an (:at 1) point: the op's :if-cut effects
stand, the interrupter runs, then the interrupted event resumes from the
directive it was cut in, re-planned from the state then."
  (with-spec (spec tm-preempt-twice
                   (state-variable here boolean false)
                   (op walk :add here :duration 2)
                   (op wave :duration 1)
                   (op nod :duration 0.5)
                   (event go :op walk)
                   (event hi :op wave)
                   (event yes :op nod))
    (let ((c (make-controller spec :timed t)))
      (is (eq t (send-event c 'go :at 0)))
      (is (eq t (send-event c 'hi :at 0.5 :when-busy :preempt)))
      (is (eq t (send-event c 'yes :at 1 :when-busy :queue)))
      (is (eq t (send-event c 'yes :at 1.5 :when-busy :preempt)))
      (is (controller-busy-p c))
      (finish-events c)
      (is (equal '("(:event go :time 0)"
                   "(:op walk :script walk :start 0 :end 2)"
                   "(:cut walk :time 2 :by hi)"
                   "(:event hi :time 2)"
                   "(:cut nil :time 2 :by yes)"
                   "(:event yes :time 2)"
                   "(:op nod :script nod :start 2 :end 2.5)"
                   "(:state (here . t))"
                   "(:event yes :time 2.5)"
                   "(:op nod :script nod :start 2.5 :end 3)"
                   "(:state (here . t))")
                 (trace-of c)))))
  (with-spec (spec tm-interleave-resume
                   (state-variable pos string home (home door street))
                   (state-variable coat boolean false)
                   (op to-door :precond pos.home :add pos.door :duration 2
                               :interrupt (:at 1) :if-cut (:add pos.home))
                   (op out :precond pos.door :add pos.street :duration 1)
                   (op put-on :add coat :duration 1)
                   (event leave :state pos.door :state pos.street)
                   (event dress :op put-on))
    (let ((c (make-controller spec :timed t)))
      (send-event c 'leave :at 0)
      (send-event c 'dress :at 0.5 :when-busy :interleave)
      (finish-events c)
      (is (equal '("(:event leave :time 0)"
                   "(:op to-door :script to-door :start 0 :end 2)"
                   "(:cut to-door :time 1 :by dress)"
                   "(:event dress :time 1)"
                   "(:op put-on :script put-on :start 1 :end 2)"
                   "(:state (pos . home) (coat . t))"
                   "(:resume leave :time 2)"
                   "(:op to-door :script to-door :start 2 :end 4)"
                   "(:op out :script out :start 4 :end 5)"
                   "(:state (pos . street) (coat . t))")
                 (trace-of c))))))

(defun tm-heal-trace (interrupt)
  "The trace of: WALK (2 s, INTERRUPT, :if-cut (:add hurt)) from 0; at 1, FIX
(:state (not hurt)) preempts it."
  (let ((spec (define-spec 'tm-heal `((state-variable hurt boolean false)
                                      (op walk :duration 2 :interrupt ,interrupt :if-cut (:add hurt))
                                      (op heal :precond hurt :sub hurt :duration 1)
                                      (event go :op walk)
                                      (event fix :state (not hurt)))
                           :package (find-package '#:player-tests))))
    (unwind-protect
         (let ((c (make-controller spec :timed t)))
           (send-event c 'go :at 0)
           (send-event c 'fix :at 1 :when-busy :preempt)
           (finish-events c)
           (trace-of c))
      (remove-spec 'tm-heal))))

(test timeline-if-cut-effects-at-the-send-time-reach-the-interrupting-plan
  "An op cut at the very time the interrupting event arrives (:anytime, or an
(:at P) point falling then) leaves its :if-cut effects before the interrupter
plans, exactly as a cut at a later point does: FIX must heal."
  (dolist (interrupt '((:at 1.5) :anytime (:at 1)))
    (let ((stop (if (equal interrupt '(:at 1.5)) "1.5" "1")))
      (is (equal (list "(:event go :time 0)"
                       "(:op walk :script walk :start 0 :end 2)"
                       (format nil "(:cut walk :time ~A :by fix)" stop)
                       (format nil "(:event fix :time ~A)" stop)
                       (format nil "(:op heal :script heal :start ~A :end ~A)" stop (if (string= stop "1") "2" "2.5"))
                       "(:state (hurt . nil))")
                 (tm-heal-trace interrupt))
          "with :interrupt ~S" interrupt))))

(test timeline-macro-whose-last-sub-op-finishes-through-a-cut-ends-normally
  "A cut that falls in a macro-op's last sub-op, which runs to its end (:never),
lets the macro-op end as it would have: its line shows its whole span, and the
state is the one it started from with its declared effects (its sub-ops'
changes are internal), as without the cut."
  (with-spec (spec tm-macro-cut
                   (state-variable a boolean false)
                   (state-variable b boolean false)
                   (op step :add b :duration 1)
                   (macro-op m :precond (not a) :add a :seq (:op step))
                   (op pause :duration 1)
                   (event go :op m)
                   (event other :op pause))
    (let ((c (make-controller spec :timed t)))
      (send-event c 'go :at 0)
      (send-event c 'other :at 0.5 :when-busy :preempt)
      (finish-events c)
      (is (equal '("(:event go :time 0)"
                   "(:op m :script m :start 0 :end 1)"
                   "(:op step :script step :start 0 :end 1)"
                   "(:cut step :time 1 :by other)"
                   "(:event other :time 1)"
                   "(:op pause :script pause :start 1 :end 2)"
                   "(:state (a . t) (b . nil))")
                 (trace-of c))))))
