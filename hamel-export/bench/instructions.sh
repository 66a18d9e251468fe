#!/usr/bin/env bash
# Instructions per call of the exported robot's CasADi functions (f, jac_, fwd1_, fwd2_,
# fwd4_, fwd8_, adj1_, jac_adj1_), counted by valgrind's callgrind: a measure of the calls' work that the
# machine's load does not move. The difference of two runs (CALLS and 2 CALLS) cancels the
# program's start-up. With PYTHON (which has casadi: the venv .ci/run makes), the same for
# CasADi's generated C of the SX robot (as run.sh builds it), on the same arguments.
#
#   hamel-export/bench/instructions.sh OUTDIR [PYTHON]
#
# OUTDIR holds libmobile_robot.so (`cargo run --release --example export -- casadi
# mobile_robot OUTDIR`). Needs cc and valgrind. Add --tool=callgrind's report
# (callgrind_annotate) by hand to see where they go.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
outdir="$(cd "$1" && pwd)"
python="${2:-}"
calls=20000
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cc -O2 -o "$work/per_call" "$here/per_call.c" -ldl
count() {
    valgrind --tool=callgrind --callgrind-out-file="$work/out" "$work/per_call" "$1" "$2" "$3" \
        2>&1 | sed -n 's/.*refs: *//p' | tr -d ,
}
per_call() {
    local one two
    one=$(count "$1" "$2" "$calls")
    two=$(count "$1" "$2" $((2 * calls)))
    echo $(( (two - one) / calls ))
}
if [ -n "$python" ]; then
    "$python" - "$work" <<PY
import sys
sys.path.insert(0, "$here/../nmpc")
import robot_parking
robot_parking.casadi_generated_c(sys.argv[1])
PY
fi
printf '%-10s %8s %8s\n' function hamel "${python:+CasADi C}"
for prefix in "" jac_ fwd1_ fwd2_ fwd4_ fwd8_ adj1_ jac_adj1_; do
    hamel=$(per_call "$outdir/libmobile_robot.so" "${prefix}mobile_robot_f")
    theirs=""
    [ -n "$python" ] && theirs=$(per_call "$work/librobot_sx.so" "${prefix}robot_sx")
    printf '%-10s %8s %8s\n' "${prefix}f" "$hamel" "$theirs"
done
