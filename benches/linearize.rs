//! The cost of a linearization, in right-hand-side evaluations: `HamelSystem::jacobian`
//! (dual numbers through the generated code, one pass per state or input component the
//! right-hand side depends on) against `HamelSystem::rhs`, for the Whipple bicycle (11
//! states, 2 inputs) and the paper's robot (8 states, 2 inputs).
//!
//! Measured interleaved: short batches of each alternate, and the figure is the median of
//! the per-round ratios (p10–p90 beside it), so that the machine's drifting speed cancels.
//! `cargo bench -p hamel-benches --bench linearize`.

use hamel::HamelSystem;
use hamel::models::{MobileRobot, WhippleBicycle};
use std::hint::black_box;
use std::time::Instant;

/// Rounds of interleaved batches.
const ROUNDS: usize = 201;
/// Seconds a batch should take, about.
const BATCH_SECONDS: f64 = 1e-3;

/// Mean seconds per call of `f` over a batch of `calls`.
fn batch(calls: usize, f: &mut dyn FnMut()) -> f64 {
    let start = Instant::now();
    for _ in 0..calls {
        f();
    }
    start.elapsed().as_secs_f64() / calls as f64
}

/// How many calls of `f` take about `BATCH_SECONDS`.
fn calibrate(f: &mut dyn FnMut()) -> usize {
    let once = batch(100, f).max(1e-9);
    ((BATCH_SECONDS / once) as usize).max(1)
}

/// The median and the 10th and 90th percentiles of the per-round ratio a/b.
fn interleaved(a: &mut dyn FnMut(), b: &mut dyn FnMut()) -> (f64, f64, f64, f64) {
    let (na, nb) = (calibrate(a), calibrate(b));
    let mut ratios = Vec::with_capacity(ROUNDS);
    let mut seconds_b = Vec::with_capacity(ROUNDS);
    for _ in 0..ROUNDS {
        let ta = batch(na, a);
        let tb = batch(nb, b);
        ratios.push(ta / tb);
        seconds_b.push(tb);
    }
    ratios.sort_by(f64::total_cmp);
    seconds_b.sort_by(f64::total_cmp);
    let at = |p: f64| ratios[((ROUNDS - 1) as f64 * p).round() as usize];
    (at(0.5), at(0.1), at(0.9), seconds_b[ROUNDS / 2])
}

fn report<S: HamelSystem>(name: &str, system: &S, x: S::State, u: S::Inputs) {
    let mut jacobian = || {
        black_box(system.jacobian(0.0, black_box(&x), &u).ok());
    };
    let mut rhs = || {
        let mut dx = x;
        black_box(system.rhs(0.0, black_box(&x), &u, &mut dx).ok());
        black_box(dx);
    };
    let (median, p10, p90, rhs_seconds) = interleaved(&mut jacobian, &mut rhs);
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
