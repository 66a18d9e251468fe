//! `HamelSystem::constraint_forces` against results nobody here computed with hamel: the
//! multipliers λ of d/dt ∂L/∂q̇ − ∂L/∂q = f + A_cᵀλ, one per constraint row, with A_c the rows
//! of `#[constraints]` as written.
//!
//! 1. The knife edge on an inclined plane: λ in closed form at any state, and along its
//!    closed-form motion; the sign convention against Newton's law with the model's own
//!    accelerations.
//! 2. The Chaplygin sleigh: the lateral contact force from Newton–Euler for the body, in
//!    closed form.
//! 3. The mobile robot: against Lagrange's equations with multipliers (the index-1 system
//!    [H_vv A_cᵀ; A_c 0][q̈; −λ] = …, `common/affine_multipliers.rs`) with the Lagrangian
//!    from the bodies' 3D motion (`common/robot_projected_lagrange.rs`), every derivative by
//!    num-dual and every solve by nalgebra; and against Newton's law for the whole robot.
//!    `MobileRobot` agrees; the catalogue's `MobileRobotPaper` does not, because the
//!    paper's L̃ (eq. 12) has the wrong terms in the constrained ω² — which the motion never
//!    sees but the multipliers do. The paper's form with those terms corrected agrees.
//! 4. The ball on the turntable (affine, time-dependent rows): λ is the horizontal contact
//!    force m r̈ of the closed-form motion, and its power −λᵀa_c is the model's `power` and
//!    the rate of the energy along a simulated run. λ does not depend on the choice of the
//!    free quasi-velocities (a sleigh and a knife edge written here with other ones), and a
//!    row multiplied by k has the multiplier λ/k (negated: −λ).
//!
//! Every tolerance is stated where it is asserted, with why; run with `--nocapture` for the
//! measured worst cases.

use std::f64::consts::PI;

use crate::common::affine_multipliers::{Mechanism, Real, reference};
use crate::common::robot_closed_form::robot_rhs;
use crate::common::robot_projected_lagrange;
use crate::common::xorshift::XorShift;
use hamel::models::{BallOnTurntable, ChaplyginSleigh, KnifeEdge, MobileRobot, MobileRobotPaper};
use hamel::{DormandPrince, HamelSystem, Simulation, Trajectory, hamel_system};

/// Random states per parameter set.
const RANDOM_POINTS: usize = 200;

/// Two evaluations of the same closed-form quantity by different arithmetic: a few hundred
/// ulps of the size of its terms at most (the generated code solves for ω̇ and evaluates the
/// first p of Hamel's equations; nothing here is ill-conditioned).
const ROUNDING: f64 = 1e-12;

/// The value of a generated method, which must not meet a singularity at the test points.
fn regular<T, E: std::fmt::Debug>(result: Result<T, E>, what: &str) -> T {
    result.unwrap_or_else(|s| panic!("{what}: singular: {s:?}"))
}

/// The recorded states of a run, with their times.
fn recorded_states<S: HamelSystem>(run: &Trajectory) -> Vec<(f64, S::State)> {
    let columns: Vec<&[f64]> = S::STATE
        .iter()
        .map(|name| run.column(name).expect("a state column"))
        .collect();
    (0..run.len())
        .map(|i| {
            let mut x = <S::State as hamel::Vector>::zeros();
            for (xi, column) in x.as_mut().iter_mut().zip(&columns) {
                *xi = column[i];
            }
            (run.times()[i], x)
        })
        .collect()
}

// ---------------------------------------------------------------------------------------
// 1. The knife edge on an inclined plane
// ---------------------------------------------------------------------------------------
//
// L = ½m(ẋ² + ẏ²) + ½Jφ̇² + m g sin(i) x (x down the slope), the row as the catalogue writes
// it c = ẋ sin φ − ẏ cos φ, so A_c = (sin φ, −cos φ, 0), and Lagrange's equations with the
// documented sign d/dt ∂L/∂q̇ − ∂L/∂q = A_cᵀλ:
//
//   m ẍ − m g sin i = λ sin φ,    m ÿ = −λ cos φ,    J φ̈ = 0.
//
// On the motion ẋ = v cos φ, ẏ = v sin φ, ω = φ̇, so ẍ = v̇ cos φ − v ω sin φ and
// ÿ = v̇ sin φ + v ω cos φ. The first equation times sin φ minus the second times cos φ
// eliminates v̇ (ẍ sin φ − ÿ cos φ = −v ω):
//
//   λ = −m v ω − m g sin(i) sin φ.
//
// A_cᵀλ restricted to (x, y) is λ n with n = (sin φ, −cos φ), the normal to the blade
// pointing to the RIGHT of the heading e = (cos φ, sin φ): λ > 0 pushes the skate to its
// right. The blade supplies the centripetal force m v ω to the left of a skate turning left
// (v ω > 0), hence −m v ω, and cancels gravity's component across the blade,
// m g sin i (e_x · n) = m g sin i sin φ, hence −m g sin i sin φ. A row in m/s gives λ in N.
//
// Along the closed-form motion (Neimark & Fufaev, *Dynamics of Nonholonomic Systems*;
// Bloch, *Nonholonomic Mechanics and Control*, §1.6; derived again in `classic_models.rs`):
// φ = φ₀ + ωt, v = C + k sin φ with k = g sin(i)/ω and C = v₀ − k sin φ₀ (φ₀ = 0 gives the
// textbook v = v₀ + (g sin i/ω) sin ωt), so m v ω = m ω C + m g sin i sin φ and
//
//   λ(t) = −m ω C − 2 m g sin(i) sin(φ₀ + ωt):
//
// a constant centripetal part plus twice gravity's cross component: once to hold the skate
// against it, once more as the centripetal force m ω (k sin φ) on the part of the speed that
// gravity has added.

/// λ at the state (φ, v, ω), derived above.
fn knife_lambda(sys: &KnifeEdge, phi: f64, v: f64, omega: f64) -> f64 {
    -sys.m * v * omega - sys.m * sys.g * sys.incline.sin() * phi.sin()
}

/// The sizes of the two terms of λ, the scale of its rounding (λ may cancel to near zero).
fn knife_lambda_scale(sys: &KnifeEdge, phi: f64, v: f64, omega: f64) -> f64 {
    (sys.m * v * omega).abs() + (sys.m * sys.g * sys.incline.sin() * phi.sin()).abs()
}

/// The catalogue's default skate, a heavier one on a steeper plane, a light one with x up
/// the slope (a negative incline), and one on a level plane (the centripetal term alone).
fn knife_edges() -> Vec<KnifeEdge> {
    vec![
        KnifeEdge::default(),
        KnifeEdge {
            m: 2.5,
            j: 0.3,
            g: 9.81,
            incline: 0.8,
        },
        KnifeEdge {
            m: 0.4,
            j: 0.02,
            g: 9.81,
            incline: -0.5,
        },
        KnifeEdge {
            m: 3.0,
            j: 1.0,
            g: 9.81,
            incline: 0.0,
        },
    ]
}

/// A configuration anywhere near the origin with any heading, a path speed and turning rate
/// of order 0.1–3 either way.
fn knife_state(rng: &mut XorShift) -> [f64; 5] {
    [
        rng.uniform(-5.0, 5.0),
        rng.uniform(-5.0, 5.0),
        rng.uniform(-PI, PI),
        rng.uniform(-3.0, 3.0),
        rng.uniform(-3.0, 3.0),
    ]
}

/// The generated λ equals −m v ω − m g sin(i) sin φ at random states, to rounding of its
/// terms' size (`ROUNDING`); also printed against |λ| alone.
#[test]
fn knife_edge_sideways_force_equals_the_closed_form_at_random_states() {
    let mut rng = XorShift::new(0xf04c_e001);
    let (mut worst, mut worst_alone) = (0.0f64, 0.0f64);
    for sys in knife_edges() {
        for _ in 0..RANDOM_POINTS {
            let x = knife_state(&mut rng);
            let [_, _, phi, v, omega] = x;
            let [lambda] = regular(sys.constraint_forces(0.0, &x, &[]), "knife edge λ");
            let expected = knife_lambda(&sys, phi, v, omega);
            let err = (lambda - expected).abs() / knife_lambda_scale(&sys, phi, v, omega);
            assert!(
                err <= ROUNDING,
                "knife edge {sys:?} at {x:?}: λ = {lambda}, closed form {expected}: relative \
                 error {err:e}"
            );
            worst = worst.max(err);
            worst_alone = worst_alone.max((lambda - expected).abs() / expected.abs());
        }
    }
    println!(
        "knife edge, λ = −m v ω − m g sin i sin φ at {} states: worst error {worst:.1e} of the \
         terms' size, {worst_alone:.1e} of |λ|",
        4 * RANDOM_POINTS
    );
}

/// The documented convention on the model's own motion: with q̈ from the generated right-hand
/// side (ẍ = v̇ cos φ − v ω sin φ, ÿ = v̇ sin φ + v ω cos φ, φ̈ = ω̇), Lagrange's equations
/// d/dt ∂L/∂q̇ − ∂L/∂q = A_cᵀλ hold with A_c = (sin φ, −cos φ, 0), the row as written, to
/// rounding of the terms' size: a λ of the opposite sign would miss by 2|λ|.
#[test]
fn knife_edge_lambda_has_the_documented_sign() {
    let mut rng = XorShift::new(0xf04c_e002);
    let mut worst = 0.0f64;
    for sys in knife_edges() {
        for _ in 0..RANDOM_POINTS {
            let x = knife_state(&mut rng);
            let [_, _, phi, v, omega] = x;
            let mut dx = [0.0; 5];
            regular(sys.rhs(0.0, &x, &[], &mut dx), "knife edge rhs");
            let [lambda] = regular(sys.constraint_forces(0.0, &x, &[]), "knife edge λ");
            let (s, c) = phi.sin_cos();
            let (vdot, omegadot) = (dx[3], dx[4]);
            let xdd = vdot * c - v * omega * s;
            let ydd = vdot * s + v * omega * c;
            let gravity = sys.m * sys.g * sys.incline.sin();
            let lhs = [sys.m * xdd - gravity, sys.m * ydd, sys.j * omegadot];
            let reaction = [lambda * s, -lambda * c, 0.0];
            let scale = (sys.m * vdot).abs() + (sys.m * v * omega).abs() + gravity.abs();
            for (l, r) in lhs.iter().zip(reaction) {
                let err = (l - r).abs() / scale;
                assert!(
                    err <= ROUNDING,
                    "knife edge {sys:?} at {x:?}: d/dt ∂L/∂q̇ − ∂L/∂q = {lhs:?}, A_cᵀλ = \
                     {reaction:?} (λ = {lambda})"
                );
                worst = worst.max(err);
            }
        }
    }
    println!(
        "knife edge, Lagrange's equations with A_cᵀλ on the model's motion: worst {worst:.1e}"
    );
}

/// Initial values of a knife-edge run: those of `classic_models.rs`.
#[derive(Clone, Copy, Debug)]
struct KnifeStart {
    phi0: f64,
    v0: f64,
    omega: f64,
}

/// λ(t) along the closed-form motion, derived above.
fn knife_lambda_along(sys: &KnifeEdge, s: &KnifeStart, t: f64) -> f64 {
    let gs = sys.g * sys.incline.sin();
    let k = gs / s.omega;
    let c = s.v0 - k * s.phi0.sin();
    -sys.m * s.omega * c - 2.0 * sys.m * gs * (s.phi0 + s.omega * t).sin()
}

/// Along simulated runs of five turns (Dormand–Prince, rtol = atol = 1e-13), λ at every
/// recorded state against λ(t) of the closed-form motion at the sample's time.
///
/// The difference is the integration's error in (φ, v) carried into λ, not λ's rounding:
/// |δλ| ≤ m |ω| |δv| + m g |sin i| |δφ| (ω stays exact, ω̇ = 0). `classic_models.rs` bounds
/// the states' absolute error at 1e-8 with rtol = 1e-12 and measures about 1e-10 in x, y;
/// φ and v, which do not grow secularly, stay well below that. At rtol = 1e-13 the budget is
/// 1e-10 relative to max |λ(t)| over the run (measured: see the output).
#[test]
fn knife_edge_lambda_along_the_closed_form_motion() {
    const ALONG_RUN: f64 = 1e-10;
    let cases = [
        (
            KnifeEdge::default(),
            KnifeStart {
                phi0: 0.0,
                v0: 0.5,
                omega: 2.0,
            },
        ),
        (
            KnifeEdge::default(),
            KnifeStart {
                phi0: 1.1,
                v0: -0.7,
                omega: -1.5,
            },
        ),
        (
            KnifeEdge {
                m: 2.5,
                j: 0.3,
                g: 9.81,
                incline: 0.8,
            },
            KnifeStart {
                phi0: -2.4,
                v0: 1.2,
                omega: 3.0,
            },
        ),
    ];
    for (sys, s) in cases {
        let period = 2.0 * PI / s.omega.abs();
        let x0 = sys
            .state_from_speeds(0.0, &[0.3, -0.2, s.phi0], &[s.v0, s.omega])
            .unwrap();
        let run = Simulation::new(&sys, x0)
            .end_time(5.0 * period)
            .sample_interval(period / 50.0)
            .run_constant(&DormandPrince::new(1e-13, 1e-13), [])
            .unwrap();
        let states = recorded_states::<KnifeEdge>(&run);
        assert!(states.len() >= 250);
        let scale = states
            .iter()
            .map(|(t, _)| knife_lambda_along(&sys, &s, *t).abs())
            .fold(0.0, f64::max);
        let (mut worst, mut worst_state) = (0.0f64, 0.0f64);
        for (t, x) in &states {
            let [lambda] = regular(sys.constraint_forces(*t, x, &[]), "knife edge λ");
            let err = (lambda - knife_lambda_along(&sys, &s, *t)).abs() / scale;
            assert!(
                err <= ALONG_RUN,
                "knife edge {s:?}, t = {t}: λ = {lambda}, closed form {}: {err:e} of max |λ| \
                 = {scale}",
                knife_lambda_along(&sys, &s, *t)
            );
            worst = worst.max(err);
            // The same state in the state formula: rounding only.
            let [_, _, phi, v, omega] = *x;
            let at_state = (lambda - knife_lambda(&sys, phi, v, omega)).abs()
                / knife_lambda_scale(&sys, phi, v, omega);
            assert!(at_state <= ROUNDING, "t = {t}: {at_state:e}");
            worst_state = worst_state.max(at_state);
        }
        println!(
            "knife edge {s:?}: λ(t) = −mωC − 2mg sin i sin φ(t) along {} samples, worst \
             {worst:.1e} of max |λ| = {scale:.3} N; at the recorded states {worst_state:.1e}",
            states.len()
        );
    }
}

// ---------------------------------------------------------------------------------------
// 2. The Chaplygin sleigh
// ---------------------------------------------------------------------------------------
//
// Newton–Euler for the body, in its frame (e_θ forward, e_⊥ = (−sin θ, cos θ) to the left),
// as in `classic_models.rs`: the centre of mass moves at v e_θ + u e_⊥, the contact point at
// −a e_θ, the blade makes u = aω, and the only horizontal force is F e_⊥ at the contact:
//
//   m (v̇ − ω u) = 0,   m (u̇ + ω v) = F,   I ω̇ = −a F.
//
// The reduced equations (Bloch, *Nonholonomic Mechanics and Control*, §1.7) v̇ = aω²,
// ω̇ = −m a v ω/(I + m a²) then give the lateral force
//
//   F = m (a ω̇ + v ω) = m v ω I/(I + m a²)   (= −I ω̇/a).
//
// With T = ½m(ẋ² + ẏ²) + ½Iθ̇² and the catalogue's row −ẋ sin θ + ẏ cos θ − a θ̇,
// A_c = (−sin θ, cos θ, −a) and A_cᵀλ = (λ e_⊥, −aλ): the force λ e_⊥ at the contact point
// and its moment about the centre of mass. So λ = F, in newtons (the row is a velocity).
// The sleigh's motion depends on the sign of the γ terms (`classic_models.rs`), and so
// does this λ.

/// F = m v ω I/(I + m a²).
fn sleigh_lambda(sys: &ChaplyginSleigh, v: f64, omega: f64) -> f64 {
    sys.m * v * omega * sys.inertia / (sys.inertia + sys.m * sys.a * sys.a)
}

/// The default sleigh; one whose inertia is small against m a² ((I + m a²)/I = 8.2, where
/// the two terms m a ω̇ and m v ω of F nearly cancel); one with the blade ahead (a < 0).
fn sleighs() -> Vec<ChaplyginSleigh> {
    vec![
        ChaplyginSleigh::default(),
        ChaplyginSleigh {
            m: 1.0,
            inertia: 0.05,
            a: 0.6,
        },
        ChaplyginSleigh {
            m: 5.0,
            inertia: 2.0,
            a: -0.3,
        },
    ]
}

/// λ = m v ω I/(I + m a²) at random states, relative to |λ|. The closed form is a product,
/// free of cancellation; the model may form it as the difference m v ω − m a²(m v ω)/(I +
/// m a²), which loses up to (I + m a²)/I (≤ 8.2 here) times the rounding of its terms, well
/// within `ROUNDING`. Also: I ω̇ = −a λ (the moment equation) with ω̇ from the generated
/// right-hand side, and m ẍ = −λ sin θ, m ÿ = λ cos θ with ẍ, ÿ differentiated by hand
/// from ẋ = v cos θ − a ω sin θ, ẏ = v sin θ + a ω cos θ along it.
#[test]
fn sleigh_lateral_force_equals_newton_euler() {
    let mut rng = XorShift::new(0xf04c_e003);
    let (mut worst, mut worst_newton) = (0.0f64, 0.0f64);
    for sys in sleighs() {
        for _ in 0..RANDOM_POINTS {
            let (v, omega) = (rng.uniform(-3.0, 3.0), rng.uniform(-3.0, 3.0));
            let theta = rng.uniform(-PI, PI);
            let x = [
                rng.uniform(-5.0, 5.0),
                rng.uniform(-5.0, 5.0),
                theta,
                v,
                omega,
            ];
            let [lambda] = regular(sys.constraint_forces(0.0, &x, &[]), "sleigh λ");
            let expected = sleigh_lambda(&sys, v, omega);
            let err = (lambda - expected).abs() / expected.abs();
            assert!(
                err <= ROUNDING,
                "sleigh {sys:?} at {x:?}: λ = {lambda}, m v ω I/(I + m a²) = {expected}: \
                 relative error {err:e}"
            );
            worst = worst.max(err);

            let mut dx = [0.0; 5];
            regular(sys.rhs(0.0, &x, &[], &mut dx), "sleigh rhs");
            let (vdot, omegadot) = (dx[3], dx[4]);
            let (s, c) = theta.sin_cos();
            let a = sys.a;
            let xdd = vdot * c - v * omega * s - a * omegadot * s - a * omega * omega * c;
            let ydd = vdot * s + v * omega * c + a * omegadot * c - a * omega * omega * s;
            let lhs = [sys.m * xdd, sys.m * ydd, sys.inertia * omegadot];
            let reaction = [-lambda * s, lambda * c, -a * lambda];
            let scale = sys.m * (vdot.abs() + (v * omega).abs() + (a * omegadot).abs())
                + sys.m * (a * omega * omega).abs();
            for (l, r) in lhs.iter().zip(reaction) {
                let e = (l - r).abs() / scale;
                assert!(
                    e <= ROUNDING,
                    "sleigh {sys:?} at {x:?}: m q̈ = {lhs:?}, A_cᵀλ = {reaction:?}"
                );
                worst_newton = worst_newton.max(e);
            }
        }
    }
    println!(
        "sleigh, λ = m v ω I/(I + m a²) at {} states: worst relative error {worst:.1e}; \
         Newton–Euler with A_cᵀλ on the model's motion {worst_newton:.1e}",
        3 * RANDOM_POINTS
    );
}

// ---------------------------------------------------------------------------------------
// 3. The mobile robot
// ---------------------------------------------------------------------------------------
//
// The reference is Lagrange's equations with multipliers in q (the index-1 system of
// `common/affine_multipliers.rs`) for the Lagrangian of the bodies' 3D motion
// (`common/robot_projected_lagrange.rs`). λ₁ belongs to the row ẋ sin ϑ − ẏ cos ϑ (no
// sideways slip; A_c₁ᵀλ₁ on (x, y) is λ₁ (sin ϑ, −cos ϑ), so λ₁ is the ground's lateral force
// on the wheels, positive to the right), λ₂ to r α̇ + r/2 (φ̇₁ + φ̇₂) − (ẋ cos ϑ + ẏ sin ϑ)
// (no slip along the path; A_c₂ᵀλ₂ on (x, y) is −λ₂ e_f, so λ₂ is the ground's traction on
// the wheels, positive backwards). Both in newtons.
//
// FOUND: the catalogue's `MobileRobotPaper` does not give these λ. Its L̃ is the paper's
// eq. (12), whose ω² terms m_w (ω²)² − m_w ω²ω⁴ differ from the bodies' ½ m_w (ω²)² +
// m_w ω²ω⁴ (the wheels' spin energy ¼ m_w r² Σᵢ (α̇ + φ̇ᵢ)², with α̇ + φ̇ᵢ = (ω² + ω⁴)/r ±
// b ω⁵/(2r)). `hamel::docs::design` notes the difference and that it does not change the
// motion: the free equations see ∂L̃/∂ω² only through γ²_{l,k} with l, k > 2, which vanish.
// The constrained equations see more. Hamel's equation of row k ≤ p,
// d/dt ∂L̃/∂ωᵏ − ∂L̃/∂q B_k + Σ_j Σ_{l>p} p_j γ^j_{l,k} ωˡ = f̃_k + λ_k, with the difference
// ΔL̃ = ½ m_w (ω²)² − 2 m_w ω²ω⁴ (paper minus bodies), Δp₂ = −2 m_w ω⁴ on the motion and
// γ²_{5,1} = +1 (dω² = dϑ ∧ ω¹), gives
//
//   Δλ₁ = Δp₂ γ²_{5,1} ω⁵ = −2 m_w ω⁴ ω⁵,     Δλ₂ = d/dt Δp₂ = −2 m_w ω̇⁴.
//
// The catalogue's `MobileRobotPaper` is the paper's form with the bodies' ω² terms: it agrees
// with the reference and with `MobileRobot`.

/// The robot as the multiplier formulation sees it: the Lagrangian from the bodies' 3D
/// motion and the rows of A(q), both from `common/robot_projected_lagrange.rs` (not the
/// model's role functions), and the motor torques on φ₁, φ₂.
struct RobotMechanism<'p>(&'p MobileRobot);

impl Mechanism<5> for RobotMechanism<'_> {
    const P: usize = 2;

    fn lagrangian<T: Real>(&self, _t: T, q: &[T; 5], qd: &[T; 5]) -> T {
        robot_projected_lagrange::lagrangian(self.0, q, qd)
    }

    fn rows<T: Real>(&self, _t: T, q: &[T; 5], qd: &[T; 5]) -> [T; 5] {
        robot_projected_lagrange::transformation_rows(self.0, q, qd)
    }

    fn forces(&self, _t: f64, _q: &[f64; 5], _qd: &[f64; 5], u: &[f64]) -> [f64; 5] {
        robot_projected_lagrange::generalized_forces(&[u[0], u[1]]).into()
    }
}

/// The default robot and one with other proportions (as in `robot.rs`).
fn robots() -> Vec<MobileRobot> {
    vec![
        MobileRobot::default(),
        MobileRobot {
            m0: 4.0,
            mw: 0.7,
            jx: 0.15,
            jy: 0.25,
            jz: 0.35,
            r: 0.15,
            b: 0.6,
            l: 0.3,
            g: 9.81,
        },
    ]
}

/// A robot state (position within 10 m, any pitch, wheels turned by up to 20 rad, speeds of
/// order 3) and torques up to 3 N m.
fn robot_sample(rng: &mut XorShift) -> ([f64; 8], [f64; 2]) {
    let x = [
        rng.uniform(-10.0, 10.0),
        rng.uniform(-10.0, 10.0),
        rng.uniform(-PI, PI),
        rng.uniform(-20.0, 20.0),
        rng.uniform(-20.0, 20.0),
        rng.uniform(-3.0, 3.0),
        rng.uniform(-3.0, 3.0),
        rng.uniform(-3.0, 3.0),
    ];
    (x, [rng.uniform(-3.0, 3.0), rng.uniform(-3.0, 3.0)])
}

/// max_k |a_k − b_k| / max_k |b_k|.
fn normwise_error(a: &[f64], b: &[f64]) -> f64 {
    let scale = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let diff = a
        .iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    diff / scale.max(f64::MIN_POSITIVE)
}

/// Two different formulations of λ for the robot: the reference assembles H_vv, ∇_qL and the
/// drift terms of the 3D Lagrangian by hyper-dual numbers and solves a 7×7 system by LU with
/// full pivoting; hamel solves Hamel's equations. Their λ differ by rounding of the forces λ
/// balances (the reference's `multiplier_scale`, printed: up to some 100 times max|λ|), i.e.
/// some 1e-14 relative; 1e-10 leaves room for ill-conditioned states and is still ~10⁹ times
/// smaller than any modelling error (the ω² slip of the paper's L̃ is ~10⁻²).
const ROBOT: f64 = 1e-10;

/// λ of `MobileRobot` in the paper's rows. The robot stated from its two wheels has as rows a
/// wheel's slip along its heading and along its axle, −ω² and −ω¹ of the paper's (the second
/// wheel's repeat them and are left out): A_new = P A_paper with P = [[0, −1], [−1, 0]], so
/// the same force A_paperᵀ λ_paper = A_newᵀ λ_new gives λ_paper = Pᵀ λ_new.
fn in_papers_rows(wheels: [f64; 2]) -> [f64; 2] {
    [-wheels[1], -wheels[0]]
}

/// λ of `MobileRobot` and of `MobileRobotPaper` (the paper's form, its ω² terms corrected) against the index-1 multiplier system
/// at random states and torques, norm-wise relative to max|λ|, and the two forms against
/// each other (the same rows up to order and sign, so the same λ in the paper's rows).
#[test]
fn robot_multipliers_equal_the_index_one_multiplier_system() {
    let mut rng = XorShift::new(0xf04c_e004);
    let (mut worst_everyday, mut worst_paper, mut worst_between) = (0.0f64, 0.0f64, 0.0f64);
    let mut scale_ratio = 0.0f64;
    for robot in robots() {
        let paper = MobileRobotPaper::from(&robot);
        let mechanism = RobotMechanism(&robot);
        for _ in 0..RANDOM_POINTS {
            let (x, u) = robot_sample(&mut rng);
            let (q, w): ([f64; 5], [f64; 3]) = (
                std::array::from_fn(|i| x[i]),
                std::array::from_fn(|i| x[5 + i]),
            );
            let r = reference(&mechanism, 0.0, &q, &w, &u);
            let everyday = in_papers_rows(regular(
                robot.constraint_forces(0.0, &x, &u),
                "MobileRobot λ",
            ));
            let corrected = regular(paper.constraint_forces(0.0, &x, &u), "paper form λ");
            let expected = r.lambda.as_slice();
            for (name, got, worst) in [
                ("MobileRobot", everyday, &mut worst_everyday),
                ("MobileRobotPaper", corrected, &mut worst_paper),
            ] {
                let err = normwise_error(&got, expected);
                assert!(
                    err <= ROBOT,
                    "{name} {robot:?} at x = {x:?}, u = {u:?}: λ = {got:?}, multiplier \
                     system {expected:?}: {err:e}"
                );
                *worst = worst.max(err);
            }
            let between = normwise_error(&corrected, &everyday);
            assert!(
                between <= ROBOT,
                "the two forms' λ at x = {x:?}, u = {u:?}: {everyday:?} vs {corrected:?}"
            );
            worst_between = worst_between.max(between);
            let own = expected.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            scale_ratio = scale_ratio.max(r.multiplier_scale / own);
        }
    }
    println!(
        "robot λ vs the multiplier system at {} states: worst {worst_everyday:.1e} \
         (MobileRobot), {worst_paper:.1e} (paper form, corrected ω² terms); between the forms \
         {worst_between:.1e}; the balanced forces' size is at most {scale_ratio:.1} max|λ|",
        2 * RANDOM_POINTS
    );
}

/// Newton's law for the whole robot, by hand. The only horizontal external forces are the
/// ground's on the wheels, −λ₁ e_a − λ₂ e_f (e_f = (cos ϑ, sin ϑ) forward, e_a = (−sin ϑ,
/// cos ϑ) to the left), so they are the total mass times the acceleration of the centre of
/// mass. The body's centre of gravity is at axle + l sin α e_f + l cos α e_z, the wheels'
/// centres at axle ∓ (b/2) e_a (their accelerations' ϑ̈, ϑ̇² parts cancel in the sum), the
/// axle moves at ω⁴ e_f and ė_f = ω⁵ e_a, ė_a = −ω⁵ e_f:
///
///   λ₁ = −(m₀ + 2m_w) ω⁴ω⁵ − m₀ l (2 cos α ω³ω⁵ + sin α ω̇⁵),
///   λ₂ = −(m₀ + 2m_w) ω̇⁴ − m₀ l (cos α ω̇³ − sin α ((ω³)² + (ω⁵)²)).
///
/// (Upright and not pitching, α = ω³ = 0, λ₁ is the centripetal −(m₀ + 2m_w) v ω.) The
/// accelerations ω̇ come from the closed form of `hamel::docs::design`
/// (`common/robot_closed_form.rs`), not from the model. Asserted to `ROUNDING` of the terms'
/// size, for `MobileRobot` and the corrected paper form.
fn robot_lambda_by_newton(p: &MobileRobot, x: &[f64; 8], u: &[f64; 2]) -> ([f64; 2], f64) {
    let mut dx = [0.0; 8];
    robot_rhs(p, x, u, &mut dx);
    let (alpha, w3, w4, w5) = (x[2], x[5], x[6], x[7]);
    let (w3dot, w4dot, w5dot) = (dx[5], dx[6], dx[7]);
    let (sa, ca) = alpha.sin_cos();
    let (mass, ml) = (p.m0 + 2.0 * p.mw, p.m0 * p.l);
    let lateral = [mass * w4 * w5, ml * 2.0 * ca * w3 * w5, ml * sa * w5dot];
    let along = [
        mass * w4dot,
        ml * ca * w3dot,
        -ml * sa * (w3 * w3 + w5 * w5),
    ];
    let scale = lateral
        .iter()
        .chain(&along)
        .fold(0.0f64, |m, v| m.max(v.abs()));
    (
        [-lateral.iter().sum::<f64>(), -along.iter().sum::<f64>()],
        scale,
    )
}

#[test]
fn robot_multipliers_are_newtons_law_for_the_whole_robot() {
    let mut rng = XorShift::new(0xf04c_e008);
    let mut worst = [0.0f64; 2];
    for robot in robots() {
        let paper = MobileRobotPaper::from(&robot);
        for _ in 0..RANDOM_POINTS {
            let (x, u) = robot_sample(&mut rng);
            let (expected, scale) = robot_lambda_by_newton(&robot, &x, &u);
            let everyday = in_papers_rows(regular(
                robot.constraint_forces(0.0, &x, &u),
                "MobileRobot λ",
            ));
            let corrected = regular(paper.constraint_forces(0.0, &x, &u), "paper form λ");
            for (i, got) in [everyday, corrected].iter().enumerate() {
                let gap = (got[0] - expected[0])
                    .abs()
                    .max((got[1] - expected[1]).abs());
                assert!(
                    gap <= ROUNDING * scale,
                    "{robot:?} at x = {x:?}, u = {u:?}: λ = {got:?}, Newton {expected:?}"
                );
                worst[i] = worst[i].max(gap / scale);
            }
        }
    }
    // The minimal case by hand: upright, rolling at 1 m/s and turning at 1 rad/s. The
    // ground pushes both wheels together towards the centre of the turn, to the left, along
    // their axles: `no_side_slip` is (m₀ + 2m_w) v ω.
    let robot = MobileRobot::default();
    let x = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 1.0];
    let lambda = regular(robot.constraint_forces(0.0, &x, &[0.0; 2]), "MobileRobot λ");
    assert!(
        (lambda[MobileRobot::NO_SIDE_SLIP] - (robot.m0 + 2.0 * robot.mw)).abs() <= ROUNDING * 12.0,
        "{lambda:?}"
    );
    println!(
        "robot λ vs Newton's law for the whole robot at {} states: worst {:.1e} (MobileRobot), \
         {:.1e} (paper form, corrected ω² terms) of the terms' size; upright at v = ω = 1: \
         λ = {lambda:?}",
        2 * RANDOM_POINTS,
        worst[0],
        worst[1]
    );
}

/// Both catalogue robot forms have the same rows (up to order and sign), so the same λ in the
/// paper's rows. (With the paper's printed ω²
/// terms in L̃ they differ by (−2 m_w ω⁴ω⁵, −2 m_w ω̇⁴), about 10⁻² relative; the smallest
/// reproduction is the default robot at x = (0, 0, 0, 0, 0, 0, 1, 1), u = 0: −14 against −12.)
#[test]
fn catalogue_robot_forms_give_the_same_lambda() {
    let mut rng = XorShift::new(0xf04c_e007);
    for robot in robots() {
        let paper = MobileRobotPaper::from(&robot);
        for _ in 0..RANDOM_POINTS {
            let (x, u) = robot_sample(&mut rng);
            let everyday = in_papers_rows(regular(
                robot.constraint_forces(0.0, &x, &u),
                "MobileRobot λ",
            ));
            let printed = regular(paper.constraint_forces(0.0, &x, &u), "MobileRobotPaper λ");
            let err = normwise_error(&printed, &everyday);
            assert!(
                err <= ROBOT,
                "{robot:?} at x = {x:?}, u = {u:?}: λ = {everyday:?} (MobileRobot), \
                 {printed:?} (MobileRobotPaper): {err:e}"
            );
        }
    }
}

// ---------------------------------------------------------------------------------------
// 4. The ball on the turntable; independence of the quasi-velocities; scaled rows
// ---------------------------------------------------------------------------------------
//
// The catalogue's rows are the horizontal velocity of the ball's contact point relative to
// the table's, ṙ + ω × (−ρ e_z) − Ω(t) e_z × r: their coefficient of (ẋ, ẏ) is the identity
// and of the Euler rates is the rolling part, so A_cᵀλ has (λ₁, λ₂) on (x, y): λ is the
// horizontal contact force on the ball, in newtons. Newton for the centre, m r̈ = λ (gravity
// and the normal force are vertical), with the closed-form z̈ = i k d/dt(Ω z), z = x + i y,
// k = I/(I + mρ²) (Burns, Am. J. Phys. 49, 56 (1981)):
//
//   λ₁ + i λ₂ = m k i (Ω̇ z + Ω ż),   i.e.   λ₁ = −m k (ε y + Ω ẏ),  λ₂ = m k (ε x + Ω ẋ).
//
// The rows' part without velocities is a_c = (Ω y, −Ω x), so the power of the constraint
// forces is −λᵀa_c = λ · (Ω e_z × r): the contact force times the velocity of the table's
// material point under the ball. No other force acts and L has no explicit t, so
// dE/dt = −λᵀa_c.

/// A homogeneous ball as in `turntable.rs` (a large radius keeps the Euler angles away
/// from their singularity over the run), and a hollow one on a table turning the other
/// way and slowing down.
fn turntable_balls() -> Vec<BallOnTurntable> {
    vec![
        BallOnTurntable {
            m: 1.0,
            radius: 10.0,
            inertia: 0.4 * 100.0,
            omega0: 1.0,
            epsilon: 0.1,
        },
        BallOnTurntable {
            m: 2.0,
            radius: 8.0,
            inertia: 2.0 / 3.0 * 2.0 * 64.0,
            omega0: -1.5,
            epsilon: 0.2,
        },
    ]
}

/// The ball's centre velocity from the rows by hand: ẋ = ρ ω_y − Ω y, ẏ = −ρ ω_x + Ω x.
fn ball_centre_velocity(b: &BallOnTurntable, t: f64, x: &[f64; 8]) -> [f64; 2] {
    let table = b.omega0 + b.epsilon * t;
    [
        b.radius * x[6] - table * x[1],
        -b.radius * x[5] + table * x[0],
    ]
}

/// Along runs of 10 s (Dormand–Prince, rtol = atol = 1e-13, sampled every 0.01 s):
///
/// * λ at each recorded state equals m k i(Ω̇ z + Ω ż) at that state (rounding of its terms'
///   size, `ROUNDING`);
/// * −λᵀa_c with a_c = (Ω y, −Ω x) by hand equals the model's `power` (no forces, no
///   explicit time in L) to rounding of the terms Σ|λ_j a_j|;
/// * E(t) − E(0), E = ½m|ṙ|² + ½I|ω|² by hand, equals ∫ −λᵀa_c dt by composite Simpson over
///   the samples. The quadrature's error with h = 0.01 s is estimated by Richardson from
///   the same sum at 2h (Simpson's error is 16 times larger there, so the difference over 15
///   estimates it): about 4e-12 of max |E − E₀|. The assertion allows 1e-10 of max |E − E₀|,
///   which covers that and the integration's error in the states (rtol 1e-13 over 10⁴
///   steps); a power off by a part in 10⁹ anywhere along the run would exceed it.
#[test]
fn turntable_constraint_forces_do_the_work() {
    const WORK: f64 = 1e-10;
    for ball in turntable_balls() {
        let (x0, y0, xd0, yd0) = (0.5, 0.2, 0.1, -0.3);
        let rho = ball.radius;
        let speeds = [
            (ball.omega0 * x0 - yd0) / rho,
            (xd0 + ball.omega0 * y0) / rho,
            0.05,
        ];
        let x = ball
            .state_from_speeds(0.0, &[x0, y0, 0.3, 1.2, 0.1], &speeds)
            .unwrap();
        let run = Simulation::new(&ball, x)
            .end_time(10.0)
            .sample_interval(0.01)
            .run_constant(&DormandPrince::new(1e-13, 1e-13), [])
            .unwrap();
        let states = recorded_states::<BallOnTurntable>(&run);
        assert_eq!(
            states.len(),
            1001,
            "an even number of intervals for Simpson"
        );
        let k = ball.inertia / (ball.inertia + ball.m * rho * rho);
        let (mut worst_newton, mut worst_power) = (0.0f64, 0.0f64);
        let mut powers = Vec::with_capacity(states.len());
        let mut energies = Vec::with_capacity(states.len());
        for (t, x) in &states {
            let (t, x) = (*t, x);
            let table = ball.omega0 + ball.epsilon * t;
            let lambda = regular(ball.constraint_forces(t, x, &[]), "ball λ");
            let [xd, yd] = ball_centre_velocity(&ball, t, x);
            let expected = [
                -ball.m * k * (ball.epsilon * x[1] + table * yd),
                ball.m * k * (ball.epsilon * x[0] + table * xd),
            ];
            let scale =
                ball.m * k * (ball.epsilon.abs() * x[0].hypot(x[1]) + table.abs() * xd.hypot(yd));
            let gap = (lambda[0] - expected[0])
                .abs()
                .max((lambda[1] - expected[1]).abs());
            assert!(
                gap <= ROUNDING * scale,
                "t = {t}: λ = {lambda:?}, m r̈ = {expected:?}"
            );
            let newton = gap / scale;
            worst_newton = worst_newton.max(newton);

            let a_c = [table * x[1], -table * x[0]];
            let by_lambda = -(lambda[0] * a_c[0] + lambda[1] * a_c[1]);
            let power = regular(ball.power(t, x, &[]), "ball power");
            let terms = (lambda[0] * a_c[0]).abs() + (lambda[1] * a_c[1]).abs();
            // Exactly zero when the table stops (Ω(t) = 0, at t = 7.5 s for the second ball).
            let gap = (by_lambda - power).abs();
            assert!(
                gap <= ROUNDING * terms,
                "t = {t}: −λᵀa_c = {by_lambda}, power {power}"
            );
            let err = if gap == 0.0 { 0.0 } else { gap / terms };
            worst_power = worst_power.max(err);
            powers.push(by_lambda);
            let spin = x[5] * x[5] + x[6] * x[6] + x[7] * x[7];
            energies.push(0.5 * ball.m * (xd * xd + yd * yd) + 0.5 * ball.inertia * spin);
        }
        // E(t_i) − E(0) at every even sample against Simpson's rule up to it.
        let h = 0.01;
        let simpson = |step: usize, upto: usize| -> f64 {
            let mut sum = 0.0;
            let mut i = 0;
            while i < upto {
                sum += (powers[i] + 4.0 * powers[i + step] + powers[i + 2 * step])
                    * (step as f64 * h)
                    / 3.0;
                i += 2 * step;
            }
            sum
        };
        let change = energies
            .iter()
            .map(|e| (e - energies[0]).abs())
            .fold(0.0, f64::max);
        let (mut worst_work, mut quadrature) = (0.0f64, 0.0f64);
        for upto in (0..states.len()).step_by(2) {
            let work = simpson(1, upto);
            let err = (energies[upto] - energies[0] - work).abs() / change;
            assert!(
                err <= WORK,
                "{ball:?} t = {}: E − E₀ = {}, ∫ −λᵀa_c dt = {work}",
                states[upto].0,
                energies[upto] - energies[0]
            );
            worst_work = worst_work.max(err);
            if upto % 4 == 0 {
                quadrature = quadrature.max((simpson(2, upto) - work).abs() / 15.0 / change);
            }
        }
        assert!(change > 0.1, "the table does work on the ball: {change}");
        println!(
            "ball {ball:?}: λ = m k i(Ω̇z + Ωż) worst {worst_newton:.1e}; −λᵀa_c vs power worst \
             {worst_power:.1e}; E − E₀ vs ∫ −λᵀa_c dt worst {worst_work:.1e} of max|E − E₀| = \
             {change:.3} J (Simpson's error estimate {quadrature:.1e})"
        );
    }
}

/// The Chaplygin sleigh with other quasi-velocities: the velocity (ẋ, ẏ) of the centre of
/// mass instead of its forward speed and the turning rate; the same T and the same row.
/// B by LU (A = [[−sin θ, cos θ, −a], [1, 0, 0], [0, 1, 0]], det = −a).
#[hamel_system]
#[derive(Clone, Debug)]
pub struct CartesianSleigh {
    /// mass (kg)
    pub m: f64,
    /// moment of inertia about the centre of mass (kg m²)
    pub inertia: f64,
    /// distance of the contact point behind the centre of mass (m)
    pub a: f64,
}

#[hamel_system(coordinates(x, y, theta), speeds(vx, vy))]
impl CartesianSleigh {
    #[kinetic_energy]
    fn kinetic_energy(&self, _q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        0.5 * self.m * (qd[0] * qd[0] + qd[1] * qd[1]) + 0.5 * self.inertia * qd[2] * qd[2]
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [-qd[0] * q[2].sin() + qd[1] * q[2].cos() - self.a * qd[2]]
    }

    #[quasi_velocities]
    fn speeds(&self, _q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [qd[0], qd[1]]
    }
}

/// The knife edge with other quasi-velocities, mixing path speed and turning rate:
/// u₁ = 2 s + 0.3 φ̇ and u₂ = φ̇ − 0.5 s with s = ẋ cos φ + ẏ sin φ; the same L and row;
/// B by LU.
#[hamel_system]
#[derive(Clone, Debug)]
pub struct MixedKnifeEdge {
    /// mass (kg)
    pub m: f64,
    /// moment of inertia about the vertical through the contact point (kg m²)
    pub j: f64,
    /// gravitational acceleration (m/s²)
    pub g: f64,
    /// inclination of the plane (rad)
    pub incline: f64,
}

#[hamel_system(coordinates(x, y, phi), speeds(u1, u2))]
impl MixedKnifeEdge {
    #[lagrangian]
    fn lagrangian(&self, q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        0.5 * self.m * (qd[0] * qd[0] + qd[1] * qd[1])
            + 0.5 * self.j * qd[2] * qd[2]
            + self.m * self.g * self.incline.sin() * q[0]
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [qd[0] * q[2].sin() - qd[1] * q[2].cos()]
    }

    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        let s = qd[0] * q[2].cos() + qd[1] * q[2].sin();
        [2.0 * s + 0.3 * qd[2], qd[2] - 0.5 * s]
    }
}

/// The catalogue's knife edge with its row multiplied by `k`: k (ẋ sin φ − ẏ cos φ) = 0, the
/// same constraint. The documented units say λ scales as 1/k; k = −1 negates it.
#[hamel_system]
#[derive(Clone, Debug)]
pub struct ScaledKnifeEdge {
    /// mass (kg)
    pub m: f64,
    /// moment of inertia about the vertical through the contact point (kg m²)
    pub j: f64,
    /// gravitational acceleration (m/s²)
    pub g: f64,
    /// inclination of the plane (rad)
    pub incline: f64,
    /// the factor of the row
    pub k: f64,
}

#[hamel_system(coordinates(x, y, phi), speeds(v, omega))]
impl ScaledKnifeEdge {
    #[lagrangian]
    fn lagrangian(&self, q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        0.5 * self.m * (qd[0] * qd[0] + qd[1] * qd[1])
            + 0.5 * self.j * qd[2] * qd[2]
            + self.m * self.g * self.incline.sin() * q[0]
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [self.k * (qd[0] * q[2].sin() - qd[1] * q[2].cos())]
    }

    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[2]]
    }
}

/// λ of a state given by its physical (q, q̇), through the model's own speeds.
fn lambda_at<S>(sys: &S, q: &[f64; 3], qd: &[f64; 3]) -> f64
where
    S: HamelSystem<Coordinates = [f64; 3], Constraints = [f64; 1], Inputs = [f64; 0]>,
{
    let x = sys
        .state_from_velocities(0.0, q, qd)
        .unwrap_or_else(|e| panic!("q = {q:?}, q̇ = {qd:?}: {e}"));
    regular(sys.constraint_forces(0.0, &x, &[]), "λ")[0]
}

/// At the same physical states (q, q̇) — random q and admissible q̇ — the sleigh with the
/// centre's velocity as its speeds gives the catalogue sleigh's λ, and the knife edge with
/// mixed speeds the catalogue knife edge's: λ is a property of the motion and the row, not of
/// the free quasi-velocities (to rounding, relative to |λ| for the sleigh — a product — and
/// to its terms' size for the knife edge). The knife edge with its row times k gives λ/k.
#[test]
fn lambda_is_independent_of_the_quasi_velocities_and_scales_with_the_row() {
    let mut rng = XorShift::new(0xf04c_e005);
    let (mut worst_sleigh, mut worst_knife, mut worst_scaled) = (0.0f64, 0.0f64, 0.0f64);
    for sys in sleighs() {
        let other = CartesianSleigh {
            m: sys.m,
            inertia: sys.inertia,
            a: sys.a,
        };
        for _ in 0..RANDOM_POINTS {
            let theta = rng.uniform(-PI, PI);
            let q = [rng.uniform(-5.0, 5.0), rng.uniform(-5.0, 5.0), theta];
            let (v, omega) = (rng.uniform(-3.0, 3.0), rng.uniform(-3.0, 3.0));
            let (s, c) = theta.sin_cos();
            // The centre of mass moves at v e_θ + a ω e_⊥.
            let qd = [v * c - sys.a * omega * s, v * s + sys.a * omega * c, omega];
            let (catalogue, cartesian) = (lambda_at(&sys, &q, &qd), lambda_at(&other, &q, &qd));
            let err = (cartesian - catalogue).abs() / catalogue.abs();
            assert!(
                err <= ROUNDING,
                "sleigh {sys:?} at q = {q:?}, q̇ = {qd:?}: λ = {catalogue} (v, ω), {cartesian} \
                 (ẋ, ẏ)"
            );
            worst_sleigh = worst_sleigh.max(err);
        }
    }
    for sys in knife_edges() {
        let mixed = MixedKnifeEdge {
            m: sys.m,
            j: sys.j,
            g: sys.g,
            incline: sys.incline,
        };
        for _ in 0..RANDOM_POINTS {
            let phi = rng.uniform(-PI, PI);
            let q = [rng.uniform(-5.0, 5.0), rng.uniform(-5.0, 5.0), phi];
            let (v, omega) = (rng.uniform(-3.0, 3.0), rng.uniform(-3.0, 3.0));
            let qd = [v * phi.cos(), v * phi.sin(), omega];
            let scale = knife_lambda_scale(&sys, phi, v, omega);
            let catalogue = lambda_at(&sys, &q, &qd);
            let other = lambda_at(&mixed, &q, &qd);
            let err = (other - catalogue).abs() / scale;
            assert!(
                err <= ROUNDING,
                "knife edge {sys:?} at q = {q:?}, q̇ = {qd:?}: λ = {catalogue} (v, ω), {other} \
                 (mixed)"
            );
            worst_knife = worst_knife.max(err);
            for k in [-1.0, 2.5, -0.125] {
                let scaled = ScaledKnifeEdge {
                    m: sys.m,
                    j: sys.j,
                    g: sys.g,
                    incline: sys.incline,
                    k,
                };
                let lambda = lambda_at(&scaled, &q, &qd);
                let err = (k * lambda - catalogue).abs() / scale;
                assert!(
                    err <= ROUNDING,
                    "row × {k}: λ = {lambda}, expected {catalogue}/{k} at q = {q:?}, q̇ = {qd:?}"
                );
                worst_scaled = worst_scaled.max(err);
            }
        }
    }
    println!(
        "λ at the same (q, q̇): sleigh (v, ω) vs (ẋ, ẏ) worst {worst_sleigh:.1e}; knife edge \
         (v, ω) vs mixed {worst_knife:.1e}; row × k gives λ/k to {worst_scaled:.1e}"
    );
}
