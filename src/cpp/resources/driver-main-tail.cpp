  TracePresenter presenter;
  ctl::Controller controller(presenter, state);
  if (next >= argc) print_line(controller.state_line());
  for (; next < argc; ++next) {
    const int index = std::atoi(argv[next]);
    if (index < 0 || index >= ctl::event_count) {
      std::fprintf(stderr, "unknown event index %s\n", argv[next]);
      return 2;
    }
    controller.send(static_cast<ctl::Event>(index));
  }
  return 0;
}

