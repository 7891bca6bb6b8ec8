  // Calls of the timed API only (send_timed, advance, finish_events):
  /// How long OP will take from START, asked when its event is planned ahead
  /// (play or run_director is called when its time comes).
  virtual double planned_duration(const Op& op, Time /*start*/) { return op.duration; }
  /// OP (nullptr when none was running), begun at START, is cut at TIME by event BY.
  virtual void cut(const Op* /*op*/, Time /*start*/, Time /*time*/, const char* /*by*/) {}
  /// EVENT, arriving at TIME while BUSY_WITH runs, is dropped (:override);
  /// CLASH is what they met on, as Player's trace prints it: ("head" posture).
  virtual void dropped(const char* /*event*/, Time /*time*/, const char* /*busy_with*/,
                       const std::string& /*clash*/) {}
  /// EVENT, arriving at TIME while events it meets run, waits behind BEHIND (:queue).
  virtual void queued(const char* /*event*/, Time /*time*/, const char* /*behind*/) {}
  /// The interrupted EVENT resumes at TIME (:interleave).
  virtual void resumed(const char* /*event*/, Time /*time*/) {}
  /// Timer TIMER goes off (trigger TRIGGER fires) at TIME and sends its event.
  virtual void timer(const char* /*timer*/, Time /*time*/) {}
  virtual void trigger(const char* /*trigger*/, Time /*time*/) {}
