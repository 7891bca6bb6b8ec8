int Controller::start_run_(const std::shared_ptr<Run>& run, Time time) {
  const int result = plan_run_(run, time);
  install_run_(run, time);
  return result;
}

// RUN, planned ahead from TIME, starts: show it, note its footprint, put its
// items on the agenda.
void Controller::install_run_(const std::shared_ptr<Run>& run, Time time) {
  if (run->resumed)
    presenter_.resumed(kEventNames[run->event], time);
  else
    presenter_.event_start(kEventNames[run->event], time);
  run->start = time;
  if (!run->planned) note_footprint_(*run);
  runs_.push_back(run);
  for (const std::shared_ptr<Item>& item : run->items) push_item_(item);
}

// EVENT arrives at TIME (now) from SOURCE: planned on trial, it starts
// (start_or_wait_) when it meets none of the running events, else POLICY
// resolves it against those it meets.  1 accepted, 0 dropped, 2 its plan failed.
int Controller::dispatch_(int event, Time time, int policy, int source) {
  note_event_for_timers_(event, source, time);
  const std::shared_ptr<Run> run = std::make_shared<Run>();
  run->event = event;
  run->policy = policy;
  run->source = source;
  if (runs_.empty()) return start_or_wait_(run, time, 0);
  const int trial = plan_on_trial_(run, time);
  if (trial < 0 || meets_running_(*run)) return resolve_busy_(run, time, policy);
  return start_or_wait_(run, time, trial);
}

// The start gate (see src/control/timeline/timeline.lisp), for every run
// about to start: RUN, planned from every change due by TIME, starts then
// only if its plan meets no running event and no op of an interrupted event
// still playing after TIME; with only such ops in the way, TIME becomes the
// time they are over and it is planned again.  True with TIME its start and
// RESULT its planning result; false, RUN holding no plan, when a running
// event is in its way.  TRIAL, unless 0, is the result of RUN's plan already
// made from TIME.
bool Controller::gate_run_(const std::shared_ptr<Run>& run, Time& time, int& result, int trial) {
  if (untried_(*run)) {
    // Taken to meet everything: planned (once: it may run code) only when
    // nothing plays, after every op still playing.
    if (!runs_.empty()) return false;
    Footprint everything;
    everything.all = true;
    time = settled_time_(nullptr, time, everything);
    result = plan_run_(run, time, true);
    return true;
  }
  result = trial != 0 ? trial : plan_footprint_(run, time, true);
  for (;;) {
    if (meets_running_(*run)) {
      forget_plan_(*run);
      return false;
    }
    const Time settled = settled_time_(nullptr, time, run->footprint);
    if (settled == time) return true;
    // Ops still playing are in its way: plan again from when they are over.
    forget_plan_(*run);
    time = settled;
    result = plan_footprint_(run, time, true);
  }
}

// RUN (planned from TIME on trial with result TRIAL, a plan meeting no running
// event, unless TRIAL is 0) passes the start gate at TIME: it starts then or
// later, or waits first in the queue.  Its planning result, or 1 when it waits.
int Controller::start_or_wait_(const std::shared_ptr<Run>& run, Time time, int trial) {
  bool clear = trial != 0 || runs_.empty();
  for (const std::shared_ptr<Item>& op : live_ops_)
    if (op->run->finished && op->end > time) clear = false;
  if (clear) {
    // Nothing can be in its way (the usual case): it starts now.
    if (trial == 0) return start_run_(run, time);
    install_run_(run, time);
    return trial;
  }
  int result = 1;
  if (!gate_run_(run, time, result, trial)) {
    queue_.push_front(run);
    return 1;
  }
  install_run_(run, time);
  return result;
}

// RUN arrives at TIME while events it meets play: do what POLICY says.
int Controller::resolve_busy_(const std::shared_ptr<Run>& run, Time time, int policy) {
  std::vector<std::shared_ptr<Run>> met;
  for (const std::shared_ptr<Run>& other : runs_)
    if (!run->planned || footprints_meet_(run->footprint, other->footprint)) met.push_back(other);
  Footprint footprint = run->footprint;
  if (!run->planned) footprint.all = true;
  forget_plan_(*run);
  if (policy == kQueue) {
    presenter_.queued(kEventNames[run->event], time,
                      kEventNames[(queue_.empty() ? met.front() : queue_.back())->event]);
    queue_.push_back(run);
    return 1;
  }
  if (policy == kOverride) {
    presenter_.dropped(kEventNames[run->event], time, kEventNames[met.front()->event],
                       clash_text_(footprint, met.front()->footprint));
    return 0;
  }
  Time cut_time = time;
  std::vector<std::shared_ptr<Run>> resumptions;
  for (const std::shared_ptr<Run>& other : met) {
    int resume = -1;
    const Time at = cut_run_(*other, time, run->event, footprint, resume);
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
  // The interrupted resume in the order they started, before the queue --
  // after RUN, should a running event keep it waiting.
  for (auto again = resumptions.rbegin(); again != resumptions.rend(); ++again) queue_.push_front(*again);
  // Its plan from the state the cuts leave is not its trial plan: the start
  // gate checks it against the runs left.
  return start_or_wait_(run, cut_time, 0);
}

// A timer or trigger sends EVENT at TIME by its own policy, once everything
// else due at TIME has happened.
void Controller::send_own_(int event, Time time, int source) {
  Send send;
  send.event = event;
  send.time = time;
  send.source = source;
  deferred_.push_back(send);
}

// The earliest moment from TIME when the ops of earlier, already cut runs
// (not RUN) that meet FOOTPRINT are all over.
Time Controller::settled_time_(const Run* run, Time time, const Footprint& footprint) const {
  Time settled = time;
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
Time Controller::cut_run_(Run& run, Time time, int by, const Footprint& footprint, int& resume) {
  Time cut_time = settled_time_(&run, time, footprint);
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
    const Time at = op_cut_time_(item, time);
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
                                       Time cut_time) {
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

