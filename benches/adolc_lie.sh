#!/usr/bin/env bash
# The robot's Lie derivatives by ADOL-C's Lie drivers, side by side with hamel's generated
# code (the issue's "against ADOL-C's Lie drivers, if they can be built here"):
#
#   bash benches/adolc_lie.sh            # 201 rounds each
#   bash benches/adolc_lie.sh 51         # quicker
#
# ADOL-C is Debian's package libadolc-dev (2.7.2 on Debian 12, with lie/drivers.h), installed
# with apt-get when its header is missing (as root, or through password-less sudo); nothing
# of ADOL-C is in this repository. `benches/adolc/robot_lie.cpp`, this project's own code,
# tapes the robot's drift, input fields and look-ahead point and calls the drivers.
#
# It prints, from `cargo bench --bench lie`, hamel's `lie_values` in right-hand sides of the
# generated rhs, and from the C++ program the same derivatives by ADOL-C at the same 64
# states: their largest relative difference from hamel's (it exits 1 above 1e-12) and their
# cost in evaluations of the robot's right-hand side written by hand in C++. Each side is
# timed by interleaved batches against its own right-hand side, the median of the per-round
# ratios with its 10th and 90th percentiles.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
rounds=${1:-201}
out="$root/target/adolc"
mkdir -p "$out"

if [ ! -e /usr/include/adolc/lie/drivers.h ]; then
    echo "installing Debian's libadolc-dev (ADOL-C with its Lie drivers)"
    if [ "$(id -u)" = 0 ]; then
        sudo=""
    elif sudo -n true 2>/dev/null; then
        sudo="sudo -n"
    else
        echo "error: ADOL-C's header adolc/lie/drivers.h is missing and apt-get needs root:" \
            "run 'apt-get install libadolc-dev' as root, then this script again" >&2
        exit 1
    fi
    $sudo apt-get install -y -q libadolc-dev >/dev/null ||
        { $sudo apt-get update -q >/dev/null && $sudo apt-get install -y -q libadolc-dev >/dev/null; }
fi
echo "ADOL-C: Debian's libadolc-dev $(dpkg-query -W -f '${Version}' libadolc-dev 2>/dev/null || echo '(version unknown)')"

g++ -O2 -std=c++17 -Wall -o "$out/robot_lie" "$root/benches/adolc/robot_lie.cpp" -ladolc
cd "$root"
HAMEL_BENCH_ROUNDS=$rounds HAMEL_LIE_VALUES="$out/robot_lie_values.txt" \
    cargo bench -q -p hamel-benches --bench lie
"$out/robot_lie" "$out/robot_lie_values.txt" "$rounds"
