#!/usr/bin/env bash
# The work–precision comparison of benches/work_precision.rs: hamel's Radau5 and Rodas5P (with
# the exact Jacobian and as a user's Ode without one), scipy's Radau, BDF and LSODA
# (scipy_stiff.py, in a Python venv made here, numpy and scipy from PyPI), Hairer's RADAU5 and
# RODAS through Assimulo (hairer_stiff.py, PyPI's assimulo-testing wheel) and diffsol's BDF and
# ESDIRK34 (the crate benches/work_precision/diffsol, which the workspace never builds), then
# the side-by-side tables and the figures (benches/work_precision/*.svg). Needs python3 and
# crates.io; the CSVs go to target/work_precision/.
#
# The machine's speed drifts, so the solvers are interleaved: ROUNDS rounds (default 5), each
# running every solver once on each problem at every tolerance (a batch of runs of at least
# 0.1 s each), problem by problem, the solver that starts moving on by one each round. The
# report takes each wall-time ratio per round before the median over the rounds.
#
#   bash benches/work_precision/run.sh [ROUNDS]
#
# A ratio at one of these eight tolerances compares two scattered curves (HIRES: scipy Radau's
# error falls 83 times from rtol 1e-4 to 1e-5); trend.py fits each curve's trend on a finer
# grid of tolerances and compares those.
set -euo pipefail
rounds=${1:-5}
root=$(cd "$(dirname "$0")/../.." && pwd)
out="$root/target/work_precision"
mkdir -p "$out"
if [ ! -x "$out/venv/bin/python" ]; then
    python3 -m venv "$out/venv"
    "$out/venv/bin/pip" install -q numpy scipy
fi
if ! "$out/venv/bin/python" -c 'import assimulo' 2>/dev/null; then
    "$out/venv/bin/pip" install -q --only-binary :all: assimulo-testing==3.9.0b2
fi
python="$out/venv/bin/python"
"$python" -c 'import numpy, scipy; print("numpy", numpy.__version__, "scipy", scipy.__version__)'
cargo build -q --release --manifest-path "$root/benches/work_precision/diffsol/Cargo.toml" \
    --target-dir "$out/diffsol-target"
hamel=$(cd "$root" && cargo bench -q -p hamel-benches --bench work_precision --no-run \
    --message-format=json | "$python" -c '
import json, sys
for line in sys.stdin:
    m = json.loads(line)
    if m.get("target", {}).get("name") == "work_precision" and m.get("executable"):
        print(m["executable"])')

run() { # solver round problem
    case $1 in
        hamel) "$hamel" round "$2" "$3" ;;
        scipy) "$python" "$root/benches/work_precision/scipy_stiff.py" "$out/scipy.csv" "$2" "$3" ;;
        hairer) "$python" "$root/benches/work_precision/hairer_stiff.py" "$out/hairer.csv" "$2" "$3" ;;
        diffsol) "$out/diffsol-target/release/work-precision-diffsol" "$out/diffsol.csv" "$2" "$3" ;;
    esac
}

rm -f "$out/hamel.csv" "$out/scipy.csv" "$out/hairer.csv" "$out/diffsol.csv"
solvers=(hamel scipy hairer diffsol)
for round in $(seq 1 "$rounds"); do
    echo "round $round of $rounds, load average: $(cut -d' ' -f1-3 /proc/loadavg)"
    for problem in ROBER VDPOL HIRES OREGO POLLU; do
        for i in 0 1 2 3; do
            run "${solvers[(round + i) % 4]}" "$round" "$problem"
        done
    done
    # Problems of hamel's alone (no ratio to take), for its table and figures.
    run hamel "$round" "stiff disk"
    run hamel "$round" "stiff robot"
done
"$hamel" report
