//! Recording a simulation's samples into a [`Sink`] with the monitors of its [`Summary`]: the
//! constraint and holonomic residuals, the energy drift and the energy balance.

use std::cell::RefCell;

use crate::error::{Error, Singularity};
use crate::events::{EventRecord, StateFunction};
use crate::integrate::Stats;
use crate::sink::Sink;
use crate::system::HamelSystem;
use crate::trajectory::{Stopped, Summary};

/// A named output column computed from the time and state (a contact point's position).
pub struct Output<'s, S: HamelSystem> {
    pub(crate) name: String,
    pub(crate) f: StateFunction<'s, S>,
}

/// What a simulation records besides the time and the state.
pub(crate) struct Columns<'a, 's, S: HamelSystem> {
    /// User outputs.
    pub outputs: &'a [Output<'s, S>],
    /// Whether to record the constraint forces λ.
    pub forces: bool,
}

impl<S: HamelSystem> Columns<'_, '_, S> {
    /// The column names: t, the state, the inputs, the outputs, `energy`, for a system that
    /// is not conservative `energy_balance`, and `lambda_<constraint>` when asked.
    pub fn names(&self) -> Vec<String> {
        let mut names: Vec<String> = ["t"]
            .iter()
            .chain(S::STATE)
            .chain(S::INPUTS)
            .map(|n| (*n).to_string())
            .collect();
        names.extend(self.outputs.iter().map(|o| o.name.clone()));
        names.push("energy".into());
        if !S::CONSERVATIVE {
            names.push("energy_balance".into());
        }
        if self.forces {
            names.extend(S::CONSTRAINTS.iter().map(|c| format!("lambda_{c}")));
        }
        names
    }
}

/// Records the samples and keeps the monitors' running maxima.
pub(crate) struct Recorder<'a, 's, S: HamelSystem, F> {
    system: &'s S,
    inputs: &'a RefCell<F>,
    columns: Columns<'a, 's, S>,
    sink: &'a mut dyn Sink,
    summary: Summary,
    /// max |W| so far, for the scale of the relative energy balance.
    max_work: f64,
    row: Vec<f64>,
}

impl<'a, 's, S, F> Recorder<'a, 's, S, F>
where
    S: HamelSystem,
    F: FnMut(f64, &S::State) -> S::Inputs,
{
    /// A recording into `sink`, whose columns it announces.
    pub fn new(
        system: &'s S,
        inputs: &'a RefCell<F>,
        columns: Columns<'a, 's, S>,
        sink: &'a mut dyn Sink,
    ) -> Result<Self, Error> {
        let names = columns.names();
        sink.begin(&names)?;
        Ok(Recorder {
            system,
            inputs,
            columns,
            sink,
            summary: Summary::new::<S>(),
            max_work: 0.0,
            row: Vec::with_capacity(names.len()),
        })
    }

    /// Records the state x at time t, with the work W done on the system since the first
    /// sample (0 for a conservative system).
    pub fn record(&mut self, t: f64, x: &S::State, work: f64) -> Result<(), Error> {
        let at = |s: Singularity| S::singular(s, t, x);
        let system = self.system;
        let energy = system.energy(t, x).map_err(at)?;
        let q = S::coordinates_of(x);
        let qd = system.generalized_velocities(t, x).map_err(at)?;
        let residual = system.constraint_residual(t, &q, &qd);
        let holonomic = system.holonomic_residual(t, &q);
        let u = (self.inputs.borrow_mut())(t, x);

        let first = self.summary.samples == 0;
        let e0 = if first {
            energy
        } else {
            self.summary.initial_energy
        };
        let balance = energy - e0 - work;
        self.row.clear();
        self.row.push(t);
        self.row.extend_from_slice(x.as_ref());
        self.row.extend_from_slice(u.as_ref());
        for output in self.columns.outputs {
            self.row.push((output.f)(t, x));
        }
        self.row.push(energy);
        if !S::CONSERVATIVE {
            self.row.push(balance);
        }
        if self.columns.forces {
            let lambda = system.constraint_forces(t, x, &u).map_err(at)?;
            self.row.extend_from_slice(lambda.as_ref());
        }
        self.sink.row(&self.row)?;
        self.max_work = nan_max(self.max_work, work.abs());
        self.monitor(e0, energy, work, residual.as_ref(), holonomic.as_ref());
        Ok(())
    }

    /// The summary's running maxima after a sample.
    fn monitor(&mut self, e0: f64, energy: f64, work: f64, residual: &[f64], holonomic: &[f64]) {
        let summary = &mut self.summary;
        summary.samples += 1;
        summary.initial_energy = e0;
        for r in residual {
            summary.max_constraint_residual = nan_max(summary.max_constraint_residual, r.abs());
        }
        for f in holonomic {
            summary.max_holonomic_residual = nan_max(summary.max_holonomic_residual, f.abs());
        }
        summary.max_energy_drift = nan_max(summary.max_energy_drift, (energy - e0).abs());
        summary.relative_energy_drift = summary.max_energy_drift / e0.abs().max(f64::MIN_POSITIVE);
        summary.work = work;
        let balance = energy - e0 - work;
        summary.max_energy_balance = nan_max(summary.max_energy_balance, balance.abs());
        // The energies that take part in the balance: E₀, the change E − E₀ and the work W.
        // E₀ alone would not do: it may be 0 (a body at rest set moving by its inputs), and
        // the balance is a difference of the other two.
        let scale = e0
            .abs()
            .max(summary.max_energy_drift)
            .max(self.max_work)
            .max(f64::MIN_POSITIVE);
        summary.relative_energy_balance = summary.max_energy_balance / scale;
    }

    /// An event, passed on to the sink.
    pub fn event(&mut self, event: &EventRecord) -> Result<(), Error> {
        if event.terminal {
            self.summary.stopped = Some(Stopped::Event {
                name: event.name.clone(),
                t: event.t,
            });
        }
        self.sink.event(event)
    }

    /// A run cancelled by its progress callback at t.
    pub fn cancelled(&mut self, t: f64) {
        self.summary.stopped = Some(Stopped::Cancelled { t });
    }

    /// The summary, with what the integration cost; the sink is told the run is over.
    pub fn finish(self, stats: Stats) -> Result<Summary, Error> {
        self.sink.end()?;
        let mut summary = self.summary;
        summary.steps = stats.steps;
        summary.rejected = stats.rejected;
        summary.evaluations = stats.evaluations;
        Ok(summary)
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
