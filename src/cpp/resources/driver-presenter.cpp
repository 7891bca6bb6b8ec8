namespace {

[[maybe_unused]] std::string number(double x) { return ctl::format_number(x); }
std::string number(ctl::Time t) { return ctl::to_string(t); }

void print_line(const std::string& line) {
  std::fwrite(line.data(), 1, line.size(), stdout);
  std::fputc(0, stdout);
}

// Records lines like Player's trace presenter; a macro's line waits for its end.
// Each line is written with a NUL after it, since names may hold newlines.
class TracePresenter : public ctl::Presenter {
public:
  double play(const ctl::Op& op, ctl::Time start) override {
    line_op(op, start, start + ctl::Time::from_seconds(op.duration));
    return op.duration;
  }
  double run_director(const ctl::Op& op, ctl::Time start) override { return play(op, start); }
  void macro_start(const ctl::Op& op, ctl::Time start) override {
    open_.push_back(OpenMacro{lines_.size(), &op, start});
    line_op(op, start, start);
  }
  // The line of this macro (OP from START): the innermost open one, unless a
  // timed controller plays macros of two events side by side.
  void macro_end(const ctl::Op& op, ctl::Time start, ctl::Time end) override {
    for (std::size_t i = open_.size(); i-- > 0;) {
      if (open_[i].op == &op && open_[i].start == start) {
        lines_[open_[i].line] = op_text(op, start, end);
        open_.erase(open_.begin() + static_cast<std::ptrdiff_t>(i));
        break;
      }
    }
    flush();
  }
  void start_autoscript(const char* proc, const char* var, const char* value, ctl::Time time) override {
    add(std::string("(:autoscript-start ") + proc + " :var " + var + " :value " + value + " :time " + number(time) + ")");
  }
  void stop_autoscript(const char* proc, const char* var, const char* value, ctl::Time time) override {
    add(std::string("(:autoscript-stop ") + proc + " :var " + var + " :value " + value + " :time " + number(time) + ")");
  }
  void event_start(const char* event, ctl::Time time) override {
    add(std::string("(:event ") + event + " :time " + number(time) + ")");
  }
  void event_failed(const char* event, const char* goal, ctl::Time time) override {
    add(std::string("(:fail ") + event + " :goal " + goal + " :time " + number(time) + ")");
  }
  void event_end(const ctl::Controller& controller) override { add(controller.state_line()); }

