;;;; cpp-timeline-dispatch.lisp -- the timed C++ layer's machine-independent
;;;; text, part two: events arriving (policies, cuts, the queue, timers and
;;;; triggers) and the clock (the twins of src/runtime/timeline/timeline.lisp,
;;;; cuts.lisp and timers.lisp).

(in-package #:player)

;;;# Dispatch, cuts and the clock

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
      StateBits mask{}, bits{};
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
