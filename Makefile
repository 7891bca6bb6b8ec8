# Player -- the two commands a newcomer needs: `make demo` and `make test`.
SBCL ?= sbcl
LISP = $(SBCL) --noinform --no-sysinit --no-userinit --disable-debugger --non-interactive \
       --eval '(require :asdf)' --eval '(push (truename ".") asdf:*central-registry*)'
DEBIAN_PACKAGES = $(shell grep -v '^\#' .ci/debian-packages)
CXXFLAGS = -std=c++17 -O2 -Wall -Wextra -Werror -pedantic

.PHONY: demo demo-policies demo-cradle demo-spheres demo-dialogue demo-model test test-fast test-times test-unchecked-engine bench bench-instructions bench-profile fuzz deps embed-example embed-scene-example golden

# Install the Debian packages Player needs, when some are missing.
deps:
	@missing=""; for p in $(DEBIAN_PACKAGES); do \
	  dpkg -s $$p >/dev/null 2>&1 || missing="$$missing $$p"; done; \
	if [ -n "$$missing" ]; then \
	  echo "installing:$$missing"; \
	  if [ "$$(id -u)" = 0 ]; then SUDO=""; else SUDO=sudo; fi; \
	  $$SUDO apt-get update -q && $$SUDO apt-get install -y -q $$missing; \
	fi

# Peedy's scenario from the papers, drawn: asleep; ev-search; ev-search; ev-bad-speech; ev-thanks.
demo: deps
	bin/player render specs/peedy.lisp --initial alert=snore,posture=sit \
	  --events ev-search,ev-search,ev-bad-speech,ev-thanks --out demo

# CHI'95's open problem drawn: Peedy flies off, is told to sit 2 s later; one
# row per :when-busy policy (queue, preempt, override, interleave).
demo-policies: deps
	bin/player render specs/peedy.lisp --events ev-fly-to@0,ev-sit@2 \
	  --policies queue,preempt,override,interleave --size 320x240 --out demo

# Newton's cradle (Clark & Palmer's transition systems, specs/newtons-cradle.lisp):
# spheres lifted and let go, planned and drawn into demo/cradle/START/, with
# demo/cradle/START/cradle.mp4 when ffmpeg is installed. START names the starting
# configuration, an event of the spec without its ev-: lift-two-left (the default),
# simple-example-animation (the paper's Figure 10: one lifted) or
# more-complex-example (its Figure 11: one at one end, two at the other).
START ?= lift-two-left
demo-cradle: deps
	bin/player render specs/newtons-cradle.lisp --events ev-$(START) --out demo/cradle/$(START) \
	  $$(command -v ffmpeg >/dev/null 2>&1 && echo --video demo/cradle/$(START)/cradle.mp4)

# Clark & Palmer's first example (specs/bouncing-spheres.lisp): two spheres from
# the upper surface collide, bounce off each other, hit the lower surface and
# part (the paper's Figure 3.3), drawn into demo/spheres/, with
# demo/spheres/spheres.mp4 when ffmpeg is installed.
demo-spheres: deps
	bin/player render specs/bouncing-spheres.lisp --events ev-figure-3-3 --out demo/spheres \
	  $$(command -v ffmpeg >/dev/null 2>&1 && echo --video demo/spheres/spheres.mp4)

# A character nobody here made (examples/wuson/): Assimp's Testwuson.X walks,
# looks at the camera, runs and is stopped mid-stride (ev-stop preempts);
# drawn into demo/model/ with demo/model/wuson.mp4 when ffmpeg is installed.
demo-model: deps
	bin/player render examples/wuson/wuson.lisp --events ev-walk@0,ev-look@1.5,ev-run@3,ev-stop@4.2 \
	  --at 5.5 --out demo/model \
	  $$(command -v ffmpeg >/dev/null 2>&1 && echo --video demo/model/wuson.mp4)

# Persona's loop end to end (examples/jukebox-conversation.txt): espeak-ng says each
# request into demo/dialogue/request-NN.wav, chat --wav hears them with pocketsphinx,
# the dialogue manager answers, Peedy's body plays it and he speaks his replies with
# the beak in sync; drawn into demo/dialogue/ with speech.wav (both voices) and,
# when ffmpeg is installed, demo/dialogue/conversation.mp4.
demo-dialogue: deps
	rm -f demo/dialogue/request-*.wav
	n=0; while IFS= read -r line; do n=$$((n+1)); \
	  bin/player speak "$$line" --out "$$(printf 'demo/dialogue/request-%02d.wav' $$n)" || exit 1; \
	done < examples/jukebox-conversation.txt
	bin/player chat specs/peedy-dialogue.lisp --seed 1 --fps 12 --render demo/dialogue \
	  --wav "$$(ls demo/dialogue/request-*.wav | paste -sd, -)" \
	  $$(command -v ffmpeg >/dev/null 2>&1 && echo --video demo/dialogue/conversation.mp4)

# The timed engine's suites first on a build with :player-unchecked-engine
# (its line: unchecked-engine: N passed, N failed, N skipped), then the whole
# suite on the default, checked build, whose "N passed, N failed" ends the output.
test: deps
	$(MAKE) --no-print-directory test-unchecked-engine
	$(LISP) --load bin/load-system.lisp --eval '(or (player-build:load-checked "player/tests") (uiop:quit 1))' \
	  --eval '(asdf:test-system "player")' \
	  --eval '(sb-ext:exit :code (if (symbol-value (find-symbol "*LAST-RUN-FAILED*" "PLAYER-TESTS")) 1 0))'

# The timed engine's suites against a build with (safety 0) in the engine
# (:player-unchecked-engine, src/control/timeline/agenda.lisp), in an SBCL of
# its own with its own fasl cache (build/unchecked-engine/): `make test' runs
# it before the full suite, so the engine is tested both ways.  Its last line
# is 'unchecked-engine: N passed, N failed, N skipped'; a failure fails the target.
test-unchecked-engine: deps
	$(LISP) --load bin/load-system.lisp --load t/unchecked-engine.lisp --eval '(run-unchecked-engine-suites)'

# The fast tier, under a minute, for between edits: every suite and every test
# runs, the heavy sweeps (random seeds, specs, streams, fuzz cases) on a sample
# (SWEEP-COUNT and SWEEP-SAMPLE in t/package.lisp, which documents the tiers).
# It proves less than `make test`, which stays the suite to run before a commit.
test-fast: deps
	PLAYER_TEST_TIER=fast $(LISP) --load bin/load-system.lisp --eval '(or (player-build:load-checked "player/tests") (uiop:quit 1))' \
	  --eval '(asdf:test-system "player")' \
	  --eval '(sb-ext:exit :code (if (symbol-value (find-symbol "*LAST-RUN-FAILED*" "PLAYER-TESTS")) 1 0))'

# What each top-level suite costs, seconds and share of the whole (t/suite-times.lisp).
# PLAYER_TEST_TIER=fast times the fast tier; PLAYER_TIMES_SUITE=reachable (or
# a,b,c, or all) breaks those suites down test by test. Wall clock: on a shared
# machine, compare the shares.
test-times: deps
	PLAYER_TEST_TIER='$(PLAYER_TEST_TIER)' PLAYER_TIMES_SUITE='$(PLAYER_TIMES_SUITE)' \
	$(LISP) --load bin/load-system.lisp --eval '(or (player-build:load-checked "player/tests") (uiop:quit 1))' \
	  --load t/suite-times.lisp --eval '(player-tests::suite-times)'

# A bigger heap than SBCL's default 1 GB: (newton-cradle 8)'s merge has 20 M edges
# (bench/cradle.lisp skips a build the machine's free memory cannot hold).
bench: deps
	$(SBCL) --dynamic-space-size 20000 $(wordlist 2,100,$(LISP)) --load bin/load-system.lisp --eval '(or (player-build:load-checked "player") (uiop:quit 1))' \
	  --load bench/run.lisp --eval '(player-bench:run-benchmarks)'

# Instructions per Peedy event (timed and whole-event), counted by valgrind:
# unlike times on a shared machine, the same on every run of one build.
bench-instructions: deps
	SBCL=$(SBCL) sh bench/instructions.sh

# The same count for the timed controller, per function (valgrind's callgrind):
# where to look first.
bench-profile: deps
	SBCL=$(SBCL) sh bench/instructions-profile.sh

# The fuzzer's long run (t/fuzz-main.lisp): 50,000 mutated specs and script libraries
# through the Lisp API, 400 through bin/player, 300 mutated models (.gltf, .glb, .x)
# through bin/player model, g++ on the C++ of hostile names, 200 hostile short inputs
# under a time and memory watch.  FUZZ_SEED=N picks other cases; FUZZ_CASES,
# FUZZ_CLI_CASES, FUZZ_MODEL_CASES, FUZZ_GXX_CASES, FUZZ_BOUNDS_CASES size the run.
fuzz: deps
	FUZZ_SEED='$(FUZZ_SEED)' FUZZ_CASES='$(FUZZ_CASES)' FUZZ_CLI_CASES='$(FUZZ_CLI_CASES)' FUZZ_MODEL_CASES='$(FUZZ_MODEL_CASES)' FUZZ_GXX_CASES='$(FUZZ_GXX_CASES)' FUZZ_BOUNDS_CASES='$(FUZZ_BOUNDS_CASES)' \
	$(LISP) --load bin/load-system.lisp --eval '(or (player-build:load-checked "player/tests") (uiop:quit 1))' \
	  --load t/fuzz-main.lisp --eval '(player-tests::fuzz-main)'

# Generate Peedy's controller as C++ and run examples/embed-cpp/main.cpp on it.
embed-example: deps
	bin/player emit-c++ specs/peedy.lisp --out build/embed-cpp
	g++ $(CXXFLAGS) -Ibuild/embed-cpp examples/embed-cpp/main.cpp build/embed-cpp/peedy.cpp \
	  -o build/embed-cpp/peedy-demo
	build/embed-cpp/peedy-demo

# Two instances of Peedy's generated controller in one program: examples/embed-cpp-scene/.
embed-scene-example: deps
	bin/player emit-c++ specs/peedy.lisp --out build/embed-cpp-scene
	g++ $(CXXFLAGS) -Ibuild/embed-cpp-scene examples/embed-cpp-scene/main.cpp build/embed-cpp-scene/peedy.cpp \
	  -o build/embed-cpp-scene/peedy-scene
	build/embed-cpp-scene/peedy-scene

# Regenerate t/golden/*.png after an intended change of the look; look at them before committing.
golden: deps
	PLAYER_REGENERATE_GOLDEN=1 $(LISP) --load bin/load-system.lisp --eval '(or (player-build:load-checked "player/tests") (uiop:quit 1))' \
	  --eval "(fiveam:run! 'player-tests::render)"
