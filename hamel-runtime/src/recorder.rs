//! Recording a simulation's samples with the monitors of its [`Summary`]: the constraint and
//! holonomic residuals, the energy drift and the energy balance.

use crate::error::{Error, Singularity};
use crate::integrate::Stats;
use crate::system::HamelSystem;
use crate::trajectory::{Summary, Trajectory};

/// Records the samples and keeps the monitors' running maxima.
pub(crate) struct Recorder<'s, S> {
    system: &'s S,
    trajectory: Trajectory,
    /// max |W| so far, for the scale of the relative energy balance.
    max_work: f64,
}

impl<'s, S: HamelSystem> Recorder<'s, S> {
    /// An empty recording with the columns t, the state, `energy` and, for a system that is
    /// not conservative, `energy_balance`.
    pub fn new(system: &'s S) -> Self {
        let balance: &[&str] = if S::CONSERVATIVE {
            &[]
        } else {
            &["energy_balance"]
        };
        let names = ["t"]
            .iter()
            .chain(S::STATE)
            .chain(&["energy"])
            .chain(balance)
            .map(|n| (*n).to_string())
            .collect();
        let summary = Summary {
            steps: 0,
            rejected: 0,
            evaluations: 0,
            samples: 0,
            max_constraint_residual: 0.0,
            initial_energy: f64::NAN,
            max_energy_drift: 0.0,
            relative_energy_drift: 0.0,
            conservative: S::CONSERVATIVE,
            holonomic_constraints: S::K,
            max_holonomic_residual: 0.0,
            work: 0.0,
            max_energy_balance: 0.0,
            relative_energy_balance: 0.0,
        };
        Recorder {
            system,
            trajectory: Trajectory::new(names, summary),
            max_work: 0.0,
        }
    }

    /// Records the state x at time t, with the work W done on the system since the first
    /// sample (0 for a conservative system).
    pub fn record(&mut self, t: f64, x: &S::State, work: f64) -> Result<(), Error> {
        let at = |s: Singularity| S::singular(s, t, x);
        let energy = self.system.energy(t, x).map_err(at)?;
        let q = S::coordinates_of(x);
        let qd = self.system.generalized_velocities(t, x).map_err(at)?;
        let residual = self.system.constraint_residual(t, &q, &qd);
        let holonomic = self.system.holonomic_residual(t, &q);

        let first = self.trajectory.is_empty();
        let e0 = if first {
            energy
        } else {
            self.trajectory.summary().initial_energy
        };
        let balance = energy - e0 - work;
        let balance_column: &[f64] = if S::CONSERVATIVE { &[] } else { &[balance] };
        self.trajectory.push(
            core::iter::once(t)
                .chain(x.as_ref().iter().copied())
                .chain([energy])
                .chain(balance_column.iter().copied()),
        );
        self.max_work = nan_max(self.max_work, work.abs());

        let summary = self.trajectory.summary_mut();
        summary.samples += 1;
        summary.initial_energy = e0;
        for r in residual.as_ref() {
            summary.max_constraint_residual = nan_max(summary.max_constraint_residual, r.abs());
        }
        for f in holonomic.as_ref() {
            summary.max_holonomic_residual = nan_max(summary.max_holonomic_residual, f.abs());
        }
        summary.max_energy_drift = nan_max(summary.max_energy_drift, (energy - e0).abs());
        summary.relative_energy_drift = summary.max_energy_drift / e0.abs().max(f64::MIN_POSITIVE);
        summary.work = work;
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
        Ok(())
    }

    /// The recording, with what the integration cost.
    pub fn finish(self, stats: Stats) -> Trajectory {
        let mut trajectory = self.trajectory;
        let summary = trajectory.summary_mut();
        summary.steps = stats.steps;
        summary.rejected = stats.rejected;
        summary.evaluations = stats.evaluations;
        trajectory
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
