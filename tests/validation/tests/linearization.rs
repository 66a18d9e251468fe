//! The linearization `HamelSystem::linearize` (dual numbers through the generated
//! right-hand side) against what nobody here wrote: hand-derived Jacobians of the classic
//! models' closed-form equations, central finite differences of the right-hand side at
//! random states, and the closed-form pitch dynamics of the paper's robot at rest.

use crate::common::xorshift::XorShift;
use hamel::models::{ChaplyginSleigh, KnifeEdge, MobileRobot, WhippleBicycle};
use hamel::{Error, HamelSystem, Linearization};

/// The largest |a − b| over the entries of a linearization's A against a reference matrix.
fn worst_against(lin: &Linearization, reference: &[[f64; 5]; 5]) -> f64 {
    let a = lin.a_matrix();
    let mut worst = 0.0f64;
    for (i, row) in reference.iter().enumerate() {
        for (j, &r) in row.iter().enumerate() {
            worst = worst.max((a[(i, j)] - r).abs());
        }
    }
    worst
}

/// The sleigh's reduced equations: ẋ = v cos θ − aω sin θ, ẏ = v sin θ + aω cos θ, θ̇ = ω,
/// v̇ = aω², ω̇ = −m a v ω/(I + m a²) (Bloch, §1.7), differentiated by hand.
#[test]
fn the_sleigh_has_its_hand_derived_jacobian() {
    let sleigh = ChaplyginSleigh::default();
    let (m, i, a) = (sleigh.m, sleigh.inertia, sleigh.a);
    let mut rng = XorShift::new(17);
    let mut worst = 0.0f64;
    for _ in 0..20 {
        let x: [f64; 5] = std::array::from_fn(|_| rng.uniform(-2.0, 2.0));
        let (theta, v, w) = (x[2], x[3], x[4]);
        let (s, c) = theta.sin_cos();
        let k = m * a / (i + m * a * a);
        let reference = [
            [0.0, 0.0, -s * v - c * a * w, c, -s * a],
            [0.0, 0.0, c * v - s * a * w, s, c * a],
            [0.0, 0.0, 0.0, 0.0, 1.0],
            [0.0, 0.0, 0.0, 0.0, 2.0 * a * w],
            [0.0, 0.0, 0.0, -k * w, -k * v],
        ];
        let lin = sleigh.linearize(0.0, &x, &[]).unwrap();
        worst = worst.max(worst_against(&lin, &reference));
    }
    println!("sleigh: worst difference from the analytic Jacobian {worst:e}");
    assert!(worst <= 1e-13, "{worst:e}");
}

/// The knife edge on an incline: ẋ = v cos φ, ẏ = v sin φ, φ̇ = ω, v̇ = g sin(i) cos φ,
/// ω̇ = 0.
#[test]
fn the_knife_edge_has_its_hand_derived_jacobian() {
    let skate = KnifeEdge::default();
    let gs = skate.g * skate.incline.sin();
    let mut rng = XorShift::new(23);
    let mut worst = 0.0f64;
    for _ in 0..20 {
        let x: [f64; 5] = std::array::from_fn(|_| rng.uniform(-2.0, 2.0));
        let (phi, v) = (x[2], x[3]);
        let (s, c) = phi.sin_cos();
        let reference = [
            [0.0, 0.0, -v * s, c, 0.0],
            [0.0, 0.0, v * c, s, 0.0],
            [0.0, 0.0, 0.0, 0.0, 1.0],
            [0.0, 0.0, -gs * s, 0.0, 0.0],
            [0.0; 5],
        ];
        let lin = skate.linearize(0.0, &x, &[]).unwrap();
        worst = worst.max(worst_against(&lin, &reference));
    }
    println!("knife edge: worst difference from the analytic Jacobian {worst:e}");
    assert!(worst <= 1e-13, "{worst:e}");
}

/// Central differences of `rhs` in every state and input direction, relative to the larger
/// of the entry and the column's scale: the truncation error is O(h²) ≈ 1e-9 of the second
/// derivatives, far inside 1e-6.
fn against_differences<S: HamelSystem>(system: &S, t: f64, x: &S::State, u: &S::Inputs) -> f64 {
    let lin = system.linearize(t, x, u).unwrap();
    let (a, b) = (lin.a_matrix(), lin.b_matrix());
    let rhs = |x: &S::State, u: &S::Inputs| {
        let mut dx = *x;
        system.rhs(t, x, u, &mut dx).unwrap();
        dx
    };
    let mut worst = 0.0f64;
    let n = x.as_ref().len();
    let columns = n + u.as_ref().len();
    for column in 0..columns {
        let (mut xp, mut xm, mut up, mut um) = (*x, *x, *u, *u);
        let h = 1e-6;
        if column < n {
            xp.as_mut()[column] += h;
            xm.as_mut()[column] -= h;
        } else {
            up.as_mut()[column - n] += h;
            um.as_mut()[column - n] -= h;
        }
        let (fp, fm) = (rhs(&xp, &up), rhs(&xm, &um));
        let exact = |row: usize| {
            if column < n {
                a[(row, column)]
            } else {
                b[(row, column - n)]
            }
        };
        let scale = (0..n).map(|r| exact(r).abs()).fold(1.0, f64::max);
        for row in 0..n {
            let difference = (fp.as_ref()[row] - fm.as_ref()[row]) / (2.0 * h);
            worst = worst.max((difference - exact(row)).abs() / scale);
        }
    }
    worst
}

#[test]
fn the_robot_agrees_with_finite_differences_at_random_states() {
    let robot = MobileRobot::default();
    let mut rng = XorShift::new(5);
    let mut worst = 0.0f64;
    for _ in 0..20 {
        let x: [f64; 8] = std::array::from_fn(|_| rng.uniform(-1.5, 1.5));
        let u = [rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0)];
        worst = worst.max(against_differences(&robot, 0.0, &x, &u));
    }
    println!("robot: worst relative difference from central differences {worst:e}");
    assert!(worst <= 1e-6, "{worst:e}");
}

#[test]
fn the_bicycle_agrees_with_finite_differences_at_random_states() {
    let bike = WhippleBicycle::default();
    let mut rng = XorShift::new(9);
    let mut worst = 0.0f64;
    for _ in 0..10 {
        let mut builder = bike.state_builder();
        for (name, range) in [
            ("psi", 3.0),
            ("phi", 0.4),
            ("delta", 0.6),
            ("roll_rate", 1.0),
            ("steer_rate", 2.0),
        ] {
            builder = builder.set(name, rng.uniform(-range, range));
        }
        let speed = rng.uniform(1.0, 8.0);
        let x = builder
            .set("rear_wheel_rate", -speed / bike.r_r)
            .build()
            .unwrap();
        let u = [rng.uniform(-5.0, 5.0), rng.uniform(-2.0, 2.0)];
        worst = worst.max(against_differences(&bike, 0.0, &x, &u));
    }
    println!("bicycle: worst relative difference from central differences {worst:e}");
    assert!(worst <= 1e-6, "{worst:e}");
}

/// The robot at rest, upright (α = 0), is an inverted pendulum on a cart: from the paper's
/// equations (`hamel::docs::design`, worked example), linearized,
/// (J_y + m₀l²) α̈ + m₀ l ω̇⁴ = m₀ g l α and m₀ l α̈ + (m₀ + 3m_w) ω̇⁴ = 0, so α̈ = λ² α with
/// λ² = m₀ g l (m₀ + 3m_w) / ((J_y + m₀l²)(m₀ + 3m_w) − m₀²l²).
#[test]
fn the_robot_upright_at_rest_is_an_inverted_pendulum() {
    for robot in [
        MobileRobot::default(),
        // A body matter can make: its moments (jx, jy, jz) = (0.4, 0.25, 0.2) keep the
        // triangle inequality (jy = 0.1 did not, and `linearize` now refuses it, as a run does).
        MobileRobot {
            l: 0.35,
            m0: 4.0,
            jy: 0.25,
            ..MobileRobot::default()
        },
    ] {
        let (m0, mw, jy, l, g) = (robot.m0, robot.mw, robot.jy, robot.l, robot.g);
        let det = (jy + m0 * l * l) * (m0 + 3.0 * mw) - m0 * m0 * l * l;
        let rate = (m0 * g * l * (m0 + 3.0 * mw) / det).sqrt();
        let lin = robot
            .linearize(0.0, &[0.0; 8], &[0.0, 0.0])
            .unwrap()
            .reduce(&["alpha", "w3", "w4"])
            .unwrap();
        let mut values: Vec<f64> = lin
            .eigenvalues()
            .unwrap()
            .iter()
            .map(|l| {
                assert!(l.im.abs() < 1e-12, "{l}");
                l.re
            })
            .collect();
        values.sort_by(f64::total_cmp);
        println!("robot upright: {values:?}, closed form ±{rate}");
        assert!((values[0] + rate).abs() <= 1e-12 * rate, "{values:?}");
        assert!(values[1].abs() <= 1e-12 * rate, "{values:?}");
        assert!((values[2] - rate).abs() <= 1e-12 * rate, "{values:?}");
        // The unstable mode tips the body forward while the wheels roll it back under it.
        let mode = &lin.modes().unwrap()[0];
        let (alpha, w4) = (
            mode.component("alpha").unwrap().re,
            mode.component("w4").unwrap().re,
        );
        assert!(alpha * w4 < 0.0, "{mode}");
    }
}

#[test]
fn a_non_finite_operating_point_is_an_error_naming_it() {
    let robot = MobileRobot::default();
    let mut x = [0.0; 8];
    x[MobileRobot::ALPHA] = f64::NAN;
    let e = robot.linearize(0.0, &x, &[0.0, 0.0]).unwrap_err();
    assert!(e.to_string().contains("alpha"), "{e}");
    let e = robot
        .linearize(0.0, &[0.0; 8], &[f64::INFINITY, 0.0])
        .unwrap_err();
    assert!(e.to_string().contains("tau1"), "{e}");
    let e = robot
        .linearize(f64::NAN, &[0.0; 8], &[0.0, 0.0])
        .unwrap_err();
    assert!(matches!(e, Error::NonFiniteOperatingPoint { .. }), "{e}");
}

#[test]
fn a_singular_configuration_is_an_error_naming_it() {
    // No moment of inertia: nothing resists turning.
    let pointlike = KnifeEdge {
        j: 0.0,
        ..KnifeEdge::default()
    };
    let e = pointlike
        .linearize(1.5, &[0.0, 0.0, 0.0, 1.0, 0.5], &[])
        .unwrap_err();
    assert!(
        matches!(e, Error::SingularMassMatrix { t: 1.5, ref speed, .. } if speed == "omega"),
        "{e}"
    );
    // The bicycle off its holonomic constraint (the pitch of another configuration).
    let bike = WhippleBicycle::default();
    let mut x = [0.0; 11];
    x[WhippleBicycle::THETA] = 0.3;
    let e = bike.linearize(0.0, &x, &[0.0, 0.0]).unwrap_err();
    assert!(e.to_string().contains("front_z"), "{e}");
}
