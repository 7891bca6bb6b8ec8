  ctl::State state = ctl::initial_state();
  const int pairs = argc > 1 ? std::atoi(argv[1]) : 0;
  int next = 2;
  for (int i = 0; i < pairs; ++i, next += 2) {
    if (next + 1 >= argc || !ctl::assign(state, argv[next], argv[next + 1])) {
      std::fprintf(stderr, "bad initial value %s\n", next < argc ? argv[next] : "(missing)");
      return 2;
    }
  }

