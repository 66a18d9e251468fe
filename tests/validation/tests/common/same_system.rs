//! `check_same_system`: does a model describe the same mechanical system as a reference
//! model? For systems with three coordinates and one constraint (the knife edge, the Chaplygin
//! sleigh): state x = (q₁, q₂, q₃, ω², ω³).
//!
//! Two models of one system, written differently, differ by rounding only. Compared at seeded
//! random states (every run checks the same ones) and along a short simulation:
//!
//! * the right-hand side (at the model's inputs `u` against the reference without inputs),
//!   the admissible velocities q̇ = B(q)ω and the reduced mass matrix, norm-wise relative:
//!   max|a − b| ≤ `STATE_TOLERANCE`·max|b|;
//! * the energy E = T + V relative to |T| + |V| (the size of its terms: E itself may cancel
//!   to nearly zero), with V = E(q, ω = 0);
//! * the user's own constraint and quasi-velocity rows at random (also inadmissible) q̇;
//! * a 2 s run with Dormand–Prince at rtol 1e-10, atol 1e-12 from the same initial state:
//!   every sample within `TRAJECTORY_TOLERANCE`·max(1, |b|).

use super::xorshift::XorShift;
use hamel::{DormandPrince, HamelSystem, Simulation};

/// Rounding, not modelling: a few hundred ulps at most.
pub const STATE_TOLERANCE: f64 = 1e-12;
/// Two adaptive integrations of right-hand sides that agree to rounding.
pub const TRAJECTORY_TOLERANCE: f64 = 1e-9;
/// Random states per model.
pub const RANDOM_STATES: usize = 64;
/// Length of the compared run (s).
pub const RUN_TIME: f64 = 2.0;

/// A system with three coordinates, one constraint and two free speeds.
pub trait ThreeByOne:
    HamelSystem<
        Coordinates = [f64; 3],
        Speeds = [f64; 2],
        Constraints = [f64; 1],
        State = [f64; 5],
        MassMatrix = [[f64; 2]; 2],
    >
{
}

impl<S> ThreeByOne for S where
    S: HamelSystem<
            Coordinates = [f64; 3],
            Speeds = [f64; 2],
            Constraints = [f64; 1],
            State = [f64; 5],
            MassMatrix = [[f64; 2]; 2],
        >
{
}

/// The worst discrepancies measured for one model (each relative as described above).
#[derive(Debug, Default, Clone, Copy)]
pub struct Discrepancy {
    pub rhs: f64,
    pub energy: f64,
    pub velocities: f64,
    pub mass_matrix: f64,
    pub rows: f64,
    pub trajectory: f64,
    pub steps: usize,
}

/// max|a − b| / max|b| (0 when both vanish).
pub fn relative(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    let diff = a
        .iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    let scale = b.iter().map(|y| y.abs()).fold(0.0, f64::max);
    if diff == 0.0 { 0.0 } else { diff / scale }
}

/// A random state: coordinates in [−3, 3]² × [−4, 4] (the heading beyond ±π too), speeds in
/// [−2, 2].
pub fn random_state(rng: &mut XorShift) -> [f64; 5] {
    [
        rng.uniform(-3.0, 3.0),
        rng.uniform(-3.0, 3.0),
        rng.uniform(-4.0, 4.0),
        rng.uniform(-2.0, 2.0),
        rng.uniform(-2.0, 2.0),
    ]
}

/// Compare `model` (driven by the constant inputs `u`) with `reference` (no inputs) at
/// random states and along a run from (q0, speeds0); panics with the state on a mismatch and
/// prints the measured discrepancies under `name`.
pub fn check_same_system<S, R>(
    name: &str,
    model: &S,
    u: S::Inputs,
    reference: &R,
    q0: [f64; 3],
    speeds0: [f64; 2],
) -> Discrepancy
where
    S: ThreeByOne,
    R: ThreeByOne<Inputs = [f64; 0]>,
{
    assert_eq!(S::STATE.len(), R::STATE.len(), "{name}: state dimension");
    let mut d = Discrepancy::default();
    let mut rng = XorShift::new(0x5eed_f0e5);
    for _ in 0..RANDOM_STATES {
        let x = random_state(&mut rng);
        let fail = |what: &str, err: f64| {
            panic!("{name}: {what} differs from the reference by {err:.3e} at x = {x:?}")
        };

        let (mut a, mut b) = ([0.0; 5], [0.0; 5]);
        model.rhs(0.0, &x, &u, &mut a).expect("model rhs");
        reference.rhs(0.0, &x, &[], &mut b).expect("reference rhs");
        let e = relative(&a, &b);
        if e.is_nan() || e > STATE_TOLERANCE {
            fail(&format!("rhs {a:?} vs {b:?}"), e);
        }
        d.rhs = d.rhs.max(e);

        let potential = reference
            .energy(0.0, &[x[0], x[1], x[2], 0.0, 0.0])
            .expect("reference energy");
        let eb = reference.energy(0.0, &x).expect("reference energy");
        let ea = model.energy(0.0, &x).expect("model energy");
        let e = (ea - eb).abs() / ((eb - potential).abs() + potential.abs());
        if e.is_nan() || e > STATE_TOLERANCE {
            fail(&format!("energy {ea} vs {eb}"), e);
        }
        d.energy = d.energy.max(e);

        let qa = model
            .generalized_velocities(0.0, &x)
            .expect("model velocities");
        let qb = reference
            .generalized_velocities(0.0, &x)
            .expect("reference velocities");
        let e = relative(&qa, &qb);
        if e.is_nan() || e > STATE_TOLERANCE {
            fail(&format!("velocities {qa:?} vs {qb:?}"), e);
        }
        d.velocities = d.velocities.max(e);

        let ma = model.mass_matrix(0.0, &x).expect("model mass matrix");
        let mb = reference
            .mass_matrix(0.0, &x)
            .expect("reference mass matrix");
        let e = relative(ma.as_flattened(), mb.as_flattened());
        if e.is_nan() || e > STATE_TOLERANCE {
            fail(&format!("mass matrix {ma:?} vs {mb:?}"), e);
        }
        d.mass_matrix = d.mass_matrix.max(e);

        // The row functions themselves, at an arbitrary (inadmissible) velocity.
        let q = [x[0], x[1], x[2]];
        let qd = [
            rng.uniform(-2.0, 2.0),
            rng.uniform(-2.0, 2.0),
            rng.uniform(-2.0, 2.0),
        ];
        let (ca, sa) = (
            model.constraint_residual(0.0, &q, &qd),
            model.speeds(0.0, &q, &qd),
        );
        let (cb, sb) = (
            reference.constraint_residual(0.0, &q, &qd),
            reference.speeds(0.0, &q, &qd),
        );
        let (ra, rb) = ([&ca[..], &sa[..]].concat(), [&cb[..], &sb[..]].concat());
        let e = relative(&ra, &rb);
        if e.is_nan() || e > STATE_TOLERANCE {
            fail(&format!("constraint and speed rows {ra:?} vs {rb:?}"), e);
        }
        d.rows = d.rows.max(e);
    }

    // The same motion, sample by sample.
    let integrator = DormandPrince::new(1e-10, 1e-12);
    let xa = model
        .state_from_speeds(0.0, &q0, &speeds0)
        .expect("model x0");
    let xb = reference
        .state_from_speeds(0.0, &q0, &speeds0)
        .expect("reference x0");
    assert_eq!(xa, xb, "{name}: initial state");
    let run_a = Simulation::new(model, xa)
        .end_time(RUN_TIME)
        .run_constant(&integrator, u)
        .unwrap_or_else(|e| panic!("{name}: the run fails: {e}"));
    let run_b = Simulation::new(reference, xb)
        .end_time(RUN_TIME)
        .run_constant(&integrator, [])
        .expect("reference run");
    assert_eq!(run_a.len(), run_b.len(), "{name}: samples");
    // The model records its inputs too; the columns both have (time, state, energy) compare.
    for column in run_b.names() {
        let a = run_a
            .column(column)
            .expect("the model records the reference's columns");
        let b = run_b.column(column).unwrap();
        for (i, (a, b)) in a.iter().zip(b).enumerate() {
            let e = (a - b).abs() / b.abs().max(1.0);
            assert!(
                e <= TRAJECTORY_TOLERANCE,
                "{name}: `{column}` leaves the reference's at t = {}: {a} vs {b}",
                run_b.times()[i]
            );
            d.trajectory = d.trajectory.max(e);
        }
    }
    let residual = run_a.summary().max_constraint_residual;
    assert!(
        residual <= 1e-12,
        "{name}: constraint residual {residual:e}"
    );
    d.steps = run_a.summary().steps;

    println!(
        "{name:<32} rhs {:.1e}  energy {:.1e}  q̇ {:.1e}  M {:.1e}  rows {:.1e}  run {:.1e} ({} steps)",
        d.rhs, d.energy, d.velocities, d.mass_matrix, d.rows, d.trajectory, d.steps
    );
    d
}
