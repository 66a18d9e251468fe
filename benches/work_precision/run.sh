#!/usr/bin/env bash
# The work–precision comparison of benches/work_precision.rs in one run: scipy's Radau and
# BDF (a Python venv made here, numpy and scipy from PyPI), diffsol's BDF and SDIRK (the
# crate benches/work_precision/diffsol, which the workspace never builds), then hamel's
# Radau5, the side-by-side tables and the figures (benches/work_precision/*.svg). Needs
# python3 and crates.io; the CSVs go to target/work_precision/.
#
#   bash benches/work_precision/run.sh
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
out="$root/target/work_precision"
mkdir -p "$out"
if [ ! -x "$out/venv/bin/python" ]; then
    python3 -m venv "$out/venv"
    "$out/venv/bin/pip" install -q numpy scipy
fi
"$out/venv/bin/python" -c 'import numpy, scipy; print("numpy", numpy.__version__, "scipy", scipy.__version__)'
"$out/venv/bin/python" "$root/benches/work_precision/scipy_stiff.py" "$out/scipy.csv"
if [ -f "$root/benches/work_precision/diffsol/Cargo.toml" ]; then
    cargo run -q --release --manifest-path "$root/benches/work_precision/diffsol/Cargo.toml" \
        --target-dir "$out/diffsol-target" -- "$out/diffsol.csv"
fi
cd "$root" && cargo bench -q -p hamel-benches --bench work_precision
