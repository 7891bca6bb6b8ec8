  // One event on the timeline, from its start to its end or cut.
  struct Run {
    int event = 0, policy = 0, source = 0, first_step = 0;
    bool resumed = false, finished = false;
    bool planned = false;                      // FOOTPRINT is known
    Time start;
    Footprint footprint;
    std::vector<std::shared_ptr<Item>> items;  // in the order they were made (until it ends)
  };
  // An event a timer or trigger sends at TIME, once the rest of that instant is done.
  struct Send {
    int event = 0;
    Time time;
    int source = 0;
  };
  bool timeline_started_ = false;
  Time now_;
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
  static std::string clash_text_(const Footprint& a, const Footprint& b);
  void start_timeline_();
  bool advance_to_(Time time, bool dispatch = true);
  bool note_instant_(Time time);
  void push_item_(const std::shared_ptr<Item>& item);
  std::shared_ptr<Item> next_item_();
  void pop_item_();
  Item& record_(int kind, Time time);
  void record_op_(int op, Time start, Time end);
  void record_delta_(const StateBits& mask, const StateBits& bits, Time time, Item* owner);
  void record_state_(const StateBits& next, Time time);
  void record_value_(int var, long long value, Time time);
  void record_value_(int var, double value, Time time);
  void record_macro_start_(int op, Time start);
  void record_macro_end_(int op, Time start, Time end);
  void project_state_(Time time);
  int dispatch_(int event, Time time, int policy, int source);
  int resolve_busy_(const std::shared_ptr<Run>& run, Time time, int policy);
  int start_run_(const std::shared_ptr<Run>& run, Time time);
  void install_run_(const std::shared_ptr<Run>& run, Time time);
  int plan_run_(const std::shared_ptr<Run>& run, Time time, bool all_due = false);
  bool untried_(const Run& run) const;
  int plan_on_trial_(const std::shared_ptr<Run>& run, Time time);
  int plan_footprint_(const std::shared_ptr<Run>& run, Time time, bool all_due);
  bool gate_run_(const std::shared_ptr<Run>& run, Time& time, int& result, int trial);
  int start_or_wait_(const std::shared_ptr<Run>& run, Time time, int trial);
  void note_footprint_(Run& run) const;
  void forget_plan_(Run& run) const;
  bool meets_running_(const Run& run) const;
  Time settled_time_(const Run* run, Time time, const Footprint& footprint) const;
  Time cut_run_(Run& run, Time time, int by, const Footprint& footprint, int& resume);
  void keep_finished_macros_(const Run& run, std::vector<std::shared_ptr<Item>>& keep, Time cut_time);
  void apply_item_(const std::shared_ptr<Item>& item);
  void finish_run_(std::shared_ptr<Run> run, Time time);
  void start_waiting_runs_(Time time);
  void arm_timer_(int timer, Time time);
  void fire_timer_(const std::shared_ptr<Item>& item, Time time);
  void send_own_(int event, Time time, int source);
  // Generated for this machine:
  int plan_event_(int event, int from);
  void record_time_variables_(int event, Time time);
  void restore_values_(const State& saved);
  void apply_value_(const Item& item, bool notify);
  Time op_cut_time_(const Item& item, Time time) const;
  bool cut_effects_(int op, StateBits& mask, StateBits& bits) const;
  void start_timers_();
  void note_event_for_timers_(int event, int source, Time time);
  void start_triggers_();
  void check_triggers_(Time time);
  bool trigger_holds_(int trigger);
