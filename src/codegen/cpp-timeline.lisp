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
;;;; follow the Lisp runtime step for step, so the traces are identical:
;;;; several runs play at once when their footprints (the channels ops
;;;; declare, the fields and runtime variables a plan touches) are disjoint,
;;;; an event arriving while others play is planned on trial to learn its
;;;; footprint, and the events timers and triggers send wait until the rest
;;;; of their instant has happened.

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
  // The timed API: ops occupy time, and an event arriving while others play
  // either plays beside them (when its plan's channels and variables meet
  // none of theirs) or is resolved by its :when-busy policy against those it
  // meets.  A controller uses either this or send/send_at, not both.
  enum class WhenBusy : int { as_declared, queue, preempt, override, interleave };
  ~Controller();
  /// E arrives at AT (not before now()): the clock advances there first; then E
  /// starts, or POLICY (by default E's :when-busy) resolves it against the
  /// running events it meets.  True when E was accepted; false when it was
  /// dropped, when it started and its plan failed (failed_goal() names the
  /// goal), when AT lies before now(), or when the timeline has stopped
  /// (timeline_error()).
  bool send_timed(Event e, double at, WhenBusy policy = WhenBusy::as_declared);
  /// Move the clock to TIME (not before now()), presenting what falls due: op
  /// starts, state changes with their autoscripts, event ends, waiting events,
  /// timers and triggers.  False when TIME lies before now() or the timeline stopped.
  bool advance(double time);
  /// Advance until no event runs or waits (armed timers stay armed); returns now().
  double finish_events();
  /// Is an event running (or waiting)?
  bool busy() const { return !runs_.empty() || !queue_.empty(); }
  /// The timed clock.
  double now() const { return timeline_started_ ? now_ : clock_; }
  /// Empty, or why the timeline stopped (over 100000 things at one instant:
  /// triggers firing each other, or zero-length ops in a loop).
  const std::string& timeline_error() const { return timeline_error_; }
"
  "The timed API's declarations in the Controller.")

(defparameter *c++-timed-item*
  "private:
  struct Run;
  // Something due on the timeline (see src/runtime/timeline/agenda.lisp).
  struct Item {
    int kind = 0;
    double time = 0;
    long long seq = 0;
    std::shared_ptr<Run> run;    // the Run it belongs to (null for a timer)
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
  };"
  "The timed layer's agenda item, in the Controller.")

(defparameter *c++-timed-footprint*
  "  // What a planned event touches (see src/runtime/timeline/footprints.lisp):
  // the channels its ops declare (ALL when one declares none), the one-hot
  // fields and the runtime variables (by slot) it mentions.
  struct Footprint {
    bool all = false;
    std::uint64_t channels[~D] = {};
    std::uint64_t fields = 0;
    std::uint64_t runtime[~D] = {};
  };"
  "The Footprint struct; its arrays are sized for the machine's channels and runtime variables.")

(defparameter *c++-timed-types*
  "  // One event on the timeline, from its start to its end or cut.
  struct Run {
    int event = 0, policy = 0, source = 0, first_step = 0;
    bool resumed = false, finished = false;
    bool planned = false;                      // FOOTPRINT is known
    double start = 0;
    Footprint footprint;
    std::vector<std::shared_ptr<Item>> items;  // in the order they were made (until it ends)
  };
  // An event a timer or trigger sends at TIME, once the rest of that instant is done.
  struct Send {
    int event = 0;
    double time = 0;
    int source = 0;
  };
  bool timeline_started_ = false;
  double now_ = 0;
  long long seq_ = 0, instant_count_ = 0;
  int step_ = 0;
  std::vector<std::shared_ptr<Item>> agenda_;    // a heap, earliest first
  std::vector<std::shared_ptr<Item>> live_ops_;  // ops presented, their end to come
  std::vector<std::shared_ptr<Run>> runs_;       // the events playing, oldest first
  std::deque<std::shared_ptr<Run>> queue_;
  std::vector<Send> deferred_;                   // sends due at now_, first first
  std::shared_ptr<Run> recording_;               // the run being planned ahead
  Item* last_op_ = nullptr;                      // whose end's change comes next
  Item* last_macro_end_ = nullptr;               // likewise
  std::vector<Item*> open_macros_;
  std::string timeline_error_;
  static bool later_(const Item& a, const Item& b);
  static bool heap_order_(const std::shared_ptr<Item>& a, const std::shared_ptr<Item>& b);
  static bool meets_everything_(const Footprint& footprint);
  static bool footprints_meet_(const Footprint& a, const Footprint& b);
  void start_timeline_();
  bool advance_to_(double time, bool dispatch = true);
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
  int resolve_busy_(const std::shared_ptr<Run>& run, double time, int policy);
  int start_run_(const std::shared_ptr<Run>& run, double time);
  void install_run_(const std::shared_ptr<Run>& run, double time);
  int plan_run_(const std::shared_ptr<Run>& run, double time);
  int plan_on_trial_(const std::shared_ptr<Run>& run, double time);
  void note_footprint_(Run& run) const;
  void forget_plan_(Run& run) const;
  bool meets_running_(const Run& run) const;
  bool meets_finishing_(const Run& run) const;
  double settled_time_(const Run* run, double time, const Footprint& footprint) const;
  double cut_run_(Run& run, double time, int by, const Footprint& footprint, int& resume);
  void keep_finished_macros_(const Run& run, std::vector<std::shared_ptr<Item>>& keep, double cut_time);
  void apply_item_(const std::shared_ptr<Item>& item);
  void finish_run_(std::shared_ptr<Run> run, double time);
  void start_waiting_runs_(double time);
  void arm_timer_(int timer, double time);
  void fire_timer_(const std::shared_ptr<Item>& item, double time);
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

(defun spec-channel-names (spec)
  "The channel names SPEC's ops declare, each once, in order of first mention."
  (let ((names '()))
    (dolist (op (spec-ops spec) (nreverse names))
      (dolist (name (op-channels op))
        (pushnew name names :test #'string=)))))

(defun channel-words (spec)
  "How many 64-bit words hold a set of SPEC's channels (at least one)."
  (max 1 (ceiling (length (spec-channel-names spec)) 64)))

(defun runtime-words (machine)
  "How many 64-bit words hold a set of MACHINE's runtime variables (at least one)."
  (max 1 (ceiling (length (runtime-vars machine)) 64)))

(defun emit-timed-members (machine)
  "The timed layer's part of the Controller declaration: the API, the agenda,
and the planning twins of the machine's procedures."
  (let* ((spec (machine-spec machine))
         (timers (max 1 (length (spec-timers spec)))))
    (emit-text *c++-timed-api*)
    (emit-text *c++-timed-item*)
    (emit *c++-timed-footprint* (channel-words spec) (runtime-words machine))
    (emit-text *c++-timed-types*)
    (emit "  std::shared_ptr<Item> timer_items_[~D];" timers)
    (emit "  double timer_due_[~D] = {};" timers)
    (emit "  long long timer_seq_[~D] = {};" timers)
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
    (emit-op-footprint-tables machine)
    (emit-table "bool" "kEventRunsCode" (mapcar (lambda (event) (if (event-runs-code-p event) "true" "false"))
                                                (spec-events spec))
                "false")
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

(defun op-channel-words (op names words)
  "OP's declared channels as WORDS 64-bit words, bit I for the Ith of NAMES."
  (let ((bits (reduce #'logior (op-channels op)
                      :key (lambda (name) (ash 1 (position name names :test #'string=)))
                      :initial-value 0)))
    (loop for word below words collect (c++-hex (ldb (byte 64 (* 64 word)) bits)))))

(defun emit-op-footprint-tables (machine)
  "What each op touches (OP-FOOTPRINT's twin): whether it declares no channels
(then it meets every op), the channels it declares, the fields it mentions."
  (let* ((spec (machine-spec machine))
         (ops (spec-ops-of machine))
         (names (spec-channel-names spec))
         (words (channel-words spec)))
    (emit-table "bool" "kOpChannelsAll" (mapcar (lambda (op) (if (op-channels op) "false" "true")) ops) "true")
    (emit "[[maybe_unused]] const std::uint64_t kOpChannels[][~D] = {~{{~{~A~^, ~}}, ~}{0}};"
          words (mapcar (lambda (op) (op-channel-words op names words)) ops))
    (emit-table "std::uint64_t" "kOpFields" (mapcar (lambda (op) (c++-hex (op-variable-fields op spec))) ops))))

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
  item->run = recording_;
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
int Controller::plan_run_(const std::shared_ptr<Run>& run, double time) {
  const State saved = state_;
  if (time > now_) project_state_(time);
  recording_ = run;
  last_op_ = last_macro_end_ = nullptr;
  open_macros_.clear();
  step_ = run->first_step;
  schedule_ = span_start_ = span_end_ = time;
  record_time_variables_(run->event, time);
  const int result = plan_event_(run->event, run->first_step);
  if (result != 1) record_(kItemFail, schedule_).goal = failed_goal_;
  record_(kItemFinish, span_end_);
  recording_.reset();
  restore_values_(saved);
  return result;
}
"
  "Planning an event ahead: the twins of the whole-event procedures record items.")

(defparameter *c++-footprints*
  "bool Controller::meets_everything_(const Footprint& footprint) {
  if (footprint.all) return true;
  for (const std::uint64_t word : footprint.channels)
    if (word != 0) return false;
  return true;
}

// Do footprints A and B share a channel or a variable?  One with no known
// channel (ALL, or none) meets every other.
bool Controller::footprints_meet_(const Footprint& a, const Footprint& b) {
  if (meets_everything_(a) || meets_everything_(b) || (a.fields & b.fields) != 0) return true;
  for (std::size_t i = 0; i < sizeof a.channels / sizeof a.channels[0]; ++i)
    if ((a.channels[i] & b.channels[i]) != 0) return true;
  for (std::size_t i = 0; i < sizeof a.runtime / sizeof a.runtime[0]; ++i)
    if ((a.runtime[i] & b.runtime[i]) != 0) return true;
  return false;
}

// RUN's footprint as planned: the channels and fields of the ops its items
// play, and the variables its changes set.
void Controller::note_footprint_(Run& run) const {
  Footprint footprint;
  for (const std::shared_ptr<Item>& item : run.items) {
    switch (item->kind) {
      case kItemOp:
        if (kOpChannelsAll[item->op]) {
          footprint.all = true;
        } else {
          for (std::size_t i = 0; i < sizeof footprint.channels / sizeof footprint.channels[0]; ++i)
            footprint.channels[i] |= kOpChannels[item->op][i];
        }
        footprint.fields |= kOpFields[item->op];
        break;
      case kItemMacroStart:
        footprint.fields |= kOpFields[item->op];
        break;
      case kItemDelta:
        footprint.fields |= item->mask;
        break;
      case kItemValue:
        footprint.runtime[item->var / 64] |= std::uint64_t{1} << (item->var % 64);
        break;
      default:
        break;
    }
  }
  run.footprint = footprint;
  run.planned = true;
}

// Drop what RUN planned on trial (it is planned again when it starts).
void Controller::forget_plan_(Run& run) const {
  run.items.clear();
  run.footprint = Footprint();
  run.planned = false;
}

// Plan RUN ahead from TIME to learn its footprint: its plan's result, or -1
// (untried) when its event runs code or a running event meets everything anyway.
int Controller::plan_on_trial_(const std::shared_ptr<Run>& run, double time) {
  if (kEventRunsCode[run->event]) return -1;
  for (const std::shared_ptr<Run>& other : runs_)
    if (meets_everything_(other->footprint)) return -1;
  const int result = plan_run_(run, time);
  note_footprint_(*run);
  return result;
}

// Does planned RUN meet a running event?
bool Controller::meets_running_(const Run& run) const {
  for (const std::shared_ptr<Run>& other : runs_)
    if (footprints_meet_(run.footprint, other->footprint)) return true;
  return false;
}

// Does planned RUN meet an op of an interrupted event that still plays out?
bool Controller::meets_finishing_(const Run& run) const {
  for (const std::shared_ptr<Item>& op : live_ops_)
    if (op->run->finished && op->end > now_ && footprints_meet_(run.footprint, op->run->footprint)) return true;
  return false;
}
"
  "Footprints: what a planned event touches, and whether two meet.")

(defparameter *c++-dispatch*
  "int Controller::start_run_(const std::shared_ptr<Run>& run, double time) {
  const int result = plan_run_(run, time);
  install_run_(run, time);
  return result;
}

// RUN, planned ahead from TIME, starts: show it, note its footprint, put its
// items on the agenda.
void Controller::install_run_(const std::shared_ptr<Run>& run, double time) {
  if (run->resumed)
    presenter_.resumed(kEventNames[run->event], time);
  else
    presenter_.event_start(kEventNames[run->event], time);
  run->start = time;
  if (!run->planned) note_footprint_(*run);
  runs_.push_back(run);
  for (const std::shared_ptr<Item>& item : run->items) push_item_(item);
}

// EVENT arrives at TIME (now) from SOURCE: planned on trial, it starts beside
// the running events when it meets none of them, else POLICY resolves it
// against those it meets.  1 accepted, 0 dropped, 2 its plan failed.
int Controller::dispatch_(int event, double time, int policy, int source) {
  note_event_for_timers_(event, source, time);
  const std::shared_ptr<Run> run = std::make_shared<Run>();
  run->event = event;
  run->policy = policy;
  run->source = source;
  if (runs_.empty()) return start_run_(run, time);
  const int trial = plan_on_trial_(run, time);
  if (trial < 0 || meets_running_(*run)) return resolve_busy_(run, time, policy);
  if (meets_finishing_(*run)) {
    // Only the last op of an interrupted event is in its way: start when that is over.
    const double start = settled_time_(nullptr, time, run->footprint);
    forget_plan_(*run);
    return start_run_(run, start);
  }
  install_run_(run, time);
  return trial;
}

// RUN arrives at TIME while events it meets play: do what POLICY says.
int Controller::resolve_busy_(const std::shared_ptr<Run>& run, double time, int policy) {
  std::vector<std::shared_ptr<Run>> met;
  for (const std::shared_ptr<Run>& other : runs_)
    if (!run->planned || footprints_meet_(run->footprint, other->footprint)) met.push_back(other);
  Footprint footprint = run->footprint;
  if (!run->planned) footprint.all = true;
  forget_plan_(*run);
  if (policy == kQueue) {
    queue_.push_back(run);
    return 1;
  }
  if (policy == kOverride) {
    presenter_.dropped(kEventNames[run->event], time, kEventNames[met.front()->event]);
    return 0;
  }
  double cut_time = time;
  std::vector<std::shared_ptr<Run>> resumptions;
  for (const std::shared_ptr<Run>& other : met) {
    int resume = -1;
    const double at = cut_run_(*other, time, run->event, footprint, resume);
    if (at > cut_time) cut_time = at;
    if (policy == kInterleave && resume >= 0) {
      const std::shared_ptr<Run> again = std::make_shared<Run>();
      again->event = other->event;
      again->policy = other->policy;
      again->source = other->source;
      again->first_step = resume;
      again->resumed = true;
      resumptions.push_back(again);
    }
  }
  // A cut falling now leaves its :if-cut state now: apply it before the new
  // event plans from it (sends of timers and triggers wait).
  if (!advance_to_(time, false)) return 0;
  // The interrupted resume in the order they started, before the queue.
  for (auto again = resumptions.rbegin(); again != resumptions.rend(); ++again) queue_.push_front(*again);
  return start_run_(run, cut_time);
}

// A timer or trigger sends EVENT at TIME by its own policy, once everything
// else due at TIME has happened.
void Controller::send_own_(int event, double time, int source) {
  Send send;
  send.event = event;
  send.time = time;
  send.source = source;
  deferred_.push_back(send);
}

// The earliest moment from TIME when the ops of earlier, already cut runs
// (not RUN) that meet FOOTPRINT are all over.
double Controller::settled_time_(const Run* run, double time, const Footprint& footprint) const {
  double settled = time;
  for (const std::shared_ptr<Item>& op : live_ops_) {
    const Run* other = op->run.get();
    if (other != run && other->finished && footprints_meet_(footprint, other->footprint) && op->end > settled)
      settled = op->end;
  }
  return settled;
}

// Interrupt RUN at TIME for event BY (whose footprint is FOOTPRINT): running
// ops stop at their next interruption point, the rest is cancelled.  Returns
// when the new event can start; RESUME is the directive RUN would resume
// from (-1: nothing left).
double Controller::cut_run_(Run& run, double time, int by, const Footprint& footprint, int& resume) {
  double cut_time = settled_time_(&run, time, footprint);
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
        change->run = item.run;
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
  // RUN is over: its kept items play out on the agenda.
  run.finished = true;
  run.items.clear();
  for (auto it = runs_.begin(); it != runs_.end(); ++it)
    if (it->get() == &run) {
      runs_.erase(it);
      break;
    }
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
  "Events arriving: starting beside others, queueing, dropping, cutting.")

(defparameter *c++-clock*
  "void Controller::start_timeline_() {
  if (timeline_started_) return;
  timeline_started_ = true;
  now_ = clock_;
  start_timers_();
  start_triggers_();
}

Controller::~Controller() {
  // A playing run and its items hold each other: let go.
  for (const std::shared_ptr<Run>& run : runs_) run->items.clear();
}

bool Controller::send_timed(Event e, double at, WhenBusy policy) {
  start_timeline_();
  if (!timeline_error_.empty() || !(at >= now_) || !advance_to_(at)) return false;
  failed_goal_ = \"\";
  const int event = static_cast<int>(e);
  const int chosen = policy == WhenBusy::as_declared ? kEventPolicies[event] : static_cast<int>(policy);
  return dispatch_(event, at, chosen, kFromOutside) == 1 && timeline_error_.empty();
}

bool Controller::advance(double time) {
  start_timeline_();
  if (!timeline_error_.empty() || !(time >= now_)) return false;
  return advance_to_(time);
}

double Controller::finish_events() {
  start_timeline_();
  while (busy() && timeline_error_.empty()) {
    const std::shared_ptr<Item> item = next_item_();
    if (!advance_to_(item ? item->time : now_) || !item) break;
  }
  return now_;
}

// Present and apply, in time order, everything due up to TIME; then now_ is
// TIME.  The events timers and triggers send at an instant are dispatched
// once everything else due then has happened (unless DISPATCH is false: then
// they wait for the advance_to_ that called this one).
bool Controller::advance_to_(double time, bool dispatch) {
  for (;;) {
    const std::shared_ptr<Item> item = next_item_();
    if (item && item->time <= time && !(dispatch && !deferred_.empty() && item->time > now_)) {
      pop_item_();
      if (!note_instant_(item->time)) return false;
      now_ = item->time;
      item->status = kDone;
      apply_item_(item);
    } else if (dispatch && !deferred_.empty()) {
      std::vector<Send> sends;
      sends.swap(deferred_);
      for (const Send& send : sends) {
        dispatch_(send.event, send.time, kEventPolicies[send.event], send.source);
        if (!timeline_error_.empty()) return false;
      }
    } else {
      break;
    }
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
      fire_timer_(item, time);
      break;
  }
}

// RUN is over at TIME: show the state, and start the waiting events that no
// running event meets any more, first first.
void Controller::finish_run_(std::shared_ptr<Run> run, double time) {
  run->finished = true;
  presenter_.event_end(*this);
  runs_.erase(std::remove(runs_.begin(), runs_.end(), run), runs_.end());
  run->items.clear();
  start_waiting_runs_(time);
}

// Start, at TIME, the first waiting runs while no running event meets the first.
void Controller::start_waiting_runs_(double time) {
  while (!queue_.empty()) {
    const std::shared_ptr<Run> next = queue_.front();
    if (runs_.empty()) {
      queue_.pop_front();
      start_run_(next, time);
      continue;
    }
    const int trial = plan_on_trial_(next, time);
    if (trial < 0 || meets_running_(*next) || meets_finishing_(*next)) {
      forget_plan_(*next);
      return;
    }
    queue_.pop_front();
    install_run_(next, time);
  }
}

// Make TIMER go off its :after seconds after TIME.  Re-arming only moves its
// due time later; its item, when the old time comes, goes back on the agenda
// for the new one (so a timer restarted by every event keeps one item).
void Controller::arm_timer_(int timer, double time) {
  timer_due_[timer] = time + kTimerAfter[timer];
  timer_seq_[timer] = ++seq_;
  if (timer_items_[timer]) return;
  const std::shared_ptr<Item> item = std::make_shared<Item>();
  item->kind = kItemTimer;
  item->time = timer_due_[timer];
  item->seq = timer_seq_[timer];
  item->timer = timer;
  timer_items_[timer] = item;
  push_item_(item);
}

// A timer's ITEM has come up at TIME: it goes off, unless it was re-armed for later.
void Controller::fire_timer_(const std::shared_ptr<Item>& item, double time) {
  const int timer = item->timer;
  if (!(timer_due_[timer] == time && timer_seq_[timer] == item->seq)) {
    item->time = timer_due_[timer];
    item->seq = timer_seq_[timer];
    item->status = kPending;
    push_item_(item);
    return;
  }
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
    (emit-text *c++-footprints*)
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
