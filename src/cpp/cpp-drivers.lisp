;;;; cpp-drivers.lisp -- the C++ programs that drive a generated controller
;;;; for `bin/player run --backend c++` and the tests: a presenter printing
;;;; the trace in the Lisp presenter's exact format, reading the initial state
;;;; and the events from the command line, whole-event or timed.

(in-package #:player.cpp)

(defparameter *driver-presenter*
  "namespace {

std::string number(double x) { return ctl::format_number(x); }

void print_line(const std::string& line) {
  std::fwrite(line.data(), 1, line.size(), stdout);
  std::fputc(0, stdout);
}

// Records lines like Player's trace presenter; a macro's line waits for its end.
// Each line is written with a NUL after it, since names may hold newlines.
class TracePresenter : public ctl::Presenter {
public:
  double play(const ctl::Op& op, double start) override {
    line_op(op, start, start + op.duration);
    return op.duration;
  }
  double run_director(const ctl::Op& op, double start) override { return play(op, start); }
  void macro_start(const ctl::Op& op, double start) override {
    open_.push_back(OpenMacro{lines_.size(), &op, start});
    line_op(op, start, start);
  }
  // The line of this macro (OP from START): the innermost open one, unless a
  // timed controller plays macros of two events side by side.
  void macro_end(const ctl::Op& op, double start, double end) override {
    for (std::size_t i = open_.size(); i-- > 0;) {
      if (open_[i].op == &op && open_[i].start == start) {
        lines_[open_[i].line] = op_text(op, start, end);
        open_.erase(open_.begin() + static_cast<std::ptrdiff_t>(i));
        break;
      }
    }
    flush();
  }
  void start_autoscript(const char* proc, const char* var, const char* value, double time) override {
    add(std::string(\"(:autoscript-start \") + proc + \" :var \" + var + \" :value \" + value + \" :time \" + number(time) + \")\");
  }
  void stop_autoscript(const char* proc, const char* var, const char* value, double time) override {
    add(std::string(\"(:autoscript-stop \") + proc + \" :var \" + var + \" :value \" + value + \" :time \" + number(time) + \")\");
  }
  void event_start(const char* event, double time) override {
    add(std::string(\"(:event \") + event + \" :time \" + number(time) + \")\");
  }
  void event_failed(const char* event, const char* goal, double time) override {
    add(std::string(\"(:fail \") + event + \" :goal \" + goal + \" :time \" + number(time) + \")\");
  }
  void event_end(const ctl::Controller& controller) override { add(controller.state_line()); }
"
  "The start of the trace-printing driver's code, after its header (it names
the controller's namespace through the alias ctl): a presenter recording
trace lines, up to its members for the timed API.")

(defparameter *driver-presenter-end*
  "
private:
  // A macro line waiting for its end: where it is, whose, and from when.
  struct OpenMacro { std::size_t line; const ctl::Op* op; double start; };
  std::vector<std::string> lines_;
  std::vector<OpenMacro> open_;
  std::size_t flushed_ = 0;

  static std::string op_text(const ctl::Op& op, double start, double end) {
    std::string kind = op.kind;
    std::string middle = kind == \"director\" ? std::string(\" :director \") + op.script
                       : kind == \"code\" ? std::string(\" :code t\")
                       : std::string(\" :script \") + op.script;
    return std::string(\"(:op \") + op.name + middle + \" :start \" + number(start) + \" :end \" + number(end) + \")\";
  }
  void line_op(const ctl::Op& op, double start, double end) { add(op_text(op, start, end)); }
  void add(const std::string& line) { lines_.push_back(line); flush(); }
  void flush() {
    if (!open_.empty()) return;
    for (; flushed_ < lines_.size(); ++flushed_) print_line(lines_[flushed_]);
  }
};

}  // namespace

"
  "The rest of the driver's presenter.")

(defparameter *driver-read-initial-state*
  "  ctl::State state = ctl::initial_state();
  const int pairs = argc > 1 ? std::atoi(argv[1]) : 0;
  int next = 2;
  for (int i = 0; i < pairs; ++i, next += 2) {
    if (next + 1 >= argc || !ctl::assign(state, argv[next], argv[next + 1])) {
      std::fprintf(stderr, \"bad initial value %s\\n\", next < argc ? argv[next] : \"(missing)\");
      return 2;
    }
  }
"
  "The start of both drivers' main(): the initial state from N, then N pairs
VARIABLE VALUE; NEXT is then the index of the first argument after them.")

(defparameter *driver-main*
  (concatenate 'string
   "// Arguments: N, then N pairs VARIABLE VALUE (as Player prints them), then the
// events' indices. Without events it prints the initial state line.
int main(int argc, char** argv) {
"
   *driver-read-initial-state*
   "  TracePresenter presenter;
  ctl::Controller controller(presenter, state);
  if (next >= argc) print_line(controller.state_line());
  for (; next < argc; ++next) {
    const int index = std::atoi(argv[next]);
    if (index < 0 || index >= ctl::event_count) {
      std::fprintf(stderr, \"unknown event index %s\\n\", argv[next]);
      return 2;
    }
    controller.send(static_cast<ctl::Event>(index));
  }
  return 0;
}
")
  "The driver's main() for the whole-event API.")

(defparameter *timed-driver-presenter*
  "  void cut(const ctl::Op* op, double, double time, const char* by) override {
    add(std::string(\"(:cut \") + (op ? op->name : \"nil\") + \" :time \" + number(time) + \" :by \" + by + \")\");
  }
  void dropped(const char* event, double time, const char* busy_with) override {
    add(std::string(\"(:dropped \") + event + \" :time \" + number(time) + \" :busy-with \" + busy_with + \")\");
  }
  void resumed(const char* event, double time) override {
    add(std::string(\"(:resume \") + event + \" :time \" + number(time) + \")\");
  }
  void timer(const char* name, double time) override {
    add(std::string(\"(:timer \") + name + \" :time \" + number(time) + \")\");
  }
  void trigger(const char* name, double time) override {
    add(std::string(\"(:trigger \") + name + \" :time \" + number(time) + \")\");
  }
  // At the end of a scenario stopped midway: the lines still waiting, an open
  // macro's with its end at its start (as Player's trace holds them).
  void print_rest() {
    for (; flushed_ < lines_.size(); ++flushed_) print_line(lines_[flushed_]);
  }
"
  "The driver presenter's members for the timed API, printing as Player's trace.")

(defparameter *timed-driver-main*
  (concatenate 'string
   "// Stop with the timeline's message when it cannot move on.
void check_timeline(const ctl::Controller& controller) {
  if (controller.timeline_error().empty()) return;
  std::fprintf(stderr, \"%s\\n\", controller.timeline_error().c_str());
  std::exit(3);
}

// Arguments: N, then N pairs VARIABLE VALUE (as Player prints them), then
// UNTIL (seconds, or - to play until no event runs or waits), POLICY (0 for
// each event's own, else 1 + the policy's position in WhenBusy's list) for
// the timed entries, then the entries: INDEX (sent when the events before it
// have ended) or INDEX@SECONDS.
int main(int argc, char** argv) {
"
   *driver-read-initial-state*
   "  if (next + 1 >= argc) {
    std::fprintf(stderr, \"missing UNTIL or POLICY\\n\");
    return 2;
  }
  const std::string until = argv[next++];
  const int policy = std::atoi(argv[next++]);
  TracePresenter presenter;
  ctl::Controller controller(presenter, state);
  for (; next < argc; ++next) {
    const std::string entry = argv[next];
    const std::size_t at = entry.find('@');
    const int index = std::atoi(entry.substr(0, at).c_str());
    if (index < 0 || index >= ctl::event_count) {
      std::fprintf(stderr, \"unknown event index %s\\n\", argv[next]);
      return 2;
    }
    const ctl::Event event = static_cast<ctl::Event>(index);
    if (at == std::string::npos) {
      controller.finish_events();
      check_timeline(controller);
      controller.send_timed(event, controller.now());
    } else {
      const double time = std::strtod(entry.c_str() + at + 1, nullptr);
      if (time < controller.now()) {
        std::fprintf(stderr, \"%s arrives at %s, before now (%s): a timed controller cannot go back\\n\",
                     ctl::event_name(event), number(time).c_str(), number(controller.now()).c_str());
        return 2;
      }
      controller.send_timed(event, time, static_cast<ctl::Controller::WhenBusy>(policy));
    }
    check_timeline(controller);
  }
  if (until == \"-\") {
    controller.finish_events();
  } else {
    const double time = std::strtod(until.c_str(), nullptr);
    if (time < controller.now()) {
      std::fprintf(stderr, \"until %s lies before now (%s): a timed controller cannot go back\\n\",
                   number(time).c_str(), number(controller.now()).c_str());
      return 2;
    }
    controller.advance(time);
  }
  check_timeline(controller);
  presenter.print_rest();
  return 0;
}
")
  "The timed driver's main(): plays a timed scenario as PLAY-EVENTS does.")

(defun driver-source (name namespace &key timed)
  "A main() printing Player's trace for the controller NAME in NAMESPACE; with
TIMED, playing a timed scenario on a controller emitted with the timed layer."
  (concatenate 'string
               (format nil "// ~A_main.cpp -- generated by Player: plays events and prints the trace.
#include \"~A.hpp\"

#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace ctl = ~A;

" name name namespace)
               *driver-presenter*
               (if timed *timed-driver-presenter* "")
               *driver-presenter-end*
               (if timed *timed-driver-main* *driver-main*)))
