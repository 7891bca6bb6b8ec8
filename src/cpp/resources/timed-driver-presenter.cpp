  void cut(const ctl::Op* op, ctl::Time, ctl::Time time, const char* by) override {
    // An op's line gave its planned end: :end says where it stopped.
    add(std::string("(:cut ") + (op ? op->name : "nil") + " :time " + number(time) + " :by " + by +
        (op ? " :end " + number(time) : std::string()) + ")");
  }
  void dropped(const char* event, ctl::Time time, const char* busy_with, const std::string& clash) override {
    add(std::string("(:dropped ") + event + " :time " + number(time) + " :busy-with " + busy_with +
        " :clash " + clash + ")");
  }
  void queued(const char* event, ctl::Time time, const char* behind) override {
    add(std::string("(:queued ") + event + " :time " + number(time) + " :behind " + behind + ")");
  }
  void resumed(const char* event, ctl::Time time) override {
    add(std::string("(:resume ") + event + " :time " + number(time) + ")");
  }
  void timer(const char* name, ctl::Time time) override {
    add(std::string("(:timer ") + name + " :time " + number(time) + ")");
  }
  void trigger(const char* name, ctl::Time time) override {
    add(std::string("(:trigger ") + name + " :time " + number(time) + ")");
  }
  // At the end of a scenario stopped midway: the lines still waiting, an open
  // macro's with its end at its start (as Player's trace holds them).
  void print_rest() {
    for (; flushed_ < lines_.size(); ++flushed_) print_line(lines_[flushed_]);
  }

