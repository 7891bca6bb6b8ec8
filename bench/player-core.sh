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

# make_core: build the core in a fresh $work (removed on exit); set $lisp.
make_core () {
  work=$(mktemp -d)
  trap 'rm -rf "$work"' EXIT
  "$SBCL" --noinform --no-sysinit --no-userinit --disable-debugger --non-interactive \
    --eval '(require :asdf)' --eval '(push (truename ".") asdf:*central-registry*)' \
    --eval '(handler-bind ((warning (function muffle-warning))) (asdf:load-system "player"))' \
    --load bench/run.lisp --load bench/instructions.lisp \
    --eval "(sb-ext:save-lisp-and-die \"$work/player.core\")" >/dev/null
  lisp="$SBCL --core $work/player.core --noinform --no-sysinit --no-userinit --disable-debugger --non-interactive"
}
