//! Control from the model (`hamel::ControlAffine`): the drift and input fields, the outputs'
//! Lie derivatives and the Lie brackets the macro generates, checked against an independent
//! computation — num-dual's dual numbers nested to the order needed, run through the model's
//! `rhs_generic` (`support/nested.rs`) — at 100 seeded random states of the robot and the
//! bicycle.

use crate::common::xorshift::XorShift;
use crate::generic_rhs;
use crate::support::nested::{Bracket, Drift, InputField, Lie, Map, Number};
use hamel::models::{MobileRobot, WhippleBicycle};
use hamel::{ControlAffine, HamelSystem};

/// Two computations of the same derivatives in different orders of operations: rounding
/// only, relative to the largest component.
const LIE_TOLERANCE: f64 = 1e-12;

generic_rhs!(MobileRobot, 8, 2);
generic_rhs!(WhippleBicycle, 11, 2);

/// The robot's look-ahead point, 0.3 m ahead of the axle's centre (as its `#[outputs]`).
struct LookAhead<'a>(&'a MobileRobot);

impl Map<8, 2> for LookAhead<'_> {
    fn eval<T: Number>(&self, x: &[T; 8]) -> [T; 2] {
        let theta = (x[3] - x[4]) * (self.0.r / self.0.b);
        [x[0] + theta.cos() * 0.3, x[1] + theta.sin() * 0.3]
    }
}

/// The largest difference of two lists relative to the largest magnitude in `reference`.
fn relative(computed: &[f64], reference: &[f64]) -> f64 {
    let scale = reference.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let worst = computed
        .iter()
        .zip(reference)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    assert!(
        scale > 0.0,
        "a reference that is zero throughout checks nothing"
    );
    worst / scale
}

fn robot_state(rng: &mut XorShift) -> [f64; 8] {
    core::array::from_fn(|i| match i {
        0 | 1 => rng.uniform(-2.0, 2.0),
        2..=4 => rng.uniform(-3.0, 3.0),
        _ => rng.uniform(-1.5, 1.5),
    })
}

#[test]
fn robot_lie_derivatives_and_brackets_match_nested_duals() {
    let robot = MobileRobot::default();
    let mut rng = XorShift::new(28);
    let f = Drift::<_, 2>(&robot);
    let g = |j| InputField::<_, 2>(&robot, j);
    let h = LookAhead(&robot);
    let mut worst = [0.0f64; 4];
    for _ in 0..100 {
        let x = robot_state(&mut rng);
        // The fields.
        let form = robot.control_affine(0.0, &x).unwrap();
        let mut computed: Vec<f64> = form.drift().iter().copied().collect();
        let mut reference: Vec<f64> = f.eval(&x).to_vec();
        for j in 0..2 {
            computed.extend(form.fields().column(j).iter());
            reference.extend(g(j).eval(&x));
        }
        worst[0] = worst[0].max(relative(&computed, &reference));
        // L_f^k h, k ≤ 2, and L_g L_f^k h, k < 2.
        let lie = robot.lie_derivatives(0.0, &x).unwrap();
        let mut computed = Vec::new();
        let mut reference = Vec::new();
        for (i, name) in ["px", "py"].iter().enumerate() {
            computed.push(lie.drift(name, 1).unwrap());
            reference.push(Lie(&h, &f).eval(&x)[i]);
            computed.push(lie.drift(name, 2).unwrap());
            reference.push(Lie(Lie(&h, &f), &f).eval(&x)[i]);
        }
        worst[1] = worst[1].max(relative(&computed, &reference));
        let (mut computed, mut reference) = (Vec::new(), Vec::new());
        for (j, input) in ["tau1", "tau2"].iter().enumerate() {
            for (i, name) in ["px", "py"].iter().enumerate() {
                computed.push(lie.along_input(input, name, 0).unwrap());
                reference.push(Lie(&h, g(j)).eval(&x)[i]);
                computed.push(lie.along_input(input, name, 1).unwrap());
                reference.push(Lie(Lie(&h, &f), g(j)).eval(&x)[i]);
            }
        }
        worst[2] = worst[2].max(relative(&computed, &reference));
        // Brackets to depth 2.
        let brackets = robot.lie_brackets(0.0, &x).unwrap();
        let (mut computed, mut reference) = (Vec::new(), Vec::new());
        let mut check = |label: &str, value: [f64; 8]| {
            computed.extend(brackets.bracket(label).unwrap().iter());
            reference.extend(value);
        };
        check("[f, g_tau1]", Bracket(&f, g(0)).eval(&x));
        check("[f, g_tau2]", Bracket(&f, g(1)).eval(&x));
        check("[g_tau1, g_tau2]", Bracket(g(0), g(1)).eval(&x));
        check("[f, [f, g_tau1]]", Bracket(&f, Bracket(&f, g(0))).eval(&x));
        check(
            "[g_tau2, [f, g_tau1]]",
            Bracket(g(1), Bracket(&f, g(0))).eval(&x),
        );
        check(
            "[g_tau1, [g_tau1, g_tau2]]",
            Bracket(g(0), Bracket(g(0), g(1))).eval(&x),
        );
        worst[3] = worst[3].max(relative(&computed, &reference));
    }
    println!(
        "robot, worst relative differences: fields {:.1e}, L_f^k h {:.1e}, L_g L_f^k h {:.1e}, brackets {:.1e}",
        worst[0], worst[1], worst[2], worst[3]
    );
    assert!(worst.iter().all(|w| *w <= LIE_TOLERANCE), "{worst:?}");
}

/// The bicycle's roll and steer angles (as its `#[outputs]`).
struct LeanAndSteer;

impl Map<11, 2> for LeanAndSteer {
    fn eval<T: Number>(&self, x: &[T; 11]) -> [T; 2] {
        [x[3], x[5]]
    }
}

/// A state of the bicycle on the constraints: random lean, steer, yaw, wheel angles and
/// speeds, the pitch from the holonomic constraint.
fn bicycle_state(bike: &WhippleBicycle, rng: &mut XorShift) -> [f64; 11] {
    let q: [f64; 8] = core::array::from_fn(|i| match i {
        3 => rng.uniform(-0.4, 0.4),
        5 => rng.uniform(-0.6, 0.6),
        4 => 0.0,
        _ => rng.uniform(-2.0, 2.0),
    });
    let q = bike.assemble(0.0, &q).unwrap();
    core::array::from_fn(|i| match i {
        0..8 => q[i],
        10 => rng.uniform(-30.0, 0.0),
        _ => rng.uniform(-2.0, 2.0),
    })
}

#[test]
fn bicycle_lie_derivatives_and_brackets_match_nested_duals() {
    let bike = WhippleBicycle::default();
    let mut rng = XorShift::new(2007);
    let f = Drift::<_, 2>(&bike);
    let g = |j| InputField::<_, 2>(&bike, j);
    let mut worst = [0.0f64; 4];
    for _ in 0..100 {
        let x = bicycle_state(&bike, &mut rng);
        let form = bike.control_affine(0.0, &x).unwrap();
        let mut computed: Vec<f64> = form.drift().iter().copied().collect();
        let mut reference: Vec<f64> = f.eval(&x).to_vec();
        for j in 0..2 {
            computed.extend(form.fields().column(j).iter());
            reference.extend(g(j).eval(&x));
        }
        worst[0] = worst[0].max(relative(&computed, &reference));
        let lie = bike.lie_derivatives(0.0, &x).unwrap();
        let (mut computed, mut reference) = (Vec::new(), Vec::new());
        for (i, name) in ["roll", "steer"].iter().enumerate() {
            computed.push(lie.drift(name, 2).unwrap());
            reference.push(Lie(Lie(LeanAndSteer, &f), &f).eval(&x)[i]);
        }
        worst[1] = worst[1].max(relative(&computed, &reference));
        let (mut computed, mut reference) = (Vec::new(), Vec::new());
        for (j, input) in ["roll_torque", "steer_torque"].iter().enumerate() {
            for (i, name) in ["roll", "steer"].iter().enumerate() {
                computed.push(lie.along_input(input, name, 1).unwrap());
                reference.push(Lie(Lie(LeanAndSteer, &f), g(j)).eval(&x)[i]);
            }
        }
        worst[2] = worst[2].max(relative(&computed, &reference));
        // The angles are coordinates: the torques reach them through the accelerations only.
        assert_eq!(lie.decoupling().unwrap().relative_degrees, [2, 2]);
        // The brackets one deep, all the catalogue's bicycle generates.
        let brackets = bike.lie_brackets(0.0, &x).unwrap();
        assert_eq!(brackets.labels().len(), 3);
        let (mut computed, mut reference) = (Vec::new(), Vec::new());
        let mut check = |label: &str, value: [f64; 11]| {
            computed.extend(brackets.bracket(label).unwrap().iter());
            reference.extend(value);
        };
        check("[f, g_roll_torque]", Bracket(&f, g(0)).eval(&x));
        check("[f, g_steer_torque]", Bracket(&f, g(1)).eval(&x));
        check(
            "[g_roll_torque, g_steer_torque]",
            Bracket(g(0), g(1)).eval(&x),
        );
        worst[3] = worst[3].max(relative(&computed, &reference));
    }
    println!(
        "bicycle, worst relative differences: fields {:.1e}, L_f^2 h {:.1e}, L_g L_f h {:.1e}, \
         brackets {:.1e}",
        worst[0], worst[1], worst[2], worst[3]
    );
    assert!(worst.iter().all(|w| *w <= LIE_TOLERANCE), "{worst:?}");
}

/// A knife edge on a level plane driven by a force F along the blade and a torque τ about
/// the vertical (Bloch, *Nonholonomic Mechanics and Control*, §1.6 without the slope).
#[hamel::hamel_system]
pub struct Skate {
    pub m: f64,
    pub j: f64,
}

#[hamel::hamel_system(
    coordinates(x, y, phi),
    speeds(v, omega),
    inputs(force, torque),
    outputs(px, py),
    control(order = 2, brackets = 3)
)]
impl Skate {
    #[kinetic_energy]
    fn kinetic_energy(&self, _q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        0.5 * self.m * (qd[0] * qd[0] + qd[1] * qd[1]) + 0.5 * self.j * qd[2] * qd[2]
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [qd[0] * q[2].sin() - qd[1] * q[2].cos()]
    }

    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[2]]
    }

    /// The contact point: the force moves it along the blade only, so the torque never
    /// reaches it in two derivatives and the decoupling matrix is singular everywhere.
    #[outputs]
    fn contact(&self, q: &[f64; 3]) -> [f64; 2] {
        [q[0], q[1]]
    }

    #[forces]
    fn drive(&self, _t: f64, q: &[f64; 3], _qd: &[f64; 3], u: &[f64; 2]) -> [f64; 3] {
        [u[0] * q[2].cos(), u[0] * q[2].sin(), u[1]]
    }
}

/// The same knife edge steered by the torque alone: its speed along the blade is an
/// integral of the motion whatever the input, so the accessibility rank is at most 4 of 5.
/// Its outputs, the heading and the turn rate, are two for one input, and the heading's
/// relative degree (2) exceeds the order generated (1).
#[hamel::hamel_system]
pub struct SteeredSkate {
    pub m: f64,
    pub j: f64,
}

#[hamel::hamel_system(
    coordinates(x, y, phi),
    speeds(v, omega),
    inputs(torque),
    outputs(heading, turn_rate),
    control(order = 1, brackets = 3)
)]
impl SteeredSkate {
    #[kinetic_energy]
    fn kinetic_energy(&self, _q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        0.5 * self.m * (qd[0] * qd[0] + qd[1] * qd[1]) + 0.5 * self.j * qd[2] * qd[2]
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [qd[0] * q[2].sin() - qd[1] * q[2].cos()]
    }

    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[2]]
    }

    #[outputs]
    fn heading_and_turn_rate(&self, q: &[f64; 3], speeds: &[f64; 2]) -> [f64; 2] {
        [q[2], speeds[1]]
    }

    #[forces]
    fn drive(&self, _t: f64, _q: &[f64; 3], _qd: &[f64; 3], u: &[f64; 1]) -> [f64; 3] {
        [0.0, 0.0, u[0]]
    }
}

/// The snakeboard (Ostrowski, Lewis, Murray and Burdick 1994; Bloch, *Nonholonomic
/// Mechanics and Control*, §1.10): a board of mass m and inertia J whose two wheel axles
/// turn by ±φ at a distance r from its centre, a rotor ψ (the rider's torso, inertia J_r) on
/// it; the torques drive ψ and φ. q = (x, y, θ, ψ, φ), two rolling constraints.
#[hamel::hamel_system]
pub struct Snakeboard {
    pub m: f64,
    pub j: f64,
    pub j_r: f64,
    pub j_w: f64,
    pub r: f64,
}

#[hamel::hamel_system(
    coordinates(x, y, theta, psi, phi),
    speeds(v, psi_rate, phi_rate),
    inputs(rotor_torque, axle_torque),
    control(brackets = 3)
)]
impl Snakeboard {
    #[kinetic_energy]
    fn kinetic_energy(&self, _q: &[f64; 5], qd: &[f64; 5]) -> f64 {
        0.5 * self.m * (qd[0] * qd[0] + qd[1] * qd[1])
            + 0.5 * self.j * qd[2] * qd[2]
            + 0.5 * self.j_r * qd[3] * qd[3]
            + self.j_r * qd[3] * qd[2]
            + self.j_w * qd[4] * qd[4]
    }

    /// Neither wheel pair slides sideways.
    #[constraints]
    fn wheels(&self, q: &[f64; 5], qd: &[f64; 5]) -> [f64; 2] {
        let (front, back) = (q[2] + q[4], q[2] - q[4]);
        let turn = self.r * qd[2] * q[4].cos();
        [
            -qd[0] * front.sin() + qd[1] * front.cos() - turn,
            -qd[0] * back.sin() + qd[1] * back.cos() + turn,
        ]
    }

    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 5], qd: &[f64; 5]) -> [f64; 3] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[3], qd[4]]
    }

    #[forces]
    fn drive(&self, _t: f64, _q: &[f64; 5], _qd: &[f64; 5], u: &[f64; 2]) -> [f64; 5] {
        [0.0, 0.0, 0.0, u[0], u[1]]
    }
}

#[test]
fn accessibility_ranks_are_what_theory_says() {
    // A force u·(cos φ, sin φ) vanishes with u: the macro sees it through the products.
    const { assert!(Skate::POWER_VANISHES_WITHOUT_INPUTS && !Skate::CONSERVATIVE) };
    let mut rng = XorShift::new(1989);
    let (skate, steered) = (Skate { m: 2.0, j: 0.3 }, SteeredSkate { m: 2.0, j: 0.3 });
    let robot = MobileRobot::default();
    let board = Snakeboard {
        m: 3.0,
        j: 0.1,
        j_r: 0.05,
        j_w: 0.01,
        r: 0.3,
    };
    for _ in 0..100 {
        let x: [f64; 5] = core::array::from_fn(|_| rng.uniform(-2.0, 2.0));
        // Sussmann–Jurdjevic: f, g_force, g_torque span 3; [f, g_force] adds the heading's
        // direction and [f, g_torque] the turning, 4; a second bracket the sideways
        // direction (v, ω ≠ 0): full rank 5 at depth 2.
        let a = skate.accessibility(0.0, &x).unwrap();
        assert_eq!(
            (a.dimension, &a.ranks[..3], a.depth),
            (5, &[3, 4, 5][..], Some(2)),
            "{a}"
        );
        // The speed v is conserved: never more than 4.
        let a = steered.accessibility(0.0, &x).unwrap();
        assert_eq!((a.rank, a.dimension), (4, 5), "{a}");
        let x = robot_state(&mut rng);
        // Both robots need brackets three deep to reach every direction of their 8 states.
        let a = robot.accessibility(0.0, &x).unwrap();
        assert_eq!((a.dimension, a.depth), (8, Some(3)), "{a}");
        let x: [f64; 8] = core::array::from_fn(|i| match i {
            4 => rng.uniform(-1.0, 1.0),
            _ => rng.uniform(-2.0, 2.0),
        });
        let a = board.accessibility(0.0, &x).unwrap();
        assert_eq!((a.dimension, a.depth), (8, Some(3)), "{a}");
    }
    let x = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8];
    println!("snakeboard: {}", board.accessibility(0.0, &x).unwrap());
    let x = robot_state(&mut XorShift::new(7));
    println!("robot: {}", robot.accessibility(0.0, &x).unwrap());
    println!(
        "skate: {}",
        skate
            .accessibility(0.0, &[0.1, 0.2, 0.3, 0.5, 0.7])
            .unwrap()
    );
    println!(
        "steered skate: {}",
        steered
            .accessibility(0.0, &[0.1, 0.2, 0.3, 0.5, 0.7])
            .unwrap()
    );
}

#[test]
fn singular_decoupling_is_an_error_naming_the_state() {
    let skate = Skate { m: 2.0, j: 0.3 };
    let reference = |_t: f64| vec![vec![0.0; 3], vec![0.0; 3]];
    let controller = hamel::control::ExactLinearization::new(&skate, 5.0, reference).unwrap();
    let e = hamel::Controller::<Skate>::control(&controller, 0.5, &[1.0, 2.0, 0.3, 0.5, 0.7])
        .unwrap_err();
    assert!(matches!(e, hamel::Error::SingularDecoupling { .. }), "{e}");
    let message = e.to_string();
    assert!(
        message.contains("t = 0.5") && message.contains("phi = 0.3"),
        "{message}"
    );
    println!("{message}");
}

#[test]
fn relative_degree_beyond_the_generated_order_is_an_error_naming_the_output() {
    let steered = SteeredSkate { m: 2.0, j: 0.3 };
    let lie = steered
        .lie_derivatives(0.5, &[0.1, 0.2, 0.3, 0.5, 0.7])
        .unwrap();
    // J ω̇ = τ: the turn rate has relative degree 1, L_g ω = 1/J.
    let rate = lie.along_input("torque", "turn_rate", 0).unwrap();
    assert!((rate - 1.0 / 0.3).abs() <= 1e-15 * rate, "{rate}");
    // The heading's L_g φ vanishes: its degree is 2, beyond `control(order = 1)`.
    assert_eq!(lie.along_input("torque", "heading", 0).unwrap(), 0.0);
    let e = lie.decoupling().unwrap_err();
    assert!(
        matches!(&e, hamel::Error::RelativeDegree { output, order: 1, .. } if output == "heading"),
        "{e}"
    );
    let message = e.to_string();
    assert!(
        message.contains("control(order = ..)")
            && message.contains("t = 0.5")
            && message.contains("phi = 0.3"),
        "{message}"
    );
    println!("{message}");
}

#[test]
fn exact_linearization_of_a_non_square_system_is_an_error() {
    let steered = SteeredSkate { m: 2.0, j: 0.3 };
    let reference = |_t: f64| vec![vec![0.0; 3], vec![0.0; 2]];
    let e = match hamel::control::ExactLinearization::new(&steered, 5.0, reference) {
        Ok(_) => panic!("two outputs and one input were taken for a square system"),
        Err(e) => e,
    };
    assert!(matches!(e, hamel::Error::DimensionMismatch { .. }), "{e}");
    let message = e.to_string();
    assert!(
        message.contains("2 outputs (heading, turn_rate) and 1 inputs (torque)"),
        "{message}"
    );
    println!("{message}");
}

#[test]
fn exact_linearization_tracks_a_figure_eight() {
    let robot = MobileRobot::default();
    // p_d = (sin t/2, ½ sin t) with its first two derivatives.
    let reference = |t: f64| {
        let (s, c) = (0.5 * t).sin_cos();
        let (s2, c2) = t.sin_cos();
        vec![
            vec![s, 0.5 * c, -0.25 * s],
            vec![0.5 * s2, 0.5 * c2, -0.5 * s2],
        ]
    };
    let controller = hamel::control::ExactLinearization::new(&robot, 10.0, reference).unwrap();
    let run = hamel::Simulation::new(&robot, [0.0; 8])
        .end_time(2.5)
        .sample_interval(0.05)
        .output("error", |t, x| {
            let (p, d) = (robot.output_values(t, x), reference(t));
            (p[0] - d[0][0]).hypot(p[1] - d[1][0])
        })
        .run_controlled(&hamel::DormandPrince::new(1e-11, 1e-13), &controller)
        .unwrap();
    let error = run.column("error").unwrap();
    let after: f64 = run
        .times()
        .iter()
        .zip(error)
        .filter(|(t, _)| **t >= 2.0)
        .fold(0.0, |m, (_, e)| m.max(*e));
    // Starts 0.3 m off; (1 + λt) e^(−λt) · 0.3 = 1.3e-8 at 2 s.
    assert!(error[0] > 0.29 && after <= 1e-6, "{} → {after:e}", error[0]);
    println!("tracking error after 2 s: {after:.2e} m");
}

/// Before, a reference missing the second output's list named the first output, with the
/// count of values it does have, and a rate of 1e300 was accepted and gave NaN inputs.
#[test]
fn a_reference_missing_an_output_and_a_rate_past_f64_are_named() {
    let robot = MobileRobot::default();
    let one_list = |_t: f64| vec![vec![0.0, 0.0, 0.0]];
    let controller = hamel::control::ExactLinearization::new(&robot, 10.0, one_list).unwrap();
    let e = hamel::Controller::<MobileRobot>::control(&controller, 0.0, &[0.0; 8]).unwrap_err();
    assert!(
        matches!(&e, hamel::Error::InvalidReference { output, given: 0, expected: 3, .. } if output == "py"),
        "{e}"
    );
    let message = e.to_string();
    assert!(message.contains("`py` gives 0 values"), "{message}");
    let three = |_t: f64| vec![vec![0.0; 3]; 3];
    let controller = hamel::control::ExactLinearization::new(&robot, 10.0, three).unwrap();
    let e = hamel::Controller::<MobileRobot>::control(&controller, 0.0, &[0.0; 8]).unwrap_err();
    assert!(e.to_string().contains("gives 3 lists of values"), "{e}");
    let reference = |_t: f64| vec![vec![0.0; 3], vec![0.0; 3]];
    let e = match hamel::control::ExactLinearization::new(&robot, 1e300, reference) {
        Ok(_) => panic!("a rate of 1e300 was accepted"),
        Err(e) => e,
    };
    assert!(
        matches!(e, hamel::Error::InvalidSetting { name: "rate", .. }),
        "{e}"
    );
    assert!(e.to_string().contains("beyond the range of f64"), "{e}");
}
