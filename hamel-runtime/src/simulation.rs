//! The simulation driver: checks a run's settings, integrates a [`HamelSystem`] with any
//! [`Integrator`], and records a [`Trajectory`] with energy and constraint monitors.

use crate::error::Error;
use crate::integrate::{Integrator, Ode};
use crate::named::NamedValues;
use crate::system::HamelSystem;
use crate::trajectory::{Summary, Trajectory};

/// A run of a system from an initial state: x0 at `t0`, recorded every `dt_out` until
/// `t_end` (defaults: from 0 to 10, every 0.01).
pub struct Simulation<'s, S: HamelSystem> {
    system: &'s S,
    x0: S::State,
    t0: f64,
    t_end: f64,
    dt_out: f64,
}

/// More samples than this is a mistaken sample interval, not a simulation: refuse it before
/// allocating gigabytes.
const MAX_SAMPLES: f64 = 1e8;

impl<'s, S: HamelSystem> Simulation<'s, S> {
    /// A run of `system` from the state `x0` (see `HamelSystem::state_from_velocities` and
    /// `state_from_speeds` to build one).
    pub fn new(system: &'s S, x0: S::State) -> Self {
        Simulation {
            system,
            x0,
            t0: 0.0,
            t_end: 10.0,
            dt_out: 0.01,
        }
    }

    pub fn start_time(mut self, t0: f64) -> Self {
        self.t0 = t0;
        self
    }

    pub fn end_time(mut self, t_end: f64) -> Self {
        self.t_end = t_end;
        self
    }

    /// The interval between recorded samples (the last interval may be shorter, so that the
    /// last sample is exactly the end time).
    pub fn sample_interval(mut self, dt_out: f64) -> Self {
        self.dt_out = dt_out;
        self
    }

    /// The sample times t0, t0 + dt, …, t_end, after checking the settings.
    pub fn sample_times(&self) -> Result<Vec<f64>, Error> {
        let (t0, t_end, dt) = (self.t0, self.t_end, self.dt_out);
        if !t0.is_finite() {
            return Err(Error::InvalidSetting {
                name: "start time",
                value: t0,
                reason: "it must be a finite number",
            });
        }
        if !(t_end.is_finite() && t_end > t0) {
            return Err(Error::InvalidSetting {
                name: "end time",
                value: t_end,
                reason: "it must be a finite number after the start time (0 unless set with `start_time`)",
            });
        }
        if !(dt.is_finite() && dt > 0.0) {
            return Err(Error::InvalidSetting {
                name: "sample interval",
                value: dt,
                reason: "it must be a positive finite number",
            });
        }
        let intervals = (t_end - t0) / dt;
        if intervals >= MAX_SAMPLES {
            return Err(Error::InvalidSetting {
                name: "sample interval",
                value: dt,
                reason: "it gives more than 10⁸ samples; choose a longer interval",
            });
        }
        // i·dt from the start rather than accumulated sums, so t0 + 100·0.01 is 1 and not
        // 1.0000000000000007; a sample closer to t_end than a billionth of dt is dropped in
        // favour of t_end itself rather than leaving a sliver of an interval.
        let mut times: Vec<f64> = (0..)
            .map(|i| t0 + i as f64 * dt)
            .take_while(|t| *t < t_end - 1e-9 * dt)
            .collect();
        times.push(t_end);
        Ok(times)
    }

    /// Runs with the inputs given as a function of time and state (a feedback law or a
    /// schedule), recording at every sample time.
    pub fn run<I: Integrator>(
        &self,
        integrator: &I,
        inputs: impl FnMut(f64, &S::State) -> S::Inputs,
    ) -> Result<Trajectory, Error> {
        self.system.validate()?;
        if let Some(i) = self.x0.as_ref().iter().position(|v| !v.is_finite()) {
            let name = S::STATE
                .get(i)
                .map_or_else(|| format!("x{i}"), |n| (*n).to_string());
            return Err(Error::NonFiniteInitialValue {
                name,
                value: self.x0.as_ref()[i],
            });
        }
        // A closed-form inverse B(q) that does not invert A(q) would make every step wrong.
        self.system
            .check_configuration(self.t0, &S::coordinates_of(&self.x0))?;
        let times = self.sample_times()?;

        let names = ["t"]
            .iter()
            .chain(S::STATE)
            .chain(&["energy"])
            .map(|n| (*n).to_string())
            .collect();
        let mut recorder = Recorder::<S>::new(self.system, Trajectory::new(names, empty_summary()));
        let mut ode = SystemOde {
            system: self.system,
            inputs,
        };
        let stats = integrator.integrate(&mut ode, self.t0, &self.x0, &times, &mut |t, x| {
            recorder.record(t, x)
        })?;

        let mut trajectory = recorder.trajectory;
        let summary = trajectory.summary_mut();
        summary.steps = stats.steps;
        summary.rejected = stats.rejected;
        summary.evaluations = stats.evaluations;
        Ok(trajectory)
    }

    /// Runs with constant inputs.
    pub fn run_constant<I: Integrator>(
        &self,
        integrator: &I,
        u: S::Inputs,
    ) -> Result<Trajectory, Error> {
        self.run(integrator, move |_, _| u)
    }
}

/// A system with its inputs as an ODE: the inputs are evaluated at every stage, and a
/// singular matrix in the right-hand side becomes an error naming the time and state.
struct SystemOde<'s, S, F> {
    system: &'s S,
    inputs: F,
}

impl<S: HamelSystem, F: FnMut(f64, &S::State) -> S::Inputs> Ode for SystemOde<'_, S, F> {
    type State = S::State;

    fn rhs(&mut self, t: f64, x: &S::State, dx: &mut S::State) -> Result<(), Error> {
        let u = (self.inputs)(t, x);
        self.system
            .rhs(t, x, &u, dx)
            .map_err(|s| S::singular(s, t, x))
    }

    fn describe(&self, x: &S::State) -> NamedValues {
        S::named_state(x)
    }
}

fn empty_summary() -> Summary {
    Summary {
        steps: 0,
        rejected: 0,
        evaluations: 0,
        samples: 0,
        max_constraint_residual: 0.0,
        initial_energy: f64::NAN,
        max_energy_drift: 0.0,
        relative_energy_drift: 0.0,
    }
}

/// Records the samples and keeps the monitors' running maxima.
struct Recorder<'s, S> {
    system: &'s S,
    trajectory: Trajectory,
}

impl<'s, S: HamelSystem> Recorder<'s, S> {
    fn new(system: &'s S, trajectory: Trajectory) -> Self {
        Recorder { system, trajectory }
    }

    fn record(&mut self, t: f64, x: &S::State) -> Result<(), Error> {
        let at = |s: crate::Singularity| S::singular(s, t, x);
        let energy = self.system.energy(t, x).map_err(at)?;
        let q = S::coordinates_of(x);
        let qd = self.system.generalized_velocities(t, x).map_err(at)?;
        let residual = self.system.constraint_residual(t, &q, &qd);

        let first = self.trajectory.is_empty();
        self.trajectory.push(
            core::iter::once(t)
                .chain(x.as_ref().iter().copied())
                .chain([energy]),
        );
        let summary = self.trajectory.summary_mut();
        summary.samples += 1;
        for r in residual.as_ref() {
            summary.max_constraint_residual = nan_max(summary.max_constraint_residual, r.abs());
        }
        if first {
            summary.initial_energy = energy;
        }
        let e0 = summary.initial_energy;
        summary.max_energy_drift = nan_max(summary.max_energy_drift, (energy - e0).abs());
        summary.relative_energy_drift = summary.max_energy_drift / e0.abs().max(f64::MIN_POSITIVE);
        Ok(())
    }
}

/// The larger of two numbers, NaN if either is: a monitor must not hide a NaN (`f64::max`
/// would drop it).
fn nan_max(a: f64, b: f64) -> f64 {
    if a.is_nan() || b.is_nan() {
        f64::NAN
    } else {
        a.max(b)
    }
}
