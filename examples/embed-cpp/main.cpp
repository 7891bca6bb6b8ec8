// main.cpp -- embedding a Player controller in a C++ program.
//
// `make embed-example` generates peedy.hpp/peedy.cpp from specs/peedy.lisp
// (bin/player emit-c++), compiles them with this file, and runs the papers'
// scenario. A real application would play animations in ConsolePresenter::play
// and return their lengths; here we print what would be played.
#include "peedy.hpp"

#include <cstdio>

namespace {

class ConsolePresenter : public peedy::Presenter {
public:
  double play(const peedy::Op& op, peedy::Time start) override {
    std::printf("%7.2f  play %-14s (script %s, %.2f s)\n", start.to_double(), op.name, op.script, op.duration);
    return op.duration;
  }
  void macro_start(const peedy::Op& op, peedy::Time start) override {
    std::printf("%7.2f  begin %s\n", start.to_double(), op.name);
  }
  void start_autoscript(const char* proc, const char* variable, const char* value,
                        peedy::Time time) override {
    std::printf("%7.2f  start autoscript %s (%s = %s)\n", time.to_double(), proc, variable, value);
  }
  void stop_autoscript(const char* proc, const char*, const char*, peedy::Time time) override {
    std::printf("%7.2f  stop autoscript %s\n", time.to_double(), proc);
  }
  void event_start(const char* event, peedy::Time time) override {
    std::printf("%7.2f  event %s\n", time.to_double(), event);
  }
  void event_failed(const char* event, const char* goal, peedy::Time time) override {
    std::printf("%7.2f  %s failed: cannot reach %s\n", time.to_double(), event, goal);
  }
};

}  // namespace

int main() {
  ConsolePresenter presenter;
  peedy::State asleep = peedy::initial_state();
  peedy::assign(asleep, "alert", "snore");
  peedy::assign(asleep, "posture", "sit");
  peedy::Controller peedy(presenter, asleep);

  const peedy::Event scenario[] = {peedy::Event::ev_search, peedy::Event::ev_search,
                                   peedy::Event::ev_bad_speech, peedy::Event::ev_thanks};
  for (peedy::Event event : scenario) {
    peedy.send(event);
    std::printf("         %s\n", peedy.state_line().c_str());
  }
  return 0;
}
