void Controller::start_timeline_() {
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

bool Controller::send_timed(Event e, Time at, WhenBusy policy) {
  start_timeline_();
  if (!timeline_error_.empty() || !(at >= now_) || !advance_to_(at)) return false;
  failed_goal_ = "";
  const int event = static_cast<int>(e);
  const int chosen = policy == WhenBusy::as_declared ? kEventPolicies[event] : static_cast<int>(policy);
  return dispatch_(event, at, chosen, kFromOutside) == 1 && timeline_error_.empty();
}

bool Controller::advance(Time time) {
  start_timeline_();
  if (!timeline_error_.empty() || !(time >= now_)) return false;
  return advance_to_(time);
}

Time Controller::finish_events() {
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
bool Controller::advance_to_(Time time, bool dispatch) {
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
bool Controller::note_instant_(Time time) {
  if (time != now_) {
    instant_count_ = 0;
    return true;
  }
  if (++instant_count_ <= kMaxItemsPerInstant) return true;
  instant_count_ = 0;
  timeline_error_ = "the timeline does not move on at time " + to_string(time) +
                    ": over 100000 things happen at that instant (triggers firing each other, "
                    "or zero-length ops in a loop)";
  return false;
}

void Controller::apply_item_(const std::shared_ptr<Item>& item) {
  const Time time = item->time;
  switch (item->kind) {
    case kItemOp:
      live_ops_.push_back(item);
      if (std::strcmp(kOps[item->op].kind, "director") == 0)
        presenter_.run_director(kOps[item->op], item->start);
      else
        presenter_.play(kOps[item->op], item->start);
      break;
    case kItemDelta:
      transition(with_delta(state_.bits, item->mask, item->bits), time);
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
void Controller::finish_run_(std::shared_ptr<Run> run, Time time) {
  run->finished = true;
  presenter_.event_end(*this);
  runs_.erase(std::remove(runs_.begin(), runs_.end(), run), runs_.end());
  run->items.clear();
  start_waiting_runs_(time);
}

// Start the waiting runs, first first, each at TIME or when the start gate
// lets it (gate_run_), until one finds a running event in its way.
void Controller::start_waiting_runs_(Time time) {
  while (!queue_.empty()) {
    const std::shared_ptr<Run> next = queue_.front();
    Time start = time;
    int result = 0;
    if (!gate_run_(next, start, result, 0)) return;
    queue_.pop_front();
    install_run_(next, start);
  }
}

// Make TIMER go off its :after seconds after TIME.  Re-arming only moves its
// due time later; its item, when the old time comes, goes back on the agenda
// for the new one (so a timer restarted by every event keeps one item).
void Controller::arm_timer_(int timer, Time time) {
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
void Controller::fire_timer_(const std::shared_ptr<Item>& item, Time time) {
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

