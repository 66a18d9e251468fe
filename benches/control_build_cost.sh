#!/usr/bin/env bash
# The debug build cost of Lie brackets for the Whipple bicycle: the catalogue's
# `WhippleBicycle` as it is (`control(order = 2)`, no brackets) against the same model asking
# for brackets of depth 1 or 2 (`control(order = 2, brackets = D)`). Each model is alone in a
# crate of its own, built against hamel, which is built once beforehand, in the dev profile
# the test suite uses (the macro and the generated code both unoptimised): a build is the
# model crate's alone, from scratch (its source touched).
#
#   bash benches/control_build_cost.sh setup DIR          # make the crates in DIR, build hamel
#   bash benches/control_build_cost.sh build DIR plain    # the catalogue's bicycle
#   bash benches/control_build_cost.sh build DIR depth1   # with brackets = 1
#   bash benches/control_build_cost.sh build DIR depth2   # with brackets = 2
#
# Time two `build` commands alternately (A B A B …) and take the median of the per-pair
# ratios: the machine's speed drifts between builds.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
command=${1:?"setup DIR | build DIR plain|depth1|depth2"}
dir=${2:?"the directory to build in"}

crate() {
    local name=$1 control=$2
    mkdir -p "$dir/$name/src"
    cat > "$dir/$name/Cargo.toml" <<TOML
[package]
name = "$name"
version = "0.1.0"
edition = "2024"
[dependencies]
hamel = { path = "$root", default-features = false }
[profile.dev]
debug = "line-tables-only"
TOML
    sed -e 's/^use crate::hamel_system;/use hamel::hamel_system;/' \
        -e 's/^\/\/!/\/\//' -e "s/^    control(order = 2),\$/    $control,/" \
        "$root/hamel-models/src/whipple_bicycle.rs" > "$dir/$name/src/main.rs"
    grep -q "^    $control,\$" "$dir/$name/src/main.rs" || {
        echo "the bicycle's control(..) line was not found" >&2
        exit 1
    }
    cat >> "$dir/$name/src/main.rs" <<RS

fn main() {
    use hamel::{ControlAffine, HamelSystem};
    let model = WhippleBicycle::default();
    let x = [0.1; 11];
    let mut dx = [0.0; 11];
    let ok = model.rhs(0.0, &x, &[0.0, 0.0], &mut dx).is_ok();
    let lie = model.lie_derivatives(0.0, &x).is_ok();
    let brackets = model.lie_brackets(0.0, &x).is_ok();
    println!("{ok} {lie} {brackets} {dx:?}");
}
RS
}

case "$command" in
setup)
    crate plain "control(order = 2)"
    crate depth1 "control(order = 2, brackets = 1)"
    crate depth2 "control(order = 2, brackets = 2)"
    for name in plain depth1 depth2; do
        (cd "$dir/$name" && CARGO_TARGET_DIR="$dir/target" cargo build --quiet)
    done
    ;;
build)
    name=${3:?"plain, depth1 or depth2"}
    touch "$dir/$name/src/main.rs"
    cd "$dir/$name" && CARGO_TARGET_DIR="$dir/target" cargo build --quiet
    ;;
*)
    echo "unknown command $command: setup DIR | build DIR plain|depth1|depth2" >&2
    exit 2
    ;;
esac
