  if (next + 1 >= argc) {
    std::fprintf(stderr, "missing UNTIL or POLICY\n");
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
      std::fprintf(stderr, "unknown event index %s\n", argv[next]);
      return 2;
    }
    const ctl::Event event = static_cast<ctl::Event>(index);
    if (at == std::string::npos) {
      controller.finish_events();
      check_timeline(controller);
      controller.send_timed(event, controller.now());
    } else {
      ctl::Time time;
      if (!ctl::parse_time(entry.substr(at + 1), time)) {
        std::fprintf(stderr, "bad time in %s\n", argv[next]);
        return 2;
      }
      if (time < controller.now()) {
        std::fprintf(stderr, "%s arrives at %s, before now (%s): a timed controller cannot go back\n",
                     ctl::event_name(event), number(time).c_str(), number(controller.now()).c_str());
        return 2;
      }
      controller.send_timed(event, time, static_cast<ctl::Controller::WhenBusy>(policy));
    }
    check_timeline(controller);
  }
  if (until == "-") {
    controller.finish_events();
  } else {
    ctl::Time time;
    if (!ctl::parse_time(until, time)) {
      std::fprintf(stderr, "bad time %s\n", until.c_str());
      return 2;
    }
    if (time < controller.now()) {
      std::fprintf(stderr, "until %s lies before now (%s): a timed controller cannot go back\n",
                   number(time).c_str(), number(controller.now()).c_str());
      return 2;
    }
    controller.advance(time);
  }
  check_timeline(controller);
  presenter.print_rest();
  return 0;
}

