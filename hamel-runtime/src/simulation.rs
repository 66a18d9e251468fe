//! The simulation driver: checks a run's settings, integrates a [`HamelSystem`] with any
//! [`Integrator`], and records a [`Trajectory`] with energy and constraint monitors.

use crate::error::Error;
use crate::integrate::Integrator;
use crate::recorder::Recorder;
use crate::system::HamelSystem;
use crate::system_ode::{BalanceOde, PlainOde, extend, project_coordinates, split};
use crate::trajectory::Trajectory;

/// A run of a system from an initial state: x0 at `t0`, recorded every `dt_out` until
/// `t_end` (defaults: from 0 to 10, every 0.01).
pub struct Simulation<'s, S: HamelSystem> {
    system: &'s S,
    x0: S::State,
    t0: f64,
    t_end: f64,
    dt_out: f64,
    project: bool,
}

/// More samples than this is a mistaken sample interval, not a simulation: refuse it before
/// allocating gigabytes.
const MAX_SAMPLES: f64 = 1e8;

impl<'s, S: HamelSystem> Simulation<'s, S> {
    /// A run of `system` from the state `x0` (see [`HamelSystem::state_builder`],
    /// `state_from_velocities` and `state_from_speeds` to build one).
    pub fn new(system: &'s S, x0: S::State) -> Self {
        Simulation {
            system,
            x0,
            t0: 0.0,
            t_end: 10.0,
            dt_out: 0.01,
            project: false,
        }
    }

    /// The time of the initial state (default 0).
    pub fn start_time(mut self, t0: f64) -> Self {
        self.t0 = t0;
        self
    }

    /// The time the run ends at, the last sample's (default 10).
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

    /// Whether to keep the holonomic constraints satisfied to rounding (default: off). When
    /// on, the dependent coordinates of the initial state and of the state after every
    /// accepted step are re-solved by Newton's method at that time (as
    /// [`HamelSystem::assemble`] does), and so are those of every recorded sample; a
    /// Dormand–Prince step then costs one evaluation more. Off, the constraints hold to the
    /// integration's accuracy, which degrades slowly over long runs
    /// ([`crate::Summary::max_holonomic_residual`] reports it). Nothing changes for a system
    /// without holonomic constraints.
    pub fn project_holonomic(mut self, on: bool) -> Self {
        self.project = on;
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
    /// schedule), recording at every sample time. A system that is not
    /// [`HamelSystem::CONSERVATIVE`] is integrated with the work done on it, Ẇ =
    /// [`HamelSystem::power`], outside the step-size control (so with the same steps), for
    /// the energy balance of the [`crate::Summary`] and the column `energy_balance`.
    pub fn run<I: Integrator>(
        &self,
        integrator: &I,
        inputs: impl FnMut(f64, &S::State) -> S::Inputs,
    ) -> Result<Trajectory, Error> {
        let x0 = self.initial_state()?;
        let times = self.sample_times()?;
        let mut recorder = Recorder::new(self.system);
        let (system, project) = (self.system, self.project);
        let stats = if S::CONSERVATIVE {
            let mut ode = PlainOde {
                system,
                inputs,
                project,
            };
            integrator.integrate(&mut ode, self.t0, &x0, &times, &mut |t, x| {
                recorder.record(t, x, 0.0)
            })?
        } else {
            let mut ode = BalanceOde {
                system,
                inputs,
                project,
            };
            let v0 = extend::<S>(&x0)?;
            integrator.integrate(&mut ode, self.t0, &v0, &times, &mut |t, v| {
                let (x, work) = split::<S>(v);
                recorder.record(t, &x, work)
            })?
        };
        Ok(recorder.finish(stats))
    }

    /// The checked initial state, its dependent coordinates re-solved when projecting.
    fn initial_state(&self) -> Result<S::State, Error> {
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
        let mut x0 = self.x0;
        if self.project {
            let t0 = self.t0;
            project_coordinates(self.system, t0, x0.as_mut(), || S::named_state(&self.x0))?;
        }
        Ok(x0)
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
