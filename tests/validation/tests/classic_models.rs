//! The classic nonholonomic models of the catalogue against results derived by hand,
//! independently of Hamel's equations:
//!
//! * the knife edge on an inclined plane against its closed-form solution (Neimark & Fufaev,
//!   *Dynamics of Nonholonomic Systems*; Bloch, *Nonholonomic Mechanics and Control*, §1.6);
//! * the Chaplygin sleigh against its reduced equations v̇ = aω², ω̇ = −m a v ω/(I + m a²)
//!   (Bloch §1.7), integrated here by a separate ODE, and against its asymptotic speed.
//!
//! Both conserve energy (no forces act) and keep the constraint residual at rounding level.
//! Every tolerance is stated where it is asserted; the measured discrepancies are printed
//! (`cargo test -p hamel-validation --test models -- classic_models:: --nocapture`).

use hamel::models::{ChaplyginSleigh, KnifeEdge};
use hamel::{DormandPrince, Error, HamelSystem, Integrator, Ode, Rk4, Simulation, Trajectory};

// ---------------------------------------------------------------------------------------------
// Shared checks
// ---------------------------------------------------------------------------------------------

/// The largest constraint residual |A_c(q) q̇| over all samples of a run, recomputed here from
/// the recorded state (q̇ = B(q) ω through the generated `velocities`), together with the
/// run's own monitor.
fn max_constraint_residual<S>(sys: &S, run: &Trajectory) -> f64
where
    S: HamelSystem,
{
    let columns: Vec<&[f64]> = S::STATE
        .iter()
        .map(|name| run.column(name).expect("a state column"))
        .collect();
    let mut worst = 0.0f64;
    for i in 0..run.len() {
        let mut x = <S::State as hamel::Vector>::zeros();
        for (xi, column) in x.as_mut().iter_mut().zip(&columns) {
            *xi = column[i];
        }
        let q = S::coordinates_of(&x);
        let qd = sys
            .generalized_velocities(0.0, &x)
            .expect("regular transformation");
        for r in sys.constraint_residual(0.0, &q, &qd).as_ref() {
            assert!(r.is_finite());
            worst = worst.max(r.abs());
        }
    }
    worst.max(run.summary().max_constraint_residual)
}

/// max over samples of |E(t) − E(0)| / |E(0)| from the run's energy column.
fn relative_energy_drift(run: &Trajectory) -> f64 {
    let energy = run.column("energy").expect("energy column");
    let e0 = energy[0];
    energy
        .iter()
        .map(|e| (e - e0).abs() / e0.abs())
        .fold(0.0, f64::max)
}

/// Constraint residual bound at every sample (the reduced state satisfies the constraints by
/// construction: only rounding in q̇ = B ω and in the constraint rows remains).
const CONSTRAINT_TOL: f64 = 1e-12;

// ---------------------------------------------------------------------------------------------
// 1. Knife edge on an inclined plane
// ---------------------------------------------------------------------------------------------
//
// Closed form. With x down the slope, L = ½m(ẋ² + ẏ²) + ½Jφ̇² + m g sinα x (α: incline) and
// the constraint ẋ sinφ − ẏ cosφ = 0, the admissible velocities are ẋ = v cosφ, ẏ = v sinφ
// (v: path speed along the blade). Lagrange–d'Alembert:
//   J φ̈ = 0                      (the constraint force is normal to the blade and passes
//                                  through the contact point: no torque)
//   m v̇ = m g sinα cosφ           (gravity's component along the blade; the constraint force
//                                  is across it)
// so φ = φ₀ + ωt and, with k = g sinα/ω,
//   v = v₀ + k (sin φ − sin φ₀)  =  C + k sin φ,   C = v₀ − k sin φ₀.
// (φ₀ = 0 gives the textbook v = v₀ + (g sinα/ω) sin ωt.) Then
//   ẋ = (C + k sinφ) cosφ = C cosφ + (k/2) sin 2φ
//   ẏ = (C + k sinφ) sinφ = C sinφ + (k/2)(1 − cos 2φ)
// and with dφ = ω dt:
//   x = x₀ + (C/ω)(sinφ − sinφ₀) − (k/4ω)(cos 2φ − cos 2φ₀)
//   y = y₀ − (C/ω)(cosφ − cosφ₀) + (k/2) t − (k/4ω)(sin 2φ − sin 2φ₀).
// Differentiating reproduces ẋ and ẏ above; `closed_form_is_a_solution` also checks the
// formulas numerically against a quadrature of ẋ = v cosφ, ẏ = v sinφ, v̇ = g sinα cosφ.
// (The secular term (k/2)t is the classic surprise: on average the skate drifts across the
// slope, not down it.)

/// Initial values of a knife-edge run.
#[derive(Clone, Copy, Debug)]
struct KnifeStart {
    x0: f64,
    y0: f64,
    phi0: f64,
    v0: f64,
    omega: f64,
}

/// The closed-form state (x, y, φ, v, ω) at time t (derived above).
fn knife_exact(sys: &KnifeEdge, s: &KnifeStart, t: f64) -> [f64; 5] {
    let w = s.omega;
    let k = sys.g * sys.incline.sin() / w;
    let c = s.v0 - k * s.phi0.sin();
    let phi = s.phi0 + w * t;
    let v = c + k * phi.sin();
    let x = s.x0 + c / w * (phi.sin() - s.phi0.sin())
        - k / (4.0 * w) * ((2.0 * phi).cos() - (2.0 * s.phi0).cos());
    let y = s.y0 - c / w * (phi.cos() - s.phi0.cos()) + 0.5 * k * t
        - k / (4.0 * w) * ((2.0 * phi).sin() - (2.0 * s.phi0).sin());
    [x, y, phi, v, w]
}

/// E = T + V = ½ m v² + ½ J ω² − m g sinα x, by hand.
fn knife_energy(sys: &KnifeEdge, state: &[f64; 5]) -> f64 {
    let [x, _, _, v, w] = *state;
    0.5 * sys.m * v * v + 0.5 * sys.j * w * w - sys.m * sys.g * sys.incline.sin() * x
}

/// The cases: the textbook one (φ₀ = 0) and ones with φ₀ ≠ 0, a negative turning rate, a
/// backward start and a steeper plane.
fn knife_cases() -> Vec<(KnifeEdge, KnifeStart)> {
    vec![
        (
            KnifeEdge::default(),
            KnifeStart {
                x0: 0.3,
                y0: -0.2,
                phi0: 0.0,
                v0: 0.5,
                omega: 2.0,
            },
        ),
        (
            KnifeEdge::default(),
            KnifeStart {
                x0: -1.0,
                y0: 0.4,
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
                x0: 0.0,
                y0: 0.0,
                phi0: -2.4,
                v0: 1.2,
                omega: 3.0,
            },
        ),
    ]
}

/// Sanity of the derivation: the closed form starts at the initial values and agrees with a
/// composite Simpson quadrature of ẋ = v cosφ, ẏ = v sinφ and v̇ = g sinα cosφ (with the
/// closed-form φ, v under the integral), to 1e-11 absolute.
#[test]
fn closed_form_is_a_solution() {
    for (sys, s) in knife_cases() {
        let e0 = knife_exact(&sys, &s, 0.0);
        assert_eq!(e0, [s.x0, s.y0, s.phi0, s.v0, s.omega]);
        let gs = sys.g * sys.incline.sin();
        let rates = |t: f64| {
            let [_, _, phi, v, _] = knife_exact(&sys, &s, t);
            [v * phi.cos(), v * phi.sin(), gs * phi.cos()]
        };
        let t_end = 5.0 * std::f64::consts::TAU / s.omega.abs();
        let n = 20_000; // even
        let h = t_end / n as f64;
        let mut integral = [0.0; 3];
        for i in 0..=n {
            let weight = if i == 0 || i == n {
                1.0
            } else if i % 2 == 1 {
                4.0
            } else {
                2.0
            };
            let r = rates(i as f64 * h);
            for (acc, ri) in integral.iter_mut().zip(r) {
                *acc += weight * ri * h / 3.0;
            }
        }
        let [x, y, _, v, _] = knife_exact(&sys, &s, t_end);
        let errors = [
            (x - s.x0 - integral[0]).abs(),
            (y - s.y0 - integral[1]).abs(),
            (v - s.v0 - integral[2]).abs(),
        ];
        println!(
            "closed form vs quadrature {s:?}: x {:.2e}, y {:.2e}, v {:.2e}",
            errors[0], errors[1], errors[2]
        );
        for e in errors {
            assert!(
                e <= 1e-11,
                "closed form disagrees with quadrature: {errors:?}"
            );
        }
    }
}

/// Five periods 2π/|ω| with Dormand–Prince at rtol = atol = 1e-12: every sample of x, y, φ,
/// v, ω within 1e-8 **absolute** of the closed form (|y| reaches ~15 here, so this is also a
/// ~1e-9 relative bound on the largest component).
#[test]
fn knife_edge_matches_closed_form() {
    const TOL: f64 = 1e-8;
    for (sys, s) in knife_cases() {
        let period = std::f64::consts::TAU / s.omega.abs();
        let x0 = sys
            .state_from_speeds(0.0, &[s.x0, s.y0, s.phi0], &[s.v0, s.omega])
            .unwrap();
        let run = Simulation::new(&sys, x0)
            .end_time(5.0 * period)
            .sample_interval(period / 50.0)
            .run_constant(&DormandPrince::new(1e-12, 1e-12), [])
            .unwrap();
        assert!(run.len() >= 250);
        let names = ["x", "y", "phi", "v", "omega"];
        let mut worst = [0.0f64; 5];
        for (i, &t) in run.times().iter().enumerate() {
            let exact = knife_exact(&sys, &s, t);
            for (j, name) in names.iter().enumerate() {
                let got = run.column(name).unwrap()[i];
                let err = (got - exact[j]).abs();
                worst[j] = worst[j].max(err);
                assert!(
                    err <= TOL,
                    "{name}({t}) = {got}, closed form {}: error {err:e} > {TOL:e} ({s:?})",
                    exact[j]
                );
            }
        }
        println!(
            "knife edge {s:?}: max abs error x {:.2e}, y {:.2e}, phi {:.2e}, v {:.2e}, omega {:.2e}; {} steps",
            worst[0],
            worst[1],
            worst[2],
            worst[3],
            worst[4],
            run.summary().steps
        );
    }
}

/// No forces besides gravity (in V) and the workless constraint: E = ½mv² + ½Jω² − m g sinα x
/// is conserved. The energy column must equal that formula at every sample to 1e-12 relative
/// to max(|E(0)|, 1 J) (the generated `energy` is right), and max |E(t) − E(0)| must stay
/// ≤ 1e-9·T_max, T_max the largest kinetic energy ½mv² + ½Jω² along the run (the integration
/// conserves it). E's zero is arbitrary (V's origin), so E(0) is no scale for the drift; T_max
/// is the energy exchanged with V, and the drift is m g sinα·Δx + m v·Δv from the state
/// errors, which the closed-form test bounds at 1e-8 (measured ~1e-10).
/// The constraint residual stays ≤ 1e-12.
#[test]
fn knife_edge_conserves_energy_and_constraint() {
    for (sys, s) in knife_cases() {
        let period = std::f64::consts::TAU / s.omega.abs();
        let x0 = sys
            .state_from_speeds(0.0, &[s.x0, s.y0, s.phi0], &[s.v0, s.omega])
            .unwrap();
        let run = Simulation::new(&sys, x0)
            .end_time(5.0 * period)
            .sample_interval(period / 50.0)
            .run_constant(&DormandPrince::new(1e-12, 1e-12), [])
            .unwrap();
        let energy = run.column("energy").unwrap();
        let e_initial = knife_energy(&sys, &knife_exact(&sys, &s, 0.0));
        let scale = e_initial.abs().max(1.0);
        for (i, e) in energy.iter().enumerate() {
            let row: [f64; 5] =
                ["x", "y", "phi", "v", "omega"].map(|name| run.column(name).unwrap()[i]);
            let by_hand = knife_energy(&sys, &row);
            assert!(
                (e - by_hand).abs() <= 1e-12 * scale,
                "energy column {e} vs ½mv² + ½Jω² − m g sinα x = {by_hand}"
            );
        }
        let drift = energy
            .iter()
            .map(|e| (e - energy[0]).abs())
            .fold(0.0, f64::max);
        let (v, w) = (run.column("v").unwrap(), run.column("omega").unwrap());
        let t_max = v
            .iter()
            .zip(w)
            .map(|(v, w)| 0.5 * sys.m * v * v + 0.5 * sys.j * w * w)
            .fold(0.0, f64::max);
        let residual = max_constraint_residual(&sys, &run);
        println!(
            "knife edge {s:?}: E0 = {e_initial}, max |E - E0| = {drift:.2e} J = {:.2e} T_max, max constraint residual {residual:.2e}",
            drift / t_max
        );
        assert!(
            drift <= 1e-9 * t_max,
            "energy drift {drift:e} J, T_max = {t_max} J"
        );
        assert!(
            residual <= CONSTRAINT_TOL,
            "constraint residual {residual:e}"
        );
    }
}

// ---------------------------------------------------------------------------------------------
// 2. Chaplygin sleigh
// ---------------------------------------------------------------------------------------------
//
// Reduced equations, derived in the body frame (e_θ forward, e_⊥ to the left). The centre of
// mass moves with velocity v e_θ + u e_⊥; the contact point sits at −a e_θ, so its velocity is
// v e_θ + (u − aω) e_⊥ and the blade's constraint is u = aω. The only horizontal force is the
// constraint force F e_⊥ at the contact point. Newton in the rotating frame and the moment
// about the centre of mass ((−a e_θ) × F e_⊥ = −aF):
//   m (v̇ − ω u) = 0,   m (u̇ + ω v) = F,   I ω̇ = −a F.
// With u = aω: v̇ = a ω², and I ω̇ = −a m (a ω̇ + v ω), i.e. ω̇ = −m a v ω / (I + m a²).
// E = ½ m (v² + a²ω²) + ½ I ω² = ½ m v² + ½ (I + m a²) ω² is conserved (dE/dt = m v a ω² −
// m a v ω² = 0). For a > 0: v̇ ≥ 0, so v grows while the sleigh turns; once v > 0, ω decays
// like exp(−m a v∞ t/(I + m a²)), and v → √(2E/m).
//
// Why this case matters: L̃ = ½ m (v² + (ω¹ + aω)²) + ½ I ω² does not depend on q, so the
// entire right-hand side of the speed equations is the γ term Σ p_j γʲ ω (p₁ = ∂L̃/∂ω¹ = m a ω
// ≠ 0 on the motion). A wrong sign of the γ terms flips both equations to v̇ = −aω²,
// ω̇ = +m a v ω/(I + m a²): the sleigh would slow down while turning and its turning would
// grow. Energy is conserved either way, so only a check like this one detects it (the knife
// edge cannot: its constrained momentum p₁ vanishes on the motion).

/// The sleigh's reduced equations plus the kinematics of the centre of mass
/// (ẋ = v cosθ − aω sinθ, ẏ = v sinθ + aω cosθ, θ̇ = ω), written by hand. State (x, y, θ, v, ω).
struct SleighReference {
    m: f64,
    inertia: f64,
    a: f64,
}

impl SleighReference {
    fn of(sys: &ChaplyginSleigh) -> Self {
        SleighReference {
            m: sys.m,
            inertia: sys.inertia,
            a: sys.a,
        }
    }

    fn derivative(&self, x: &[f64; 5]) -> [f64; 5] {
        let [_, _, theta, v, w] = *x;
        let (s, c) = theta.sin_cos();
        [
            v * c - self.a * w * s,
            v * s + self.a * w * c,
            w,
            self.a * w * w,
            -self.m * self.a * v * w / (self.inertia + self.m * self.a * self.a),
        ]
    }
}

impl Ode for SleighReference {
    type State = [f64; 5];

    fn rhs(&mut self, _t: f64, x: &[f64; 5], dx: &mut [f64; 5]) -> Result<(), Error> {
        *dx = self.derivative(x);
        Ok(())
    }
}

/// The reference solution at the given sample times, by classical RK4 with step `h`.
fn sleigh_reference(sys: &ChaplyginSleigh, x0: [f64; 5], times: &[f64], h: f64) -> Vec<[f64; 5]> {
    let mut out = Vec::with_capacity(times.len());
    Rk4::new(h)
        .integrate(
            &mut SleighReference::of(sys),
            times[0],
            &x0,
            times,
            &mut |_, x| {
                out.push(*x);
                Ok(())
            },
        )
        .unwrap();
    out
}

fn sleigh_energy(sys: &ChaplyginSleigh, v: f64, w: f64) -> f64 {
    0.5 * sys.m * v * v + 0.5 * (sys.inertia + sys.m * sys.a * sys.a) * w * w
}

/// Initial (v₀, ω₀, θ₀): forward and turning, and backward (the sleigh reverses
/// and ends up going forward).
const SLEIGH_STARTS: [(f64, f64, f64); 3] = [(0.3, 2.0, 0.3), (1.0, -0.7, -1.0), (-0.5, 0.4, 2.0)];

/// v(t), ω(t) of the generated simulator (Dormand–Prince, rtol = atol = 1e-12) against the
/// hand-written reduced equations integrated by RK4 (h = 1e-3, itself checked against
/// h = 5e-4): every sample within 1e-9 absolute. The coordinates are compared too,
/// to 1e-8 absolute (positions grow to ~30 here).
#[test]
fn sleigh_matches_reduced_equations() {
    for (v0, w0, theta0) in SLEIGH_STARTS {
        let sys = ChaplyginSleigh::default();
        let q0 = [0.2, -0.1, theta0];
        let x0 = sys.state_from_speeds(0.0, &q0, &[v0, w0]).unwrap();
        let run = Simulation::new(&sys, x0)
            .end_time(25.0)
            .sample_interval(0.05)
            .run_constant(&DormandPrince::new(1e-12, 1e-12), [])
            .unwrap();
        let times = run.times();
        let start = [q0[0], q0[1], q0[2], v0, w0];
        let reference = sleigh_reference(&sys, start, times, 1e-3);
        let finer = sleigh_reference(&sys, start, times, 5e-4);
        let mut reference_error = [0.0f64; 5];
        for (a, b) in reference.iter().zip(&finer) {
            for j in 0..5 {
                reference_error[j] = reference_error[j].max((a[j] - b[j]).abs());
            }
        }
        // The reference must be far more accurate than the tolerances below: its change
        // from h to h/2 stays under 1e-12 for the speeds and 1e-10 for the coordinates
        // (there, rounding in x + h·Σ over 10⁴–10⁵ steps at |x| ~ 30 dominates).
        for (j, e) in reference_error.iter().enumerate() {
            let bound = if j >= 3 { 1e-12 } else { 1e-10 };
            assert!(
                *e <= bound,
                "the RK4 reference is not converged: {reference_error:?}"
            );
        }

        let names = ["x", "y", "theta", "v", "omega"];
        let mut worst = [0.0f64; 5];
        for (i, &t) in times.iter().enumerate() {
            for (j, name) in names.iter().enumerate() {
                let got = run.column(name).unwrap()[i];
                let err = (got - reference[i][j]).abs();
                worst[j] = worst[j].max(err);
                let tol = if j >= 3 { 1e-9 } else { 1e-8 };
                assert!(
                    err <= tol,
                    "{name}({t}) = {got}, reduced equations give {}: error {err:e} > {tol:e}",
                    reference[i][j]
                );
            }
        }
        println!(
            "sleigh v0 = {v0}, omega0 = {w0}: max abs error x {:.2e}, y {:.2e}, theta {:.2e}, v {:.2e}, omega {:.2e}; {} steps; reference h vs h/2 {:.1e}",
            worst[0],
            worst[1],
            worst[2],
            worst[3],
            worst[4],
            run.summary().steps,
            reference_error.iter().fold(0.0f64, |a, b| a.max(*b))
        );
    }
}

/// A small deterministic generator (SplitMix64), so failures reproduce.
struct SplitMix(u64);

impl SplitMix {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [lo, hi).
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        let unit = (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
        lo + (hi - lo) * unit
    }
}

/// The generated right-hand side at 400 random states (and random parameters, including a
/// contact point ahead of the centre of mass, a < 0) against the hand-written equations:
/// norm-wise relative error ≤ 1e-12, separately for the speed part (v̇, ω̇) and the
/// kinematic part (ẋ, ẏ, θ̇), measured in the max-norm:
/// ‖F_generated − F_hand‖∞ ≤ 1e-12 ‖F_hand‖∞.
#[test]
fn sleigh_rhs_matches_reduced_equations_at_random_states() {
    let mut rng = SplitMix(0x5EED_5E1C);
    let mut worst_speed = 0.0f64;
    let mut worst_kinematics = 0.0f64;
    for i in 0..400 {
        let sys = if i < 200 {
            ChaplyginSleigh::default()
        } else {
            ChaplyginSleigh {
                m: rng.uniform(0.2, 20.0),
                inertia: rng.uniform(0.01, 5.0),
                a: rng.uniform(-1.5, 1.5),
            }
        };
        let x = [
            rng.uniform(-50.0, 50.0),
            rng.uniform(-50.0, 50.0),
            rng.uniform(-10.0, 10.0),
            rng.uniform(-5.0, 5.0),
            rng.uniform(-5.0, 5.0),
        ];
        let mut dx = [0.0; 5];
        sys.rhs(0.0, &x, &[], &mut dx).unwrap();
        let hand = SleighReference::of(&sys).derivative(&x);
        let rel = |range: std::ops::Range<usize>| {
            let diff = range
                .clone()
                .map(|k| (dx[k] - hand[k]).abs())
                .fold(0.0, f64::max);
            let norm = range.map(|k| hand[k].abs()).fold(0.0, f64::max);
            diff / norm
        };
        let (speed, kinematics) = (rel(3..5), rel(0..3));
        worst_speed = worst_speed.max(speed);
        worst_kinematics = worst_kinematics.max(kinematics);
        assert!(
            speed <= 1e-12,
            "speed part at {x:?} ({sys:?}): generated {:?}, v̇ = aω², ω̇ = −m a v ω/(I + m a²) give {:?}",
            &dx[3..],
            &hand[3..]
        );
        assert!(
            kinematics <= 1e-12,
            "kinematics at {x:?} ({sys:?}): generated {:?}, by hand {:?}",
            &dx[..3],
            &hand[..3]
        );
        // The sign the γ terms must produce: the forward speed never decreases when the
        // contact point is behind (a > 0), and grows whenever the sleigh turns.
        if sys.a > 0.0 && x[4] != 0.0 {
            assert!(dx[3] > 0.0, "v̇ = {} at {x:?} with a > 0", dx[3]);
        }
    }
    println!(
        "sleigh rhs at 400 random states: max norm-wise relative error, speeds {worst_speed:.2e}, kinematics {worst_kinematics:.2e}"
    );
}

/// Long runs: ω decays and v tends to √(2E/m), E = ½ m v² + ½ (I + m a²) ω² from the initial
/// values. On the way v never decreases (a > 0: v̇ = aω² ≥ 0) and it ends above v₀.
///
/// The bound: exact energy conservation gives √(2E/m) − v = (I + m a²) ω² / (m (√(2E/m) + v)),
/// which is below 1e-20 once |ω| ≤ 1e-10 and v > 0.1; so at the end we require |ω| ≤ 1e-10
/// and |v − √(2E/m)| ≤ 1e-9 (the integration error's budget).
#[test]
fn sleigh_speed_tends_to_sqrt_2e_over_m() {
    let sys = ChaplyginSleigh::default();
    for (v0, w0, theta0) in SLEIGH_STARTS {
        let x0 = sys
            .state_from_speeds(0.0, &[0.0, 0.0, theta0], &[v0, w0])
            .unwrap();
        let run = Simulation::new(&sys, x0)
            .end_time(150.0)
            .sample_interval(0.1)
            .run_constant(&DormandPrince::new(1e-12, 1e-12), [])
            .unwrap();
        let v = run.column("v").unwrap();
        let w = run.column("omega").unwrap();
        let e = sleigh_energy(&sys, v0, w0);
        let limit = (2.0 * e / sys.m).sqrt();
        for pair in v.windows(2) {
            assert!(
                pair[1] >= pair[0] - 1e-12,
                "v decreased from {} to {} although the contact point is behind",
                pair[0],
                pair[1]
            );
        }
        let (v_end, w_end) = (*v.last().unwrap(), *w.last().unwrap());
        println!(
            "sleigh v0 = {v0}, omega0 = {w0}: v(150) = {v_end}, sqrt(2E/m) = {limit}, difference {:.2e}, omega(150) = {w_end:.2e}",
            v_end - limit
        );
        assert!(v_end > v0, "the sleigh did not speed up: {v0} → {v_end}");
        assert!(
            w_end.abs() <= 1e-10,
            "ω has not decayed: {w_end:e}; run longer"
        );
        assert!(
            (v_end - limit).abs() <= 1e-9,
            "v(∞) = {v_end}, √(2E/m) = {limit}"
        );
    }
}

/// Energy E = ½ m v² + ½ (I + m a²) ω²: the energy column equals it at every sample to 1e-12
/// relative, and drifts ≤ 1e-10 relative from E(0); the constraint residual stays ≤ 1e-12.
#[test]
fn sleigh_conserves_energy_and_constraint() {
    let sys = ChaplyginSleigh::default();
    for (v0, w0, theta0) in SLEIGH_STARTS {
        let x0 = sys
            .state_from_speeds(0.0, &[1.0, 2.0, theta0], &[v0, w0])
            .unwrap();
        let run = Simulation::new(&sys, x0)
            .end_time(40.0)
            .sample_interval(0.02)
            .run_constant(&DormandPrince::new(1e-12, 1e-12), [])
            .unwrap();
        let energy = run.column("energy").unwrap();
        let (v, w) = (run.column("v").unwrap(), run.column("omega").unwrap());
        let e_initial = sleigh_energy(&sys, v0, w0);
        for i in 0..run.len() {
            let by_hand = sleigh_energy(&sys, v[i], w[i]);
            assert!(
                (energy[i] - by_hand).abs() <= 1e-12 * e_initial,
                "energy column {} vs ½mv² + ½(I + ma²)ω² = {by_hand}",
                energy[i]
            );
        }
        let drift = relative_energy_drift(&run);
        let residual = max_constraint_residual(&sys, &run);
        println!(
            "sleigh v0 = {v0}, omega0 = {w0}: E0 = {e_initial}, relative energy drift {drift:.2e}, max constraint residual {residual:.2e}"
        );
        assert!(drift <= 1e-10, "energy drift {drift:e}");
        assert!(
            residual <= CONSTRAINT_TOL,
            "constraint residual {residual:e}"
        );
    }
}
