#!/usr/bin/env bash
# The build cost of diffsol, measured for the choice of the stiff integrator (see the module
# documentation of hamel-runtime/src/integrate/radau.rs): fresh builds, debug then release, of
# a crate with what hamel-runtime already depends on (nalgebra without default features,
# num-dual) and of the same crate with diffsol added (default features off, its nalgebra
# backend only) and a BDF solve of Robertson's problem through it. Prints wall and CPU time of
# each build. Needs crates.io; takes a few minutes.
#
#   bash benches/diffsol_build_cost.sh
set -euo pipefail
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
mkdir -p "$dir/base/src" "$dir/with/src"
cat > "$dir/base/Cargo.toml" <<'TOML'
[package]
name = "base"
version = "0.1.0"
edition = "2021"
[dependencies]
nalgebra = { version = "0.35", default-features = false, features = ["std"] }
num-dual = "0.15"
TOML
cat > "$dir/base/src/main.rs" <<'RS'
fn main() {
    let m = nalgebra::DMatrix::<f64>::identity(3, 3);
    println!("{}", m.lu().determinant());
}
RS
sed 's/name = "base"/name = "with"/' "$dir/base/Cargo.toml" > "$dir/with/Cargo.toml"
echo 'diffsol = { version = "0.18", default-features = false, features = ["nalgebra"] }' >> "$dir/with/Cargo.toml"
cat > "$dir/with/src/main.rs" <<'RS'
use diffsol::{NalgebraLU, NalgebraMat, OdeBuilder, OdeSolverMethod};
fn main() {
    let m = nalgebra::DMatrix::<f64>::identity(3, 3);
    println!("{}", m.lu().determinant());
    // Robertson's stiff chemical kinetics with BDF and an exact Jacobian action.
    let problem = OdeBuilder::<NalgebraMat<f64>>::new()
        .rtol(1e-6)
        .atol([1e-8, 1e-10, 1e-8])
        .rhs_implicit(
            |x, _p, _t, y| {
                y[0] = -0.04 * x[0] + 1e4 * x[1] * x[2];
                y[1] = 0.04 * x[0] - 1e4 * x[1] * x[2] - 3e7 * x[1] * x[1];
                y[2] = 3e7 * x[1] * x[1];
            },
            |x, _p, _t, v, y| {
                y[0] = -0.04 * v[0] + 1e4 * (v[1] * x[2] + x[1] * v[2]);
                y[1] = 0.04 * v[0] - 1e4 * (v[1] * x[2] + x[1] * v[2]) - 6e7 * x[1] * v[1];
                y[2] = 6e7 * x[1] * v[1];
            },
        )
        .init(|_p, _t, y| { y[0] = 1.0; y[1] = 0.0; y[2] = 0.0; }, 3)
        .build()
        .unwrap();
    let mut solver = problem.bdf::<NalgebraLU<f64>>().unwrap();
    let (_, ts, _) = solver.solve(40.0).unwrap();
    println!("{} output times, the last {}", ts.len(), ts[ts.len() - 1]);
}
RS
for v in base with; do
    (cd "$dir/$v" && cargo fetch -q)
    echo "$v: $(cd "$dir/$v" && cargo tree -e normal --prefix none | sort -u | wc -l) crates"
done
for profile in dev release; do
    for v in base with; do
        rm -rf "$dir/$v/target"
        /usr/bin/time -f "$v, $profile: wall %e s, user %U s, system %S s" \
            cargo build -q --profile "$profile" --manifest-path "$dir/$v/Cargo.toml"
    done
done
(cd "$dir/with" && cargo run -q --release)
