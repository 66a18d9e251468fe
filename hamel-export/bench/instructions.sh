#!/usr/bin/env bash
# Instructions per call of the exported robot's mobile_robot_f and jac_mobile_robot_f (by x
# and u), counted by valgrind's callgrind: a measure of the C boundary's own work that the
# machine's load does not move. The difference of two runs (CALLS and 2 CALLS) cancels the
# program's start-up.
#
#   hamel-export/bench/instructions.sh OUTDIR [CALLS]
#
# OUTDIR holds libmobile_robot.so (`cargo run --release --example export -- casadi
# mobile_robot OUTDIR`). Needs cc and valgrind. Add --tool=callgrind's report
# (callgrind_annotate) by hand to see where they go.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
outdir="$(cd "$1" && pwd)"
calls="${2:-100000}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cc -O2 -o "$work/per_call" "$here/per_call.c" -ldl
count() {
    valgrind --tool=callgrind --callgrind-out-file="$work/out" "$work/per_call" \
        "$outdir/libmobile_robot.so" "$1" "$2" 2>&1 | sed -n 's/.*refs: *//p' | tr -d ,
}
for name in mobile_robot_f jac_mobile_robot_f; do
    one=$(count "$name" "$calls")
    two=$(count "$name" $((2 * calls)))
    echo "$name: $(( (two - one) / calls )) instructions per call"
done
