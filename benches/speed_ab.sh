#!/usr/bin/env bash
# The generated right-hand side's speed at two commits, for a change to the macro: builds the
# `speed` benchmark (speed.rs) at each commit in a scratch copy of the tree, then runs the two
# programs in turn, A B A B … (B first in every other pair), each for a short run of 21 rounds,
# and prints per variant the ratio A/B of the ns per call taken pair by pair: its median and
# p10–p90. The robot's variants are first divided by the hand-written closed form (c) of the
# same run, which both programs share, so that a pair's drift in the machine's speed cancels;
# the N-trailer's are compared directly. An A/A run (one commit twice) shows the noise: about
# ±1 % p10–p90 on two busy cores.
#
#   bash benches/speed_ab.sh A_COMMIT B_COMMIT [PAIRS]     (PAIRS: 30 by default)
set -euo pipefail
a_commit=$1
b_commit=$2
pairs=${3:-30}
repo=$(git rev-parse --show-toplevel)
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
build() {
    mkdir -p "$dir/$1"
    git -C "$repo" archive "$2" | tar -x -C "$dir/$1"
    (cd "$dir/$1" && CARGO_TARGET_DIR="$dir/$1/target" cargo bench -q -p hamel-benches \
        --bench speed --no-run 2>/dev/null)
    find "$dir/$1/target/release/deps" -maxdepth 1 -type f -name 'speed-*' ! -name '*.d' \
        -exec cp {} "$dir/$1.bin" \;
}
build a "$a_commit"
build b "$b_commit"
# One run: "variant ns" lines, the robot's relative to (c).
run() {
    (cd "$repo/benches" && HAMEL_BENCH_ROUNDS=21 "$dir/$1.bin" --bench) | awk '
        /\(c\) closed form/ { c = $(NF-1) }
        /^  \((a|b)\) generated|MobileRobotPaper/ && !/unprepared/ {
            name = $0; sub(/^ +/, "", name); sub(/  +.*/, "", name); robot[name] = $(NF-1) }
        /^  stated from bodies and contacts / { robot["bicycle stated from bodies"] = $(NF-1) }
        /^ +[0-9]+ +[0-9]+ +[0-9.]+ / { print "N=" $1, $3 }
        END { for (k in robot) print k, robot[k] / c }'
}
for i in $(seq "$pairs"); do
    if [ $((i % 2)) -eq 1 ]; then
        run a > "$dir/ra"; run b > "$dir/rb"
    else
        run b > "$dir/rb"; run a > "$dir/ra"
    fi
    # Pair the two runs' lines by variant: "variant ratio".
    awk 'NR == FNR { v = $NF; $NF = ""; a[$0] = v; next }
         { v = $NF; $NF = ""; if ($0 in a) print $0 "\t" a[$0] / v }' "$dir/ra" "$dir/rb" \
        >> "$dir/ratios"
done
echo "A = $a_commit, B = $b_commit, $pairs pairs: ratio A/B of ns per call (median, p10–p90)"
sort -t"$(printf '\t')" -k1,1 -k2,2g "$dir/ratios" | awk -F'\t' '
    function report() { if (n) printf "  %-45s %.3f  %.3f–%.3f\n", key, v[int(n / 2) + 1],
                                v[int(0.1 * (n - 1) + 1.5)], v[int(0.9 * (n - 1) + 1.5)] }
    $1 != key { report(); key = $1; n = 0 }
    { v[++n] = $2 }
    END { report() }'
