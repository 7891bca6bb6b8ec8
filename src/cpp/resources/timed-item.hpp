private:
  struct Run;
  // Something due on the timeline (see src/control/timeline/agenda.lisp).
  struct Item {
    int kind = 0;
    Time time;
    long long seq = 0;
    std::shared_ptr<Run> run;    // the Run it belongs to (null for a timer)
    int event = 0;               // its Run's event
    int op = 0;
    Time start, end;
    StateBits mask{}, bits{};    // a state change: fields MASK become BITS
    int var = 0;                 // a runtime value: variable VAR becomes INTEGER or NUMBER
    long long integer = 0;
    double number = 0;
    Item* owner = nullptr;       // an op end's change -> the op; a macro start -> its end
    const char* goal = "";
    int step = 0;                // the top-level directive that made it
    int status = 0;              // pending, done or cancelled
    int timer = 0;
  };
