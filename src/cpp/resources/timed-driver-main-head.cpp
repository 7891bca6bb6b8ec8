// Stop with the timeline's message when it cannot move on.
void check_timeline(const ctl::Controller& controller) {
  if (controller.timeline_error().empty()) return;
  std::fprintf(stderr, "%s\n", controller.timeline_error().c_str());
  std::exit(3);
}

// Arguments: N, then N pairs VARIABLE VALUE (as Player prints them), then
// UNTIL (seconds, or - to play until no event runs or waits), POLICY (0 for
// each event's own, else 1 + the policy's position in WhenBusy's list) for
// the timed entries, then the entries: INDEX (sent when the events before it
// have ended) or INDEX@SECONDS, seconds an exact decimal (ctl::parse_time).
int main(int argc, char** argv) {

