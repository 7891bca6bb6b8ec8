bool Controller::meets_everything_(const Footprint& footprint) {
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

// What footprints A and B, which meet, share, as the :clash of a :dropped
// line (footprint-clash in src/control/timeline/footprints.lisp): :all when
// either has no known channel, else the channels both use, sorted; then the
// variables both mention, plannable ones in order, then runtime ones by slot
// (none when either has an op on no known channel: the Lisp does not work
// them out).
std::string Controller::clash_text_(const Footprint& a, const Footprint& b) {
  std::vector<std::string> names;
  if (meets_everything_(a) || meets_everything_(b)) {
    names.push_back(":all");
  } else {
    std::vector<std::string> channels;
    for (std::size_t i = 0; i < sizeof a.channels / sizeof a.channels[0]; ++i)
      for (int bit = 0; bit < 64; ++bit)
        if ((a.channels[i] & b.channels[i]) >> bit & 1u) channels.push_back(kChannelNames[i * 64 + bit]);
    std::sort(channels.begin(), channels.end());
    names.insert(names.end(), channels.begin(), channels.end());
  }
  if (a.all || b.all) return "(:all)";
  const StateBits shared = common_bits(a.fields, b.fields);
  for (std::size_t i = 0; i < sizeof kFieldNames / sizeof kFieldNames[0] - 1; ++i)
    if (bits_meet(shared, kFieldMasks[i])) names.push_back(kFieldNames[i]);
  for (std::size_t i = 0; i < sizeof a.runtime / sizeof a.runtime[0]; ++i)
    for (int bit = 0; bit < 64; ++bit)
      if ((a.runtime[i] & b.runtime[i]) >> bit & 1u) names.push_back(kRuntimeNames[i * 64 + bit]);
  std::string text = "(";
  for (std::size_t i = 0; i < names.size(); ++i) text += (i ? " " : "") + names[i];
  return text + ")";
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
int Controller::plan_on_trial_(const std::shared_ptr<Run>& run, Time time) {
  return untried_(*run) ? -1 : plan_footprint_(run, time, false);
}

// Plan RUN ahead from TIME (ALL_DUE: see plan_run_) and note its footprint.
int Controller::plan_footprint_(const std::shared_ptr<Run>& run, Time time, bool all_due) {
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

