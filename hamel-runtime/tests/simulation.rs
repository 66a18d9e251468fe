//! The simulation driver on a hand-written system: a skate (knife edge) on a level plane,
//! with the closed-form solution of its free motion.

#[cfg(feature = "ensemble")]
mod ensembles;

use crate::common;

use std::ops::ControlFlow;
use std::time::{Duration, Instant};

use hamel_runtime::{
    DormandPrince, Error, HamelSystem, MAX_SAMPLES, NamedValues, Parameters, Rk4, Simulation,
    Singularity, Stopped,
};

/// A skate: a rigid body on the plane at (x, y) with heading θ, whose blade cannot slide
/// sideways: ẋ sin θ − ẏ cos θ = 0. Quasi-velocities: the sideways slip (constrained to
/// zero), the forward speed v = ẋ cos θ + ẏ sin θ and the turning rate ω = θ̇. Inputs: a
/// forward force and a turning torque.
///
/// With Lagrangian L = ½m(ẋ² + ẏ²) + ½Iθ̇² = ½m(slip² + v²) + ½Iω², Hamel's equations are
/// m v̇ = F, I ω̇ = τ: the γ terms multiply the slip momentum, which is zero.
///
/// The force and torque do work, so the skate is not conservative; `Skate<true>` claims to
/// be (as a skate without inputs would), for runs with zero inputs that compare the plain
/// integration with the one that carries the work along.
struct Skate<const CONSERVATIVE: bool = false> {
    mass: f64,
    inertia: f64,
}

impl<const C: bool> Parameters for Skate<C> {
    const NAMES: &'static [&'static str] = &["mass", "inertia"];
    const DOCS: &'static [&'static str] = &[
        "mass of the skate",
        "moment of inertia about the contact point",
    ];

    fn get(&self, name: &str) -> Option<f64> {
        match name {
            "mass" => Some(self.mass),
            "inertia" => Some(self.inertia),
            _ => None,
        }
    }

    fn set(&mut self, name: &str, value: f64) -> Result<(), Error> {
        match name {
            "mass" => self.mass = value,
            "inertia" => self.inertia = value,
            _ => {
                return Err(Error::UnknownParameter {
                    name: name.into(),
                    known: Self::NAMES.join(", "),
                });
            }
        }
        Ok(())
    }
}

impl<const C: bool> Skate<C> {
    /// The reduced mass matrix diag(m, I), or the first pivot that is not positive.
    fn pivots(&self) -> Result<[f64; 2], Singularity> {
        for (speed, value) in [self.mass, self.inertia].into_iter().enumerate() {
            if value.is_nan() || value <= 0.0 {
                return Err(Singularity::MassMatrix { speed, value });
            }
        }
        Ok([self.mass, self.inertia])
    }
}

impl<const C: bool> HamelSystem for Skate<C> {
    type Coordinates = [f64; 3];
    type Speeds = [f64; 2];
    type Constraints = [f64; 1];
    type State = [f64; 5];
    type Inputs = [f64; 2];
    type Holonomic = [f64; 0];
    type HolonomicJacobian = [f64; 0];
    type Extended = [f64; 6];
    type MassMatrix = [[f64; 2]; 2];
    type Gamma = [[[f64; 2]; 2]; 3];
    type StateJacobian = [f64; 25];
    type InputJacobian = [f64; 10];

    const N: usize = 3;
    const P: usize = 1;
    const M: usize = 2;
    const K: usize = 0;
    const COORDINATES: &'static [&'static str] = &["x", "y", "theta"];
    const SPEEDS: &'static [&'static str] = &["v", "omega"];
    const CONSTRAINTS: &'static [&'static str] = &["no_slip"];
    const INPUTS: &'static [&'static str] = &["force", "torque"];
    const STATE: &'static [&'static str] = &["x", "y", "theta", "v", "omega"];
    const DEPENDENT: &'static [usize] = &[];
    const CONSERVATIVE: bool = C;

    fn rhs(
        &self,
        _t: f64,
        x: &[f64; 5],
        u: &[f64; 2],
        dx: &mut [f64; 5],
    ) -> Result<(), Singularity> {
        let [m, i] = self.pivots()?;
        let [_, _, theta, v, omega] = *x;
        *dx = [v * theta.cos(), v * theta.sin(), omega, u[0] / m, u[1] / i];
        Ok(())
    }

    fn generalized_velocities(&self, _t: f64, x: &[f64; 5]) -> Result<[f64; 3], Singularity> {
        let [_, _, theta, v, omega] = *x;
        Ok([v * theta.cos(), v * theta.sin(), omega])
    }

    fn energy(&self, _t: f64, x: &[f64; 5]) -> Result<f64, Singularity> {
        Ok(0.5 * self.mass * x[3] * x[3] + 0.5 * self.inertia * x[4] * x[4])
    }

    /// f·q̇ with the generalized force (F cos θ, F sin θ, τ): F v + τ ω.
    fn power(&self, _t: f64, x: &[f64; 5], u: &[f64; 2]) -> Result<f64, Singularity> {
        Ok(u[0] * x[3] + u[1] * x[4])
    }

    /// m ẍ = F cos θ + λ sin θ with ẍ = v̇ cos θ − v ω sin θ and m v̇ = F: λ = −m v ω, the
    /// centripetal force of the turn.
    fn multipliers(&self, _t: f64, x: &[f64; 5], _u: &[f64; 2]) -> Result<[f64; 1], Singularity> {
        Ok([-self.mass * x[3] * x[4]])
    }

    fn constraint_residual(&self, _t: f64, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [qd[0] * q[2].sin() - qd[1] * q[2].cos()]
    }

    fn speeds(&self, _t: f64, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[2]]
    }

    fn holonomic_residual(&self, _t: f64, _q: &[f64; 3]) -> [f64; 0] {
        []
    }

    fn holonomic_jacobian(&self, _t: f64, _q: &[f64; 3]) -> [f64; 0] {
        []
    }

    fn mass_matrix(&self, _t: f64, _x: &[f64; 5]) -> Result<[[f64; 2]; 2], Singularity> {
        let [m, i] = self.pivots()?;
        Ok([[m, 0.0], [0.0, i]])
    }

    /// B = Aᵀ in closed form (A is a rotation in the plane, plus the identity for θ).
    fn inverse_defect(&self, _t: f64, q: &[f64; 3]) -> Result<f64, Singularity> {
        let (s, c) = q[2].sin_cos();
        let a = [[s, -c, 0.0], [c, s, 0.0], [0.0, 0.0, 1.0]];
        let mut defect = 0.0f64;
        for i in 0..3 {
            for j in 0..3 {
                // (A·Aᵀ)ᵢⱼ = rowᵢ · rowⱼ
                let p: f64 = (0..3).map(|k| a[i][k] * a[j][k]).sum();
                defect = defect.max((p - if i == j { 1.0 } else { 0.0 }).abs());
            }
        }
        Ok(defect)
    }

    /// γʲ_{l,k} with A = (slip; forward; turn) rows (sin θ, −cos θ, 0), (cos θ, sin θ, 0),
    /// (0, 0, 1) and B = A⁻¹ = Aᵀ: only γ¹_{v,ω} = −1 = −γ¹_{ω,v} is nonzero.
    fn gamma(&self, _t: f64, _q: &[f64; 3]) -> Result<[[[f64; 2]; 2]; 3], Singularity> {
        let mut g = [[[0.0; 2]; 2]; 3];
        g[0][0][1] = -1.0;
        g[0][1][0] = 1.0;
        Ok(g)
    }

    /// ∂F/∂x of F = (v cos θ, v sin θ, ω, F/m, τ/I): only the rows of ẋ and ẏ depend on the
    /// state (through θ and v), and θ̇ = ω; ∂F/∂u is diag(1/m, 1/I) in the rows of v̇ and ω̇.
    fn jacobian(
        &self,
        _t: f64,
        x: &[f64; 5],
        _u: &[f64; 2],
    ) -> Result<([f64; 25], [f64; 10]), Singularity> {
        let [m, i] = self.pivots()?;
        let [_, _, theta, v, _] = *x;
        let (s, c) = theta.sin_cos();
        let mut a = [0.0; 25];
        a[2] = -v * s;
        a[3] = c;
        a[5 + 2] = v * c;
        a[5 + 3] = s;
        a[2 * 5 + 4] = 1.0;
        let mut b = [0.0; 10];
        b[3 * 2] = 1.0 / m;
        b[4 * 2 + 1] = 1.0 / i;
        Ok((a, b))
    }
}

const SKATE: Skate = Skate {
    mass: 2.0,
    inertia: 0.5,
};
/// Starts at (1, −0.5) heading 0.3 rad, speed 1.5, turning at 0.7 rad/s.
const X0: [f64; 5] = [1.0, -0.5, 0.3, 1.5, 0.7];

/// Free motion: v and ω constant, so the skate runs on a circle of radius v/ω.
fn circle(t: f64) -> [f64; 5] {
    let [x0, y0, th0, v, w] = X0;
    let th = th0 + w * t;
    [
        x0 + v / w * (th.sin() - th0.sin()),
        y0 - v / w * (th.cos() - th0.cos()),
        th,
        v,
        w,
    ]
}

/// The free skate at tolerance 1e-12 for 20 s: the run checked against the circle. Before
/// the energy balance and the projection existed (the runtime at commit 729cd22) this run
/// took 366 steps, no rejection and 2198 evaluations; a conservative system must still, and
/// so must a system that is not, whose work is integrated alongside outside the step-size
/// control.
#[test]
fn free_skate_runs_on_its_circle() {
    let conservative = Skate::<true> {
        mass: 2.0,
        inertia: 0.5,
    };
    let run = |simulation: Simulation<'_, Skate<true>>| {
        simulation
            .end_time(20.0)
            .sample_interval(0.05)
            .run_constant(&DormandPrince::new(1e-12, 1e-12), [0.0, 0.0])
            .unwrap()
    };
    let trajectory = run(Simulation::new(&conservative, X0));
    let summary = trajectory.summary();
    println!("{trajectory:?}\n{summary}");
    assert_eq!(
        (summary.steps, summary.rejected, summary.evaluations),
        (366, 0, 2198)
    );

    assert_eq!(
        trajectory.names(),
        [
            "t", "x", "y", "theta", "v", "omega", "force", "torque", "energy"
        ]
    );
    assert_eq!(trajectory.len(), 401);
    assert_eq!(summary.samples, 401);
    assert_eq!(trajectory.times()[0], 0.0);
    assert_eq!(*trajectory.times().last().unwrap(), 20.0);
    let mut worst = 0.0f64;
    for row in trajectory.rows() {
        let exact = circle(row[0]);
        for (value, expected) in row[1..6].iter().zip(exact) {
            worst = worst.max((value - expected).abs());
        }
    }
    println!("largest deviation from the circle: {worst:.3e}");
    assert!(worst <= 1e-9, "deviation {worst:e}");

    // v and ω have zero derivatives, so the energy cannot drift at all; the constraint holds
    // to rounding.
    let e0 = 0.5 * 2.0 * 1.5 * 1.5 + 0.5 * 0.5 * 0.7 * 0.7;
    assert_eq!(summary.initial_energy, e0);
    assert_eq!(summary.max_energy_drift, 0.0);
    assert_eq!(summary.relative_energy_drift, 0.0);
    assert!(
        summary.max_constraint_residual <= 4.0 * f64::EPSILON * 1.5,
        "{summary}"
    );
    assert!(
        trajectory
            .column("energy")
            .unwrap()
            .iter()
            .all(|e| *e == e0)
    );
    assert_eq!((summary.work, summary.max_energy_balance), (0.0, 0.0));
    assert_eq!(summary.max_holonomic_residual, 0.0);

    // The same skate, not conservative: the same steps and numbers, the work (zero here) and
    // the balance besides.
    let forced = Simulation::new(&SKATE, X0)
        .end_time(20.0)
        .sample_interval(0.05)
        .run_constant(&DormandPrince::new(1e-12, 1e-12), [0.0, 0.0])
        .unwrap();
    let with_work = forced.summary();
    assert_eq!(
        (with_work.steps, with_work.rejected, with_work.evaluations),
        (366, 0, 2198)
    );
    assert_eq!(forced.names().last().unwrap(), "energy_balance");
    for name in trajectory.names() {
        assert_eq!(trajectory.column(name), forced.column(name), "{name}");
    }
    assert!(
        forced
            .column("energy_balance")
            .unwrap()
            .iter()
            .all(|b| *b == 0.0)
    );
    assert_eq!(with_work.work, 0.0);
}

#[test]
fn csv_header_names_time_state_inputs_and_energy() {
    let trajectory = Simulation::new(&SKATE, X0)
        .end_time(0.25)
        .sample_interval(0.1)
        .run_constant(&Rk4::new(0.01), [0.0, 0.0])
        .unwrap();
    let mut out = Vec::new();
    trajectory.write_csv(&mut out).unwrap();
    let text = String::from_utf8(out).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(
        lines[0],
        "t,x,y,theta,v,omega,force,torque,energy,energy_balance"
    );
    assert_eq!(lines.len(), 1 + 4, "samples 0, 0.1, 0.2 and the end 0.25");
    assert_eq!(lines[1], "0.0,1.0,-0.5,0.3,1.5,0.7,0.0,0.0,2.3725,0.0");
    let last: Vec<f64> = lines[4].split(',').map(|f| f.parse().unwrap()).collect();
    assert_eq!(last[0], 0.25);
    for (value, expected) in last[1..6].iter().zip(circle(0.25)) {
        assert!((value - expected).abs() < 1e-10);
    }
}

/// A constant torque: ω = ω₀ + (τ/I)t, so E(t) = ½mv² + ½I ω(t)² is known; the drift monitor
/// must report exactly the work done. Inputs may also depend on the state (feedback).
#[test]
fn inputs_drive_the_system_and_the_monitor_sees_the_work() {
    let torque = 0.2;
    let simulation = Simulation::new(&SKATE, X0)
        .start_time(1.0)
        .end_time(3.0)
        .sample_interval(0.5);
    let trajectory = simulation
        .run(&Rk4::new(0.01), |_, _| [0.0, torque])
        .unwrap();
    assert_eq!(trajectory.times(), [1.0, 1.5, 2.0, 2.5, 3.0]);
    let omega_end = 0.7 + torque / 0.5 * 2.0;
    let energy = |w: f64| 0.5 * 2.0 * 1.5 * 1.5 + 0.5 * 0.5 * w * w;
    let summary = trajectory.summary();
    assert!((trajectory.column("omega").unwrap()[4] - omega_end).abs() < 1e-12);
    assert!((summary.max_energy_drift - (energy(omega_end) - energy(0.7))).abs() < 1e-12);
    assert!((summary.relative_energy_drift - summary.max_energy_drift / energy(0.7)).abs() < 1e-15);
    assert_eq!(summary.steps, 200);
    // One more than four a step: the slope at the last step's end, for its dense output.
    assert_eq!(summary.evaluations, 801);

    // Feedback that brakes the forward speed: v̇ = −v/m·k decays exponentially.
    let brake = simulation
        .run(&DormandPrince::new(1e-10, 1e-10), |_, x| [-0.8 * x[3], 0.0])
        .unwrap();
    let v_end = brake.column("v").unwrap()[4];
    assert!(
        (v_end - 1.5 * (-0.8 / 2.0 * 2.0f64).exp()).abs() < 1e-8,
        "{v_end}"
    );
}

#[test]
fn sample_times_end_exactly_at_the_end_time() {
    let simulation = Simulation::new(&SKATE, X0)
        .end_time(2.0)
        .sample_interval(0.1);
    let times = simulation.sample_times().unwrap();
    assert_eq!(times.len(), 21);
    // i·dt from the start, not summed: ten additions of 0.1 give 0.9999999999999999.
    assert_eq!(times[10], 1.0);
    assert_eq!(*times.last().unwrap(), 2.0);
    // An interval that does not divide the span: the last one is shorter.
    let uneven = Simulation::new(&SKATE, X0)
        .start_time(-1.0)
        .end_time(0.5)
        .sample_interval(0.4);
    let times = uneven.sample_times().unwrap();
    assert_eq!(times.len(), 5);
    assert_eq!((times[0], times[4]), (-1.0, 0.5));
    assert!((times[3] - 0.2).abs() < 1e-15);
    // No sliver: an end a hair beyond a multiple of the interval replaces that sample.
    let hair = Simulation::new(&SKATE, X0)
        .end_time(1.0 + 1e-12)
        .sample_interval(0.25);
    assert_eq!(
        hair.sample_times().unwrap(),
        [0.0, 0.25, 0.5, 0.75, 1.0 + 1e-12]
    );
}

#[test]
fn bad_settings_and_initial_values_are_errors_naming_them() {
    let dp = DormandPrince::new(1e-8, 1e-8);
    let run = |sim: Simulation<'_, Skate>| sim.run_constant(&dp, [0.0, 0.0]);

    let mut x0 = X0;
    x0[2] = f64::NAN;
    match run(Simulation::new(&SKATE, x0)) {
        Err(Error::NonFiniteInitialValue { name, value }) => {
            assert!(name == "theta" && value.is_nan())
        }
        other => panic!("{other:?}"),
    }
    for (sim, setting, value) in [
        (Simulation::new(&SKATE, X0).end_time(0.0), "end time", 0.0),
        (
            Simulation::new(&SKATE, X0).end_time(f64::INFINITY),
            "end time",
            f64::INFINITY,
        ),
        (
            Simulation::new(&SKATE, X0).start_time(11.0),
            "end time",
            10.0,
        ),
        (
            Simulation::new(&SKATE, X0).start_time(f64::NEG_INFINITY),
            "start time",
            f64::NEG_INFINITY,
        ),
        (
            Simulation::new(&SKATE, X0).sample_interval(0.0),
            "sample interval",
            0.0,
        ),
        (
            Simulation::new(&SKATE, X0).sample_interval(-0.1),
            "sample interval",
            -0.1,
        ),
    ] {
        match run(sim) {
            Err(Error::InvalidSetting { name, value: v, .. }) => {
                assert_eq!((name, v), (setting, value))
            }
            other => panic!("expected {setting} = {value} to be invalid, got {other:?}"),
        }
    }
    // More samples than the limit: refused before the run, with the count.
    match run(Simulation::new(&SKATE, X0).sample_interval(1e-12)) {
        Err(Error::TooManySamples {
            interval,
            samples,
            limit,
            ..
        }) => {
            assert_eq!((interval, limit), (1e-12, hamel_runtime::MAX_SAMPLES));
            assert!((samples - 1e13).abs() <= 2.0, "{samples}");
        }
        other => panic!("expected too many samples, got {other:?}"),
    }
    // A parameter that is not a number is caught before anything runs ...
    let broken: Skate = Skate {
        mass: f64::NAN,
        inertia: 0.5,
    };
    match Simulation::new(&broken, X0).run_constant(&dp, [0.0, 0.0]) {
        Err(Error::InvalidParameter { name, .. }) => assert_eq!(name, "mass"),
        other => panic!("{other:?}"),
    }
    // ... one that makes the mass matrix singular at the first evaluation, naming the time
    // and the state.
    let massless: Skate = Skate {
        mass: 2.0,
        inertia: 0.0,
    };
    match Simulation::new(&massless, X0)
        .start_time(0.5)
        .run_constant(&dp, [0.0, 0.0])
    {
        Err(Error::SingularMassMatrix {
            t,
            speed,
            value,
            state,
        }) => {
            assert_eq!((t, speed.as_str(), value), (0.5, "omega", 0.0));
            assert_eq!(state, NamedValues::new(<Skate>::STATE, &X0));
        }
        other => panic!("{other:?}"),
    }
}

/// Feedback that brakes the skate, F = −0.8 v, and turns it towards a steady rate,
/// τ = 0.3 − 0.1 ω: m v̇ = −0.8 v and I ω̇ = 0.3 − 0.1 ω give v = v₀ e^{−0.4 s} and
/// ω = 3 + (ω₀ − 3) e^{−0.2 s} after a time s, so the work the inputs have done is
/// W = ½m(v² − v₀²) + ½I(ω² − ω₀²), known in closed form.
fn feedback(_t: f64, x: &[f64; 5]) -> [f64; 2] {
    [-0.8 * x[3], 0.3 - 0.1 * x[4]]
}

fn feedback_work(s: f64) -> f64 {
    let v = 1.5 * (-0.4 * s).exp();
    let omega = 3.0 + (0.7 - 3.0) * (-0.2 * s).exp();
    0.5 * 2.0 * (v * v - 1.5 * 1.5) + 0.5 * 0.5 * (omega * omega - 0.7 * 0.7)
}

#[test]
fn the_work_done_balances_the_energy() {
    let simulation = Simulation::new(&SKATE, X0)
        .start_time(1.0)
        .end_time(3.0)
        .sample_interval(0.5);
    let trajectory = simulation
        .run(&DormandPrince::new(1e-10, 1e-10), feedback)
        .unwrap();
    let summary = trajectory.summary();
    println!("feedback, tol 1e-10:\n{summary}");
    let exact = feedback_work(2.0);
    println!("work {} (exact {exact})", summary.work);
    assert!((summary.work - exact).abs() <= 1e-10, "{}", summary.work);
    assert!(summary.max_energy_drift > 1.0, "the energy changes by O(1)");
    assert!(summary.max_energy_balance <= 1e-9, "{summary}");
    assert!(summary.relative_energy_balance <= 1e-9, "{summary}");
    // The column is the balance at every sample, and the work at the end closes it.
    let balance = trajectory.column("energy_balance").unwrap();
    let largest = balance.iter().fold(0.0f64, |m, b| m.max(b.abs()));
    assert_eq!(largest, summary.max_energy_balance);
    let energy = trajectory.column("energy").unwrap();
    let closed = energy[4] - energy[0] - summary.work;
    assert_eq!(closed, balance[4]);

    // The work takes no part in the step-size control: the runs take the steps they took
    // before it was integrated (the runtime at commit 729cd22).
    let coarse = simulation
        .run(&DormandPrince::new(1e-9, 1e-9), feedback)
        .unwrap();
    let s = coarse.summary();
    assert_eq!((s.steps, s.rejected, s.evaluations), (19, 0, 116));
    let brake = simulation
        .run(&DormandPrince::new(1e-10, 1e-10), |_, x| [-0.8 * x[3], 0.0])
        .unwrap();
    let s = brake.summary();
    assert_eq!((s.steps, s.rejected, s.evaluations), (27, 0, 164));
}

/// From rest, E₀ = 0: the drift relative to E₀ is meaningless (it printed 2.9e307), the
/// balance relative to the energy that changed hands is not. A constant force and torque do
/// W = (F² / 2m + τ² / 2I)t². Both relative figures are now relative to the largest energy
/// in the balance, here the work, and the summary says so; the change of a forced system's
/// energy is not printed as a drift.
#[test]
fn the_balance_of_a_body_set_moving_from_rest() {
    let rest = [1.0, -0.5, 0.3, 0.0, 0.0];
    let trajectory = Simulation::new(&SKATE, rest)
        .end_time(4.0)
        .sample_interval(0.1)
        .run_constant(&DormandPrince::new(1e-10, 1e-10), [0.3, 0.5])
        .unwrap();
    let summary = trajectory.summary();
    println!("from rest:\n{summary}");
    let work = (0.3 * 0.3 / (2.0 * 2.0) + 0.5 * 0.5 / (2.0 * 0.5)) * 16.0;
    assert_eq!(summary.initial_energy, 0.0);
    assert!(
        (summary.work - work).abs() <= 1e-12 * work,
        "{} vs {work}",
        summary.work
    );
    assert!((summary.max_energy_drift - work).abs() <= 1e-12 * work);
    // Before: max |E − E₀| / f64::MIN_POSITIVE > 1e300. Now relative to the work done.
    assert!(
        matches!(summary.energy_scale, hamel_runtime::EnergyScale::Work(w) | hamel_runtime::EnergyScale::EnergyChange(w) if (w - work).abs() <= 1e-9 * work),
        "{:?}",
        summary.energy_scale
    );
    assert!((summary.relative_energy_drift - 1.0).abs() < 1e-9);
    assert!(!summary.energy_inaccurate());
    assert!(summary.max_energy_balance <= 1e-9, "{summary}");
    assert!(
        summary.relative_energy_balance <= summary.max_energy_balance / work * (1.0 + 1e-12),
        "{summary}"
    );
    let text = summary.to_string();
    assert!(text.contains("\nwork                     4.36\n"), "{text}");
    assert!(
        !text.contains("holonomic") && !text.contains("drift"),
        "{text}"
    );
    assert!(text.contains("of the largest"), "{text}");
}

/// The hand-derived Jacobian against central differences of the right-hand side, at a state
/// where every entry that can be nonzero is.
#[test]
fn the_skates_jacobian_is_the_derivative_of_its_rate() {
    let u = [0.3, -0.2];
    let (a, b) = SKATE.jacobian(0.0, &X0, &u).unwrap();
    let (fa, fb) = common::central_differences(&SKATE, 0.0, &X0, &u);
    let (da, db) = (
        common::relative_difference(&a, &fa),
        common::relative_difference(&b, &fb),
    );
    println!("relative difference from central differences: A {da:.1e}, B {db:.1e}");
    assert!(da <= 1e-8 && db <= 1e-8, "{da:e} {db:e}");
}

// ---------------------------------------------------------------------------------------------
// Runs that must end, and mistakes that must be errors (issue 20). Each test says what the
// case gave before.
// ---------------------------------------------------------------------------------------------

/// A sink that counts rows and keeps nothing: a stream of billions of samples.
#[derive(Default)]
struct Counting {
    rows: u64,
}

impl hamel_runtime::Sink for Counting {
    fn begin(&mut self, _columns: &[String]) -> Result<(), Error> {
        Ok(())
    }
    fn row(&mut self, _values: &[f64]) -> Result<(), Error> {
        self.rows += 1;
        Ok(())
    }
}

/// Runs `f` on a thread of its own and waits at most `limit` for it: a hang fails the test
/// instead of the suite.
fn within<T: Send + 'static>(limit: Duration, f: impl FnOnce() -> T + Send + 'static) -> T {
    let (send, receive) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let _ = send.send(f());
    });
    receive
        .recv_timeout(limit)
        .unwrap_or_else(|_| panic!("the run did not end within {limit:?}"))
}

/// A stream over 1 s with samples every `interval` and a progress callback that cancels
/// after `after` of computing: the summary (or error), and how long after the cancel the
/// run returned.
fn cancelled_stream(
    interval: f64,
    max_samples: u64,
    after: Duration,
) -> (Result<hamel_runtime::Summary, Error>, Option<Duration>) {
    let cancelled_at = std::cell::Cell::new(None::<Instant>);
    let mut sink = Counting::default();
    let result = Simulation::new(&SKATE, X0)
        .end_time(1.0)
        .sample_interval(interval)
        .max_samples(max_samples)
        .on_progress(|p| {
            if p.elapsed >= after {
                cancelled_at.set(Some(Instant::now()));
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        })
        .stream(
            &DormandPrince::new(1e-8, 1e-8),
            |_, _| [0.0, 0.0],
            &mut sink,
        );
    (result, cancelled_at.get().map(|at| at.elapsed()))
}

/// Before: samples every 1e-12 over 1 s, cancelled after 3 s, had not returned after 20 s
/// (the one step held 10¹² samples and progress was consulted between steps only). Now the
/// count is checked before the run like the step limits, and with the limit raised the run
/// is cancelled between the samples of its step.
#[test]
fn a_trillion_samples_are_refused_or_cancelled_at_once() {
    let limit = Duration::from_secs(20);
    let (refused, _) = within(limit, || {
        cancelled_stream(1e-12, MAX_SAMPLES, Duration::ZERO)
    });
    match refused {
        Err(Error::TooManySamples { samples, limit, .. }) => {
            assert!(samples >= 1e12 && limit == MAX_SAMPLES, "{samples}");
        }
        other => panic!("expected too many samples, got {other:?}"),
    }
    let (cancelled, since) = within(limit, || {
        cancelled_stream(1e-12, u64::MAX, Duration::from_millis(100))
    });
    let summary = cancelled.expect("a cancelled run is Ok");
    assert!(
        matches!(summary.stopped, Some(Stopped::Cancelled { .. })),
        "{summary}"
    );
    let since = since.expect("the callback cancelled");
    assert!(
        since < Duration::from_secs(1),
        "returned {since:?} after the cancel"
    );
}

/// Before: 10⁹ samples took 18 s to cancel. Now the run ends within 1 s of the cancel.
#[test]
fn a_billion_samples_end_within_a_second_of_the_cancel() {
    let (result, since) = within(Duration::from_secs(20), || {
        cancelled_stream(1e-9, MAX_SAMPLES, Duration::from_millis(100))
    });
    let summary = result.expect("a cancelled run is Ok");
    match summary.stopped {
        Some(Stopped::Cancelled { t }) => assert!(t > 0.0 && t < 1.0, "{t}"),
        ref other => panic!("expected a cancel, got {other:?}"),
    }
    assert!(summary.samples > 1 && (summary.samples as f64) < 1e9);
    let since = since.expect("the callback cancelled");
    assert!(
        since < Duration::from_secs(1),
        "returned {since:?} after the cancel"
    );
}

/// Before: a callback that answered `Break` at once did not cancel a run shorter than 50 ms
/// (it was first called after 50 ms). Now it is called at the start.
#[test]
fn a_cancel_at_once_cancels_even_a_short_run() {
    let calls = std::cell::Cell::new(0);
    let trajectory = Simulation::new(&SKATE, X0)
        .end_time(1.0)
        .on_progress(|_| {
            calls.set(calls.get() + 1);
            ControlFlow::Break(())
        })
        .run_constant(&DormandPrince::new(1e-8, 1e-8), [0.0, 0.0])
        .unwrap();
    let summary = trajectory.summary();
    assert_eq!(summary.stopped, Some(Stopped::Cancelled { t: 0.0 }));
    assert_eq!((trajectory.len(), summary.steps), (1, 0));
    // Once at the start, once at the end.
    assert_eq!(calls.get(), 2);
}

/// Before: `output("energy", ..)` and `output("x", ..)` duplicated columns (`column("energy")`
/// then returned the user's), and `output("t,y", ..)` broke the CSV header (9 names for 8
/// columns). Now each is an error naming the output.
#[test]
fn output_names_that_clash_or_break_the_csv_are_errors() {
    let dp = DormandPrince::new(1e-8, 1e-8);
    let with = |name: &str| {
        Simulation::new(&SKATE, X0)
            .end_time(0.1)
            .output(name.to_string(), |_, x: &[f64; 5]| x[0])
            .output("tip", |_, x: &[f64; 5]| x[1])
    };
    for clash in [
        "energy",
        "x",
        "theta",
        "energy_balance",
        "tip",
        "t",
        "force",
    ] {
        let e = with(clash).run_constant(&dp, [0.0, 0.0]).unwrap_err();
        match &e {
            Error::DuplicateName { kind, name, .. } => {
                assert_eq!((*kind, name.as_str()), ("column", clash))
            }
            other => panic!("`{clash}`: expected a duplicate name, got {other:?}"),
        }
        assert!(e.to_string().contains(&format!("`{clash}`")), "{e}");
    }
    for bad in ["t,y", "a\"b", "two\nlines", "", " padded"] {
        let mut sink = Counting::default();
        let e = with(bad)
            .stream(&dp, |_, _| [0.0, 0.0], &mut sink)
            .unwrap_err();
        match &e {
            Error::InvalidColumnName { name, .. } => assert_eq!(name, bad),
            other => panic!("{bad:?}: expected an invalid column name, got {other:?}"),
        }
        assert_eq!(sink.rows, 0, "refused before any row");
    }
    // A new name is fine.
    with("nose").run_constant(&dp, [0.0, 0.0]).unwrap();
}

/// Before: a NaN from the input function went into the right-hand side and was reported as
/// whatever it broke first (for a generated model, "the reduced mass matrix ... outside the
/// model's geometry"). Now the input is named, with the time and the state.
#[test]
fn a_non_finite_input_is_named() {
    let dp = DormandPrince::new(1e-8, 1e-8);
    let e = Simulation::new(&SKATE, X0)
        .run(&dp, |t, _| [0.0, if t > 0.5 { f64::NAN } else { 0.1 }])
        .unwrap_err();
    match &e {
        Error::NonFiniteInput { name, value, t, .. } => {
            assert_eq!(name, "torque");
            assert!(value.is_nan() && *t > 0.5, "{t}");
        }
        other => panic!("expected a non-finite input, got {other:?}"),
    }
    assert!(e.to_string().contains("the input `torque` is NaN"), "{e}");
    // Constant inputs are checked before the run, at the start time.
    let e = Simulation::new(&SKATE, X0)
        .start_time(0.25)
        .run_constant(&Rk4::new(0.1), [f64::INFINITY, 0.0])
        .unwrap_err();
    assert!(
        matches!(&e, Error::NonFiniteInput { name, t, .. } if name == "force" && *t == 0.25),
        "{e:?}"
    );
}

/// Before: a span of 1e-15 at t = 1 reported "step size underflow ... the step shrank to
/// 1.11e-15", which was the whole span. Now the span is named as too short.
#[test]
fn a_span_too_short_to_integrate_says_so() {
    let e = Simulation::new(&SKATE, X0)
        .start_time(1.0)
        .end_time(1.0 + 1e-15)
        .run_constant(&DormandPrince::new(1e-8, 1e-8), [0.0, 0.0])
        .unwrap_err();
    match &e {
        Error::SpanTooShort { t0, t_end, .. } => assert_eq!((*t0, *t_end), (1.0, 1.0 + 1e-15)),
        other => panic!("expected a span too short, got {other:?}"),
    }
    assert!(e.to_string().contains("too short to integrate"), "{e}");
    // A fixed step covers any span.
    Simulation::new(&SKATE, X0)
        .start_time(1.0)
        .end_time(1.0 + 1e-15)
        .run_constant(&Rk4::new(0.1), [0.0, 0.0])
        .unwrap();
}

/// A directory of its own for a test's files, emptied.
fn scratch(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("hamel-runtime-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The names in a directory, sorted.
fn listing(dir: &std::path::Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// Before: `Trajectory::save_csv` and `CsvSink::create` wrote in place, so a crash or a full
/// disk left a partial file under the final name (and a stream that failed, the rows until
/// the failure). Now the final name appears only when the file is whole, with its manifest,
/// and a failed stream leaves no file at all.
#[test]
fn files_are_written_whole_or_not_at_all() {
    use hamel_runtime::CsvSink;
    use hamel_runtime::whole_file::check_manifest;
    let dir = scratch("whole");
    let run = Simulation::new(&SKATE, X0)
        .end_time(1.0)
        .sample_interval(0.1)
        .run(&DormandPrince::new(1e-9, 1e-9), |_, _| [0.0, 0.0])
        .unwrap();
    let saved = dir.join("run.csv");
    run.save_csv(&saved).unwrap();
    assert_eq!(listing(&dir), ["run.csv", "run.csv.manifest"]);
    assert_eq!(
        check_manifest(&saved).unwrap().unwrap().rows,
        run.len() as u64
    );
    // Cut after its first rows, at a row boundary: a valid CSV, but not the file written.
    let text = std::fs::read_to_string(&saved).unwrap();
    let cut: String = text.lines().take(4).map(|l| format!("{l}\n")).collect();
    std::fs::write(&saved, cut).unwrap();
    let e = check_manifest(&saved).unwrap_err();
    assert!(e.to_string().contains("truncated"), "{e}");

    // A stream into a file: absent while the run writes it, whole with its manifest after.
    let streamed = dir.join("stream.csv");
    let mut sink = CsvSink::create(&streamed).unwrap();
    let summary = Simulation::new(&SKATE, X0)
        .end_time(1.0)
        .sample_interval(0.01)
        .on_progress(|_| {
            assert!(!streamed.exists(), "the file appeared before the run ended");
            ControlFlow::Continue(())
        })
        .stream(
            &DormandPrince::new(1e-9, 1e-9),
            |_, _| [0.0, 0.0],
            &mut sink,
        )
        .unwrap();
    drop(sink);
    let manifest = check_manifest(&streamed).unwrap().expect("a manifest");
    assert_eq!(manifest.rows, summary.samples as u64);
    assert_eq!(
        listing(&dir),
        [
            "run.csv",
            "run.csv.manifest",
            "stream.csv",
            "stream.csv.manifest"
        ]
    );

    // A stream that fails (a NaN force half way) leaves no file, and no temporary one.
    let failed = dir.join("failed.csv");
    let mut sink = CsvSink::create(&failed).unwrap();
    let e = Simulation::new(&SKATE, X0)
        .end_time(1.0)
        .sample_interval(0.01)
        .stream(
            &DormandPrince::new(1e-9, 1e-9),
            |t, _| [if t > 0.5 { f64::NAN } else { 0.0 }, 0.0],
            &mut sink,
        )
        .unwrap_err();
    drop(sink);
    assert!(!failed.exists(), "{e}");
    assert_eq!(listing(&dir).len(), 4, "{:?}", listing(&dir));
    std::fs::remove_dir_all(&dir).unwrap();
}
