;;;; cpp-timeline.lisp -- the C++ backend's timed layer: the twin of
;;;; src/control/timeline/ (MAKE-CONTROLLER :TIMED T), emitted only when
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
;;;;
;;;; This file: checks, names, the header's declarations and the tables.
;;;; cpp-timeline-agenda.lisp, cpp-timeline-dispatch.lisp and
;;;; cpp-timeline-clock.lisp hold the machine-independent C++ text; cpp-timeline-machine.lisp what is
;;;; generated for each machine.

(in-package #:player.cpp)

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
  // Something due on the timeline (see src/control/timeline/agenda.lisp).
  struct Item {
    int kind = 0;
    double time = 0;
    long long seq = 0;
    std::shared_ptr<Run> run;    // the Run it belongs to (null for a timer)
    int event = 0;               // its Run's event
    int op = 0;
    double start = 0, end = 0;
    StateBits mask{}, bits{};    // a state change: fields MASK become BITS
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
  "  // What a planned event touches (see src/control/timeline/footprints.lisp):
  // the channels its ops declare (ALL when one declares none), the one-hot
  // fields and the runtime variables (by slot) it mentions.
  struct Footprint {
    bool all = false;
    std::uint64_t channels[~D] = {};
    StateBits fields{};
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
  void record_delta_(const StateBits& mask, const StateBits& bits, double time, Item* owner);
  void record_state_(const StateBits& next, double time);
  void record_value_(int var, long long value, double time);
  void record_value_(int var, double value, double time);
  void record_macro_start_(int op, double start);
  void record_macro_end_(int op, double start, double end);
  void project_state_(double time);
  int dispatch_(int event, double time, int policy, int source);
  int resolve_busy_(const std::shared_ptr<Run>& run, double time, int policy);
  int start_run_(const std::shared_ptr<Run>& run, double time);
  void install_run_(const std::shared_ptr<Run>& run, double time);
  int plan_run_(const std::shared_ptr<Run>& run, double time, bool all_due = false);
  bool untried_(const Run& run) const;
  int plan_on_trial_(const std::shared_ptr<Run>& run, double time);
  int plan_footprint_(const std::shared_ptr<Run>& run, double time, bool all_due);
  bool gate_run_(const std::shared_ptr<Run>& run, double& time, int& result, int trial);
  int start_or_wait_(const std::shared_ptr<Run>& run, double time, int trial);
  void note_footprint_(Run& run) const;
  void forget_plan_(Run& run) const;
  bool meets_running_(const Run& run) const;
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
  bool cut_effects_(int op, StateBits& mask, StateBits& bits) const;
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
  "// The timed layer (see src/control/timeline/): what an agenda item does,
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
    (emit-table "StateBits" "kFieldMasks" (mapcar (lambda (var) (c++-bits (var-field-mask var)))
                                                  (plannable-vars machine))
                "StateBits{}")
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
    (emit "[[maybe_unused]] StateBits changed_fields(const StateBits& old_bits, const StateBits& new_bits) {")
    (emit "  const StateBits differing = differing_bits(old_bits, new_bits);")
    (emit "  StateBits mask{};")
    (emit "  for (const StateBits& field : kFieldMasks)")
    (emit "    if (bits_meet(differing, field)) add_bits(mask, field);")
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
    (emit-table "StateBits" "kOpFields" (mapcar (lambda (op) (c++-bits (op-variable-fields op spec))) ops)
                "StateBits{}")))

(defun event-number (event spec)
  "EVENT's index among SPEC's events (its Event value)."
  (position event (spec-events spec)))
