//! A reduced mass matrix that is singular to rounding but not exactly: a skate whose moment of
//! inertia about its contact point is I·cos²θ, so that at θ = π/2 nothing resists turning. In
//! floating point cos(π/2) is 6.1e-17, not 0, so the pivot of the turning rate is I·3.7e-33: a
//! number, but one that the rounding of θ decides. Judged against its own diagonal entry, which
//! it equals (nothing couples to the turning rate), it passed, and `rhs` returned the
//! acceleration 1.6e16, `linearize` entries of 1e32. Judged against the matrix's scale, its
//! trace m + I·cos²θ, it is zero: every evaluation is an error that names the speed, the time
//! and the state.
//!
//! The dynamics, for checking the states where the matrix is regular: with
//! T = ½ m (ẋ² + ẏ²) + ½ I cos²θ θ̇², the blade −ẋ sinθ + ẏ cosθ = 0 and the speeds
//! v = ẋ cosθ + ẏ sinθ, ω = θ̇, the reduced mass matrix is diag(m, I cos²θ), v is constant
//! (no force along the blade, and T does not couple v to ω) and Hamel's equation for ω is
//! d/dt(I cos²θ ω) = ∂T/∂θ = −I cosθ sinθ ω², i.e. ω̇ = tanθ·ω².

use super::assert_message;
use hamel::{Error, HamelSystem, Simulation, Singularity, hamel_system};
use std::f64::consts::FRAC_PI_2;

#[hamel_system]
pub struct CosInertiaSkate {
    pub m: f64,
    pub inertia: f64,
}

#[hamel_system(coordinates(x, y, theta), speeds(v, omega))]
impl CosInertiaSkate {
    #[kinetic_energy]
    fn kinetic_energy(&self, q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        let c = q[2].cos();
        0.5 * self.m * (qd[0] * qd[0] + qd[1] * qd[1]) + 0.5 * self.inertia * c * c * qd[2] * qd[2]
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [-qd[0] * q[2].sin() + qd[1] * q[2].cos()]
    }

    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[2]]
    }
}

const SKATE: CosInertiaSkate = CosInertiaSkate {
    m: 2.0,
    inertia: 0.1,
};

/// The state at heading θ, moving at v = 1 and turning at ω = 1.
fn at(theta: f64) -> [f64; 5] {
    [0.5, -0.25, theta, 1.0, 1.0]
}

#[test]
fn a_pivot_zero_beside_the_matrix_trace_is_a_singular_mass_matrix() {
    let x = at(FRAC_PI_2);
    // The matrix itself is what it is: the turning inertia is the rounding of cos(π/2).
    let mass = SKATE.mass_matrix(0.0, &x).unwrap();
    assert_eq!(mass[0], [2.0, 0.0]);
    assert!(mass[1][1] > 0.0 && mass[1][1] < 1e-32, "{mass:?}");

    // The right-hand side refuses it, naming the turning rate and its pivot.
    let mut dx = [0.0; 5];
    match SKATE.rhs(0.0, &x, &[], &mut dx) {
        Err(Singularity::MassMatrix { speed: 1, value }) => assert_eq!(value, mass[1][1]),
        other => panic!("expected a singular mass matrix, got {other:?} with dx = {dx:?}"),
    }

    // So does the linearization, which differentiates that right-hand side.
    let e = SKATE.linearize(0.75, &x, &[]).unwrap_err();
    match &e {
        Error::SingularMassMatrix {
            t,
            speed,
            value,
            state,
        } => {
            assert_eq!((*t, speed.as_str(), *value), (0.75, "omega", mass[1][1]));
            assert_eq!(state.get("theta"), Some(FRAC_PI_2));
        }
        other => panic!("expected a singular mass matrix, got {other:?}"),
    }
    assert_message(
        &e,
        &[
            "singular reduced mass matrix at t = 0.75",
            "the motion along `omega` has no inertia",
            "beside the matrix's trace",
            "its pivot in the LDLᵀ factorization, 3.749e-34",
            "theta = 1.571, v = 1, omega = 1",
        ],
    );

    // And a run started there stops at its start time.
    let e = Simulation::new(&SKATE, x)
        .start_time(2.0)
        .end_time(3.0)
        .run_constant(&hamel::DormandPrince::new(1e-9, 1e-12), [])
        .unwrap_err();
    assert!(
        matches!(e, Error::SingularMassMatrix { t: 2.0, ref speed, .. } if speed == "omega"),
        "{e:?}"
    );
}

/// The threshold is the matrix's scale, its trace m + I cos²θ, times 10⁻¹³: a turning inertia
/// I cos²θ of 10⁻¹⁰ of m is a regular matrix whose solve gives the closed form ω̇ = tanθ·ω², one
/// of 10⁻¹⁴ of m is not.
#[test]
fn the_pivot_is_judged_against_the_matrix_scale() {
    let regular = [0.3, 1.0, FRAC_PI_2 - 1e-3];
    for theta in regular {
        let x = at(theta);
        let mut dx = [0.0; 5];
        SKATE.rhs(0.0, &x, &[], &mut dx).unwrap();
        let expected = theta.tan();
        assert!(
            (dx[4] - expected).abs() <= 1e-12 * expected.abs(),
            "θ = {theta}: ω̇ = {}, tanθ·ω² = {expected}",
            dx[4]
        );
        assert_eq!(dx[3], 0.0, "v is constant");
    }
    // I cos²θ = 2·10⁻¹⁰ m is above 10⁻¹³ of the trace m + I cos²θ, 2·10⁻¹⁴ m below it
    // (cos θ ≈ π/2 − θ there); above, the acceleration is still the closed form's.
    let ratio = SKATE.m / SKATE.inertia;
    let above = FRAC_PI_2 - (2e-10 * ratio).sqrt();
    let below = FRAC_PI_2 - (2e-14 * ratio).sqrt();
    let mut dx = [0.0; 5];
    SKATE.rhs(0.0, &at(above), &[], &mut dx).unwrap();
    assert!(
        (dx[4] - above.tan()).abs() <= 1e-9 * above.tan(),
        "{} against {}",
        dx[4],
        above.tan()
    );
    assert!(matches!(
        SKATE.rhs(0.0, &at(below), &[], &mut dx),
        Err(Singularity::MassMatrix { speed: 1, .. })
    ));
}
