//! Control from the model (`hamel::ControlAffine`): the drift and input fields, the outputs'
//! Lie derivatives and the Lie brackets the macro generates, checked against an independent
//! computation — num-dual's dual numbers nested to the order needed, run through the model's
//! `rhs_generic` (`support/nested.rs`) — at 100 seeded random states of the robot and the
//! bicycle.

#[path = "support/nested.rs"]
mod nested;
#[path = "common/xorshift.rs"]
mod xorshift;

use hamel::models::{MobileRobot, WhippleBicycle};
use hamel::{ControlAffine, HamelSystem};
use nested::{Bracket, Drift, InputField, Lie, Map, Number};
use xorshift::XorShift;

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
fn bicycle_lie_derivatives_match_nested_duals() {
    let bike = WhippleBicycle::default();
    let mut rng = XorShift::new(2007);
    let f = Drift::<_, 2>(&bike);
    let g = |j| InputField::<_, 2>(&bike, j);
    let mut worst = [0.0f64; 3];
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
    }
    println!(
        "bicycle, worst relative differences: fields {:.1e}, L_f^2 h {:.1e}, L_g L_f h {:.1e}",
        worst[0], worst[1], worst[2]
    );
    assert!(worst.iter().all(|w| *w <= LIE_TOLERANCE), "{worst:?}");
}
