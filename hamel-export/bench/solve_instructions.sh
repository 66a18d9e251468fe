#!/usr/bin/env bash
# Instructions per parking solve (callgrind), on hamel's functions and on CasADi's generated C
# of the SX robot, and how many of them are the model's functions with their sines and
# cosines: the difference of K and K + 2 solves (each after a first solve) over two, which
# cancels Python's start-up and the first solve's.
#
#   hamel-export/bench/solve_instructions.sh OUTDIR PYTHON [--constant-parameters]
#
# OUTDIR holds libmobile_robot.so; PYTHON has casadi (the venv .ci/run makes). Needs valgrind
# (a few minutes: each solve runs about 50 times slower under it).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
outdir="$(cd "$1" && pwd)"
python="$2"
shift 2
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
# Total instructions of a run, and those of the model's library and of libm's sines and
# cosines (callgrind_annotate's per-function totals); the model's exported functions' own
# instructions into $work/functions.$model.$solves.
count() {
    local model="$1" solves="$2"
    shift 2
    valgrind --tool=callgrind --callgrind-out-file="$work/out" \
        "$python" "$here/solve_split.py" "$outdir" --only "$model" --solves "$solves" "$@" \
        >/dev/null 2>&1
    callgrind_annotate --threshold=100 "$work/out" 2>/dev/null |
        sed -n 's/^ *\([0-9,]*\) .*???:\([a-z0-9_]*\(mobile_robot_f\|robot_sx\)\) \[.*/\2 \1/p' |
        tr -d , | sort >"$work/functions.$model.$solves"
    callgrind_annotate --threshold=100 "$work/out" 2>/dev/null | awk '
        /PROGRAM TOTALS/ { gsub(",", "", $1); total = $1 }
        /libmobile_robot\.so|librobot_sx\.so|:__(sin|cos|sincos)_fma/ { gsub(",", "", $1); model += $1 }
        END { print total, model }'
}
printf '%-6s %14s %14s\n' model "per solve (M)" "the model's (M)"
for model in hamel sx-c; do
    read -r total1 model1 < <(count "$model" 1 "$@")
    read -r total3 model3 < <(count "$model" 3 "$@")
    printf '%-6s %14d %14d\n' "$model" $(( (total3 - total1) / 2000000 )) $(( (model3 - model1) / 2000000 ))
done
# The exported functions' own instructions (without what they call: the compiled code of
# hamel's, the sines and cosines), per solve.
echo "the exported functions' own instructions per solve (M; hamel's compiled code is apart)"
for model in hamel sx-c; do
    join -a 2 "$work/functions.$model.1" "$work/functions.$model.3" |
        awk '{ one = (NF == 3) ? $2 : 0; printf "  %-28s %8.1f\n", $1, ($NF - one) / 2e6 }'
done
echo "load: $(uptime)"
