//! Bad input gives an `Err` whose message names the problem: every case asserts the error's
//! variant, its fields, and substrings of its `Display` text (what a user reads). The messages
//! are printed (`cargo test -p hamel-validation --test models -- bad_input:: --nocapture`)
//! for review.
//!
//! The faulty models are defined here: a knife edge whose chosen quasi-velocity degenerates
//! (A(q) singular, B from the generated LU), one with a typo in its closed-form inverse, and
//! a skate whose reduced mass matrix becomes singular when a sliding bead passes over the
//! contact point; and, in `near_singular_mass`, a skate whose turning inertia I·cos²θ is
//! singular to rounding at θ = π/2.

use std::f64::consts::FRAC_PI_2;

use hamel::geometry::{Body, Contact, Inertia, Rotation3, Shape, Surface, Vector3};
use hamel::models::{
    BallOnTurntable, ChaplyginSleigh, KnifeEdge, MobileRobot, NTrailer2, WhippleBicycle,
};
use hamel::{
    DormandPrince, Error, HamelSystem, Parameters, Rk4, Simulation, Singularity, hamel_system,
};

mod near_singular_mass;

use crate::common::robot_by_hand::MobileRobotByHand;

/// The message of an error after checking that it contains every `part`.
#[track_caller]
fn assert_message(e: &Error, parts: &[&str]) -> String {
    let text = e.to_string();
    println!("{text}");
    for part in parts {
        assert!(
            text.contains(part),
            "the message does not mention `{part}`:\n{text}"
        );
    }
    text
}

/// A robot standing at (0.5, −0.3), upright, heading along x (ϑ = 0 because φ₁ = φ₂).
const ROBOT_Q: [f64; 5] = [0.5, -0.3, 0.1, 0.0, 0.0];

/// Admissible velocities at `ROBOT_Q`: rolling forward at 0.4 m/s, pitching at 0.2 rad/s,
/// not turning. ẋ = ω⁴, φ̇ᵢ = −α̇ + ω⁴/r (the robot's kinematics in `hamel::docs::design`,
/// with ϑ = 0, ω⁵ = 0).
fn robot_admissible_qd() -> [f64; 5] {
    let r = MobileRobot::default().r;
    let (alpha_dot, forward) = (0.2, 0.4);
    let wheel = -alpha_dot + forward / r;
    [forward, 0.0, alpha_dot, wheel, wheel]
}

// ---------------------------------------------------------------------------------------------
// 1. Initial velocities that violate the constraints
// ---------------------------------------------------------------------------------------------

#[test]
fn sideways_velocity_violates_no_side_slip() {
    let robot = MobileRobot::default();
    // The admissible velocities are accepted...
    robot
        .state_from_velocities(0.0, &ROBOT_Q, &robot_admissible_qd())
        .unwrap();
    // ...and a sideways velocity ẏ = 0.2 m/s is not: at ϑ = 0 the wheels' slip along their
    // axles (to the left, y) is ẏ = 0.2.
    let mut qd = robot_admissible_qd();
    qd[1] = 0.2;
    let e = robot.state_from_velocities(0.0, &ROBOT_Q, &qd).unwrap_err();
    match &e {
        Error::ConstraintViolation {
            name,
            residual,
            tolerance,
        } => {
            assert_eq!(name, "no_side_slip");
            assert_eq!(*residual, 0.2);
            // 1e-10 relative to the largest velocity component, max|q̇| = 0.4/r − 0.2 = 3.8.
            assert!((tolerance - 3.8e-10).abs() < 1e-20, "tolerance {tolerance}");
        }
        other => panic!("expected a constraint violation, got {other:?}"),
    }
    assert_message(
        &e,
        &[
            "constraint `no_side_slip`",
            "residual is 0.2",
            "state_from_speeds",
        ],
    );
}

#[test]
fn spinning_wheels_of_a_robot_at_rest_violate_no_slip() {
    let robot = MobileRobot::default();
    // Both wheels turn at 1 rad/s while the robot stands still: their slip along their
    // heading is −r(φ̇₁ + φ̇₂)/2 = −0.1.
    let qd = [0.0, 0.0, 0.0, 1.0, 1.0];
    let e = robot.state_from_velocities(0.0, &ROBOT_Q, &qd).unwrap_err();
    match &e {
        Error::ConstraintViolation { name, residual, .. } => {
            assert_eq!(name, "no_slip");
            assert!((residual + 0.1).abs() < 1e-16, "residual {residual}");
        }
        other => panic!("expected a constraint violation, got {other:?}"),
    }
    assert_message(&e, &["constraint `no_slip`", "residual is -0.1"]);
}

// ---------------------------------------------------------------------------------------------
// 2. A parameter that is not a finite number
// ---------------------------------------------------------------------------------------------

#[track_caller]
fn assert_invalid_parameter(e: &Error, expected: &str) {
    match e {
        Error::InvalidParameter { name, value } => {
            assert_eq!(name, expected);
            assert!(!value.is_finite());
        }
        other => panic!("expected an invalid parameter, got {other:?}"),
    }
    assert_message(e, &[&format!("parameter `{expected}`"), "finite"]);
}

#[test]
fn nan_parameter_is_refused_everywhere() {
    let good = MobileRobot::default();
    let x0 = good
        .state_from_velocities(0.0, &ROBOT_Q, &robot_admissible_qd())
        .unwrap();
    let bad = MobileRobot {
        m0: f64::NAN,
        ..Default::default()
    };
    let from_velocities = bad
        .state_from_velocities(0.0, &ROBOT_Q, &robot_admissible_qd())
        .unwrap_err();
    assert_invalid_parameter(&from_velocities, "m0");
    assert!(from_velocities.to_string().contains("is NaN"));
    let from_speeds = bad
        .state_from_speeds(0.0, &ROBOT_Q, &[0.2, 0.4, 0.0])
        .unwrap_err();
    assert_invalid_parameter(&from_speeds, "m0");

    let sim = Simulation::new(&bad, x0).end_time(1.0);
    let constant = sim
        .run_constant(&DormandPrince::new(1e-8, 1e-10), [0.0, 0.0])
        .unwrap_err();
    assert_invalid_parameter(&constant, "m0");
    let mut called = false;
    let feedback = sim
        .run(&Rk4::new(0.01), |_, _| {
            called = true;
            [0.1, -0.1]
        })
        .unwrap_err();
    assert_invalid_parameter(&feedback, "m0");
    assert!(
        !called,
        "the inputs were evaluated before the parameters were checked"
    );

    // An infinite parameter too, named even when it is not the first field.
    let steep = MobileRobot {
        g: f64::INFINITY,
        ..Default::default()
    };
    let e = Simulation::new(&steep, x0)
        .run_constant(&Rk4::new(0.01), [0.0, 0.0])
        .unwrap_err();
    assert_invalid_parameter(&e, "g");
    assert!(e.to_string().contains("is inf"));
}

/// `Parameters::set` refuses a value that is not a finite number and keeps the old one; an
/// unknown name is named as such whatever the value.
#[test]
fn set_refuses_non_finite_parameter_values() {
    let mut robot = MobileRobot::default();
    for value in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let e = robot.set("m0", value).unwrap_err();
        assert_invalid_parameter(&e, "m0");
        assert_eq!(robot.m0, 10.0, "the parameter changed to {value}");
    }
    // An entry of an array parameter, by its indexed name.
    let mut train = NTrailer2::default();
    let before = train.get("d1");
    let e = train.set("d1", f64::NAN).unwrap_err();
    assert_invalid_parameter(&e, "d1");
    assert_eq!(train.get("d1"), before);
    // Finite values, negative or zero included, are set.
    robot.set("m0", -0.0).unwrap();
    assert_eq!(robot.get("m0"), Some(0.0));
    let e = robot.set("mass", f64::NAN).unwrap_err();
    assert!(
        matches!(&e, Error::UnknownParameter { name, .. } if name == "mass"),
        "{e}"
    );
}

// ---------------------------------------------------------------------------------------------
// 3. Quasi-velocities that make A(q) singular (B from the generated LU)
// ---------------------------------------------------------------------------------------------

// The models' items are `pub`: the macro reads the role functions at compile time and the
// generated code never calls some of them, so private ones draw dead-code warnings.

/// The catalogue's knife edge with a badly chosen second quasi-velocity, φ̇ cosφ instead of
/// φ̇, and no `#[velocities]`: A(q) = [[sinφ, −cosφ, 0], [cosφ, sinφ, 0], [0, 0, cosφ]] has
/// det A = cosφ, singular at φ = ±π/2, where the quasi-velocities no longer determine φ̇.
#[hamel_system]
#[derive(Clone, Debug)]
pub struct CosSkate {
    m: f64,
    j: f64,
    g: f64,
    incline: f64,
}

#[hamel_system(coordinates(x, y, phi), speeds(v, turn))]
impl CosSkate {
    #[lagrangian]
    pub fn lagrangian(&self, q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        0.5 * self.m * (qd[0] * qd[0] + qd[1] * qd[1])
            + 0.5 * self.j * qd[2] * qd[2]
            + self.m * self.g * self.incline.sin() * q[0]
    }

    #[constraints]
    pub fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [qd[0] * q[2].sin() - qd[1] * q[2].cos()]
    }

    #[quasi_velocities]
    pub fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[2] * q[2].cos()]
    }
}

fn cos_skate() -> CosSkate {
    let k = KnifeEdge::default();
    CosSkate {
        m: k.m,
        j: k.j,
        g: k.g,
        incline: k.incline,
    }
}

#[test]
fn degenerate_quasi_velocity_is_a_singular_transformation() {
    let sys = cos_skate();
    // Away from cosφ = 0 the model is fine (and agrees with the catalogue's knife edge: φ̇ =
    // turn / cosφ, so turn = ω cosφ).
    let phi = 0.7;
    let mut dx = [0.0; 5];
    sys.rhs(0.0, &[0.1, 0.2, phi, 1.0, 0.5 * phi.cos()], &[], &mut dx)
        .unwrap();
    let mut reference = [0.0; 5];
    KnifeEdge::default()
        .rhs(0.0, &[0.1, 0.2, phi, 1.0, 0.5], &[], &mut reference)
        .unwrap();
    for k in 0..4 {
        assert!(
            (dx[k] - reference[k]).abs() < 1e-12,
            "{dx:?} vs {reference:?}"
        );
    }
    // d/dt (φ̇ cosφ) = φ̈ cosφ − φ̇² sinφ with φ̈ = 0, φ̇ = 0.5.
    assert!((dx[4] + 0.25 * phi.sin()).abs() < 1e-12, "{dx:?}");

    // At φ = π/2 (cos = 6e-17 in f64) the LU's pivot cosφ is below its tolerance.
    let x = [0.1, 0.2, FRAC_PI_2, 1.0, 0.0];
    match sys.rhs(0.0, &x, &[], &mut dx) {
        // The coordinate A(q) fails to determine there: φ (index 2).
        Err(Singularity::Transformation { coordinate, value }) => {
            assert_eq!(coordinate, 2, "coordinate {coordinate}");
            assert!(value.abs() <= 1e-15, "pivot value {value}");
        }
        other => panic!("expected a singular transformation, got {other:?}"),
    }
    assert!(matches!(
        sys.generalized_velocities(0.0, &x),
        Err(Singularity::Transformation { .. })
    ));

    // Started exactly there, the simulation names the time and the state.
    for integrator in [
        &DormandPrince::new(1e-10, 1e-10) as &dyn RunWith<CosSkate>,
        &Rk4::new(0.01),
    ] {
        let e = integrator.run(&Simulation::new(&sys, x).start_time(2.5).end_time(3.0));
        match &e {
            Error::SingularTransformation {
                t, value, state, ..
            } => {
                assert_eq!(*t, 2.5);
                assert!(value.abs() <= 1e-15);
                assert_eq!(state.get("phi"), Some(FRAC_PI_2));
                assert_eq!(state.get("turn"), Some(0.0));
            }
            other => panic!("expected a singular transformation, got {other:?}"),
        }
        assert_message(
            &e,
            &[
                "singular velocity transformation at t = 2.5",
                "do not determine the velocity of `phi`",
                "phi = 1.571,",
                "x = 0.1, y = 0.2",
                "v = 1, turn = 0",
            ],
        );
    }
}

/// The two integrators behind one call, so a case can be run with both.
trait RunWith<S: HamelSystem> {
    fn run(&self, sim: &Simulation<'_, S>) -> Error;
}

impl<S: HamelSystem<Inputs = [f64; 0]>> RunWith<S> for DormandPrince {
    fn run(&self, sim: &Simulation<'_, S>) -> Error {
        sim.run_constant(self, []).unwrap_err()
    }
}

impl<S: HamelSystem<Inputs = [f64; 0]>> RunWith<S> for Rk4 {
    fn run(&self, sim: &Simulation<'_, S>) -> Error {
        sim.run_constant(self, []).unwrap_err()
    }
}

/// A skate on a level plane whose second quasi-velocity is x·φ̇: A(q) has det = x, singular on
/// the line x = 0, which a skate sliding straight along x crosses.
#[hamel_system]
#[derive(Clone, Debug)]
pub struct LineSkate {
    m: f64,
    j: f64,
}

#[hamel_system(coordinates(x, y, phi), speeds(v, turn))]
impl LineSkate {
    #[kinetic_energy]
    pub fn kinetic_energy(&self, _q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        0.5 * self.m * (qd[0] * qd[0] + qd[1] * qd[1]) + 0.5 * self.j * qd[2] * qd[2]
    }

    #[constraints]
    pub fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [qd[0] * q[2].sin() - qd[1] * q[2].cos()]
    }

    #[quasi_velocities]
    pub fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[2] * q[0]]
    }
}

/// The skate starts at x = −1 heading along x (φ = 0) at v = 1 without turning: x = −1 + t
/// exactly (φ stays 0, so ẋ = v cosφ = 1 and v̇ = 0 exactly), and RK4 with step 1/4 lands on
/// x = 0 exactly at t = 1 (every stage value is a multiple of 1/8, and h/6·6 rounds to h).
#[test]
fn a_run_that_reaches_a_singular_transformation() {
    let sys = LineSkate { m: 1.0, j: 0.1 };
    let x0 = sys
        .state_from_speeds(0.0, &[-1.0, 0.0, 0.0], &[1.0, 0.0])
        .unwrap();
    // Up to just before the line, all is well.
    let before = Simulation::new(&sys, x0)
        .end_time(0.75)
        .sample_interval(0.25)
        .run_constant(&Rk4::new(0.25), [])
        .unwrap();
    assert_eq!(before.column("x").unwrap(), [-1.0, -0.75, -0.5, -0.25]);

    let e = Simulation::new(&sys, x0)
        .end_time(2.0)
        .sample_interval(0.5)
        .run_constant(&Rk4::new(0.25), [])
        .unwrap_err();
    match &e {
        Error::SingularTransformation {
            t, value, state, ..
        } => {
            assert_eq!(*t, 1.0);
            assert_eq!(*value, 0.0);
            assert_eq!(state.get("x"), Some(0.0));
            assert_eq!(state.get("v"), Some(1.0));
        }
        other => panic!("expected a singular transformation, got {other:?}"),
    }
    assert_message(
        &e,
        &[
            "singular velocity transformation at t = 1:",
            "x = 0, y = 0, phi = 0, v = 1, turn = 0",
        ],
    );

    // Started on the line, at a later start time.
    let on_line = sys
        .state_from_speeds(0.0, &[0.0, 3.0, 0.4], &[1.0, 0.0])
        .unwrap();
    let e = Simulation::new(&sys, on_line)
        .start_time(-4.0)
        .end_time(0.0)
        .run_constant(&DormandPrince::new(1e-9, 1e-9), [])
        .unwrap_err();
    assert!(matches!(e, Error::SingularTransformation { t: -4.0, .. }));
    assert_message(&e, &["at t = -4:", "x = 0, y = 3, phi = 0.4"]);
}

// ---------------------------------------------------------------------------------------------
// 4. A closed-form inverse that is not the inverse
// ---------------------------------------------------------------------------------------------

/// A typo in a closed-form inverse is a compile error (the macro evaluates B(q)·A(q) − I at
/// generic configurations and parameters; see `ui/tests/ui/inverse_is_not_the_inverse.rs`). What
/// remains for run time is an inverse that is right only for some parameter values: this
/// sleigh's inverse uses |a| where a belongs, right for a ≥ 0 (so it compiles), wrong for a
/// contact point in front of the centre of mass (a < 0).
#[hamel_system]
#[derive(Clone, Debug)]
pub struct SignBlindSleigh {
    m: f64,
    inertia: f64,
    a: f64,
}

#[hamel_system(coordinates(x, y, theta), speeds(v, omega))]
impl SignBlindSleigh {
    #[kinetic_energy]
    pub fn kinetic_energy(&self, _q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        0.5 * self.m * (qd[0] * qd[0] + qd[1] * qd[1]) + 0.5 * self.inertia * qd[2] * qd[2]
    }

    #[constraints]
    pub fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [-qd[0] * q[2].sin() + qd[1] * q[2].cos() - self.a * qd[2]]
    }

    #[quasi_velocities]
    pub fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[2]]
    }

    /// ẋ = −sinθ (w₀ + a w₂) + cosθ w₁, ẏ = cosθ (w₀ + a w₂) + sinθ w₁ — with |a|.
    #[velocities]
    pub fn velocities(&self, q: &[f64; 3], w: &[f64; 3]) -> [f64; 3] {
        let (s, c) = q[2].sin_cos();
        let lateral = w[0] + self.a.abs() * w[2];
        [-s * lateral + c * w[1], c * lateral + s * w[1], w[2]]
    }
}

#[test]
fn inverse_wrong_for_these_parameters_is_an_inverse_mismatch() {
    let q = [0.5, -1.0, 0.3];
    let behind = SignBlindSleigh {
        m: 2.0,
        inertia: 0.5,
        a: 0.4,
    };
    assert!(behind.state_from_speeds(0.0, &q, &[1.0, 0.5]).is_ok());

    let in_front = SignBlindSleigh {
        a: -0.4,
        ..behind.clone()
    };
    let e = in_front
        .state_from_speeds(0.0, &q, &[1.0, 0.5])
        .unwrap_err();
    match &e {
        // A·B − I has one nonzero entry: the constraint row against B's ω-column, |a| − a = 0.8.
        Error::InverseMismatch {
            defect,
            configuration,
        } => {
            let expected = 0.8;
            assert!(
                (defect - expected).abs() < 1e-14,
                "defect {defect} vs {expected}"
            );
            assert_eq!(configuration.get("theta"), Some(0.3));
        }
        other => panic!("expected an inverse mismatch, got {other:?}"),
    }
    assert_message(
        &e,
        &[
            "`#[velocities]`",
            "not the inverse",
            "by 0.8 at",
            "x = 0.5, y = -1, theta = 0.3",
        ],
    );

    // The same from state_from_velocities and from a run started there.
    let qd = [
        0.3f64.cos() * 1.0 - 0.3f64.sin() * (-0.4 * 0.5),
        0.3f64.sin() + 0.3f64.cos() * (-0.4 * 0.5),
        0.5,
    ];
    let e = in_front.state_from_velocities(0.0, &q, &qd).unwrap_err();
    assert!(matches!(e, Error::InverseMismatch { .. }), "{e:?}");
    let x0 = [q[0], q[1], q[2], 1.0, 0.5];
    let e = Simulation::new(&in_front, x0)
        .run_constant(&DormandPrince::new(1e-9, 1e-9), [])
        .unwrap_err();
    assert!(matches!(e, Error::InverseMismatch { .. }), "{e:?}");
}

// ---------------------------------------------------------------------------------------------
// 5. Initial values that are not finite
// ---------------------------------------------------------------------------------------------

#[track_caller]
fn assert_non_finite(e: &Error, expected: &str) {
    match e {
        Error::NonFiniteInitialValue { name, value } => {
            assert_eq!(name, expected);
            assert!(!value.is_finite());
        }
        other => panic!("expected a non-finite initial value, got {other:?}"),
    }
    assert_message(
        e,
        &[
            &format!("initial value of `{expected}`"),
            "must be a finite number",
        ],
    );
}

#[test]
fn non_finite_initial_values_are_named() {
    let robot = MobileRobot::default();
    let qd = robot_admissible_qd();

    let mut q = ROBOT_Q;
    q[2] = f64::NAN;
    assert_non_finite(
        &robot.state_from_velocities(0.0, &q, &qd).unwrap_err(),
        "alpha",
    );
    q[2] = 0.1;
    q[4] = f64::NEG_INFINITY;
    assert_non_finite(
        &robot.state_from_speeds(0.0, &q, &[0.0; 3]).unwrap_err(),
        "phi2",
    );

    let mut bad_qd = qd;
    bad_qd[3] = f64::INFINITY;
    let e = robot
        .state_from_velocities(0.0, &ROBOT_Q, &bad_qd)
        .unwrap_err();
    assert_non_finite(&e, "d/dt phi1");

    let e = robot
        .state_from_speeds(0.0, &ROBOT_Q, &[0.0, f64::NAN, 0.0])
        .unwrap_err();
    assert_non_finite(&e, "w4");

    // A state assembled by hand and handed to the simulation.
    let good = robot.state_from_velocities(0.0, &ROBOT_Q, &qd).unwrap();
    for (i, name) in MobileRobot::STATE.iter().enumerate() {
        let mut x0 = good;
        x0[i] = if i % 2 == 0 { f64::NAN } else { f64::INFINITY };
        let e = Simulation::new(&robot, x0)
            .run_constant(&DormandPrince::new(1e-8, 1e-10), [0.0, 0.0])
            .unwrap_err();
        assert_non_finite(&e, name);
    }
}

// ---------------------------------------------------------------------------------------------
// 6. Invalid settings of the run and of the integrators
// ---------------------------------------------------------------------------------------------

#[track_caller]
fn assert_invalid_setting(e: &Error, expected: &str, value: f64) {
    match e {
        Error::InvalidSetting { name, value: v, .. } => {
            assert_eq!(*name, expected);
            assert!(
                v.to_bits() == value.to_bits(),
                "value {v}, expected {value}"
            );
        }
        other => panic!("expected an invalid setting, got {other:?}"),
    }
    // Values read as a person would write them: `-1e-6`, not `-0.000001`.
    assert_message(
        e,
        &[&format!(
            "invalid setting `{expected}` = {}",
            hamel::Num(value)
        )],
    );
}

#[test]
fn invalid_settings_are_named() {
    let robot = MobileRobot::default();
    let x0 = robot
        .state_from_velocities(0.0, &ROBOT_Q, &robot_admissible_qd())
        .unwrap();
    let u = [0.0, 0.0];
    let sim = || Simulation::new(&robot, x0).end_time(0.5);
    let ok = DormandPrince::new(1e-8, 1e-10);
    sim().run_constant(&ok, u).unwrap();

    // Integrator settings.
    let cases: [(DormandPrince, &str, f64); 7] = [
        (DormandPrince::new(-1e-6, 1e-10), "rtol", -1e-6),
        (DormandPrince::new(f64::NAN, 1e-10), "rtol", f64::NAN),
        (DormandPrince::new(1e-6, 0.0), "atol", 0.0),
        (DormandPrince::new(1e-6, -1e-9), "atol", -1e-9),
        (ok.with_initial_step(0.0), "initial step", 0.0),
        (ok.with_max_step(-0.1), "max step", -0.1),
        (ok.with_fixed_step(0.0), "fixed step", 0.0),
    ];
    for (integrator, name, value) in cases {
        let e = sim().run_constant(&integrator, u).unwrap_err();
        assert_invalid_setting(&e, name, value);
    }
    for step in [0.0, -0.01, f64::INFINITY] {
        let e = sim().run_constant(&Rk4::new(step), u).unwrap_err();
        assert_invalid_setting(&e, "step", step);
    }

    // Run settings.
    let e = sim().end_time(-1.0).run_constant(&ok, u).unwrap_err();
    assert_invalid_setting(&e, "end time", -1.0);
    assert_message(&e, &["after the start time"]);
    let e = sim()
        .start_time(2.0)
        .end_time(2.0)
        .run_constant(&ok, u)
        .unwrap_err();
    assert_invalid_setting(&e, "end time", 2.0);
    let e = sim().start_time(f64::NAN).run_constant(&ok, u).unwrap_err();
    assert_invalid_setting(&e, "start time", f64::NAN);
    for dt in [0.0, -0.01, f64::NAN] {
        let e = sim().sample_interval(dt).run_constant(&ok, u).unwrap_err();
        assert_invalid_setting(&e, "sample interval", dt);
        assert_message(&e, &["positive"]);
    }
    let e = sim()
        .end_time(1e3)
        .sample_interval(1e-5)
        .run_constant(&ok, u)
        .unwrap_err();
    assert_invalid_setting(&e, "sample interval", 1e-5);
    assert_message(&e, &["more than 4 GiB in memory", "Simulation::stream"]);
    // More samples than any run should have: refused before the run, streamed or not.
    let e = sim()
        .end_time(1e3)
        .sample_interval(1e-9)
        .run_constant(&ok, u)
        .unwrap_err();
    assert!(matches!(e, Error::TooManySamples { .. }), "{e}");
    assert_message(&e, &["1e12 samples", "`max_samples`"]);
}

// ---------------------------------------------------------------------------------------------
// 7. A singular reduced mass matrix
// ---------------------------------------------------------------------------------------------

/// The catalogue's knife edge given no moment of inertia (j = 0): nothing resists turning,
/// M = diag(m, j) is singular at every state, and the turning rate's equation reads 0·ω̇ = 0.
#[test]
fn skate_without_moment_of_inertia_has_a_singular_mass_matrix() {
    let sys = KnifeEdge {
        j: 0.0,
        ..Default::default()
    };
    // The parameters are finite, so the state is built.
    let x0 = sys
        .state_from_speeds(0.0, &[0.0, 0.0, 0.2], &[1.0, 0.5])
        .unwrap();
    let m = sys.mass_matrix(0.0, &x0).unwrap();
    assert_eq!(m, [[1.0, 0.0], [0.0, 0.0]]);
    let mut dx = [0.0; 5];
    assert_eq!(
        sys.rhs(0.0, &x0, &[], &mut dx),
        Err(Singularity::MassMatrix {
            speed: 1,
            value: 0.0
        })
    );
    let e = Simulation::new(&sys, x0)
        .start_time(1.5)
        .end_time(2.0)
        .run_constant(&DormandPrince::new(1e-9, 1e-9), [])
        .unwrap_err();
    match &e {
        Error::SingularMassMatrix {
            t,
            speed,
            value,
            state,
        } => {
            assert_eq!((*t, speed.as_str(), *value), (1.5, "omega", 0.0));
            assert_eq!(state.get("omega"), Some(0.5));
        }
        other => panic!("expected a singular mass matrix, got {other:?}"),
    }
    assert_message(
        &e,
        &[
            "singular reduced mass matrix at t = 1.5",
            "the motion along `omega` has no inertia",
            "x = 0, y = 0, phi = 0.2, v = 1, omega = 0.5",
        ],
    );
}

/// A skate carrying a bead: a point mass m₀ at the blade's contact point (blade and rod
/// massless) and a bead of mass m_b that slides without friction on a rod along the blade, a
/// distance s ahead of the contact point. The only rotational inertia about the contact point
/// is the bead's, m_b s², so when the bead passes over the contact point nothing resists
/// turning.
///
/// q = (x, y, φ, s); quasi-velocities v (path speed), φ̇, ṡ. The bead moves at
/// (v + ṡ) e_φ + s φ̇ e_⊥, so T = ½ m₀ v² + ½ m_b ((v + ṡ)² + s² φ̇²) and
/// M = [[m₀ + m_b, 0, m_b], [0, m_b s², 0], [m_b, 0, m_b]], det M = m₀ m_b² s²: singular at
/// s = 0 (LDLᵀ pivot 1 is m_b s²).
#[hamel_system]
#[derive(Clone, Debug)]
pub struct BeadSkate {
    m0: f64,
    mb: f64,
}

#[hamel_system(coordinates(x, y, phi, s), speeds(v, turn, slide))]
impl BeadSkate {
    #[kinetic_energy]
    pub fn kinetic_energy(&self, q: &[f64; 4], qd: &[f64; 4]) -> f64 {
        let (sn, c) = q[2].sin_cos();
        let s = q[3];
        let bx = qd[0] + qd[3] * c - s * qd[2] * sn;
        let by = qd[1] + qd[3] * sn + s * qd[2] * c;
        0.5 * self.m0 * (qd[0] * qd[0] + qd[1] * qd[1]) + 0.5 * self.mb * (bx * bx + by * by)
    }

    #[constraints]
    pub fn blade(&self, q: &[f64; 4], qd: &[f64; 4]) -> [f64; 1] {
        [qd[0] * q[2].sin() - qd[1] * q[2].cos()]
    }

    #[quasi_velocities]
    pub fn speeds(&self, q: &[f64; 4], qd: &[f64; 4]) -> [f64; 3] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[2], qd[3]]
    }
}

/// The bead starts 1 m ahead of the contact point sliding back at 1 m/s, the skate at rest and
/// not turning. With φ̇ = 0 no force acts along the rod, so v and ṡ stay constant (exactly: the
/// turning terms vanish identically) and s = 1 − t. RK4 with step 1/4 lands on s = 0 exactly
/// at t = 1 (stage values are multiples of 1/8).
#[test]
fn bead_over_the_contact_point_makes_the_mass_matrix_singular() {
    let sys = BeadSkate { m0: 2.0, mb: 0.5 };
    let m_at = |s: f64| {
        sys.mass_matrix(0.0, &[0.0, 0.0, 0.0, s, 0.0, 0.0, 0.0])
            .unwrap()
    };
    assert_eq!(
        m_at(2.0),
        [[2.5, 0.0, 0.5], [0.0, 2.0, 0.0], [0.5, 0.0, 0.5]]
    );
    assert_eq!(m_at(0.0)[1][1], 0.0);

    let x0 = sys
        .state_from_speeds(0.0, &[0.3, -0.2, 0.0, 1.0], &[0.0, 0.0, -1.0])
        .unwrap();
    let before = Simulation::new(&sys, x0)
        .end_time(0.75)
        .sample_interval(0.25)
        .run_constant(&Rk4::new(0.25), [])
        .unwrap();
    assert_eq!(before.column("s").unwrap(), [1.0, 0.75, 0.5, 0.25]);

    let e = Simulation::new(&sys, x0)
        .end_time(2.0)
        .sample_interval(0.5)
        .run_constant(&Rk4::new(0.25), [])
        .unwrap_err();
    match &e {
        Error::SingularMassMatrix {
            t,
            speed,
            value,
            state,
        } => {
            assert_eq!((*t, speed.as_str(), *value), (1.0, "turn", 0.0));
            assert_eq!(state.get("s"), Some(0.0));
            assert_eq!(state.get("slide"), Some(-1.0));
        }
        other => panic!("expected a singular mass matrix, got {other:?}"),
    }
    assert_message(
        &e,
        &[
            "singular reduced mass matrix at t = 1:",
            "the motion along `turn` has no inertia",
            "x = 0.3, y = -0.2, phi = 0, s = 0, v = 0, turn = 0, slide = -1",
        ],
    );

    // Started with the bead on the contact point: at the start time.
    let x0 = sys
        .state_from_speeds(0.0, &[0.0, 0.0, 1.0, 0.0], &[1.0, 0.2, 0.3])
        .unwrap();
    let e = Simulation::new(&sys, x0)
        .run_constant(&DormandPrince::new(1e-9, 1e-9), [])
        .unwrap_err();
    assert!(
        matches!(
            e,
            Error::SingularMassMatrix { t: 0.0, ref speed, .. } if speed == "turn"
        ),
        "{e:?}"
    );
    assert_message(&e, &["at t = 0:", "s = 0"]);
}

// ---------------------------------------------------------------------------------------------
// 8. Parameters that make the reduced mass matrix indefinite
// ---------------------------------------------------------------------------------------------

/// The checks on an indefinite reduced mass matrix, at a state `x0` built by hand (so not
/// checked by a state builder): `rhs` returns the singularity, a run stops at its start time
/// naming the speed, and the message names the parameters as the likely cause.
#[track_caller]
fn assert_indefinite<S: HamelSystem>(sys: &S, x0: S::State, u: S::Inputs, speed: &str) {
    let mut dx = x0;
    match sys.rhs(0.0, &x0, &u, &mut dx) {
        Err(Singularity::IndefiniteMassMatrix { speed: j, value }) => {
            assert_eq!(S::SPEEDS[j], speed);
            assert!(value < 0.0, "pivot {value}");
        }
        other => panic!("expected an indefinite mass matrix, got {other:?}"),
    }
    let e = Simulation::new(sys, x0)
        .start_time(0.5)
        .end_time(1.0)
        .run_constant(&DormandPrince::new(1e-9, 1e-9), u)
        .unwrap_err();
    match &e {
        Error::IndefiniteMassMatrix {
            t,
            speed: named,
            value,
            ..
        } => {
            assert_eq!((*t, named.as_str()), (0.5, speed));
            assert!(*value < 0.0);
        }
        other => panic!("expected an indefinite mass matrix, got {other:?}"),
    }
    assert_message(
        &e,
        &[
            "not positive definite at t = 0.5",
            &format!("along `{speed}`"),
            "negative",
            "parameters",
            "mass or moment of inertia",
        ],
    );
}

/// A negative mass or moment of inertia that the admissible motions feel makes the reduced
/// mass matrix indefinite. Before, each run stopped with "singular reduced mass matrix … has
/// no inertia here" (its pivot being, say, −56.88) and the states were built without a word.
#[test]
fn negative_masses_make_an_indefinite_mass_matrix() {
    let skate = KnifeEdge {
        m: -1.0,
        ..Default::default()
    };
    assert_indefinite(&skate, [0.0, 0.0, 0.2, 1.0, 0.5], [], "v");
    let spinner = KnifeEdge {
        j: -0.1,
        ..Default::default()
    };
    assert_indefinite(&spinner, [0.0, 0.0, 0.2, 1.0, 0.5], [], "omega");

    // The sleigh's turning inertia about the contact point is I + m a²: I = −0.5 with
    // m a² = 0.32 leaves −0.18.
    let sleigh = ChaplyginSleigh {
        inertia: -0.5,
        ..Default::default()
    };
    assert_indefinite(&sleigh, [0.0, 0.0, 0.0, 1.0, 2.0], [], "omega");

    let ball = BallOnTurntable {
        m: -1.0,
        ..Default::default()
    };
    assert_indefinite(
        &ball,
        [0.3, 0.0, 0.0, 0.5, 0.0, 0.0, 0.0, 0.0],
        [],
        "omega_x",
    );

    // The robot (written by hand from its energy) with its body lighter than nothing: the
    // pitch's pivot m₀l² + J_y + … is negative.
    let robot = MobileRobotByHand::from(&MobileRobot {
        m0: -10.0,
        ..Default::default()
    });
    let x0 = [0.0, 0.0, 0.1, 0.0, 0.0, 0.2, 0.4, 0.3];
    assert_indefinite(&robot, x0, [0.0, 0.0], "w3");
}

/// A model stated from its bodies refuses a body no matter makes before any step, naming the
/// body: a negative mass, a negative moment of inertia, moments that break the triangle
/// inequality. Before, they ran into an indefinite mass matrix, or — a negative moment the
/// motion does not feel at the start — into a step size underflow somewhere in the run.
#[test]
fn bodies_no_matter_makes_are_refused_before_any_step() {
    let upright = |bike: &WhippleBicycle| {
        let mut x = [0.0; 11];
        x[WhippleBicycle::N + WhippleBicycle::REAR_WHEEL_RATE] = -5.0 / bike.r_r;
        x
    };
    let cases = [
        (
            WhippleBicycle {
                m_b: -85.0,
                ..Default::default()
            },
            "rear_frame",
            "mass is -85",
        ),
        (
            WhippleBicycle {
                i_fxx: -0.1405,
                ..Default::default()
            },
            "front_wheel",
            "cannot be negative",
        ),
        (
            WhippleBicycle {
                i_bzz: 30.0,
                ..Default::default()
            },
            "rear_frame",
            "triangle inequality",
        ),
    ];
    for (bike, body, reason) in cases {
        let x0 = upright(&bike);
        let run = Simulation::new(&bike, x0)
            .end_time(1.0)
            .run_constant(&DormandPrince::new(1e-9, 1e-9), [0.0, 0.0]);
        let built = bike.state_builder().set("phi", 0.01).build();
        // Linearizing it is refused as a run is: its eigenvalues and LQR gains were computed
        // from the impossible body.
        let linearized = bike.linearize(0.0, &x0, &[0.0, 0.0]);
        for e in [
            run.unwrap_err(),
            built.unwrap_err(),
            linearized.unwrap_err(),
        ] {
            assert!(
                matches!(&e, Error::UnphysicalBody { body: b, .. } if b == body),
                "{e}"
            );
            assert_message(&e, &[&format!("body `{body}`"), reason, "parameters"]);
        }
    }
    let robot = MobileRobot {
        jy: -0.3,
        ..Default::default()
    };
    let e = robot.state_builder().build().unwrap_err();
    assert_message(&e, &["body `body`", "cannot be negative"]);
}

/// A ball on the plane of a frame scaled by `s` (−1 a reflection, 0 no normal at all): the
/// frame of a plane must be a rotation.
#[hamel_system]
pub struct BallOnScaledPlane {
    pub r: f64,
    pub s: f64,
}

#[hamel_system(coordinates(x, y, z, qw, qx, qy, qz), speeds(wx, wy, wz))]
impl BallOnScaledPlane {
    #[bodies]
    fn bodies(&self, q: &[f64; 7]) -> [Body; 1] {
        let orientation = Rotation3::from_quaternion(q[3], q[4], q[5], q[6]);
        let ball = Body::new(
            1.0,
            Inertia::principal(0.004, 0.004, 0.004),
            Vector3::new(q[0], q[1], q[2]),
            orientation,
        );
        [ball.with_shape(Shape::sphere(self.r))]
    }

    #[gravity]
    fn gravity(&self) -> Vector3 {
        Vector3::new(0.0, 0.0, -9.81)
    }

    #[constraints]
    fn unit(&self, q: &[f64; 7], qd: &[f64; 7]) -> [f64; 1] {
        [q[3] * qd[3] + q[4] * qd[4] + q[5] * qd[5] + q[6] * qd[6]]
    }

    #[contacts(determines(z))]
    fn contacts(&self, q: &[f64; 7]) -> [Contact; 1] {
        let [ball] = self.bodies(q);
        let s = self.s;
        let frame = Rotation3::from_matrix_unchecked([[s, 0.0, 0.0], [0.0, s, 0.0], [0.0, 0.0, s]]);
        [Contact::rolling(
            ball,
            Surface::plane(Vector3::zeros(), frame),
        )]
    }

    #[quasi_velocities]
    fn spin(&self, q: &[f64; 7], _qd: &[f64; 7]) -> [f64; 3] {
        let [ball] = self.bodies(q);
        angular_velocity!(ball.orientation).to_array()
    }
}

/// Geometry no body can have is refused before any step, naming the body and the radius or
/// the frame: before, a ball of radius −0.05 in a bowl ran with its centre below the bowl, a
/// ball of radius 0 ran, a plane scaled by 2 held the ball a radius above it and a reflected
/// one under it; a ball no smaller than its bowl, or at its sphere's centre, was a Newton
/// iteration that did not converge.
#[test]
fn geometry_no_body_can_have_is_refused_before_any_step() {
    use crate::rolling::{BowlBall, SphereBall};
    let bowl = |r: f64, bowl: f64| BowlBall {
        m: 1.0,
        r,
        i: 0.004,
        bowl,
        g: 9.81,
    };
    let in_bowl = |model: &BowlBall| {
        let x0 = [0.1, 0.0, model.r.abs(), 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0];
        let run = Simulation::new(model, x0)
            .end_time(0.1)
            .run_constant(&DormandPrince::new(1e-9, 1e-9), []);
        let built = model.state_builder().set("x", 0.1).set("qw", 1.0).build();
        let linearized = model.linearize(0.0, &x0, &[]);
        [
            run.unwrap_err(),
            built.unwrap_err(),
            linearized.unwrap_err(),
        ]
    };
    let cases = [
        (
            bowl(-0.05, 0.5),
            "the shape of body `body0`",
            "radius is -0.05",
        ),
        (bowl(0.0, 0.5), "the shape of body `body0`", "radius is 0"),
        (
            bowl(0.5, 0.5),
            "contact 0 (body `body0` on a bowl)",
            "not smaller than the bowl's, 0.5",
        ),
        (
            bowl(0.1, -1.0),
            "contact 0 (body `body0` on a bowl)",
            "the bowl's radius is -1",
        ),
    ];
    for (model, what, reason) in cases {
        for e in in_bowl(&model) {
            assert!(matches!(&e, Error::ImpossibleGeometry { .. }), "{e}");
            assert_message(&e, &[what, reason]);
        }
    }
    let sphere = SphereBall {
        m: 1.0,
        r: 0.1,
        i: 0.004,
        sphere: 1.0,
        g: 9.81,
    };
    let e = sphere.state_builder().set("qw", 1.0).build().unwrap_err();
    assert_message(
        &e,
        &[
            "contact 0 (body `body0` on a sphere)",
            "at the sphere's centre",
        ],
    );
    for (s, reason) in [
        (2.0, "not a rotation: its axes have lengths 2, 2 and 2"),
        (-1.0, "reflection"),
        (0.0, "z axis is the zero vector"),
    ] {
        let model = BallOnScaledPlane { r: 0.1, s };
        let e = model
            .state_builder()
            .set("z", 0.1)
            .set("qw", 1.0)
            .build()
            .unwrap_err();
        assert_message(
            &e,
            &[
                "contact 0 (body `body0` on a plane)",
                "the plane's frame",
                reason,
            ],
        );
        let x0 = [0.0, 0.0, 0.1, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0];
        let run = Simulation::new(&model, x0)
            .end_time(0.1)
            .run_constant(&DormandPrince::new(1e-9, 1e-9), []);
        assert_message(&run.unwrap_err(), &["the plane's frame", reason]);
    }
    // A rotation passes.
    let upright = BallOnScaledPlane { r: 0.1, s: 1.0 };
    assert!(
        upright
            .state_builder()
            .set("z", 0.1)
            .set("qw", 1.0)
            .build()
            .is_ok()
    );
}

/// A state is not built where the reduced mass matrix is indefinite: every way of building
/// one names the speed, at the time given.
#[test]
fn states_are_not_built_with_an_indefinite_mass_matrix() {
    let robot = MobileRobotByHand::from(&MobileRobot {
        m0: -10.0,
        ..Default::default()
    });
    let from_speeds = robot
        .state_from_speeds(2.0, &ROBOT_Q, &[0.2, 0.4, 0.0])
        .unwrap_err();
    let from_velocities = robot
        .state_from_velocities(2.0, &ROBOT_Q, &robot_admissible_qd())
        .unwrap_err();
    let built = robot
        .state_builder()
        .at_time(2.0)
        .set("alpha", 0.1)
        .build()
        .unwrap_err();
    for e in [from_speeds, from_velocities, built] {
        assert!(
            matches!(&e, Error::IndefiniteMassMatrix { t: 2.0, speed, .. } if speed == "w3"),
            "{e}"
        );
        assert_message(&e, &["at t = 2:", "along `w3`", "parameters"]);
    }

    // A singular matrix is the dynamics' business, reported when a run meets it: a knife
    // edge without a moment of inertia still gives a state (section 7).
    let pointlike = KnifeEdge {
        j: 0.0,
        ..Default::default()
    };
    pointlike
        .state_from_speeds(0.0, &[0.0, 0.0, 0.2], &[1.0, 0.5])
        .unwrap();
}

// ---------------------------------------------------------------------------------------------
// 9. A right-hand side that meets a value that is not finite
// ---------------------------------------------------------------------------------------------

/// A skate whose moment of inertia about the vertical depends on where it is, j·√(1 − x²)
/// (a made-up geometry that exists for |x| ≤ 1 only): beyond, the reduced mass matrix's entry
/// for the turning rate is NaN, while A(q) stays finite.
#[hamel_system]
#[derive(Clone, Debug)]
pub struct StripSkate {
    m: f64,
    j: f64,
}

#[hamel_system(coordinates(x, y, phi), speeds(v, turn))]
impl StripSkate {
    #[kinetic_energy]
    pub fn kinetic_energy(&self, q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        let inertia = self.j * (1.0 - q[0] * q[0]).sqrt();
        0.5 * self.m * (qd[0] * qd[0] + qd[1] * qd[1]) + 0.5 * inertia * qd[2] * qd[2]
    }

    #[constraints]
    pub fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [qd[0] * q[2].sin() - qd[1] * q[2].cos()]
    }

    #[quasi_velocities]
    pub fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[2]]
    }
}

/// Before, a NaN pivot or diagonal entry was reported as a singular matrix ("has no inertia
/// here (its pivot … is NaN)"), a NaN in A(q) as a singular transformation.
#[test]
fn a_non_finite_value_is_not_called_singular() {
    let sys = StripSkate { m: 1.0, j: 0.1 };
    let x = [2.0, 0.0, 0.0, 1.0, 0.5];
    let mut dx = [0.0; 5];
    assert_eq!(
        sys.rhs(0.0, &x, &[], &mut dx),
        Err(Singularity::NonFinite {
            speed: Some(StripSkate::TURN)
        })
    );
    let e = Simulation::new(&sys, x)
        .start_time(1.25)
        .end_time(2.0)
        .run_constant(&DormandPrince::new(1e-9, 1e-9), [])
        .unwrap_err();
    match &e {
        Error::NonFiniteDynamics { t, speed, state } => {
            assert_eq!((*t, speed.as_deref()), (1.25, Some("turn")));
            assert_eq!(state.get("x"), Some(2.0));
        }
        other => panic!("expected a non-finite right-hand side, got {other:?}"),
    }
    assert_message(
        &e,
        &[
            "not a finite number at t = 1.25",
            "reduced mass matrix",
            "`turn`",
            "outside the model's geometry",
            "x = 2, y = 0",
        ],
    );

    // The bicycle lying flat on the ground (rolled by π/2, so the front wheel's axle is
    // vertical): the lowest point of the front wheel is a division by zero, and A(q), whose
    // rolling rows use it, has NaN entries.
    let bike = WhippleBicycle::default();
    let mut flat = [0.0; 11];
    flat[WhippleBicycle::PHI] = FRAC_PI_2;
    let mut dx = [0.0; 11];
    assert_eq!(
        bike.rhs(0.0, &flat, &[0.0, 0.0], &mut dx),
        Err(Singularity::NonFinite { speed: None })
    );
    let e = Simulation::new(&bike, flat)
        .run_constant(&Rk4::new(0.01), [0.0, 0.0])
        .unwrap_err();
    assert!(
        matches!(
            e,
            Error::NonFiniteDynamics {
                t: 0.0,
                speed: None,
                ..
            }
        ),
        "{e}"
    );
    assert_message(&e, &["at t = 0", "A(q)", "phi = 1.571"]);
}

// ---------------------------------------------------------------------------------------------
// 9. Answers that were Ok with garbage, and messages that blamed the wrong thing (issue 20)
// ---------------------------------------------------------------------------------------------

/// The bicycle upright at 4 m/s, and the same state with its pitch θ 0.1 rad off: its front
/// wheel then floats above the ground (the holonomic constraint `front_z` misses by the
/// wheel's height).
fn bicycle_on_and_off_the_ground() -> (WhippleBicycle, [f64; 11], [f64; 11]) {
    let bike = WhippleBicycle::default();
    let on = bike
        .state_builder()
        .set("rear_wheel_rate", -4.0 / bike.r_r)
        .build()
        .unwrap();
    let mut off = on;
    off[WhippleBicycle::THETA] += 0.1;
    (bike, on, off)
}

/// Before: a run started off the holonomic surface returned `Ok`; only the summary's
/// `max_holonomic_residual` showed it, while `linearize` refused the same state. Now the run
/// refuses it too, naming the constraint.
#[test]
fn a_run_off_the_holonomic_surface_names_the_constraint() {
    let (bike, on, off) = bicycle_on_and_off_the_ground();
    let sim = |x| Simulation::new(&bike, x).end_time(0.1);
    sim(on)
        .run_constant(&DormandPrince::new(1e-8, 1e-10), [0.0, 0.0])
        .unwrap();
    for project in [false, true] {
        let e = sim(off)
            .project_holonomic(project)
            .run_constant(&DormandPrince::new(1e-8, 1e-10), [0.0, 0.0])
            .unwrap_err();
        match &e {
            Error::HolonomicViolation {
                constraint,
                residual,
                ..
            } => {
                assert_eq!(constraint, "front_z");
                assert!(residual.abs() > 1e-3, "{residual}");
            }
            other => panic!("expected a holonomic violation, got {other:?}"),
        }
        assert_message(&e, &["holonomic constraint `front_z`", "theta = 0.1"]);
    }
    // The same as linearize says.
    let e = bike.linearize(0.0, &off, &[0.0, 0.0]).unwrap_err();
    assert!(matches!(e, Error::HolonomicViolation { .. }), "{e}");
}

/// Before: `constraint_forces` with inputs [NaN, inf] returned [NaN, NaN], and at a state off
/// the holonomic surface it returned numbers. Now both are errors naming the value or the
/// constraint.
#[test]
fn constraint_forces_refuse_what_no_motion_passes_through() {
    let (bike, on, off) = bicycle_on_and_off_the_ground();
    let lambda = bike.constraint_forces(0.0, &on, &[0.0, 0.0]).unwrap();
    assert!(lambda.iter().all(|l| l.is_finite()));
    let e = bike
        .constraint_forces(0.0, &on, &[f64::NAN, f64::INFINITY])
        .unwrap_err();
    match &e {
        Error::NonFiniteArgument {
            function,
            name,
            value,
        } => {
            assert_eq!(
                (*function, name.as_str()),
                ("constraint_forces", "roll_torque")
            );
            assert!(value.is_nan());
        }
        other => panic!("expected a non-finite argument, got {other:?}"),
    }
    assert_message(&e, &["`constraint_forces`", "`roll_torque` = NaN"]);
    let mut nan_state = on;
    nan_state[WhippleBicycle::N + WhippleBicycle::STEER_RATE] = f64::NAN;
    let e = bike
        .constraint_forces(0.0, &nan_state, &[0.0, 0.0])
        .unwrap_err();
    assert!(
        matches!(&e, Error::NonFiniteArgument { name, .. } if name == "steer_rate"),
        "{e}"
    );
    let e = bike.constraint_forces(0.0, &off, &[0.0, 0.0]).unwrap_err();
    assert!(
        matches!(&e, Error::HolonomicViolation { constraint, .. } if constraint == "front_z"),
        "{e}"
    );
    // The generated multipliers, unchecked, are what they were.
    assert!(bike.multipliers(0.0, &off, &[0.0, 0.0]).is_ok());
}

/// Before: a NaN from the input function reached the right-hand side and was reported as
/// "the reduced mass matrix, for `w4` ... outside the model's geometry". Now the input is
/// named, at the time the function returned it.
#[test]
fn a_nan_input_is_not_blamed_on_the_mass_matrix() {
    let robot = MobileRobot::default();
    let x0 = robot
        .state_from_velocities(0.0, &ROBOT_Q, &robot_admissible_qd())
        .unwrap();
    let e = Simulation::new(&robot, x0)
        .end_time(1.0)
        .run(&DormandPrince::new(1e-8, 1e-10), |t, _| {
            [if t < 0.5 { 0.1 } else { f64::NAN }, 0.0]
        })
        .unwrap_err();
    match &e {
        Error::NonFiniteInput { name, t, .. } => {
            assert_eq!(name, "tau1");
            assert!(*t >= 0.5, "{t}");
        }
        other => panic!("expected a non-finite input, got {other:?}"),
    }
    let text = assert_message(&e, &["the input `tau1` is NaN", "state: x = "]);
    assert!(!text.contains("mass matrix"), "{text}");
}

/// Before: the relative energy drift of a conservative run with RK4 steps far too large was
/// 1.2e6, printed like any other figure. Now the summary flags it; a forced system is judged
/// by its energy balance, not by the change of its energy (which printed 17 beside a balance
/// of 3e-10).
#[test]
fn an_energy_error_beyond_a_percent_is_flagged() {
    let sleigh = ChaplyginSleigh::default();
    let x0 = sleigh
        .state_from_speeds(0.0, &[0.0, 0.0, 0.0], &[1.0, 2.0])
        .unwrap();
    let coarse = Simulation::new(&sleigh, x0)
        .end_time(20.0)
        .sample_interval(1.5)
        .run_constant(&Rk4::new(1.5), [])
        .unwrap();
    let s = coarse.summary();
    assert!(s.conservative && s.energy_inaccurate(), "{s}");
    let text = s.to_string();
    println!("{text}");
    assert!(
        text.contains("\nwarning: the energy's relative error"),
        "{text}"
    );
    // The robot driven by its motors: the energy changes by O(1), the balance holds.
    let robot = MobileRobot::default();
    let x0 = robot
        .state_from_velocities(0.0, &ROBOT_Q, &robot_admissible_qd())
        .unwrap();
    let driven = Simulation::new(&robot, x0)
        .end_time(2.0)
        .run_constant(&DormandPrince::new(1e-10, 1e-12), [0.3, -0.2])
        .unwrap();
    let s = driven.summary();
    assert!(s.relative_energy_drift > 1e-3, "{s}");
    assert!(
        s.relative_energy_balance < 1e-8 && !s.energy_inaccurate(),
        "{s}"
    );
    assert!(!s.to_string().contains("drift"), "{s}");
}
