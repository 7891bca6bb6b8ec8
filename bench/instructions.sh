#!/bin/sh
# instructions.sh -- instructions per Peedy event, counted by valgrind's
# cachegrind: through a timed controller (half the events preempting, as
# `make bench` sends them) and through the whole-event API.  This machine's
# speed swings by 2x within seconds, so timings cannot tell two builds 10 %
# apart; these counts can (they are the same on every run of one build).
# Also shows the level-1 instruction-cache misses per event: the timed
# controller's code once did not fit the cache.  Counted for each build of
# ENGINES (default: checked, the default build, then unchecked, the engine
# at (safety 0) with :player-unchecked-engine).  Run by `make bench-instructions`.
set -e
. bench/player-core.sh
require_tool valgrind valgrind
ENGINES=${ENGINES:-checked unchecked}
# cachegrind's totals for KIND (timed or whole) and PASSES passes after the warm-up:
# instructions, I1 misses, D1 misses.
count () {
  valgrind --tool=cachegrind --cache-sim=yes --cachegrind-out-file=/dev/null \
    $lisp --eval "(player-bench::instructions-workload :$1 $2)" 2>&1 |
    awk '/I   refs:/ {gsub(",", "", $4); i = $4} /I1  misses:/ {gsub(",", "", $4); i1 = $4}
         /D1  misses:/ {gsub(",", "", $4); d1 = $4} END {print i, i1, d1}'
}
for engine in $ENGINES; do
  make_core $engine
  for kind in timed whole; do
    set -- $(count $kind 0) $(count $kind 2)
    # Two passes of 20,000 events each, less the warm-up run's counts.
    awk -v kind=$kind -v engine=$engine -v i0=$1 -v a0=$2 -v d0=$3 -v i2=$4 -v a2=$5 -v d2=$6 'BEGIN {
      printf "%-9s %-6s %6.0f instructions, %5.1f I1 misses, %5.1f D1 misses per event\n",
             engine, kind, (i2 - i0) / 40000, (a2 - a0) / 40000, (d2 - d0) / 40000 }'
  done
done
