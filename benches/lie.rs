//! What the robot's Lie derivatives cost in right-hand-side evaluations: the generated
//! `lie_values` (the look-ahead point's L_f h, L_f² h and its decoupling matrix
//! L_g L_f h, with L_g h — everything exact input–output linearization reads) against the
//! generated right-hand side, on the same 64 seeded states. The issue's bound: at most 5
//! right-hand sides. Also the drift and input fields together (`control_affine_values`).
//!
//! Measured interleaved (`hamel_benches::interleave`): the figure is the median over the
//! rounds of the per-round ratio, with its 10th and 90th percentiles.
//!
//! ```text
//! cargo bench -p hamel-benches --bench lie
//! HAMEL_BENCH_ROUNDS=51 cargo bench -p hamel-benches --bench lie   # quicker
//! ```
//!
//! With `HAMEL_LIE_VALUES=FILE` it also writes the states and the generated values to FILE,
//! one state a line (x, then L_f^k h, then L_g L_f^k h in the order of `lie_values`): what
//! `benches/adolc_lie.sh` checks ADOL-C's Lie drivers against.

use hamel::models::MobileRobot;
use hamel::{ControlAffine, HamelSystem};
use hamel_benches::interleave::{ratio, round_robin, seconds};
use hamel_benches::robot_samples;
use std::hint::black_box;

fn main() {
    let robot = MobileRobot::default();
    let samples = robot_samples();
    if let Some(path) = std::env::var_os("HAMEL_LIE_VALUES") {
        write_values(&robot, &samples, std::path::Path::new(&path));
    }
    let mut rhs = || {
        let mut dx = [0.0; 8];
        for (x, u) in &samples {
            let ok = robot.rhs(0.0, black_box(x), black_box(u), &mut dx).is_ok();
            black_box((ok, &dx));
        }
    };
    let mut lie = || {
        for (x, _) in &samples {
            black_box(robot.lie_values(0.0, black_box(x)).is_ok());
        }
    };
    let mut fields = || {
        for (x, _) in &samples {
            black_box(robot.control_affine_values(0.0, black_box(x)).is_ok());
        }
    };
    let rounds = round_robin(&mut [&mut rhs, &mut lie, &mut fields]);
    let per_state = |v| seconds(&rounds, v).median / samples.len() as f64 * 1e9;
    let (l, f) = (ratio(&rounds, 1, 0), ratio(&rounds, 2, 0));
    println!(
        "robot, {} rounds: rhs {:.0} ns a state; lie_values {:.0} ns = {:.2} rhs (p10–p90 \
         {:.2}–{:.2}); control_affine_values {:.0} ns = {:.2} rhs (p10–p90 {:.2}–{:.2})",
        rounds.len(),
        per_state(0),
        per_state(1),
        l.median,
        l.p10,
        l.p90,
        per_state(2),
        f.median,
        f.p10,
        f.p90
    );
}

/// Each state and its generated Lie derivatives, one line each, every number to the last
/// bit (Rust's shortest representation that reads back exactly).
fn write_values(robot: &MobileRobot, samples: &[([f64; 8], [f64; 2])], path: &std::path::Path) {
    let mut text = String::new();
    for (x, _) in samples {
        let (lie, along) = robot
            .lie_values(0.0, x)
            .unwrap_or_else(|e| panic!("lie_values at {x:?}: {e}"));
        let numbers: Vec<String> = x
            .iter()
            .chain(&lie)
            .chain(&along)
            .map(|v| format!("{v:e}"))
            .collect();
        text.push_str(&numbers.join(" "));
        text.push('\n');
    }
    std::fs::write(path, text).unwrap_or_else(|e| panic!("writing {}: {e}", path.display()));
    println!(
        "wrote {} states and their Lie derivatives to {}",
        samples.len(),
        path.display()
    );
}
