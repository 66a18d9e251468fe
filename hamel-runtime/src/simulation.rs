//! The simulation driver: checks a run's settings, integrates a [`HamelSystem`] with any
//! [`Integrator`], records the samples into a [`Trajectory`] or streams them into a
//! [`Sink`], with energy and constraint monitors, events, extra output columns and a
//! progress callback that can cancel the run. What the integrator reports goes to the
//! run's observer ([`crate::driver`]).

use std::ops::ControlFlow;
use std::time::Duration;

use crate::assembly;
use crate::crossing::CrossingWatch;
use crate::driver::{Driver, ProgressFn, States};
use crate::error::Error;
use crate::events::{EVENT_TOLERANCE, Event, Watch};
use crate::integrate::{Grid, Integrator, SampleTimes};
use crate::recorder::{Columns, Output, Recorder};
use crate::sink::Sink;
use crate::system::HamelSystem;
use crate::system_ode::{
    BalanceOde, PlainOde, RunInputs, extend, inertia_diagonal, prepared, project_coordinates, split,
};
use crate::trajectory::{Summary, Trajectory};

/// Where a run is, for a progress callback.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Progress {
    /// The time reached.
    pub t: f64,
    /// The run's start and end times.
    pub t0: f64,
    pub t_end: f64,
    /// Accepted steps so far.
    pub steps: usize,
    /// Wall-clock time since the run started.
    pub elapsed: Duration,
}

impl Progress {
    /// The fraction of the span done, in [0, 1].
    pub fn fraction(&self) -> f64 {
        ((self.t - self.t0) / (self.t_end - self.t0)).clamp(0.0, 1.0)
    }
}

/// How often, at most, the progress callback is called (besides at the start and the end).
pub const PROGRESS_INTERVAL: Duration = Duration::from_millis(50);

/// Samples × columns above which an in-memory run is refused (8 bytes each: 4 GiB), in favour
/// of streaming them ([`Simulation::stream`]).
const MAX_IN_MEMORY: f64 = 512.0 * 1024.0 * 1024.0;

/// The default limit on the samples of one run (`Simulation::max_samples`): 10¹⁰, hours of
/// writing at the fastest, so that a sample interval far too small for the span is an error
/// before the run instead of a run that does not end.
pub const MAX_SAMPLES: u64 = 10_000_000_000;

/// A run of a system from an initial state: x0 at `t0`, recorded every `dt_out` until
/// `t_end` (defaults: from 0 to 10, every 0.01).
pub struct Simulation<'s, S: HamelSystem> {
    system: &'s S,
    x0: S::State,
    t0: f64,
    t_end: f64,
    dt_out: f64,
    project: bool,
    events: Vec<Event<'s, S>>,
    event_tolerance: f64,
    outputs: Vec<Output<'s, S>>,
    forces: bool,
    progress: Option<ProgressFn<'s>>,
    watch_crossings: bool,
    max_samples: u64,
}

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
            events: Vec::new(),
            event_tolerance: EVENT_TOLERANCE,
            outputs: Vec::new(),
            forces: false,
            watch_crossings: true,
            progress: None,
            max_samples: MAX_SAMPLES,
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

    /// Watches an event: its sign changes are located on the integrator's dense output and
    /// recorded ([`Trajectory::events`]); a terminal one ends the run at its time.
    pub fn event(mut self, event: Event<'s, S>) -> Self {
        self.events.push(event);
        self
    }

    /// The time tolerance of event location, relative to the step the event falls in
    /// (default [`crate::EVENT_TOLERANCE`], 10⁻¹²).
    pub fn event_tolerance(mut self, relative: f64) -> Self {
        self.event_tolerance = relative;
        self
    }

    /// Records one more column, `name`, computed from the time and the state at every sample
    /// (a contact point's position, a distance). The name must be new (not `energy`, not a
    /// state's or another output's) and free of commas, quotes and line breaks, or the run is
    /// the error [`Error::DuplicateName`] or [`Error::InvalidColumnName`].
    pub fn output(
        mut self,
        name: impl Into<String>,
        f: impl Fn(f64, &S::State) -> f64 + 's,
    ) -> Self {
        self.outputs.push(Output {
            name: name.into(),
            f: Box::new(f),
        });
        self
    }

    /// Records the constraint forces λ ([`HamelSystem::constraint_forces`]) in the columns
    /// `lambda_<constraint>` (default: off).
    pub fn record_constraint_forces(mut self, on: bool) -> Self {
        self.forces = on;
        self
    }

    /// Whether to check, after every accepted step, that the run has not crossed a
    /// configuration where A(q, t) is singular (default: on). A crossing is flagged in
    /// [`crate::Summary::singular_crossings`] (and printed with the summary): the run goes on,
    /// but its results after it are unreliable. The check costs n + 1 evaluations of the rows
    /// and the sign of an n × n determinant per step, and nothing for a model whose det A
    /// depends on the parameters alone
    /// ([`HamelSystem::TRANSFORMATION_DETERMINANT_CONSTANT`]), which never crosses one.
    pub fn watch_singular_crossings(mut self, on: bool) -> Self {
        self.watch_crossings = on;
        self
    }

    /// Calls `f` with the run's progress: at the start, then every 50 ms of computing at most
    /// (between steps, and between the samples of a step that holds many), and once at the
    /// end; `ControlFlow::Break(())` cancels the run there: it ends at the time reached, its
    /// summary says so ([`crate::Summary::stopped`]), and what was recorded is kept.
    pub fn on_progress(mut self, f: impl Fn(&Progress) -> ControlFlow<()> + 's) -> Self {
        self.progress = Some(Box::new(f));
        self
    }

    /// The most samples the run may have (default [`MAX_SAMPLES`], 10¹⁰): a run whose span
    /// and sample interval give more is the error [`Error::TooManySamples`] before it starts.
    pub fn max_samples(mut self, n: u64) -> Self {
        self.max_samples = n;
        self
    }

    /// The sample times, after checking the settings; computed on demand, so that a run of
    /// 10⁸ samples does not hold 10⁸ times.
    pub fn samples(&self) -> Result<Grid, Error> {
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
        if !(dt.is_finite() && dt > 0.0 && (t_end - t0) / dt < 1e15) {
            return Err(Error::InvalidSetting {
                name: "sample interval",
                value: dt,
                reason: "it must be a positive finite number, at most 10¹⁵ of which fill the span",
            });
        }
        let count = ((t_end - t0) / dt).ceil() + 1.0;
        if count > self.max_samples as f64 {
            return Err(Error::TooManySamples {
                interval: dt,
                span: t_end - t0,
                samples: count,
                limit: self.max_samples,
            });
        }
        if !(self.event_tolerance.is_finite() && self.event_tolerance >= 0.0) {
            return Err(Error::InvalidSetting {
                name: "event tolerance",
                value: self.event_tolerance,
                reason: "it must be a finite number ≥ 0 (relative to a step)",
            });
        }
        Ok(Grid::new(t0, t_end, dt))
    }

    /// The sample times t0, t0 + dt, …, t_end as a vector (see [`Simulation::samples`]).
    pub fn sample_times(&self) -> Result<Vec<f64>, Error> {
        let grid = self.samples()?;
        Ok((0..grid.count()).map(|i| grid.time(i)).collect())
    }

    /// Runs with the inputs given as a function of time and state (a feedback law or a
    /// schedule), recording at every sample time into a [`Trajectory`] in memory. The
    /// initial configuration must satisfy the holonomic constraints to
    /// [`crate::HOLONOMIC_TOLERANCE`] of their scale ([`Error::HolonomicViolation`] names the
    /// one it misses), and the inputs must be finite numbers wherever they are evaluated
    /// ([`Error::NonFiniteInput`] names the input, the time and the state). A system
    /// that is not [`HamelSystem::CONSERVATIVE`] is integrated with the work done on it,
    /// Ẇ = [`HamelSystem::power`], outside the step-size control (so with the same steps),
    /// for the energy balance of the [`crate::Summary`] and the column `energy_balance`. The
    /// inputs are recorded too, at the samples (they are called there once more).
    pub fn run<I: Integrator>(
        &self,
        integrator: &I,
        inputs: impl FnMut(f64, &S::State) -> S::Inputs,
    ) -> Result<Trajectory, Error> {
        let grid = self.samples()?;
        self.check_columns(&grid)?;
        let mut trajectory = Trajectory::expecting(grid.count(), Summary::new::<S>());
        let inputs = RunInputs::function(inputs);
        let summary = self.drive(integrator, &inputs, &grid, &mut trajectory)?;
        trajectory.set_summary(summary);
        Ok(trajectory)
    }

    /// Runs with constant inputs: [`Simulation::run`] with `|_, _| u`, to the same bits, but
    /// the inputs are checked once instead of at every stage, and when they are zero and the
    /// model's power vanishes without inputs
    /// ([`HamelSystem::POWER_VANISHES_WITHOUT_INPUTS`]) the work done on the system, zero,
    /// is not integrated.
    pub fn run_constant<I: Integrator>(
        &self,
        integrator: &I,
        u: S::Inputs,
    ) -> Result<Trajectory, Error> {
        let grid = self.samples()?;
        self.check_columns(&grid)?;
        let mut trajectory = Trajectory::expecting(grid.count(), Summary::new::<S>());
        let inputs = RunInputs::constant(u);
        let summary = self.drive(integrator, &inputs, &grid, &mut trajectory)?;
        trajectory.set_summary(summary);
        Ok(trajectory)
    }

    /// Runs as [`Simulation::run`] does, but hands every sample to `sink` as it is produced
    /// (a [`crate::CsvSink`] writes it to a file), so that a run of any length needs the
    /// same memory; returns the summary. Events go to `sink` too (`Sink::event`).
    pub fn stream<I: Integrator>(
        &self,
        integrator: &I,
        inputs: impl FnMut(f64, &S::State) -> S::Inputs,
        sink: &mut dyn Sink,
    ) -> Result<Summary, Error> {
        let grid = self.samples()?;
        self.columns().check()?;
        self.drive(integrator, &RunInputs::function(inputs), &grid, sink)
    }

    /// The extra columns' names, and that the samples fit in memory.
    fn check_columns(&self, grid: &Grid) -> Result<(), Error> {
        let columns = self.columns();
        columns.check()?;
        let size = grid.count() as f64 * columns.names().len() as f64;
        if size > MAX_IN_MEMORY {
            return Err(Error::InvalidSetting {
                name: "sample interval",
                value: self.dt_out,
                reason: "the samples would take more than 4 GiB in memory: stream them to a \
                         file with `Simulation::stream` and a `CsvSink`, or sample less often",
            });
        }
        Ok(())
    }

    /// What the run records besides the time and the state.
    fn columns(&self) -> Columns<'_, 's, S> {
        Columns {
            outputs: &self.outputs,
            forces: self.forces,
        }
    }

    /// The run itself: the initial state and inputs checked, the inputs shared between the
    /// ODE and the recorder, the plain or the work-extended ODE integrated.
    fn drive<I: Integrator, F: FnMut(f64, &S::State) -> S::Inputs>(
        &self,
        integrator: &I,
        inputs: &RunInputs<S, F>,
        grid: &Grid,
        sink: &mut dyn Sink,
    ) -> Result<Summary, Error> {
        let x0 = self.initial_state()?;
        inputs.check_start(self.t0, &x0)?;
        let recorder = Recorder::new(self.system, inputs, self.columns(), sink)?;
        let watch = Watch::new(&self.events, self.event_tolerance, self.t0, &x0)?;
        let crossings = (self.watch_crossings && !S::TRANSFORMATION_DETERMINANT_CONSTANT)
            .then(|| CrossingWatch::new(self.system, self.t0, &x0));
        let mut driver = Driver::new(
            self.system,
            recorder,
            (watch, !self.events.is_empty()),
            crossings,
            self.progress.as_ref(),
            (self.t0, self.t_end),
        );
        let (system, project) = (self.system, self.project);
        // No work is done on a conservative system, nor on one whose power vanishes without
        // inputs when they are zero: its energy balance is its energy drift.
        let stats = if S::CONSERVATIVE || (S::POWER_VANISHES_WITHOUT_INPUTS && inputs.are_zero()) {
            let mut ode = PlainOde {
                system,
                prepared: prepared(system),
                inputs,
                project,
                start_inertia: inertia_diagonal(system, self.t0, &x0),
            };
            let mut states = States {
                driver: &mut driver,
                split: |x: &S::State| (*x, 0.0),
            };
            integrator.integrate_observed(&mut ode, self.t0, &x0, grid, &mut states)?
        } else {
            let mut ode = BalanceOde {
                system,
                prepared: prepared(system),
                inputs,
                project,
                start_inertia: inertia_diagonal(system, self.t0, &x0),
            };
            let v0 = extend::<S>(&x0)?;
            let mut states = States {
                driver: &mut driver,
                split: split::<S>,
            };
            integrator.integrate_observed(&mut ode, self.t0, &v0, grid, &mut states)?
        };
        let mut summary = driver.finish(stats)?;
        summary.symmetric_not_reversible = integrator.symmetric() && !S::REVERSIBLE;
        Ok(summary)
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
        let q0 = S::coordinates_of(&self.x0);
        self.system.check_configuration(self.t0, &q0)?;
        // A start off the holonomic constraints is a state no motion passes through (and
        // its projection would silently move it). A constraint that is not a number there
        // is left to the first evaluation, which names the state as outside the geometry.
        let residual = self.system.holonomic_residual(self.t0, &q0);
        if residual.as_ref().iter().all(|f| f.is_finite()) {
            assembly::check(self.system, self.t0, &q0)?;
        }
        let mut x0 = self.x0;
        if self.project {
            let t0 = self.t0;
            project_coordinates(self.system, t0, x0.as_mut(), || S::named_state(&self.x0))?;
        }
        Ok(x0)
    }
}
