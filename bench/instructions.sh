#!/bin/sh
# instructions.sh -- instructions per Peedy event, counted by valgrind's
# cachegrind: through a timed controller (half the events preempting, as
# `make bench` sends them) and through the whole-event API.  This machine's
# speed swings by 2x within seconds, so timings cannot tell two builds 10 %
# apart; these counts can (they are the same on every run of one build).
# Also shows the level-1 instruction-cache misses per event: the timed
# controller's code once did not fit the cache.  Run by `make bench-instructions`.
set -e
SBCL=${SBCL:-sbcl}
if ! command -v valgrind >/dev/null 2>&1; then
  echo "player: error: valgrind is not installed (Debian package valgrind: apt-get install valgrind)" >&2
  exit 1
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# A core with Player and the benchmarks loaded: valgrind then runs only the events.
"$SBCL" --noinform --no-sysinit --no-userinit --disable-debugger --non-interactive \
  --eval '(require :asdf)' --eval '(push (truename ".") asdf:*central-registry*)' \
  --eval '(handler-bind ((warning (function muffle-warning))) (asdf:load-system "player"))' \
  --load bench/run.lisp --load bench/instructions.lisp \
  --eval "(sb-ext:save-lisp-and-die \"$work/player.core\")" >/dev/null
# cachegrind's totals for KIND (timed or whole) and PASSES passes after the warm-up:
# instructions, I1 misses, D1 misses.
count () {
  valgrind --tool=cachegrind --cache-sim=yes --cachegrind-out-file=/dev/null \
    "$SBCL" --core "$work/player.core" --noinform --no-sysinit --no-userinit --disable-debugger \
    --non-interactive --eval "(player-bench::instructions-workload :$1 $2)" 2>&1 |
    awk '/I   refs:/ {gsub(",", "", $4); i = $4} /I1  misses:/ {gsub(",", "", $4); i1 = $4}
         /D1  misses:/ {gsub(",", "", $4); d1 = $4} END {print i, i1, d1}'
}
for kind in timed whole; do
  set -- $(count $kind 0) $(count $kind 2)
  # Two passes of 20,000 events each, less the warm-up run's counts.
  awk -v kind=$kind -v i0=$1 -v a0=$2 -v d0=$3 -v i2=$4 -v a2=$5 -v d2=$6 'BEGIN {
    printf "%-6s %6.0f instructions, %5.1f I1 misses, %5.1f D1 misses per event\n",
           kind, (i2 - i0) / 40000, (a2 - a0) / 40000, (d2 - d0) / 40000 }'
done
