# player-core.sh -- sourced by the valgrind benchmarks (instructions.sh,
# instructions-profile.sh): REQUIRE_TOOL, and MAKE_CORE, a core with Player
# and the benchmarks loaded in a temporary directory $work, run as $lisp, so
# valgrind counts only the events, not loading the system.
SBCL=${SBCL:-sbcl}

# require_tool TOOL PACKAGE: one clear error, naming the Debian package, unless TOOL is there.
require_tool () {
  if ! command -v "$1" >/dev/null 2>&1; then
    echo "player: error: $1 is not installed (Debian package $2: apt-get install $2)" >&2
    exit 1
  fi
}

# make_core [ENGINE]: build the core in a fresh $work (removed on exit); set
# $lisp.  ENGINE is checked (the default build) or unchecked: Player built
# with :player-unchecked-engine, its fasls in build/unchecked-engine/ as
# `make test-unchecked-engine' builds them (t/unchecked-engine.lisp).
make_core () {
  work=${work:-$(mktemp -d)}
  trap 'rm -rf "$work"' EXIT
  case "${1:-checked}" in
    checked) engine_form='nil' ;;
    unchecked) engine_form='(progn (load "t/unchecked-engine.lisp") (pushnew :player-unchecked-engine *features*)
                 (asdf:initialize-output-translations (unchecked-engine-output-translations (truename "./"))))' ;;
    *) echo "player: error: make_core: engine $1 is neither checked nor unchecked" >&2; exit 1 ;;
  esac
  "$SBCL" --noinform --no-sysinit --no-userinit --disable-debugger --non-interactive \
    --eval '(require :asdf)' --eval '(push (truename ".") asdf:*central-registry*)' \
    --eval "$engine_form" \
    --eval '(handler-bind ((warning (function muffle-warning))) (asdf:load-system "player"))' \
    --load bench/run.lisp --load bench/instructions.lisp \
    --eval "(sb-ext:save-lisp-and-die \"$work/player-${1:-checked}.core\")" >/dev/null
  lisp="$SBCL --core $work/player-${1:-checked}.core --noinform --no-sysinit --no-userinit --disable-debugger --non-interactive"
}
