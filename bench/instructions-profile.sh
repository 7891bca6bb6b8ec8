#!/bin/sh
# instructions-profile.sh -- where a timed Peedy event's instructions go, per
# function, counted exactly by valgrind's callgrind (make bench-profile).
# callgrind cannot follow SBCL's signals through start-up, so it starts with
# counting off and is switched on for one pass of 20,000 events; its
# addresses are named with a map of the core's code written by a native run
# (under valgrind the heap is moved by a constant, found from one function).
# ENGINE=unchecked profiles the build with :player-unchecked-engine.
set -e
. bench/player-core.sh
require_tool valgrind valgrind
require_tool callgrind_control valgrind
require_tool python3 python3
make_core "${ENGINE:-checked}"
$lisp --eval "(player-bench::write-code-map \"$work/native.map\")" \
      --eval "(player-bench::write-anchor \"$work/native-anchor\")"
valgrind --tool=callgrind --instr-atstart=no --dump-instr=yes --callgrind-out-file="$work/callgrind.out" \
  $lisp --eval "(player-bench::profiled-workload \"$work/\")" >"$work/valgrind.log" 2>&1 &
while [ ! -f "$work/ready" ]; do sleep 1; done
callgrind_control -i on >/dev/null 2>&1
while [ ! -f "$work/done" ]; do sleep 1; done
callgrind_control -i off >/dev/null 2>&1
callgrind_control -d >/dev/null 2>&1
wait
python3 - "$work" <<'PY'
import bisect, glob, sys
work = sys.argv[1]
shift = int(open(work + '/anchor').read(), 16) - int(open(work + '/native-anchor').read(), 16)
ranges = []
for line in open(work + '/native.map'):
    fields = line.rstrip('\n').split(' ', 2)
    if len(fields) == 3:            # a name holding a newline goes on over lines
        ranges.append((int(fields[0], 16) + shift, int(fields[1], 16), fields[2]))
ranges.sort()
starts = [r[0] for r in ranges]
def name(address):
    i = bisect.bisect_right(starts, address) - 1
    if i >= 0 and address < ranges[i][0] + ranges[i][1]:
        return ranges[i][2]
    return 'outside Lisp code'
cost, address, after_call = {}, 0, False
dump = max(glob.glob(work + '/callgrind.out*'), key=lambda p: len(open(p).read()))
for line in open(dump):
    if line.startswith('calls='):
        after_call = True          # the next line is a call's inclusive cost
        continue
    if not line or line[0] not in '0123456789+-*':
        continue
    fields = line.split()
    token = fields[0]
    if token.startswith('0x'): address = int(token, 16)
    elif token[0] == '+': address += int(token[1:])
    elif token[0] == '-': address -= int(token[1:])
    if after_call:
        after_call = False
        continue
    if len(fields) >= 3:
        key = name(address)
        cost[key] = cost.get(key, 0) + int(fields[2])
events = 20000
total = sum(cost.values())
print("%d instructions per timed event, one pass of %d events; each row counts the instructions of that function's own code" % (total / events, events))
for key, value in sorted(cost.items(), key=lambda kv: -kv[1])[:40]:
    print('%8.1f  %5.1f%%  %s' % (value / events, 100.0 * value / total, key))
PY
