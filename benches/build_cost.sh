#!/usr/bin/env bash
# The release build cost of the Whipple bicycle stated from its bodies and contacts (the
# catalogue's `WhippleBicycle`) against the same bicycle written by hand
# (`tests/validation/tests/common/whipple_by_hand.rs`): each model alone in a crate of its
# own, built against hamel, which is built once beforehand. A build is the model crate's
# alone, from scratch (its source touched): the macro's expansion and the compilation of
# what it generates, with a `main` that calls the right-hand side and the Jacobian, so that
# the generated code is compiled to machine code in the crate (a library alone would leave
# its inline generic methods to the program that calls them).
#
#   bash benches/build_cost.sh setup DIR         # make the crates in DIR, build hamel
#   bash benches/build_cost.sh build DIR bodies  # one release build of the model from bodies
#   bash benches/build_cost.sh build DIR hand    # one release build of the model by hand
#   bash benches/build_cost.sh build DIR robot   # one release build of the catalogue's robots
#
# Time the two `build` commands alternately (A B A B …) and take the median of the per-pair
# ratios: the machine's speed drifts between builds. To compare two commits' builds of the same
# model, set up a DIR with this script in each commit's tree (`git archive`; the script builds
# against the tree it is in) and time their `build` commands alternately.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
command=${1:?"setup DIR | build DIR bodies|hand|robot"}
dir=${2:?"the directory to build in"}

crate() {
    local name=$1 source=$2 model=$3 state=${4:-11}
    mkdir -p "$dir/$name/src"
    cat > "$dir/$name/Cargo.toml" <<TOML
[package]
name = "$name"
version = "0.1.0"
edition = "2024"
[dependencies]
hamel = { path = "$root", default-features = false }
[profile.release]
debug = false
TOML
    sed -e 's/^use crate::hamel_system;/use hamel::hamel_system;/' \
        -e 's/^\/\/!/\/\//' "$source" > "$dir/$name/src/main.rs"
    cat >> "$dir/$name/src/main.rs" <<RS

fn main() {
    use hamel::HamelSystem;
    let model = $model;
    let x = [0.1; $state];
    let mut dx = [0.0; $state];
    let ok = model.rhs(0.0, &x, &[0.0, 0.0], &mut dx).is_ok();
    let jacobian = model.linearize(0.0, &x, &[0.0, 0.0]).is_ok();
    println!("{ok} {jacobian} {dx:?}");
}
RS
}

case "$command" in
setup)
    crate bodies "$root/hamel-models/src/whipple_bicycle.rs" "WhippleBicycle::default()"
    crate hand "$root/tests/validation/tests/common/whipple_by_hand.rs" \
        "WhippleByHand::from(&hamel::models::WhippleBicycle::default())"
    crate robot "$root/hamel-models/src/mobile_robot.rs" "MobileRobot::default()" 8
    for name in bodies hand robot; do
        (cd "$dir/$name" && CARGO_TARGET_DIR="$dir/target" cargo build --release --quiet)
    done
    ;;
build)
    name=${3:?"bodies, hand or robot"}
    touch "$dir/$name/src/main.rs"
    cd "$dir/$name" && CARGO_TARGET_DIR="$dir/target" cargo build --release --quiet
    ;;
*)
    echo "unknown command $command: setup DIR | build DIR bodies|hand|robot" >&2
    exit 2
    ;;
esac
