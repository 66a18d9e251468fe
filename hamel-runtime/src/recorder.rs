//! Recording a simulation's samples into a [`Sink`] with the monitors of its [`Summary`]: the
//! constraint and holonomic residuals, the energy drift and the energy balance. Everything
//! here runs at the samples only, never at the integrator's stages.

use crate::error::{Error, Singularity};
use crate::events::{EventRecord, StateFunction};
use crate::integrate::Stats;
use crate::sink::Sink;
use crate::system::HamelSystem;
use crate::system_ode::RunInputs;
use crate::trajectory::{EnergyScale, Stopped, Summary};
use crate::vector::Vector;

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

    /// The outputs' names must be usable as column names: not empty, without a CSV
    /// separator, quote or line break, and none repeated or already a column of the run.
    pub fn check(&self) -> Result<(), Error> {
        let names = self.names();
        for output in self.outputs {
            let name = output.name.as_str();
            let reason = if name.is_empty() {
                Some("a column needs a name")
            } else if name.contains([',', '"', '\n', '\r']) {
                Some("a column name may not contain a comma, a quote or a line break (CSV)")
            } else if name.trim() != name {
                Some("a column name may not begin or end with white space")
            } else {
                None
            };
            if let Some(reason) = reason {
                return Err(Error::InvalidColumnName {
                    kind: "output",
                    name: name.to_string(),
                    reason,
                });
            }
            if names.iter().filter(|n| *n == name).count() > 1 {
                return Err(Error::DuplicateName {
                    kind: "column",
                    name: name.to_string(),
                    context: "an output's name must differ from the other outputs' and from \
                              the columns every run records (t, the state, the inputs, energy, \
                              energy_balance, lambda_<constraint>)",
                });
            }
        }
        Ok(())
    }
}

/// The inputs u must be finite: the first that is not is named, with the time and state.
/// Called at every stage, so the check is inline and the error built out of line.
#[inline]
pub(crate) fn check_inputs<S: HamelSystem>(
    u: &S::Inputs,
    t: f64,
    x: &S::State,
) -> Result<(), Error> {
    if u.as_ref().iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(non_finite_input::<S>(u, t, x))
    }
}

#[cold]
#[inline(never)]
fn non_finite_input<S: HamelSystem>(u: &S::Inputs, t: f64, x: &S::State) -> Error {
    let i = u.as_ref().iter().position(|v| !v.is_finite()).unwrap_or(0);
    Error::NonFiniteInput {
        name: S::INPUTS
            .get(i)
            .map_or_else(|| format!("u{i}"), |n| (*n).to_string()),
        value: u.as_ref()[i],
        t,
        state: S::named_state(x),
    }
}

/// Records the samples and keeps the monitors' running maxima.
pub(crate) struct Recorder<'a, 's, S: HamelSystem, F> {
    system: &'s S,
    inputs: &'a RunInputs<S, F>,
    columns: Columns<'a, 's, S>,
    sink: &'a mut dyn Sink,
    summary: Summary,
    /// max |W| so far, for the scale of the relative energy balance.
    max_work: f64,
    /// The largest kinetic energy T₂ so far (conservative systems only): the scale of a
    /// drift whose E₀ is small beside the motion.
    max_kinetic: f64,
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
        inputs: &'a RunInputs<S, F>,
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
            max_kinetic: 0.0,
            row: Vec::with_capacity(names.len()),
        })
    }

    /// Records the state x at time t, with the work W done on the system since the first
    /// sample (0 for a conservative system).
    pub fn record(&mut self, t: f64, x: &S::State, work: f64) -> Result<(), Error> {
        let at = |s: Singularity| S::singular(s, t, x);
        let system = self.system;
        let u = self.inputs.at(t, x)?;
        let energy = system.energy(t, x).map_err(at)?;
        let q = S::coordinates_of(x);
        let qd = system.generalized_velocities(t, x).map_err(at)?;
        let residual = system.constraint_residual(t, &q, &qd);
        let holonomic = system.holonomic_residual(t, &q);
        if S::CONSERVATIVE {
            self.max_kinetic = nan_max(self.max_kinetic, kinetic_energy(system, t, x, energy)?);
        }

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
            let lambda = system.multipliers(t, x, &u).map_err(at)?;
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
        summary.work = work;
        let balance = energy - e0 - work;
        summary.max_energy_balance = nan_max(summary.max_energy_balance, balance.abs());
    }

    /// The scale of the energy monitors and the drift and balance relative to it, from the
    /// running maxima: formed once, when the run is over (they depend on the maxima alone, so
    /// this is what the last sample would have made of them).
    fn relative_energy(&mut self) {
        let summary = &mut self.summary;
        if summary.samples == 0 {
            return;
        }
        let e0 = summary.initial_energy;
        summary.energy_scale = if S::CONSERVATIVE {
            EnergyScale::conservative(e0, self.max_kinetic)
        } else {
            EnergyScale::forced(e0, summary.max_energy_drift, self.max_work)
        };
        let scale = summary.energy_scale.value().max(f64::MIN_POSITIVE);
        summary.relative_energy_drift = summary.max_energy_drift / scale;
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
    pub fn finish(mut self, stats: Stats) -> Result<Summary, Error> {
        self.sink.end()?;
        self.relative_energy();
        let mut summary = self.summary;
        summary.steps = stats.steps;
        summary.rejected = stats.rejected;
        summary.evaluations = stats.evaluations;
        Ok(summary)
    }
}

/// T₂ = E(q, s) − E(q, 0), the energy of the motion with speeds s above that of the same
/// configuration at rest: for a conservative system, whose rows have no affine part, the
/// kinetic energy quadratic in the velocities, ½ sᵀM s (E = T₂ − T₀ + V).
fn kinetic_energy<S: HamelSystem>(
    system: &S,
    t: f64,
    x: &S::State,
    energy: f64,
) -> Result<f64, Error> {
    let mut at_rest = *x;
    at_rest.as_mut()[S::Coordinates::LEN..].fill(0.0);
    let resting = system
        .energy(t, &at_rest)
        .map_err(|s| S::singular(s, t, x))?;
    Ok(energy - resting)
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
