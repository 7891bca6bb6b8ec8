Controller::Item& Controller::record_(int kind, Time time) {
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

void Controller::record_op_(int op, Time start, Time end) {
  Item& item = record_(kItemOp, start);
  item.op = op;
  item.start = start;
  item.end = end;
  last_op_ = &item;
}

void Controller::record_delta_(const StateBits& mask, const StateBits& bits, Time time, Item* owner) {
  Item& item = record_(kItemDelta, time);
  item.mask = mask;
  item.bits = bits;
  item.owner = owner;
  state_.bits = with_delta(state_.bits, mask, bits);
}

// A macro's end: the fields its effects change.
void Controller::record_state_(const StateBits& next, Time time) {
  const StateBits mask = changed_fields(state_.bits, next);
  record_delta_(mask, common_bits(next, mask), time, last_macro_end_);
}

void Controller::record_value_(int var, long long value, Time time) {
  Item& item = record_(kItemValue, time);
  item.var = var;
  item.integer = value;
}

void Controller::record_value_(int var, double value, Time time) {
  Item& item = record_(kItemValue, time);
  item.var = var;
  item.number = value;
}

void Controller::record_macro_start_(int op, Time start) {
  Item& item = record_(kItemMacroStart, start);
  item.op = op;
  item.start = start;
  open_macros_.push_back(&item);
}

void Controller::record_macro_end_(int op, Time start, Time end) {
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
void Controller::project_state_(Time time) {
  std::vector<const Item*> due;
  for (const std::shared_ptr<Item>& item : agenda_)
    if (item->status == kPending && (item->kind == kItemDelta || item->kind == kItemValue) &&
        item->time <= time)
      due.push_back(item.get());
  std::sort(due.begin(), due.end(), [](const Item* a, const Item* b) { return later_(*b, *a); });
  for (const Item* item : due) {
    if (item->kind == kItemDelta)
      state_.bits = with_delta(state_.bits, item->mask, item->bits);
    else
      apply_value_(*item, false);
  }
}

// Plan RUN ahead from TIME: its items, then the state put back (labels stay).
// With ALL_DUE, the changes due at TIME = now_ not applied yet count too (a
// run starting while the items of the instant are being applied).
int Controller::plan_run_(const std::shared_ptr<Run>& run, Time time, bool all_due) {
  const State saved = state_;
  if (all_due || time > now_) project_state_(time);
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

