// main.cpp -- two Peedys in one C++ program: a scene of several characters.
//
// The generated controller holds no global state, so one program runs any
// number of independent instances over the same compiled plans (the C++
// counterpart of `defscene`).  Each member here has its own Presenter and
// Controller; events are addressed as in Player's scenes, MEMBER/EVENT or
// all/EVENT, and reach only the members they name.
//
// `make embed-scene-example` generates peedy.hpp/peedy.cpp from
// specs/peedy.lisp (bin/player emit-c++), compiles them with this file and
// runs it.  Each output line is prefixed with its member's name.
#include "peedy.hpp"

#include <cstdio>
#include <string>
#include <vector>

namespace {

// Prints what a member's body would play, prefixed with the member's name.
class MemberPresenter : public peedy::Presenter {
public:
  explicit MemberPresenter(std::string name) : name_(std::move(name)) {}
  double play(const peedy::Op& op, peedy::Time start) override {
    std::printf("%s: %6.2f  play %s (%.2f s)\n", name_.c_str(), start.to_double(), op.name, op.duration);
    return op.duration;
  }
  void event_start(const char* event, peedy::Time time) override {
    std::printf("%s: %6.2f  event %s\n", name_.c_str(), time.to_double(), event);
  }
  void event_failed(const char* event, const char* goal, peedy::Time time) override {
    std::printf("%s: %6.2f  %s failed: cannot reach %s\n", name_.c_str(), time.to_double(), event, goal);
  }

private:
  std::string name_;
};

struct Member {
  std::string name;
  MemberPresenter presenter;
  peedy::Controller controller;
  Member(const std::string& member, const peedy::State& initial)
      : name(member), presenter(member), controller(presenter, initial) {}
};

// Send ADDRESS (MEMBER/EVENT or all/EVENT) to the members it names; false
// when it names no member or no event.
bool send(std::vector<Member*>& scene, const std::string& address) {
  std::string::size_type slash = address.find('/');
  if (slash == std::string::npos) return false;
  std::string who = address.substr(0, slash);
  peedy::Event event;
  if (!peedy::find_event(address.substr(slash + 1).c_str(), event)) return false;
  bool found = false;
  for (Member* member : scene) {
    if (who == "all" || who == member->name) {
      member->controller.send(event);
      found = true;
    }
  }
  return found;
}

}  // namespace

int main() {
  peedy::State awake = peedy::initial_state();
  peedy::State asleep = peedy::initial_state();
  peedy::assign(asleep, "alert", "snore");
  peedy::assign(asleep, "posture", "sit");
  Member left("left", awake);
  Member right("right", asleep);
  std::vector<Member*> scene = {&left, &right};

  const char* scenario[] = {"left/ev-search", "right/ev-thanks", "all/ev-hop"};
  for (const char* address : scenario) {
    if (!send(scene, address)) {
      std::printf("no member or event: %s\n", address);
      return 1;
    }
  }
  for (Member* member : scene) {
    std::printf("%s: %s\n", member->name.c_str(), member->controller.state_line().c_str());
  }
  return 0;
}
