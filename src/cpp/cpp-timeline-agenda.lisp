;;;; cpp-timeline-agenda.lisp -- the timed C++ layer's machine-independent
;;;; text, part one: the agenda heap, recording items while an event is
;;;; planned ahead, and footprints (the twins of src/control/timeline/
;;;; agenda.lisp, recorder.lisp and footprints.lisp).

(in-package #:player.cpp)

;;;# The agenda, recording and footprints (machine-independent)

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

void Controller::record_delta_(const StateBits& mask, const StateBits& bits, double time, Item* owner) {
  Item& item = record_(kItemDelta, time);
  item.mask = mask;
  item.bits = bits;
  item.owner = owner;
  state_.bits = with_delta(state_.bits, mask, bits);
}

// A macro's end: the fields its effects change.
void Controller::record_state_(const StateBits& next, double time) {
  const StateBits mask = changed_fields(state_.bits, next);
  record_delta_(mask, common_bits(next, mask), time, last_macro_end_);
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
      state_.bits = with_delta(state_.bits, item->mask, item->bits);
    else
      apply_value_(*item, false);
  }
}

// Plan RUN ahead from TIME: its items, then the state put back (labels stay).
// With ALL_DUE, the changes due at TIME = now_ not applied yet count too (a
// run starting while the items of the instant are being applied).
int Controller::plan_run_(const std::shared_ptr<Run>& run, double time, bool all_due) {
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
  if (meets_everything_(a) || meets_everything_(b) || bits_meet(a.fields, b.fields)) return true;
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
        add_bits(footprint.fields, kOpFields[item->op]);
        break;
      case kItemMacroStart:
        add_bits(footprint.fields, kOpFields[item->op]);
        break;
      case kItemDelta:
        add_bits(footprint.fields, item->mask);
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

// Is RUN taken to meet everything without being planned: its event runs code
// (planning it would run the code), or a running event meets everything anyway?
bool Controller::untried_(const Run& run) const {
  if (kEventRunsCode[run.event]) return true;
  for (const std::shared_ptr<Run>& other : runs_)
    if (meets_everything_(other->footprint)) return true;
  return false;
}

// Plan RUN ahead from TIME to learn its footprint: its plan's result, or -1
// (untried, see untried_).
int Controller::plan_on_trial_(const std::shared_ptr<Run>& run, double time) {
  return untried_(*run) ? -1 : plan_footprint_(run, time, false);
}

// Plan RUN ahead from TIME (ALL_DUE: see plan_run_) and note its footprint.
int Controller::plan_footprint_(const std::shared_ptr<Run>& run, double time, bool all_due) {
  const int result = plan_run_(run, time, all_due);
  note_footprint_(*run);
  return result;
}

// Does planned RUN meet a running event?
bool Controller::meets_running_(const Run& run) const {
  for (const std::shared_ptr<Run>& other : runs_)
    if (footprints_meet_(run.footprint, other->footprint)) return true;
  return false;
}
"
  "Footprints: what a planned event touches, and whether two meet.")
