#!/usr/bin/env bash
# Speed of hamel's exported robot against CasADi's generated C of the SX robot, called as
# CasADi calls external functions (interleaved batches; median per call and of the per-round
# ratios, p10-p90):
#
#   hamel-export/bench/run.sh OUTDIR PYTHON [ROUNDS] [BATCH]
#
# OUTDIR holds libmobile_robot.so (`cargo run --release --example export -- casadi
# mobile_robot OUTDIR`); PYTHON has casadi (the venv .ci/run makes). CasADi's C is generated
# by hamel-export/nmpc/robot_parking.py's `casadi_generated_c` and compiled by cc -O3.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
outdir="$(cd "$1" && pwd)"
python="$2"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
"$python" - "$work" <<PY
import sys
sys.path.insert(0, "$here/../nmpc")
import robot_parking
robot_parking.casadi_generated_c(sys.argv[1])
PY
cc -O2 -o "$work/external_speed" "$here/external_speed.c" -ldl
echo "A = hamel's mobile_robot_f, B = CasADi's generated C of the SX robot (robot_sx); load: $(uptime)"
"$work/external_speed" "$outdir/libmobile_robot.so" mobile_robot_f "$work/librobot_sx.so" robot_sx "${3:-31}" "${4:-20000}"
