public:
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
  bool send_timed(Event e, Time at, WhenBusy policy = WhenBusy::as_declared);
  /// The same, AT in seconds (Time::from_seconds: the nearest microsecond).
  bool send_timed(Event e, double at, WhenBusy policy = WhenBusy::as_declared) {
    return send_timed(e, Time::from_seconds(at), policy);
  }
  /// Move the clock to TIME (not before now()), presenting what falls due: op
  /// starts, state changes with their autoscripts, event ends, waiting events,
  /// timers and triggers.  False when TIME lies before now() or the timeline stopped.
  bool advance(Time time);
  bool advance(double seconds) { return advance(Time::from_seconds(seconds)); }
  /// Advance until no event runs or waits (armed timers stay armed); returns now().
  Time finish_events();
  /// Is an event running (or waiting)?
  bool busy() const { return !runs_.empty() || !queue_.empty(); }
  /// The timed clock.
  Time now() const { return timeline_started_ ? now_ : clock_; }
  /// Empty, or why the timeline stopped (over 100000 things at one instant:
  /// triggers firing each other, or zero-length ops in a loop).
  const std::string& timeline_error() const { return timeline_error_; }

