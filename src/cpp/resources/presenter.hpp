/// What the embedding program implements: it plays ops and reports durations.
/// Every member has a default, so a presenter overrides only what it needs.
/// Times are exact Time values (to_double() for seconds); durations are seconds.
class Presenter {
public:
  virtual ~Presenter() = default;
  /// Play OP (a script or :code op) from START; return its duration in seconds.
  virtual double play(const Op& op, Time /*start*/) { return op.duration; }
  /// Run the director of a :director op from START; return its duration.
  virtual double run_director(const Op& op, Time /*start*/) { return op.duration; }
  /// A macro-op starts at START; its sub-ops follow; it ends at END.
  virtual void macro_start(const Op& /*op*/, Time /*start*/) {}
  virtual void macro_end(const Op& /*op*/, Time /*start*/, Time /*end*/) {}
  /// Autoscript PROC starts (stops) because VARIABLE took (left) VALUE at TIME.
  virtual void start_autoscript(const char* /*proc*/, const char* /*variable*/,
                                const char* /*value*/, Time /*time*/) {}
  virtual void stop_autoscript(const char* /*proc*/, const char* /*variable*/,
                               const char* /*value*/, Time /*time*/) {}
  /// EVENT starts at TIME; it failed to achieve GOAL at TIME; it ended.
  virtual void event_start(const char* /*event*/, Time /*time*/) {}
  virtual void event_failed(const char* /*event*/, const char* /*goal*/, Time /*time*/) {}
  virtual void event_end(const Controller& /*controller*/) {}
  /// A :code directive or op: its Lisp form has no C++ meaning, so the
  /// controller calls this hook, named after the event or op, instead.
  virtual void code_hook(const char* /*hook*/) {}
