//! The N-trailer (`hamel::models::NTrailer{1,2,8,24}`, one `macro_rules!` for every N)
//! against the geometry, the classical kinematics and an independent formulation of its
//! dynamics, all written here from the train's description alone:
//!
//! * the axle centres P₀ = (x, y), Pᵢ = Pᵢ₋₁ − dᵢ (cos θᵢ, sin θᵢ), their velocities and
//!   accelerations by num-dual's dual and hyper-dual numbers on that one position formula;
//!   no axle slides sideways: Ṗᵢ · (−sin θᵢ, cos θᵢ) = 0 at every sample, and the sampled
//!   path of every axle centre is tangent to its axle;
//! * the classical N-trailer kinematics (Laumond, IEEE Trans. Robot. Autom. 9, 1993;
//!   Sørdalen, ICRA 1993): θ̇ᵢ = (vᵢ₋₁/dᵢ) sin(θᵢ₋₁ − θᵢ), vᵢ = vᵢ₋₁ cos(θᵢ₋₁ − θᵢ), v₀ = v —
//!   for N = 1 the tractor–trailer relation θ̇₁ = (v/d₁) sin(θ₀ − θ₁);
//! * the energy T = Σ ½ mᵢ |Ṗᵢ|² + ½ Iᵢ θ̇ᵢ², conserved without inputs;
//! * the accelerations from the Lagrange–d'Alembert equations with multipliers,
//!   M q̈ + h = Aᵀλ, A q̈ + Ȧ q̇ = 0, solved by nalgebra, at seeded random states;
//! * steady turning, a closed-form motion of the dynamics for every N: the axle centres on
//!   concentric circles of radii Rᵢ = √(Rᵢ₋₁² − dᵢ²), the whole train turning at one rate.
//!
//! The parameters are read by name through `Parameters` (`m0`, `d3`, …), so one generic
//! function checks every N.

use crate::common::xorshift::XorShift;
use hamel::models::{NTrailer1, NTrailer2, NTrailer8, NTrailer24};
use hamel::{DormandPrince, HamelSystem, Simulation, Trajectory, Vector};
use nalgebra::{DMatrix, DVector};
use num_dual::{Dual64, DualNum, HyperDual64};

/// Dormand–Prince tolerances of the runs.
const RTOL: f64 = 1e-10;
const ATOL: f64 = 1e-12;
/// Length of the runs (s) and their sample interval.
const RUN_TIME: f64 = 4.0;
const SAMPLE: f64 = 0.005;
/// The tractor's forward speed (m/s) and turning rate (rad/s) at the start.
const SPEEDS0: [f64; 2] = [1.0, 0.6];

/// The train's data, read from a model through `Parameters`.
struct Train {
    m: Vec<f64>,
    inertia: Vec<f64>,
    d: Vec<f64>,
}

impl Train {
    fn of<S: HamelSystem>(model: &S) -> Train {
        // n = N + 3 coordinates: x, y and the N + 1 headings.
        let axles = S::N - 2;
        let read = |name: &str, i: usize| model.get(&format!("{name}{i}")).unwrap();
        Train {
            m: (0..axles).map(|i| read("m", i)).collect(),
            inertia: (0..axles).map(|i| read("inertia", i)).collect(),
            d: (0..axles).map(|i| read("d", i)).collect(),
        }
    }

    fn trailers(&self) -> usize {
        self.d.len() - 1
    }

    /// The axle centres: the tractor's at (x, y), each trailer's dᵢ behind its hitch, the
    /// centre of the axle ahead. Over dual numbers, for the derivatives.
    fn axles<T: DualNum<Primitive = f64> + Copy>(&self, q: &[T]) -> Vec<[T; 2]> {
        let mut p = vec![[q[0], q[1]]];
        for i in 1..=self.trailers() {
            let (s, c) = q[2 + i].sin_cos();
            let ahead = p[i - 1];
            p.push([ahead[0] - c * self.d[i], ahead[1] - s * self.d[i]]);
        }
        p
    }

    /// Each axle centre's position, velocity and q̇ᵀ(∂²P/∂q²)q̇ (its acceleration at q̈ = 0):
    /// the position formula on hyper-dual numbers seeded with q̇ in both directions.
    fn kinematics(&self, q: &[f64], qd: &[f64]) -> Vec<[[f64; 2]; 3]> {
        let seeded: Vec<HyperDual64> = (0..q.len())
            .map(|k| HyperDual64::new(q[k], qd[k], qd[k], 0.0))
            .collect();
        self.axles(&seeded)
            .iter()
            .map(|p| [p.map(|c| c.re), p.map(|c| c.eps1), p.map(|c| c.eps1eps2)])
            .collect()
    }

    /// The largest velocity of an axle centre across its axle, over the axles.
    fn side_slip(&self, q: &[f64], qd: &[f64]) -> f64 {
        let axles = self.kinematics(q, qd);
        (0..axles.len())
            .map(|i| {
                let (s, c) = q[2 + i].sin_cos();
                let [_, v, _] = axles[i];
                (-v[0] * s + v[1] * c).abs()
            })
            .fold(0.0, f64::max)
    }

    fn kinetic_energy(&self, q: &[f64], qd: &[f64]) -> f64 {
        let axles = self.kinematics(q, qd);
        (0..axles.len())
            .map(|i| {
                let [_, v, _] = axles[i];
                let rate = qd[2 + i];
                0.5 * self.m[i] * (v[0] * v[0] + v[1] * v[1]) + 0.5 * self.inertia[i] * rate * rate
            })
            .sum()
    }

    /// q̇ by the classical kinematics, from the tractor's speed v and turning rate ω.
    fn classical_velocities(&self, q: &[f64], v: f64, omega: f64) -> Vec<f64> {
        let (s0, c0) = q[2].sin_cos();
        let mut qd = vec![v * c0, v * s0, omega];
        let mut speed = v;
        for i in 1..=self.trailers() {
            let hitch_angle = q[1 + i] - q[2 + i];
            qd.push(speed / self.d[i] * hitch_angle.sin());
            speed *= hitch_angle.cos();
        }
        qd
    }
}

/// ∂Pᵢ/∂q: two rows per axle, from dual numbers seeded along each coordinate in turn.
fn jacobians(train: &Train, q: &[f64]) -> Vec<DMatrix<f64>> {
    let n = q.len();
    let mut j = vec![DMatrix::zeros(2, n); train.trailers() + 1];
    for k in 0..n {
        let seeded: Vec<Dual64> = (0..n)
            .map(|l| Dual64::new(q[l], if l == k { 1.0 } else { 0.0 }))
            .collect();
        for (i, p) in train.axles(&seeded).iter().enumerate() {
            j[i][(0, k)] = p[0].eps;
            j[i][(1, k)] = p[1].eps;
        }
    }
    j
}

/// q̈ from the Lagrange–d'Alembert equations with multipliers, M q̈ + h = f + Aᵀλ. With
/// T = ½ q̇ᵀM q̇ of point masses and spins, M = Σ mᵢ JᵢᵀJᵢ + Σ Iᵢ eᵢeᵢᵀ and the
/// velocity-dependent part of the inertial forces is h = Σ mᵢ Jᵢᵀ (J̇ᵢ q̇). Constraint row i
/// is nᵢᵀJᵢ q̇ with nᵢ = (−sin θᵢ, cos θᵢ); its time derivative gives
/// A q̈ = −(nᵢ·J̇ᵢq̇ + ṅᵢ·Ṗᵢ).
fn reference_accelerations(train: &Train, q: &[f64], qd: &[f64], f: &[f64]) -> Vec<f64> {
    let (n, p) = (q.len(), train.trailers() + 1);
    let j = jacobians(train, q);
    let axles = train.kinematics(q, qd);
    let mut kkt = DMatrix::zeros(n + p, n + p);
    let mut rhs = DVector::zeros(n + p);
    rhs.rows_mut(0, n).copy_from_slice(f);
    for i in 0..p {
        let [_, v, curvature] = axles[i];
        let (s, c) = q[2 + i].sin_cos();
        let normal = [-s, c];
        for a in 0..n {
            for b in 0..n {
                kkt[(a, b)] +=
                    train.m[i] * (j[i][(0, a)] * j[i][(0, b)] + j[i][(1, a)] * j[i][(1, b)]);
            }
            rhs[a] -= train.m[i] * (j[i][(0, a)] * curvature[0] + j[i][(1, a)] * curvature[1]);
            let row = normal[0] * j[i][(0, a)] + normal[1] * j[i][(1, a)];
            kkt[(n + i, a)] = row;
            kkt[(a, n + i)] = -row;
        }
        kkt[(2 + i, 2 + i)] += train.inertia[i];
        // ṅᵢ = −θ̇ᵢ (cos θᵢ, sin θᵢ).
        let normal_rate_dot_v = -qd[2 + i] * (c * v[0] + s * v[1]);
        rhs[n + i] = -(normal[0] * curvature[0] + normal[1] * curvature[1] + normal_rate_dot_v);
    }
    let solution = kkt.lu().solve(&rhs).expect("the KKT matrix is regular");
    solution.rows(0, n).iter().copied().collect()
}

/// A train whose bodies all differ (a mix-up of indices would show): masses, inertias and
/// hitch lengths set by name. `d0` is unused by the model; it is set too.
fn varied<S: HamelSystem + Default>() -> S {
    let mut model = S::default();
    for i in 0..S::N - 2 {
        let k = i as f64;
        model
            .set(&format!("m{i}"), 1.0 + 0.3 * (7 * i % 5) as f64)
            .unwrap();
        model
            .set(&format!("inertia{i}"), 0.05 + 0.02 * (3 * i % 4) as f64)
            .unwrap();
        model
            .set(&format!("d{i}"), 0.4 + 0.1 * (5 * i % 3) as f64 + 0.01 * k)
            .unwrap();
    }
    model.set("m0", 3.0).unwrap();
    model.set("inertia0", 0.2).unwrap();
    model
}

/// The initial configuration: the tractor at the origin heading 0.3 rad; trailer i's heading
/// differs from the one ahead by ±(0.2 + 0.1 (i mod 3)) rad, alternately, so that the train
/// starts zigzagged with no two axles aligned. The first trailer is turned right of the
/// tractor, which turns left: its hitch angle has to swing over to the other side.
fn initial_configuration(trailers: usize) -> Vec<f64> {
    let mut q = vec![0.0, 0.0, 0.3];
    for i in 1..=trailers {
        let sign = if i % 2 == 0 { -1.0 } else { 1.0 };
        q.push(q[1 + i] + sign * (0.2 + 0.1 * (i % 3) as f64));
    }
    q
}

/// A run without inputs from the zigzagged start, the tractor turning.
fn run<S: HamelSystem>(model: &S) -> Trajectory {
    let q = S::Coordinates::from_slice(&initial_configuration(S::N - 3)).unwrap();
    let speeds = S::Speeds::from_slice(&SPEEDS0).unwrap();
    let x0 = model.state_from_speeds(0.0, &q, &speeds).unwrap();
    Simulation::new(model, x0)
        .end_time(RUN_TIME)
        .sample_interval(SAMPLE)
        .run_constant(&DormandPrince::new(RTOL, ATOL), S::Inputs::zeros())
        .unwrap()
}

/// The worst figures of a run, over its samples (and axles).
#[derive(Debug, Default)]
struct Figures {
    /// |Ṗᵢ · nᵢ| from q and the model's q̇ (m/s).
    side_slip: f64,
    /// |dPᵢ/dt · nᵢ| / |dPᵢ/dt| with dPᵢ/dt by finite differences of the sampled path.
    path_slip: f64,
    /// max |q̇ − q̇_classical| (rad/s, m/s).
    classical: f64,
    /// max |E(t) − E(0)| / E(0).
    energy_drift: f64,
    /// max |E − T_geometry| / E(0): the model's energy against T computed here.
    energy_vs_geometry: f64,
}

fn measure<S: HamelSystem>(model: &S) -> Figures {
    let train = Train::of(model);
    let trajectory = run(model);
    let n = S::N;
    let energy = trajectory.column("energy").unwrap();
    let mut f = Figures::default();
    for (k, row) in trajectory.rows().enumerate() {
        let x = S::State::from_slice(&row[1..=S::State::LEN]).unwrap();
        let q = &row[1..=n];
        let qd = model.generalized_velocities(row[0], &x).unwrap();
        let qd = qd.as_ref();
        f.side_slip = f.side_slip.max(train.side_slip(q, qd));
        let classical = train.classical_velocities(q, row[1 + n], row[2 + n]);
        for (a, b) in qd.iter().zip(&classical) {
            f.classical = f.classical.max((a - b).abs());
        }
        let e0 = energy[0];
        f.energy_drift = f.energy_drift.max((energy[k] - e0).abs() / e0);
        let t = train.kinetic_energy(q, qd);
        f.energy_vs_geometry = f.energy_vs_geometry.max((energy[k] - t).abs() / e0);
    }
    f.path_slip = path_slip(&train, &trajectory, n);
    f
}

/// How far the sampled path of every axle centre is from tangent to its axle: the velocity
/// dPᵢ/dt by the five-point central difference of the sampled positions, its component
/// across the axle relative to its length.
fn path_slip(train: &Train, trajectory: &Trajectory, n: usize) -> f64 {
    let t = trajectory.times();
    let axles: Vec<Vec<[f64; 2]>> = trajectory
        .rows()
        .map(|row| train.axles(&row[1..=n]))
        .collect();
    let mut worst = 0.0f64;
    for k in 2..t.len() - 2 {
        let h = t[k + 1] - t[k];
        // Only where the samples are evenly spaced (the last interval may be shorter).
        if (t[k + 2] - t[k - 2] - 4.0 * h).abs() > 1e-12 {
            continue;
        }
        let [a, b, c, d] = [&axles[k - 2], &axles[k - 1], &axles[k + 1], &axles[k + 2]];
        let row = trajectory.row(k).unwrap();
        // The headings θ₀ … θ_N, after t, x and y.
        for (i, heading) in row[3..=n].iter().enumerate() {
            let rate = |x: usize| (a[i][x] - 8.0 * b[i][x] + 8.0 * c[i][x] - d[i][x]) / (12.0 * h);
            let (vx, vy) = (rate(0), rate(1));
            let (s, c) = heading.sin_cos();
            worst = worst.max((-vx * s + vy * c).abs() / vx.hypot(vy));
        }
    }
    worst
}

/// Rounding: a few ulps per axle of the recursion along the train (25 axles at most).
const ROUNDING: f64 = 1e-14;
/// Energy conservation with Dormand–Prince at `RTOL` over `RUN_TIME`: the drift is the
/// integration error, a modest multiple of the local tolerance; it scales with it (measured
/// 1.5e-11 … 9.1e-11 at RTOL = 1e-10, 1.8e-13 … 1.1e-12 at 1e-12, N = 1 … 24).
const ENERGY_DRIFT: f64 = 10.0 * RTOL;
/// The sampled path's slip is the error of the five-point difference: its truncation, ∝ h⁴
/// (for N = 24, 6.8e-9 at h = 5 ms, 1.0e-7 at 10 ms, whatever RTOL), and the derivative of the
/// dense output's interpolation error, which does not shrink with h but with RTOL (N = 1,
/// whose integration takes the longest steps: 4.3e-9 at RTOL = 1e-10, 5.1e-10 at 1e-12). A
/// sliding axle would show a slip of the order of its hitch angle, 0.1 or more.
const PATH_SLIP: f64 = 1e-7;

fn check_run<S: HamelSystem>(name: &str, model: &S) {
    let f = measure(model);
    println!(
        "{name}: side slip {:.1e} m/s, path slip {:.1e}, classical kinematics {:.1e}, \
         energy drift {:.1e}, energy vs geometry {:.1e}",
        f.side_slip, f.path_slip, f.classical, f.energy_drift, f.energy_vs_geometry
    );
    assert!(f.side_slip <= ROUNDING, "{name}: {f:?}");
    assert!(f.classical <= ROUNDING, "{name}: {f:?}");
    assert!(f.energy_vs_geometry <= ROUNDING, "{name}: {f:?}");
    assert!(f.energy_drift <= ENERGY_DRIFT, "{name}: {f:?}");
    assert!(f.path_slip <= PATH_SLIP, "{name}: {f:?}");
}

#[test]
fn one_trailer_rolls_and_conserves_energy() {
    check_run("N = 1", &varied::<NTrailer1>());
}

#[test]
fn two_trailers_roll_and_conserve_energy() {
    check_run("N = 2", &varied::<NTrailer2>());
}

#[test]
fn eight_trailers_roll_and_conserve_energy() {
    check_run("N = 8", &varied::<NTrailer8>());
}

#[test]
fn twenty_four_trailers_roll_and_conserve_energy() {
    check_run("N = 24", &varied::<NTrailer24>());
}

/// Random states per model.
const RANDOM_STATES: usize = 32;

/// Random states (seeded): any position and tractor heading, hitch angles within ±1.2 rad
/// (short of jackknifing), speeds of both signs, and random inputs.
fn random_state<S: HamelSystem>(rng: &mut XorShift) -> (S::State, S::Inputs) {
    let mut x = vec![rng.uniform(-2.0, 2.0), rng.uniform(-2.0, 2.0)];
    x.push(rng.uniform(-3.0, 3.0));
    for i in 1..=S::N - 3 {
        x.push(x[1 + i] + rng.uniform(-1.2, 1.2));
    }
    x.push(rng.uniform(-2.0, 2.0));
    x.push(rng.uniform(-1.5, 1.5));
    let u = [rng.uniform(-3.0, 3.0), rng.uniform(-1.0, 1.0)];
    (
        S::State::from_slice(&x).unwrap(),
        S::Inputs::from_slice(&u).unwrap(),
    )
}

/// The worst relative difference between the model's right-hand side and the one from the
/// Lagrange–d'Alembert equations, with the classical q̇, over random states; and the worst
/// difference between the model's power and the inputs' F v + τ ω.
fn dynamics_discrepancy<S: HamelSystem + Default>() -> (f64, f64) {
    let model = varied::<S>();
    let train = Train::of(&model);
    let n = S::N;
    let mut rng = XorShift::new(0x7a11e5 + n as u64);
    let (mut worst_rhs, mut worst_power) = (0.0f64, 0.0f64);
    for _ in 0..RANDOM_STATES {
        let (x, u) = random_state::<S>(&mut rng);
        let (xs, us) = (x.as_ref(), u.as_ref());
        let q = &xs[..n];
        let (v, omega) = (xs[n], xs[n + 1]);
        let qd = train.classical_velocities(q, v, omega);
        let (s0, c0) = q[2].sin_cos();
        let mut f = vec![0.0; n];
        (f[0], f[1], f[2]) = (us[0] * c0, us[0] * s0, us[1]);
        let qdd = reference_accelerations(&train, q, &qd, &f);
        // v = ẋ cos θ₀ + ẏ sin θ₀ and ω = θ̇₀, differentiated.
        let v_dot = qdd[0] * c0 + qdd[1] * s0 + qd[2] * (-qd[0] * s0 + qd[1] * c0);
        let mut expected = qd.clone();
        expected.extend([v_dot, qdd[2]]);
        let mut dx = S::State::zeros();
        model.rhs(0.0, &x, &u, &mut dx).unwrap();
        let scale = expected.iter().fold(1.0f64, |m, e| m.max(e.abs()));
        for (a, b) in dx.as_ref().iter().zip(&expected) {
            worst_rhs = worst_rhs.max((a - b).abs() / scale);
        }
        let power = model.power(0.0, &x, &u).unwrap();
        worst_power = worst_power.max((power - (us[0] * v + us[1] * omega)).abs());
    }
    (worst_rhs, worst_power)
}

#[test]
fn accelerations_match_the_lagrange_dalembert_equations() {
    for (name, (rhs, power)) in [
        ("N = 1", dynamics_discrepancy::<NTrailer1>()),
        ("N = 2", dynamics_discrepancy::<NTrailer2>()),
        ("N = 8", dynamics_discrepancy::<NTrailer8>()),
        ("N = 24", dynamics_discrepancy::<NTrailer24>()),
    ] {
        println!("{name}: rhs vs Lagrange–d'Alembert {rhs:.1e}, power vs F v + τ ω {power:.1e}");
        assert!(rhs <= 1e-12, "{name}: {rhs:e}");
        assert!(power <= 1e-12, "{name}: {power:e}");
    }
}

/// Steady turning about the origin at the rate `omega`: the tractor's axle centre at
/// (R₀, 0) heading π/2, each trailer's axle tangent to its own circle about the origin. Its
/// centre Pᵢ is then at the radius Rᵢ = √(Rᵢ₋₁² − dᵢ²) (the hitch Pᵢ₋₁ lies dᵢ along the
/// tangent at Pᵢ), and its heading lags the one ahead by asin(dᵢ/Rᵢ₋₁). Every body moves
/// uniformly on its circle and spins at `omega`: each needs only a centripetal force, across
/// its axle, which its wheels supply; the hitches transmit nothing. So the whole train turns
/// rigidly: θᵢ(t) = θᵢ(0) + ωt, v = ωR₀, P₀(t) = R₀ (cos ωt, sin ωt).
fn steady_turning<S: HamelSystem>(train: &Train, r0: f64, omega: f64) -> (S::State, Vec<f64>) {
    let mut q = vec![r0, 0.0, std::f64::consts::FRAC_PI_2];
    let mut radii = vec![r0];
    for i in 1..=train.trailers() {
        let ahead = radii[i - 1];
        q.push(q[1 + i] - (train.d[i] / ahead).asin());
        radii.push((ahead * ahead - train.d[i] * train.d[i]).sqrt());
    }
    q.extend([omega * r0, omega]);
    (S::State::from_slice(&q).unwrap(), radii)
}

/// The worst deviation from steady turning over a run at the relative tolerance `rtol`: of
/// the headings from θᵢ(0) + ωt, of the speeds from (ωR₀, ω), of the tractor from its
/// circle's point R₀ (cos ωt, sin ωt) and of every axle centre from its radius; and the
/// number of steps taken.
fn steady_turning_deviation<S: HamelSystem + Default>(rtol: f64) -> (f64, usize) {
    let model = varied::<S>();
    let train = Train::of(&model);
    let (r0, omega) = (STEADY_RADIUS, 0.5);
    let (x0, radii) = steady_turning::<S>(&train, r0, omega);
    let trajectory = Simulation::new(&model, x0)
        .end_time(RUN_TIME)
        .sample_interval(0.1)
        .run_constant(&DormandPrince::new(rtol, 1e-2 * rtol), S::Inputs::zeros())
        .unwrap();
    let (n, x0) = (S::N, x0.as_ref());
    let mut worst = 0.0f64;
    for row in trajectory.rows() {
        let (t, x) = (row[0], &row[1..]);
        let (s, c) = (omega * t).sin_cos();
        let mut errors = vec![x[0] - r0 * c, x[1] - r0 * s];
        errors.extend((2..n).map(|k| x[k] - (x0[k] + omega * t)));
        errors.extend([x[n] - omega * r0, x[n + 1] - omega]);
        let axles = train.axles(&x[..n]);
        errors.extend((0..axles.len()).map(|i| axles[i][0].hypot(axles[i][1]) - radii[i]));
        worst = errors.iter().fold(worst, |m, e| m.max(e.abs()));
    }
    (worst, trajectory.summary().steps)
}

/// The tractor's radius in steady turning (m): larger than the 24 trailers' √(Σ dᵢ²) ≈ 3.3 m.
const STEADY_RADIUS: f64 = 4.0;

/// The deviation is the integration error: each step's local error is at most `rtol` times
/// the size of the state (R₀ or the largest heading, ≈ 4), and on this neutrally stable
/// motion they add up at most linearly, so steps·rtol·R₀ bounds it; and it shrinks with the
/// tolerance (by 100× in it, a modelling error would not move).
fn check_steady_turning<S: HamelSystem + Default>(name: &str) {
    let (deviation, steps) = steady_turning_deviation::<S>(RTOL);
    let (tight, _) = steady_turning_deviation::<S>(1e-2 * RTOL);
    println!(
        "{name}: steady turning, worst deviation {deviation:.1e} over {RUN_TIME} s in {steps} \
         steps at rtol {RTOL:e}; {tight:.1e} at rtol {:e}",
        1e-2 * RTOL
    );
    assert!(
        deviation <= steps as f64 * RTOL * STEADY_RADIUS,
        "{name}: {deviation:e}"
    );
    assert!(
        tight <= 0.1 * deviation,
        "{name}: {tight:e} vs {deviation:e}"
    );
}

#[test]
fn steady_turning_is_a_rigid_rotation_of_the_train() {
    check_steady_turning::<NTrailer1>("N = 1");
    check_steady_turning::<NTrailer2>("N = 2");
    check_steady_turning::<NTrailer8>("N = 8");
    check_steady_turning::<NTrailer24>("N = 24");
}

/// For one trailer, the tractor–trailer relations in their textbook form (Laumond 1993;
/// Sørdalen 1993), at every sample of a run: θ̇₁ = (v/d₁) sin(θ₀ − θ₁), and the trailer's
/// axle centre moves along its axle at v₁ = v cos(θ₀ − θ₁).
#[test]
fn one_trailer_follows_the_tractor_trailer_kinematics() {
    let model = varied::<NTrailer1>();
    let trajectory = run(&model);
    let d1 = model.d[1];
    let (mut worst_rate, mut worst_speed) = (0.0f64, 0.0f64);
    for row in trajectory.rows() {
        let x: [f64; 6] = row[1..7].try_into().unwrap();
        let [xd, yd, _, theta1_dot] = model.generalized_velocities(row[0], &x).unwrap();
        let [_, _, theta0, theta1, v, _] = x;
        let rate = v / d1 * (theta0 - theta1).sin();
        worst_rate = worst_rate.max((theta1_dot - rate).abs());
        // The trailer's axle centre, d₁ behind the tractor's: its velocity along the axle.
        let (s1, c1) = theta1.sin_cos();
        let trailer = [xd + d1 * theta1_dot * s1, yd - d1 * theta1_dot * c1];
        let along = trailer[0] * c1 + trailer[1] * s1;
        worst_speed = worst_speed.max((along - v * (theta0 - theta1).cos()).abs());
    }
    println!(
        "N = 1: θ̇₁ against (v/d₁) sin(θ₀ − θ₁) {worst_rate:.1e} rad/s, \
         v₁ against v cos(θ₀ − θ₁) {worst_speed:.1e} m/s"
    );
    assert!(worst_rate <= ROUNDING && worst_speed <= ROUNDING);
    // The run is not trivial: the hitch angle changes by a good fraction of a radian.
    let hitch: Vec<f64> = trajectory.rows().map(|row| row[3] - row[4]).collect();
    let range = hitch.iter().fold(f64::MIN, |m, h| m.max(*h))
        - hitch.iter().fold(f64::MAX, |m, h| m.min(*h));
    println!("N = 1: the hitch angle ranges over {range:.2} rad");
    assert!(range > 0.2);
}
