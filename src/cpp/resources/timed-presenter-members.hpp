  // Calls of the timed API only (send_timed, advance, finish_events):
  /// How long OP will take from START, asked when its event is planned ahead
  /// (play or run_director is called when its time comes).
  virtual double planned_duration(const Op& op, double /*start*/) { return op.duration; }
  /// OP (nullptr when none was running), begun at START, is cut at TIME by event BY.
  virtual void cut(const Op* /*op*/, double /*start*/, double /*time*/, const char* /*by*/) {}
  /// EVENT, arriving at TIME while BUSY_WITH runs, is dropped (:override);
  /// CLASH is what they met on, as Player's trace prints it: ("head" posture).
  virtual void dropped(const char* /*event*/, double /*time*/, const char* /*busy_with*/,
                       const std::string& /*clash*/) {}
  /// EVENT, arriving at TIME while events it meets run, waits behind BEHIND (:queue).
  virtual void queued(const char* /*event*/, double /*time*/, const char* /*behind*/) {}
  /// The interrupted EVENT resumes at TIME (:interleave).
  virtual void resumed(const char* /*event*/, double /*time*/) {}
  /// Timer TIMER goes off (trigger TRIGGER fires) at TIME and sends its event.
  virtual void timer(const char* /*timer*/, double /*time*/) {}
  virtual void trigger(const char* /*trigger*/, double /*time*/) {}
