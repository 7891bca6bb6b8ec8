;;;; cpp-timeline-machine.lisp -- the timed C++ layer's code generated for
;;;; one machine: planning twins of the op and event procedures, the tables
;;;; and hooks the machine-independent text calls, and the source they make.

(in-package #:player.cpp)

;;;# Generated for the machine

(defun emit-planning-executor (op machine)
  "OP's planning twin: record the op (and its end's state change) instead of playing it."
  (let ((index (op-index op machine)))
    (emit-op-procedure-opening op (planning-id (op-id op)))
    (emit "  const Time start = schedule_;")
    (emit "  const Time end = start + Time::from_seconds(presenter_.planned_duration(kOps[~D], start));" index)
    (emit "  record_op_(~D, start, end);" index)
    (emit "  note_op_end(end);")
    (unless (zerop (op-effect-mask op))
      (emit "  record_delta_(~A, ~A, end, last_op_);" (c++-bits (op-effect-mask op)) (c++-bits (op-effect-bits op))))
    (emit "  return 1;~%}~%")))

(defun emit-planning-macro-executor (op machine)
  "A macro-op's planning twin: its span and sub-ops recorded, its effects a change at its end."
  (let ((index (op-index op machine)))
    (emit "int Controller::~A() {" (planning-id (op-id op)))
    (emit "  if (active_[~D]) return fail(~A);" index (c++-string (lisp-text (op-name op))))
    (when (op-c++ op) (emit "  ~A" (op-c++ op)))
    (emit "  const Time start = schedule_, outer_start = span_start_, outer_end = span_end_;")
    (emit "  const StateBits before = state_.bits;")
    (emit "  record_macro_start_(~D, start);" index)
    (emit "  span_start_ = span_end_ = start;")
    (emit "  active_[~D] = true;" index)
    (emit "  const int result = ~A();" (planning-id (macro-seq-id op)))
    (emit "  const Time end = span_end_;")
    (emit "  active_[~D] = false;" index)
    (emit "  span_start_ = outer_start;")
    (emit "  span_end_ = outer_end > end ? outer_end : end;")
    (emit "  schedule_ = end;")
    (emit "  record_macro_end_(~D, start, end);" index)
    (emit "  if (result == 1) record_state_(~A, end);" (effects-expression op "before"))
    (emit "  return result;~%}~%")
    (emit "int Controller::~A() {" (planning-id (macro-seq-id op)))
    (emit-steps (directive-steps (op-seq op) machine) "  " machine (op-name op))
    (emit "  return 1;~%}~%")))

(defun emit-event-suffixes (event machine)
  "EVENT's planning twin: its directives from FROM on, one case each (the
case braced, so a directive's C++ is its own scope)."
  (let ((steps (directive-steps (event-directives event) machine)))
    (emit "int Controller::~A(int from) {" (planning-id (event-id event)))
    (emit "  switch (from) {")
    (let ((*indent* "      ") (*owner* (event-name event)) (*hook-count* 0))
      (loop for step in steps
            for k from 0
            do (emit "    case ~D: {" k)
               (emit-line "step_ = ~D;" k)
               (emit-step step machine)
               (emit "    }")
               (emit "    [[fallthrough]];")))
    (emit "    default:~%      break;~%  }~%  return 1;~%}~%")))

(defun emit-planning-setters (machine)
  "The planning twins of the number setters: record the value, set it silently."
  (dolist (var (runtime-vars machine))
    (when (eq (var-kind var) :number)
      (emit "void Controller::~A(~A value, Time time) {"
            (planning-id (var-setter-id var)) (runtime-c++-type var))
      (emit "  record_value_(~D, value, time);" (runtime-slot var))
      (emit "  state_.~A = value;~%}~%" (var-id var)))))

(defun emit-plan-event (machine)
  "plan_event_(): run an event's planning twin from a directive."
  (emit "int Controller::plan_event_(int event, int from) {")
  (emit "  switch (event) {")
  (loop for event in (spec-events (machine-spec machine))
        for i from 0
        do (emit "    case ~D:~%      return ~A(from);" i (planning-id (event-id event))))
  (emit "    default:~%      (void)from;~%      return 1;~%  }~%}~%"))

(defun emit-record-time-variables (machine)
  "record_time_variables_(): the time variables an event sets when it starts, as value items."
  (emit "void Controller::record_time_variables_(int event, Time time) {")
  (emit "  switch (event) {")
  (loop for event in (spec-events (machine-spec machine))
        for i from 0
        when (event-time-variables event)
          do (emit "    case ~D:" i)
             (dolist (var (event-time-variables event))
               (emit "      record_value_(~D, time.to_double(), time);" (runtime-slot var))
               (emit "      state_.~A = time.to_double();" (var-id var)))
             (emit "      break;"))
  (emit "    default:~%      (void)time;~%      break;~%  }~%}~%"))

(defun emit-restore-values (machine)
  "restore_values_(): the plannable state and runtime values from SAVED (labels stay)."
  (emit "void Controller::restore_values_(const State& saved) {")
  (emit "  state_.bits = saved.bits;")
  (dolist (var (runtime-vars machine))
    (emit "  state_.~A = saved.~A;" (var-id var) (var-id var)))
  (emit "}~%"))

(defun emit-apply-value (machine)
  "apply_value_(): a value item, telling autoscripts (NOTIFY) or silently."
  (emit "void Controller::apply_value_(const Item& item, bool notify) {")
  (emit "  (void)notify;")
  (emit "  switch (item.var) {")
  (dolist (var (runtime-vars machine))
    (let ((field (if (string= (runtime-c++-type var) "long long") "integer" "number")))
      (emit "    case ~D:  // ~A" (runtime-slot var) (c++-comment-text (lisp-text (var-name var))))
      (if (eq (var-kind var) :number)
          (emit "      if (notify) ~A(item.~A, item.time); else state_.~A = item.~A;"
                (var-setter-id var) field (var-id var) field)
          (emit "      state_.~A = item.~A;" (var-id var) field))
      (emit "      break;")))
  (emit "    default:~%      break;~%  }~%}~%"))

(defun op-cut-points (op)
  "OP's numeric interruption points, in seconds, sorted."
  (sort (mapcar (lambda (point) (seconds->micros (to-double point))) (op-interrupt op)) #'<))

(defun emit-op-cut-time (machine)
  "op_cut_time_(): when an op running at TIME can stop (its next interruption point, else its end)."
  (emit "Time Controller::op_cut_time_(const Item& item, Time time) const {")
  (emit "  switch (item.op) {")
  (dolist (op (spec-ops-of machine))
    (let ((interrupt (op-interrupt op)))
      (cond ((eq interrupt :anytime)
             (emit "    case ~D:  // ~A: :interrupt :anytime" (op-index op machine)
                   (c++-comment-text (lisp-text (op-name op))))
             (emit "      return time > item.start ? time : item.start;"))
            ((listp interrupt)
             (emit "    case ~D: {  // ~A: :interrupt (:at ...)" (op-index op machine)
                   (c++-comment-text (lisp-text (op-name op))))
             (emit "      static const Time points[] = {~{~A~^, ~}};" (mapcar #'c++-micros (op-cut-points op)))
             (emit "      for (const Time point : points) {")
             (emit "        const Time at = item.start + point;")
             (emit "        if (at >= time && at <= item.end) return at;")
             (emit "      }")
             (emit "      return item.end;")
             (emit "    }")))))
  (emit "    default:  // :interrupt :never~%      (void)time;~%      return item.end;~%  }~%}~%"))

(defun emit-cut-effects (machine)
  "cut_effects_(): the state change of an op's :if-cut, when it has one."
  (emit "bool Controller::cut_effects_(int op, StateBits& mask, StateBits& bits) const {")
  (emit "  (void)mask;~%  (void)bits;")
  (emit "  switch (op) {")
  (dolist (op (spec-ops-of machine))
    (let ((delta (cut-effect-delta op)))
      (when delta
        (emit "    case ~D:  // ~A" (op-index op machine) (c++-comment-text (lisp-text (op-name op))))
        (emit "      mask = ~A;~%      bits = ~A;~%      return true;" (c++-bits (car delta)) (c++-bits (cdr delta))))))
  (emit "    default:~%      return false;~%  }~%}~%"))

(defun timer-restart-test (timer spec)
  "C++ true when an event (EVENT, from SOURCE) re-arms TIMER, or NIL when none does."
  (let ((restart-on (timer-restart-on timer)))
    (cond ((eq restart-on :any) "source == kFromOutside")
          (restart-on (format nil "~{event == ~D~^ || ~}"
                              (mapcar (lambda (event) (event-number event spec)) restart-on))))))

(defun emit-timers (machine)
  "start_timers_() and note_event_for_timers_()."
  (let ((spec (machine-spec machine)))
    (emit "void Controller::start_timers_() {")
    (loop for timer in (spec-timers spec)
          for i from 0
          do (emit "  arm_timer_(~D, now_);  // ~A" i (c++-comment-text (lisp-text (timer-name timer)))))
    (emit "}~%")
    (emit "void Controller::note_event_for_timers_(int event, int source, Time time) {")
    (emit "  (void)event;~%  (void)source;~%  (void)time;")
    (loop for timer in (spec-timers spec)
          for i from 0
          for test = (timer-restart-test timer spec)
          when test
            do (emit "  if (~A) arm_timer_(~D, time);" test i))
    (emit "}~%")))

(defun emit-triggers (machine)
  "trigger_holds_(), start_triggers_() and check_triggers_(): rising edges send events."
  (let ((triggers (spec-triggers (machine-spec machine))))
    (emit "bool Controller::trigger_holds_(int trigger) {")
    (emit "  switch (trigger) {")
    (loop for trigger in triggers
          for i from 0
          do (emit "    case ~D:  // ~A" i (c++-comment-text (lisp-text (trigger-name trigger))))
             (emit "      return ~A;" (c++-condition (trigger-condition trigger) machine)))
    (emit "    default:~%      return false;~%  }~%}~%")
    (emit "void Controller::start_triggers_() {")
    (loop for i below (length triggers)
          do (emit "  trigger_held_[~D] = trigger_holds_(~D);" i i))
    (emit "}~%")
    (emit "void Controller::check_triggers_(Time time) {")
    (if (null triggers)
        (emit "  (void)time;")
        (progn
          (emit "  schedule_ = time;")
          (emit "  for (int i = 0; i < ~D; ++i) {" (length triggers))
          (emit "    const bool holds = trigger_holds_(i);")
          (emit "    if (holds && !trigger_held_[i]) {")
          (emit "      trigger_held_[i] = true;")
          (emit "      presenter_.trigger(kTriggerNames[i], time);")
          (emit "      send_own_(kTriggerEvents[i], time, kFromTrigger);")
          (emit "    }")
          (emit "    trigger_held_[i] = holds;")
          (emit "  }")))
    (emit "}~%")))

(defun emit-timed-source (machine)
  "The timed layer's .cpp part: tables, the agenda machinery, and the planning
twins of the machine's procedures."
  (let ((spec (machine-spec machine))
        (*planning* t))
    (emit "// The timed layer (EMIT-C++ :timed t): see src/cpp/cpp-timeline.lisp.~%")
    (emit-timed-tables machine)
    ;; The machine-independent runtime, twins of src/control/timeline/: the
    ;; agenda (agenda.lisp), recording while planning ahead (recorder.lisp),
    ;; footprints (footprints.lisp), dispatch, the start gate and cuts
    ;; (arrivals.lisp, timeline.lisp, cuts.lisp), the clock (advance.lisp, timers.lisp).
    (dolist (part '("timeline-agenda.cpp" "timeline-recording.cpp" "timeline-footprints.cpp"
                    "timeline-dispatch.cpp" "timeline-clock.cpp"))
      (emit-resource part))
    (emit-planning-setters machine)
    (loop for goal across (machine-goal-table machine) do (emit-achiever goal machine))
    (dolist (op (spec-ops spec))
      (if (eq (op-kind op) :macro)
          (emit-planning-macro-executor op machine)
          (emit-planning-executor op machine)))
    (dolist (event (spec-events spec)) (emit-event-suffixes event machine))
    (emit-plan-event machine)
    (emit-record-time-variables machine)
    (emit-restore-values machine)
    (emit-apply-value machine)
    (emit-op-cut-time machine)
    (emit-cut-effects machine)
    (emit-timers machine)
    (emit-triggers machine)))
