//! A run that crosses a configuration where A(q) — the constraint rows over the
//! quasi-velocity rows — is singular returns `Ok`, but its summary flags the crossing with
//! its time and configuration.
//!
//! The model: the knife edge on a level plane, free, with the quasi-velocities ẋ and φ̇
//! instead of the forward speed and φ̇. Then A = [[sin φ, −cos φ, 0], [1, 0, 0], [0, 0, 1]],
//! det A = cos φ, singular wherever the blade points along y. The motion itself is regular
//! there: φ̇ is constant (no torque; J φ̈ = 0) and the speed v is constant, so φ(t) = φ₀ + ωt
//! and the crossings are at t = (π/2 + kπ − φ₀)/ω (Neimark & Fufaev, *Dynamics of
//! Nonholonomic Systems*, ch. III; Bloch, *Nonholonomic Mechanics and Control*, §1.6). Only
//! the description fails: ẏ = ẋ tan φ is 0·∞ there, and the same run's energy drifts a
//! thousand times more after the crossing than before it.

use hamel::models::KnifeEdge;
use hamel::{DormandPrince, HamelSystem, Simulation, hamel_system, transformation_determinant};
use std::f64::consts::PI;

#[hamel_system]
#[derive(Clone, Debug, PartialEq)]
pub struct KnifeAlongX {
    /// mass (kg)
    pub m: f64,
    /// moment of inertia about the vertical (kg m²)
    pub j: f64,
}

#[hamel_system(coordinates(x, y, phi), speeds(xdot, omega))]
impl KnifeAlongX {
    #[lagrangian]
    pub fn lagrangian(&self, _q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        0.5 * self.m * (qd[0] * qd[0] + qd[1] * qd[1]) + 0.5 * self.j * qd[2] * qd[2]
    }

    #[constraints]
    pub fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [qd[0] * q[2].sin() - qd[1] * q[2].cos()]
    }

    /// ẋ, which stops determining the motion where the blade points along y.
    #[quasi_velocities]
    pub fn speeds(&self, _q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [qd[0], qd[2]]
    }
}

const MODEL: KnifeAlongX = KnifeAlongX { m: 1.0, j: 0.1 };

/// Heading φ₀, forward speed v, turning rate ω: the state from the velocities.
fn start(phi0: f64, v: f64, omega: f64) -> [f64; 5] {
    let qd = [v * phi0.cos(), v * phi0.sin(), omega];
    MODEL
        .state_from_velocities(0.0, &[0.0, 0.0, phi0], &qd)
        .expect("a regular state")
}

fn method() -> DormandPrince {
    DormandPrince::new(1e-10, 1e-12)
}

/// det A = cos φ: the determinant the runtime reads off the rows is the closed form's.
#[test]
fn determinant_is_cos_phi() {
    for phi in [-3.0, -1.0, 0.0, 0.4, PI / 2.0, 2.0, 5.0] {
        let det = transformation_determinant(&MODEL, 0.0, &[0.3, -0.2, phi]);
        assert!((det - phi.cos()).abs() <= 1e-15, "φ = {phi}: {det}");
    }
}

/// The macro says when det A depends on the parameters alone, and a run then skips the
/// watch: never for this model, whose det A is cos φ; for the catalogue's robot, sleigh and
/// N-trailer it finds them constant, and the robot's det A read off its rows is the same at
/// configurations far apart.
/// The knife edge's det A is −1 too, but through sin² + cos², which the macro does not
/// simplify there: it says false, which is safe (the watch runs).
#[test]
fn the_watch_is_skipped_only_where_det_a_is_constant() {
    use hamel::models::{ChaplyginSleigh, KnifeEdge, MobileRobot, NTrailer2, WhippleBicycle};
    let constant = [
        KnifeAlongX::TRANSFORMATION_DETERMINANT_CONSTANT,
        WhippleBicycle::TRANSFORMATION_DETERMINANT_CONSTANT,
        KnifeEdge::TRANSFORMATION_DETERMINANT_CONSTANT,
        MobileRobot::TRANSFORMATION_DETERMINANT_CONSTANT,
        ChaplyginSleigh::TRANSFORMATION_DETERMINANT_CONSTANT,
        NTrailer2::TRANSFORMATION_DETERMINANT_CONSTANT,
    ];
    assert_eq!(constant, [false, false, false, true, true, true]);
    let robot = MobileRobot::default();
    let q = [0.1, -0.2, 0.3, 0.4, -0.5];
    for phi in [0.0, 1.0, 2.0, 4.0] {
        let q = [q[0], q[1], q[2], phi, -phi];
        let det = transformation_determinant(&robot, 0.0, &q);
        let first = transformation_determinant(&robot, 0.0, &[0.0; 5]);
        assert!(
            (det - first).abs() <= 1e-12 * first.abs(),
            "{det} vs {first}"
        );
    }
}

#[test]
fn crossings_are_flagged_at_the_closed_form_times() {
    let mut worst = 0.0f64;
    for (phi0, v, omega, t_end, expected) in [
        // (φ₀, v, ω, end): the crossings (π/2 + kπ − φ₀)/ω before the end.
        (0.3, 1.0, 1.0, 5.0, vec![PI / 2.0 - 0.3, 1.5 * PI - 0.3]),
        (
            1.0,
            0.5,
            2.0,
            3.5,
            vec![
                (PI / 2.0 - 1.0) / 2.0,
                (1.5 * PI - 1.0) / 2.0,
                (2.5 * PI - 1.0) / 2.0,
            ],
        ),
        (-0.2, 2.0, -1.5, 2.0, vec![(-PI / 2.0 + 0.2) / -1.5]),
    ] {
        let run = Simulation::new(&MODEL, start(phi0, v, omega))
            .end_time(t_end)
            .sample_interval(0.05)
            .run_constant(&method(), [])
            .expect("the run itself succeeds");
        let crossings = &run.summary().singular_crossings;
        let times: Vec<f64> = crossings.iter().map(|c| c.t).collect();
        assert_eq!(
            times.len(),
            expected.len(),
            "φ₀ = {phi0}: {times:?} vs {expected:?}"
        );
        for (crossing, t) in crossings.iter().zip(&expected) {
            let error = (crossing.t - t).abs();
            assert!(
                error <= 1e-9,
                "φ₀ = {phi0}: crossing at {}, closed form {t}",
                crossing.t
            );
            let phi = crossing.configuration.get("phi").unwrap();
            assert!((phi.cos()).abs() <= 1e-9, "φ = {phi} at the crossing");
            worst = worst.max(error);
        }
        // The summary prints each crossing as a warning.
        let text = run.summary().to_string();
        assert_eq!(
            text.matches("warning: crossed a configuration").count(),
            expected.len()
        );
    }
    println!("worst crossing time error {worst:.1e}");
}

/// What the flag is for: the energy drift jumps at the crossing, while the same motion
/// described by the forward speed (the catalogue's knife edge) runs on at the tolerance's level
/// with nothing flagged.
#[test]
fn the_flag_marks_where_accuracy_is_lost() {
    let (phi0, v, omega) = (0.3, 1.0, 1.0);
    let crossing = PI / 2.0 - phi0;
    let run = Simulation::new(&MODEL, start(phi0, v, omega))
        .end_time(2.5)
        .sample_interval(0.01)
        .run_constant(&method(), [])
        .unwrap();
    let (times, energy) = (run.times(), run.column("energy").unwrap());
    let drift_in = |from: f64, to: f64| {
        times
            .iter()
            .zip(energy)
            .filter(|(t, _)| (from..to).contains(*t))
            .map(|(_, e)| (e - energy[0]).abs() / energy[0])
            .fold(0.0, f64::max)
    };
    let (before, after) = (
        drift_in(0.0, crossing - 0.05),
        drift_in(crossing + 0.05, 2.6),
    );
    println!("relative energy drift before the crossing {before:.1e}, after it {after:.1e}");
    assert!(after > 100.0 * before, "before {before:e}, after {after:e}");
    assert_eq!(run.summary().singular_crossings.len(), 1);

    let catalogue = KnifeEdge {
        incline: 0.0,
        ..KnifeEdge::default()
    };
    let x0 = catalogue
        .state_from_velocities(
            0.0,
            &[0.0, 0.0, phi0],
            &[v * phi0.cos(), v * phi0.sin(), omega],
        )
        .unwrap();
    let regular = Simulation::new(&catalogue, x0)
        .end_time(2.5)
        .sample_interval(0.01)
        .run_constant(&method(), [])
        .unwrap();
    println!(
        "forward-speed description: relative energy drift {:.1e}",
        regular.summary().relative_energy_drift
    );
    assert!(regular.summary().singular_crossings.is_empty());
    assert!(regular.summary().relative_energy_drift < after / 100.0);
}

#[test]
fn a_run_that_stays_on_one_side_is_not_flagged_and_the_check_can_be_switched_off() {
    // Turning from 0.3 rad to 1.3 rad: cos φ stays positive.
    let quiet = Simulation::new(&MODEL, start(0.3, 1.0, 1.0))
        .end_time(1.0)
        .run_constant(&method(), [])
        .unwrap();
    assert!(quiet.summary().singular_crossings.is_empty());
    assert!(!quiet.summary().to_string().contains("warning"));

    let unwatched = Simulation::new(&MODEL, start(0.3, 1.0, 1.0))
        .end_time(4.0)
        .watch_singular_crossings(false)
        .run_constant(&method(), [])
        .unwrap();
    assert!(unwatched.summary().singular_crossings.is_empty());
}
