//! B = A(q)⁻¹ derived at compile time must not add singularities of its own: the robot, which
//! gives no inverse, has B in closed form from its block structure (a rotation block in
//! (ẋ, ẏ) whose determinant sin²ϑ + cos²ϑ folds to 1, the pitch row, and the wheels' block
//! with determinant −r²/b). A solve that divided by sin ϑ or cos ϑ would fail at headings
//! ϑ = ±90° or 0°, 180°; these states, and a run that turns through all of them, must agree
//! with the hand-written closed form (`common/robot_closed_form.rs`).

use crate::common::robot_closed_form::robot_rhs;
use hamel::models::MobileRobot;
use hamel::{DormandPrince, HamelSystem, Simulation};
use std::f64::consts::{FRAC_PI_2, PI};

/// The wheel angles (φ₁, φ₂) that give the heading ϑ = r(φ₁ − φ₂)/b.
fn wheels_for(robot: &MobileRobot, theta: f64) -> (f64, f64) {
    let half = 0.5 * theta * robot.b / robot.r;
    (0.3 + half, 0.3 - half)
}

#[test]
fn headings_where_a_sine_or_cosine_vanishes_are_regular() {
    let robot = MobileRobot::default();
    let mut worst = 0.0f64;
    for theta in [FRAC_PI_2, -FRAC_PI_2, 0.0, PI, -PI, 3.0 * FRAC_PI_2] {
        let (phi1, phi2) = wheels_for(&robot, theta);
        for (alpha, w) in [(0.3, [0.2, 0.5, 0.4]), (-1.1, [-0.7, 1.3, -2.0])] {
            let x = [0.4, -0.2, alpha, phi1, phi2, w[0], w[1], w[2]];
            let u = [0.3, -0.1];
            let (mut generated, mut closed) = ([0.0; 8], [0.0; 8]);
            robot
                .rhs(0.0, &x, &u, &mut generated)
                .unwrap_or_else(|e| panic!("ϑ = {theta}: {e:?}"));
            robot_rhs(&robot, &x, &u, &mut closed);
            for (g, c) in generated.iter().zip(&closed) {
                let e = (g - c).abs() / c.abs().max(1.0);
                assert!(e <= 1e-13, "ϑ = {theta}: {generated:?} vs {closed:?}");
                worst = worst.max(e);
            }
        }
    }
    println!("generated against closed form at ϑ ∈ {{±90°, 0°, ±180°, 270°}}: {worst:.1e}");
}

#[test]
fn a_run_turning_through_every_axis_direction_stays_exact() {
    let robot = MobileRobot::default();
    // Yawing at 1.5 rad/s for 6 s: the heading passes ±90° and 180° several times.
    let x0 = [0.0, 0.0, 0.2, 0.0, 0.0, 0.0, 0.6, 1.5];
    let run = Simulation::new(&robot, x0)
        .end_time(6.0)
        .sample_interval(0.01)
        .run_constant(&DormandPrince::new(1e-11, 1e-13), [0.0, 0.0])
        .expect("no singularity on the way");
    let summary = run.summary();
    println!("{summary}");
    assert!(summary.singular_crossings.is_empty());
    assert!(summary.relative_energy_drift < 1e-8, "{summary}");
    let (phi1, phi2) = (run.column("phi1").unwrap(), run.column("phi2").unwrap());
    let last = run.len() - 1;
    let theta_end = robot.r * (phi1[last] - phi2[last]) / robot.b;
    assert!(theta_end > 2.0 * PI, "turned through ϑ = {theta_end}");
    // The recorded motion satisfies the closed form's equations: its right-hand side at
    // each sample equals the generated one.
    for i in 0..run.len() {
        let x: [f64; 8] = std::array::from_fn(|k| run.column(MobileRobot::STATE[k]).unwrap()[i]);
        let (mut generated, mut closed) = ([0.0; 8], [0.0; 8]);
        robot.rhs(0.0, &x, &[0.0, 0.0], &mut generated).unwrap();
        robot_rhs(&robot, &x, &[0.0, 0.0], &mut closed);
        for (g, c) in generated.iter().zip(&closed) {
            assert!(
                (g - c).abs() <= 1e-12 * c.abs().max(1.0),
                "t = {}",
                run.times()[i]
            );
        }
    }
}
