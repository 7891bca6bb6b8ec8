;;;; cpp-timeline.lisp -- the C++ backend's timed layer: the twin of
;;;; src/runtime/timeline/ (MAKE-CONTROLLER :TIMED T), emitted only when
;;;; C++-SOURCES is asked for it (EMIT-C++ :TIMED T, or RUN-C++-TRACE with a
;;;; timed scenario), so the whole-event code is exactly what it always was.
;;;;
;;;; The Controller gets send_timed, advance and finish_events.  An event is
;;;; planned ahead when it starts by planning twins of the whole-event
;;;; procedures (plan_achieve_goalN_, plan_op_X_, one plan_ev_E_(from) per
;;;; event with a case per top-level directive, so an interrupted event can
;;;; resume); they record agenda items instead of presenting.  The agenda is a
;;;; heap of items ordered by (time, seq); cuts, policies, timers and triggers
;;;; follow the Lisp runtime step for step, so the traces are identical.

(in-package #:player)

;;;# Checks and names

(defun check-c++-interruption-points (spec)
  "Signal a PLAYER-ERROR when an op of SPEC gives :interrupt (:at NAME): a
critical time needs a script library, which the C++ controller has not."
  (dolist (op (spec-ops spec))
    (let ((interrupt (op-interrupt op)))
      (when (and (listp interrupt) (notevery #'realp interrupt))
        (error 'player-error-with-message
               :message (format nil "op ~A: :interrupt (:at ~{~A~^ ~}) names critical times; give seconds for C++ (only a script library knows critical times)"
                                (lisp-text (op-name op)) (mapcar #'lisp-text interrupt)))))))

(defparameter *c++-timed-members*
  '("send_timed" "advance" "finish_events" "busy" "now" "timeline_error" "WhenBusy")
  "The public names the timed layer adds to the Controller, kept from user names.")

(defun reserve-timed-names (table)
  "Take the timed layer's public member names in identifier TABLE."
  (dolist (name *c++-timed-members*)
    (setf (gethash name (cdr table)) t)))

(defun var-setter-id (var) (format nil "set_~A" (var-id var)))

(defun runtime-slot (var)
  "The number by which the timed layer's value items name runtime VAR."
  (var-slot var))

;;;# The header

(defparameter *c++-timed-presenter-members*
  "  // Calls of the timed API only (send_timed, advance, finish_events):
  /// How long OP will take from START, asked when its event is planned ahead
  /// (play or run_director is called when its time comes).
  virtual double planned_duration(const Op& op, double /*start*/) { return op.duration; }
  /// OP (nullptr when none was running), begun at START, is cut at TIME by event BY.
  virtual void cut(const Op* /*op*/, double /*start*/, double /*time*/, const char* /*by*/) {}
  /// EVENT, arriving at TIME while BUSY_WITH runs, is dropped (:override).
  virtual void dropped(const char* /*event*/, double /*time*/, const char* /*busy_with*/) {}
  /// The interrupted EVENT resumes at TIME (:interleave).
  virtual void resumed(const char* /*event*/, double /*time*/) {}
  /// Timer TIMER goes off (trigger TRIGGER fires) at TIME and sends its event.
  virtual void timer(const char* /*timer*/, double /*time*/) {}
  virtual void trigger(const char* /*trigger*/, double /*time*/) {}"
  "The Presenter's members the timed layer calls.")

(defun emit-timed-presenter-members ()
  "The Presenter's virtual members for the timed API."
  (emit-text *c++-timed-presenter-members*))

(defparameter *c++-timed-api*
  "public:
  // The timed API: ops occupy time, and an event arriving while another plays
  // is resolved by its :when-busy policy.  A controller uses either this or
  // send/send_at, not both.
  enum class WhenBusy : int { as_declared, queue, preempt, override, interleave };
  /// E arrives at AT (not before now()): the clock advances there first; then E
  /// starts, or POLICY (by default E's :when-busy) resolves it against the
  /// running event.  True when E was accepted; false when it was dropped, when
  /// it started and its plan failed (failed_goal() names the goal), when AT
  /// lies before now(), or when the timeline has stopped (timeline_error()).
  bool send_timed(Event e, double at, WhenBusy policy = WhenBusy::as_declared);
  /// Move the clock to TIME (not before now()), presenting what falls due: op
  /// starts, state changes with their autoscripts, event ends, waiting events,
  /// timers and triggers.  False when TIME lies before now() or the timeline stopped.
  bool advance(double time);
  /// Advance until no event runs or waits (armed timers stay armed); returns now().
  double finish_events();
  /// Is an event running (or waiting)?
  bool busy() const { return current_ != nullptr; }
  /// The timed clock.
  double now() const { return timeline_started_ ? now_ : clock_; }
  /// Empty, or why the timeline stopped (over 100000 things at one instant:
  /// triggers firing each other, or zero-length ops in a loop).
  const std::string& timeline_error() const { return timeline_error_; }
"
  "The timed API's declarations in the Controller.")

(defparameter *c++-timed-types*
  "private:
  // Something due on the timeline (see src/runtime/timeline/agenda.lisp).
  struct Item {
    int kind = 0;
    double time = 0;
    long long seq = 0;
    long long run = 0;           // the id of its Run (0 for a timer)
    int event = 0;               // its Run's event
    int op = 0;
    double start = 0, end = 0;
    std::uint64_t mask = 0, bits = 0;  // a state change: fields MASK become BITS
    int var = 0;                 // a runtime value: variable VAR becomes INTEGER or NUMBER
    long long integer = 0;
    double number = 0;
    Item* owner = nullptr;       // an op end's change -> the op; a macro start -> its end
    const char* goal = \"\";
    int step = 0;                // the top-level directive that made it
    int status = 0;              // pending, done or cancelled
    int timer = 0;
  };
  // One event on the timeline, from its start to its end or cut.
  struct Run {
    long long id = 0;
    int event = 0, policy = 0, source = 0, first_step = 0;
    bool resumed = false;
    double start = 0;
    std::vector<std::shared_ptr<Item>> items;  // in the order they were made
  };
  bool timeline_started_ = false;
  double now_ = 0;
  long long seq_ = 0, runs_ = 0, instant_count_ = 0;
  int step_ = 0;
  std::vector<std::shared_ptr<Item>> agenda_;    // a heap, earliest first
  std::vector<std::shared_ptr<Item>> live_ops_;  // ops presented, their end to come
  std::shared_ptr<Run> current_;
  std::deque<std::shared_ptr<Run>> queue_;
  Run* recording_ = nullptr;                     // the run being planned ahead
  Item* last_op_ = nullptr;                      // whose end's change comes next
  Item* last_macro_end_ = nullptr;               // likewise
  std::vector<Item*> open_macros_;
  std::string timeline_error_;
  static bool later_(const Item& a, const Item& b);
  static bool heap_order_(const std::shared_ptr<Item>& a, const std::shared_ptr<Item>& b);
  void start_timeline_();
  bool advance_to_(double time);
  bool note_instant_(double time);
  void push_item_(const std::shared_ptr<Item>& item);
  std::shared_ptr<Item> next_item_();
  void pop_item_();
  Item& record_(int kind, double time);
  void record_op_(int op, double start, double end);
  void record_delta_(std::uint64_t mask, std::uint64_t bits, double time, Item* owner);
  void record_state_(std::uint64_t next, double time);
  void record_value_(int var, long long value, double time);
  void record_value_(int var, double value, double time);
  void record_macro_start_(int op, double start);
  void record_macro_end_(int op, double start, double end);
  void project_state_(double time);
  int dispatch_(int event, double time, int policy, int source);
  int start_run_(const std::shared_ptr<Run>& run, double time);
  int plan_run_(Run& run, double time);
  double settled_time_(long long run, double time) const;
  double cut_run_(Run& run, double time, int by, int& resume);
  void keep_finished_macros_(const Run& run, std::vector<std::shared_ptr<Item>>& keep, double cut_time);
  void apply_item_(const std::shared_ptr<Item>& item);
  void finish_run_(long long run, double time);
  void arm_timer_(int timer, double time);
  void fire_timer_(int timer, double time);
  void send_own_(int event, double time, int source);
  // Generated for this machine:
  int plan_event_(int event, int from);
  void record_time_variables_(int event, double time);
  void restore_values_(const State& saved);
  void apply_value_(const Item& item, bool notify);
  double op_cut_time_(const Item& item, double time) const;
  bool cut_effects_(int op, std::uint64_t& mask, std::uint64_t& bits) const;
  void start_timers_();
  void note_event_for_timers_(int event, int source, double time);
  void start_triggers_();
  void check_triggers_(double time);
  bool trigger_holds_(int trigger);"
  "The timed layer's private types, members and procedures in the Controller.")

(defun emit-timed-members (machine)
  "The timed layer's part of the Controller declaration: the API, the agenda,
and the planning twins of the machine's procedures."
  (let ((spec (machine-spec machine)))
    (emit-text *c++-timed-api*)
    (emit-text *c++-timed-types*)
    (emit "  std::shared_ptr<Item> timer_items_[~D];" (max 1 (length (spec-timers spec))))
    (emit "  bool trigger_held_[~D] = {};" (max 1 (length (spec-triggers spec))))
    (dolist (var (runtime-vars machine))
      (when (eq (var-kind var) :number)
        (emit "  void ~A(~A value, double time);" (planning-id (var-setter-id var)) (runtime-c++-type var))))
    (loop for goal across (machine-goal-table machine)
          do (emit "  int ~A();" (planning-id (goal-fn-id goal))))
    (dolist (op (spec-ops spec))
      (emit "  int ~A();" (planning-id (op-id op)))
      (when (eq (op-kind op) :macro)
        (emit "  int ~A();" (planning-id (macro-seq-id op)))))
    (dolist (event (spec-events spec))
      (emit "  int ~A(int from);" (planning-id (event-id event))))))

(defun macro-seq-id (op) (format nil "~A_seq" (op-id op)))

;;;# Tables

(defparameter *c++-timed-constants*
  "// The timed layer (see src/runtime/timeline/): what an agenda item does,
// its status, the :when-busy policies and where an event comes from.
constexpr int kItemOp = 0, kItemDelta = 1, kItemValue = 2, kItemMacroStart = 3,
              kItemMacroEnd = 4, kItemFail = 5, kItemFinish = 6, kItemTimer = 7;
constexpr int kPending = 0, kDone = 1, kCancelled = 2;
constexpr int kQueue = 1, kOverride = 3, kInterleave = 4;
constexpr int kFromOutside = 0, kFromTimer = 1, kFromTrigger = 2;
constexpr long long kMaxItemsPerInstant = 100000;"
  "The timed layer's constants (policy numbers as in Controller::WhenBusy).")

(defun policy-number (policy)
  "POLICY's number in Controller::WhenBusy."
  (1+ (position policy *when-busy-policies*)))

(defun emit-table (type name items &optional (dummy "0"))
  "const TYPE NAME[] = {ITEMS..., DUMMY}: never empty."
  (emit "[[maybe_unused]] const ~A ~A[] = {~{~A, ~}~A};" type name items dummy))

(defun emit-timed-tables (machine)
  "The timed layer's tables: policies, field masks, timers and triggers."
  (let ((spec (machine-spec machine)))
    (emit "namespace {~%")
    (emit-text *c++-timed-constants*)
    (emit-table "int" "kEventPolicies"
                (mapcar (lambda (event) (princ-to-string (policy-number (event-policy event spec))))
                        (spec-events spec)))
    (emit-table "std::uint64_t" "kFieldMasks" (mapcar (lambda (var) (c++-hex (var-field-mask var)))
                                                      (plannable-vars machine)))
    (emit-table "char* const" "kTimerNames"
                (mapcar (lambda (timer) (c++-string (lisp-text (timer-name timer)))) (spec-timers spec))
                "nullptr")
    (emit-table "double" "kTimerAfter" (mapcar (lambda (timer) (c++-double (timer-after timer))) (spec-timers spec)))
    (emit-table "int" "kTimerEvents" (mapcar (lambda (timer) (princ-to-string (event-number (timer-event timer) spec)))
                                             (spec-timers spec)))
    (emit-table "bool" "kTimerRepeats" (mapcar (lambda (timer) (if (timer-repeat timer) "true" "false"))
                                               (spec-timers spec))
                "false")
    (emit-table "char* const" "kTriggerNames"
                (mapcar (lambda (trigger) (c++-string (lisp-text (trigger-name trigger)))) (spec-triggers spec))
                "nullptr")
    (emit-table "int" "kTriggerEvents"
                (mapcar (lambda (trigger) (princ-to-string (event-number (trigger-event trigger) spec)))
                        (spec-triggers spec)))
    (emit "~%// The one-hot fields that differ between two states.")
    (emit "[[maybe_unused]] std::uint64_t changed_fields(std::uint64_t old_bits, std::uint64_t new_bits) {")
    (emit "  std::uint64_t mask = 0;")
    (emit "  for (const std::uint64_t field : kFieldMasks)")
    (emit "    if ((old_bits ^ new_bits) & field) mask |= field;")
    (emit "  return mask;~%}~%")
    (emit "}  // namespace~%")))

(defun event-number (event spec)
  "EVENT's index among SPEC's events (its Event value)."
  (position event (spec-events spec)))

;;;# The agenda, recording, dispatch, cuts and the clock (machine-independent)

(defparameter *c++-agenda*
  "bool Controller::later_(const Item& a, const Item& b) {
  return a.time > b.time || (a.time == b.time && a.seq > b.seq);
}

bool Controller::heap_order_(const std::shared_ptr<Item>& a, const std::shared_ptr<Item>& b) {
  return later_(*a, *b);
}

void Controller::push_item_(const std::shared_ptr<Item>& item) {
  agenda_.push_back(item);
  std::push_heap(agenda_.begin(), agenda_.end(), heap_order_);
}

void Controller::pop_item_() {
  std::pop_heap(agenda_.begin(), agenda_.end(), heap_order_);
  agenda_.pop_back();
}

// The earliest pending item, or null; cancelled items on top are dropped.
std::shared_ptr<Controller::Item> Controller::next_item_() {
  while (!agenda_.empty()) {
    if (agenda_.front()->status != kCancelled) return agenda_.front();
    pop_item_();
  }
  return nullptr;
}
"
  "The agenda: a binary heap of items by (time, seq).")

(defparameter *c++-recording*
  "Controller::Item& Controller::record_(int kind, double time) {
  const std::shared_ptr<Item> item = std::make_shared<Item>();
  item->kind = kind;
  item->time = time;
  item->seq = ++seq_;
  item->run = recording_->id;
  item->event = recording_->event;
  item->step = step_;
  recording_->items.push_back(item);
  return *item;
}

void Controller::record_op_(int op, double start, double end) {
  Item& item = record_(kItemOp, start);
  item.op = op;
  item.start = start;
  item.end = end;
  last_op_ = &item;
}

void Controller::record_delta_(std::uint64_t mask, std::uint64_t bits, double time, Item* owner) {
  Item& item = record_(kItemDelta, time);
  item.mask = mask;
  item.bits = bits;
  item.owner = owner;
  state_.bits = (state_.bits & ~mask) | bits;
}

// A macro's end: the fields its effects change.
void Controller::record_state_(std::uint64_t next, double time) {
  const std::uint64_t mask = changed_fields(state_.bits, next);
  record_delta_(mask, next & mask, time, last_macro_end_);
}

void Controller::record_value_(int var, long long value, double time) {
  Item& item = record_(kItemValue, time);
  item.var = var;
  item.integer = value;
}

void Controller::record_value_(int var, double value, double time) {
  Item& item = record_(kItemValue, time);
  item.var = var;
  item.number = value;
}

void Controller::record_macro_start_(int op, double start) {
  Item& item = record_(kItemMacroStart, start);
  item.op = op;
  item.start = start;
  open_macros_.push_back(&item);
}

void Controller::record_macro_end_(int op, double start, double end) {
  Item* opening = open_macros_.back();
  open_macros_.pop_back();
  Item& item = record_(kItemMacroEnd, end);
  item.op = op;
  item.start = start;
  item.end = end;
  opening->end = end;
  opening->owner = &item;
  last_macro_end_ = &item;
}

// Put into the state the pending changes due by TIME, telling no one.
void Controller::project_state_(double time) {
  std::vector<const Item*> due;
  for (const std::shared_ptr<Item>& item : agenda_)
    if (item->status == kPending && (item->kind == kItemDelta || item->kind == kItemValue) &&
        item->time <= time)
      due.push_back(item.get());
  std::sort(due.begin(), due.end(), [](const Item* a, const Item* b) { return later_(*b, *a); });
  for (const Item* item : due) {
    if (item->kind == kItemDelta)
      state_.bits = (state_.bits & ~item->mask) | item->bits;
    else
      apply_value_(*item, false);
  }
}

// Plan RUN ahead from TIME: its items, then the state put back (labels stay).
int Controller::plan_run_(Run& run, double time) {
  const State saved = state_;
  if (time > now_) project_state_(time);
  recording_ = &run;
  last_op_ = last_macro_end_ = nullptr;
  open_macros_.clear();
  step_ = run.first_step;
  schedule_ = span_start_ = span_end_ = time;
  record_time_variables_(run.event, time);
  const int result = plan_event_(run.event, run.first_step);
  if (result != 1) record_(kItemFail, schedule_).goal = failed_goal_;
  record_(kItemFinish, span_end_);
  recording_ = nullptr;
  restore_values_(saved);
  return result;
}
"
  "Planning an event ahead: the twins of the whole-event procedures record items.")

(defparameter *c++-dispatch*
  "int Controller::start_run_(const std::shared_ptr<Run>& run, double time) {
  if (run->resumed)
    presenter_.resumed(kEventNames[run->event], time);
  else
    presenter_.event_start(kEventNames[run->event], time);
  run->start = time;
  current_ = run;
  const int result = plan_run_(*run, time);
  for (const std::shared_ptr<Item>& item : run->items) push_item_(item);
  return result;
}

// EVENT arrives at TIME (now) from SOURCE: 1 accepted, 0 dropped, 2 its plan failed.
int Controller::dispatch_(int event, double time, int policy, int source) {
  note_event_for_timers_(event, source, time);
  const std::shared_ptr<Run> run = std::make_shared<Run>();
  run->id = ++runs_;
  run->event = event;
  run->policy = policy;
  run->source = source;
  if (!current_) return start_run_(run, time);
  if (policy == kQueue) {
    queue_.push_back(run);
    return 1;
  }
  if (policy == kOverride) {
    presenter_.dropped(kEventNames[event], time, kEventNames[current_->event]);
    return 0;
  }
  int resume = -1;
  const double cut_time = cut_run_(*current_, time, event, resume);
  // A cut falling now leaves its :if-cut state now: apply it before the new
  // event plans from it.
  if (!advance_to_(time)) return 0;
  if (policy == kInterleave && resume >= 0) {
    const std::shared_ptr<Run> again = std::make_shared<Run>();
    again->id = ++runs_;
    again->event = current_->event;
    again->policy = current_->policy;
    again->source = current_->source;
    again->first_step = resume;
    again->resumed = true;
    queue_.push_front(again);
  }
  return start_run_(run, cut_time);
}

void Controller::send_own_(int event, double time, int source) {
  dispatch_(event, time, kEventPolicies[event], source);
}

// When ops of runs other than RUN, cut or finishing, are all over.
double Controller::settled_time_(long long run, double time) const {
  double settled = time;
  for (const std::shared_ptr<Item>& op : live_ops_) {
    const double end = op->run == run ? time : op->end;
    if (end > settled) settled = end;
  }
  return settled;
}

// Interrupt RUN at TIME for event BY: running ops stop at their next
// interruption point, the rest is cancelled.  Returns when the new event can
// start; RESUME is the directive RUN would resume from (-1: nothing left).
double Controller::cut_run_(Run& run, double time, int by, int& resume) {
  double cut_time = settled_time_(run.id, time);
  std::vector<std::shared_ptr<Item>> keep;
  std::vector<const Item*> shown;
  const Item* finishing = nullptr;
  resume = -1;
  const auto resume_at = [&resume](const Item& item) {
    if (resume < 0 || item.step < resume) resume = item.step;
  };
  for (auto it = run.items.rbegin(); it != run.items.rend(); ++it) {
    Item& item = **it;
    if (item.kind != kItemOp || item.status != kDone || !(item.end > time)) continue;
    const double at = op_cut_time_(item, time);
    if (at > cut_time) cut_time = at;
    if (at < item.end) {
      std::uint64_t mask = 0, bits = 0;
      item.end = at;
      resume_at(item);
      if (cut_effects_(item.op, mask, bits)) {
        const std::shared_ptr<Item> change = std::make_shared<Item>();
        change->kind = kItemDelta;
        change->time = at;
        change->seq = ++seq_;
        change->run = run.id;
        change->event = run.event;
        change->mask = mask;
        change->bits = bits;
        change->step = item.step;
        keep.push_back(change);
        push_item_(change);
      }
      shown.push_back(&item);
    } else {
      finishing = &item;
      for (const std::shared_ptr<Item>& other : run.items)
        if (other->owner == &item) keep.push_back(other);
    }
  }
  keep_finished_macros_(run, keep, cut_time);
  for (auto it = run.items.rbegin(); it != run.items.rend(); ++it) {
    Item& item = **it;
    if (item.status != kPending || std::find(keep.begin(), keep.end(), *it) != keep.end()) continue;
    if (item.kind != kItemFinish) resume_at(item);
    item.status = kCancelled;
  }
  std::vector<const Item*> closing;
  for (const std::shared_ptr<Item>& item : run.items)
    if (item->kind == kItemMacroStart && item->status == kDone && item->owner &&
        item->owner->status == kCancelled)
      closing.push_back(item.get());
  std::sort(closing.begin(), closing.end(), [](const Item* a, const Item* b) { return a->seq > b->seq; });
  for (const Item* item : closing) presenter_.macro_end(kOps[item->op], item->start, cut_time);
  if (!shown.empty()) {
    for (const Item* item : shown) presenter_.cut(&kOps[item->op], item->start, item->end, kEventNames[by]);
  } else if (finishing) {
    presenter_.cut(&kOps[finishing->op], finishing->start, cut_time, kEventNames[by]);
  } else {
    presenter_.cut(nullptr, time, cut_time, kEventNames[by]);
  }
  run.items = keep;
  return cut_time;
}

// Keep the end (and end state change) of each macro of RUN that ends by
// CUT_TIME with every pending item inside it kept: its last sub-op runs to
// its end through the cut, so the macro ends then, declared effects and all.
void Controller::keep_finished_macros_(const Run& run, std::vector<std::shared_ptr<Item>>& keep,
                                       double cut_time) {
  const auto kept = [&keep](const Item* item) {
    for (const std::shared_ptr<Item>& other : keep)
      if (other.get() == item) return true;
    return false;
  };
  for (const std::shared_ptr<Item>& item : run.items) {
    if (item->kind != kItemMacroEnd || item->status != kPending || !(item->time <= cut_time)) continue;
    const Item* opening = nullptr;
    for (const std::shared_ptr<Item>& other : run.items)
      if (other->owner == item.get()) {
        opening = other.get();
        break;
      }
    if (!opening) continue;
    bool finished = true;
    for (const std::shared_ptr<Item>& inner : run.items)
      if (inner->status == kPending && !kept(inner.get()) && inner->seq > opening->seq &&
          inner->seq < item->seq)
        finished = false;
    if (!finished) continue;
    keep.push_back(item);
    for (const std::shared_ptr<Item>& other : run.items)
      if (other->owner == item.get()) keep.push_back(other);
  }
}
"
  "Events arriving: starting, queueing, dropping, cutting.")

(defparameter *c++-clock*
  "void Controller::start_timeline_() {
  if (timeline_started_) return;
  timeline_started_ = true;
  now_ = clock_;
  start_timers_();
  start_triggers_();
}

bool Controller::send_timed(Event e, double at, WhenBusy policy) {
  start_timeline_();
  if (!timeline_error_.empty() || !(at >= now_) || !advance_to_(at)) return false;
  failed_goal_ = \"\";
  const int event = static_cast<int>(e);
  const int chosen = policy == WhenBusy::as_declared ? kEventPolicies[event] : static_cast<int>(policy);
  return dispatch_(event, at, chosen, kFromOutside) == 1;
}

bool Controller::advance(double time) {
  start_timeline_();
  if (!timeline_error_.empty() || !(time >= now_)) return false;
  return advance_to_(time);
}

double Controller::finish_events() {
  start_timeline_();
  while (current_ && timeline_error_.empty()) {
    const std::shared_ptr<Item> item = next_item_();
    if (!advance_to_(item ? item->time : now_) || !item) break;
  }
  return now_;
}

bool Controller::advance_to_(double time) {
  for (std::shared_ptr<Item> item = next_item_(); item && item->time <= time; item = next_item_()) {
    pop_item_();
    if (!note_instant_(item->time)) return false;
    now_ = item->time;
    item->status = kDone;
    apply_item_(item);
  }
  now_ = time;
  live_ops_.erase(std::remove_if(live_ops_.begin(), live_ops_.end(),
                                 [time](const std::shared_ptr<Item>& op) { return op->end <= time; }),
                  live_ops_.end());
  clock_ = time;
  return true;
}

// Count the items applied at TIME; stop when they never end.
bool Controller::note_instant_(double time) {
  if (time != now_) {
    instant_count_ = 0;
    return true;
  }
  if (++instant_count_ <= kMaxItemsPerInstant) return true;
  instant_count_ = 0;
  timeline_error_ = \"the timeline does not move on at time \" + format_number(time) +
                    \": over 100000 things happen at that instant (triggers firing each other, \"
                    \"or zero-length ops in a loop)\";
  return false;
}

void Controller::apply_item_(const std::shared_ptr<Item>& item) {
  const double time = item->time;
  switch (item->kind) {
    case kItemOp:
      live_ops_.push_back(item);
      if (std::strcmp(kOps[item->op].kind, \"director\") == 0)
        presenter_.run_director(kOps[item->op], item->start);
      else
        presenter_.play(kOps[item->op], item->start);
      break;
    case kItemDelta:
      transition((state_.bits & ~item->mask) | item->bits, time);
      check_triggers_(time);
      break;
    case kItemValue:
      apply_value_(*item, true);
      check_triggers_(time);
      break;
    case kItemMacroStart:
      presenter_.macro_start(kOps[item->op], item->start);
      break;
    case kItemMacroEnd:
      presenter_.macro_end(kOps[item->op], item->start, time);
      break;
    case kItemFail:
      presenter_.event_failed(kEventNames[item->event], item->goal, time);
      break;
    case kItemFinish:
      finish_run_(item->run, time);
      break;
    default:
      fire_timer_(item->timer, time);
      break;
  }
}

void Controller::finish_run_(long long run, double time) {
  presenter_.event_end(*this);
  if (!current_ || current_->id != run) return;
  current_.reset();
  if (queue_.empty()) return;
  const std::shared_ptr<Run> next = queue_.front();
  queue_.pop_front();
  start_run_(next, time);
}

void Controller::arm_timer_(int timer, double time) {
  if (timer_items_[timer]) timer_items_[timer]->status = kCancelled;
  const std::shared_ptr<Item> item = std::make_shared<Item>();
  item->kind = kItemTimer;
  item->time = time + kTimerAfter[timer];
  item->seq = ++seq_;
  item->timer = timer;
  timer_items_[timer] = item;
  push_item_(item);
}

void Controller::fire_timer_(int timer, double time) {
  timer_items_[timer].reset();
  presenter_.timer(kTimerNames[timer], time);
  if (kTimerRepeats[timer]) arm_timer_(timer, time);
  send_own_(kTimerEvents[timer], time, kFromTimer);
}
"
  "The clock: advancing, applying items, finishing runs, timers.")

;;;# Generated for the machine

(defun emit-planning-executor (op machine)
  "OP's planning twin: record the op (and its end's state change) instead of playing it."
  (let ((index (op-index op machine)))
    (emit "int Controller::~A() {" (planning-id (op-id op)))
    (when (op-c++ op) (emit "  ~A" (op-c++ op)))
    (when (eq (op-kind op) :code)
      (emit "  // :code ~A has no C++ meaning: the embedder implements the hook."
            (code-comment-text (op-code op)))
      (emit "  presenter_.code_hook(~A);" (c++-string (lisp-text (op-name op)))))
    (emit "  const double start = schedule_;")
    (emit "  const double end = start + presenter_.planned_duration(kOps[~D], start);" index)
    (emit "  record_op_(~D, start, end);" index)
    (emit "  note_op_end(end);")
    (unless (zerop (op-effect-mask op))
      (emit "  record_delta_(~A, ~A, end, last_op_);" (c++-hex (op-effect-mask op)) (c++-hex (op-effect-bits op))))
    (emit "  return 1;~%}~%")))

(defun emit-planning-macro-executor (op machine)
  "A macro-op's planning twin: its span and sub-ops recorded, its effects a change at its end."
  (let ((index (op-index op machine)))
    (emit "int Controller::~A() {" (planning-id (op-id op)))
    (emit "  if (active_[~D]) return fail(~A);" index (c++-string (lisp-text (op-name op))))
    (when (op-c++ op) (emit "  ~A" (op-c++ op)))
    (emit "  const double start = schedule_, outer_start = span_start_, outer_end = span_end_;")
    (emit "  const std::uint64_t before = state_.bits;")
    (emit "  record_macro_start_(~D, start);" index)
    (emit "  span_start_ = span_end_ = start;")
    (emit "  active_[~D] = true;" index)
    (emit "  const int result = ~A();" (planning-id (macro-seq-id op)))
    (emit "  const double end = span_end_;")
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
      (emit "void Controller::~A(~A value, double time) {"
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
  (emit "void Controller::record_time_variables_(int event, double time) {")
  (emit "  switch (event) {")
  (loop for event in (spec-events (machine-spec machine))
        for i from 0
        when (event-time-variables event)
          do (emit "    case ~D:" i)
             (dolist (var (event-time-variables event))
               (emit "      record_value_(~D, time, time);" (runtime-slot var))
               (emit "      state_.~A = time;" (var-id var)))
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
  (sort (mapcar #'to-double (op-interrupt op)) #'<))

(defun emit-op-cut-time (machine)
  "op_cut_time_(): when an op running at TIME can stop (its next interruption point, else its end)."
  (emit "double Controller::op_cut_time_(const Item& item, double time) const {")
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
             (emit "      static const double points[] = {~{~A~^, ~}};" (mapcar #'c++-double (op-cut-points op)))
             (emit "      for (const double point : points) {")
             (emit "        const double at = item.start + point;")
             (emit "        if (at >= time && at <= item.end) return at;")
             (emit "      }")
             (emit "      return item.end;")
             (emit "    }")))))
  (emit "    default:  // :interrupt :never~%      (void)time;~%      return item.end;~%  }~%}~%"))

(defun emit-cut-effects (machine)
  "cut_effects_(): the state change of an op's :if-cut, when it has one."
  (emit "bool Controller::cut_effects_(int op, std::uint64_t& mask, std::uint64_t& bits) const {")
  (emit "  (void)mask;~%  (void)bits;")
  (emit "  switch (op) {")
  (dolist (op (spec-ops-of machine))
    (let ((delta (cut-effect-delta op)))
      (when delta
        (emit "    case ~D:  // ~A" (op-index op machine) (c++-comment-text (lisp-text (op-name op))))
        (emit "      mask = ~A;~%      bits = ~A;~%      return true;" (c++-hex (car delta)) (c++-hex (cdr delta))))))
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
    (emit "void Controller::note_event_for_timers_(int event, int source, double time) {")
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
    (emit "void Controller::check_triggers_(double time) {")
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
    (emit "// The timed layer (EMIT-C++ :timed t): see src/codegen/cpp-timeline.lisp.~%")
    (emit-timed-tables machine)
    (emit-text *c++-agenda*)
    (emit-text *c++-recording*)
    (emit-text *c++-dispatch*)
    (emit-text *c++-clock*)
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
