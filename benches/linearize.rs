//! The cost of a linearization, in right-hand-side evaluations: `HamelSystem::jacobian`
//! (dual numbers through the generated code, one pass per state or input component the
//! right-hand side depends on) against `HamelSystem::rhs`, for the Whipple bicycle (11
//! states, 2 inputs) and the paper's robot (8 states, 2 inputs).
//!
//! Measured interleaved: short batches of each alternate, and the figure is the median of
//! the per-round ratios (p10–p90 beside it), so that the machine's drifting speed cancels.
//! `cargo bench -p hamel-benches --bench linearize` (`HAMEL_BENCH_ROUNDS=21` for a quick run).

use hamel::HamelSystem;
use hamel::models::{MobileRobot, WhippleBicycle};
use hamel_benches::interleave::{Spread, interleaved};
use std::hint::black_box;

fn report<S: HamelSystem>(name: &str, system: &S, x: S::State, u: S::Inputs) {
    let mut jacobian = || {
        black_box(system.jacobian(0.0, black_box(&x), &u).ok());
    };
    let mut rhs = || {
        let mut dx = x;
        black_box(system.rhs(0.0, black_box(&x), &u, &mut dx).ok());
        black_box(dx);
    };
    let (
        Spread {
            median, p10, p90, ..
        },
        rhs_seconds,
    ) = interleaved(&mut jacobian, &mut rhs);
    println!(
        "{name}: jacobian / rhs = {median:.1} (p10–p90 {p10:.1}–{p90:.1}), rhs {:.3} µs",
        rhs_seconds * 1e6
    );
}

fn main() {
    let bike = WhippleBicycle::default();
    let x = bike
        .state_builder()
        .set("phi", 0.05)
        .set("delta", -0.02)
        .set("roll_rate", 0.1)
        .set("steer_rate", -0.3)
        .set("rear_wheel_rate", -4.6 / bike.r_r)
        .build()
        .expect("a consistent state");
    report("Whipple bicycle (11 states)", &bike, x, [0.0, 0.0]);
    let robot = MobileRobot::default();
    report(
        "mobile robot (8 states)",
        &robot,
        [0.1, 0.2, 0.3, 0.4, 0.5, 0.1, 0.5, 0.4],
        [0.1, -0.1],
    );
}
