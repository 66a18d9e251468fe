//! What a study's row keeps of a run or a linearization: named columns and their values.

use crate::error::Error;
use crate::modes::Mode;
use crate::system::HamelSystem;
use crate::trajectory::{Stopped, Trajectory};

/// The columns a study keeps of each simulation, chosen from its trajectory:
///
/// * [`Self::final_state`]: `final_<state>` for each state component;
/// * [`Self::summary`]: `steps`, `rejected`, `evaluations`, `samples`, `energy_error` (the
///   drift or balance relative to its scale, [`crate::Summary::energy_error`]),
///   `max_constraint_residual`, `max_holonomic_residual`, `singular_crossings` and
///   `stopped_at` (the time a terminal event or a cancel ended the run, NaN if it ran to its
///   end);
/// * [`Self::event`]: `<event>_first` (the time of its first occurrence, NaN if none) and
///   `<event>_count`;
/// * [`Self::sample_at`]: `<column>@<t>` for each of the trajectory's state columns at the
///   sample time t.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Outputs {
    final_state: bool,
    summary: bool,
    events: Vec<String>,
    times: Vec<f64>,
}

/// The summary's columns, in order.
const SUMMARY: [&str; 9] = [
    "steps",
    "rejected",
    "evaluations",
    "samples",
    "energy_error",
    "max_constraint_residual",
    "max_holonomic_residual",
    "singular_crossings",
    "stopped_at",
];

impl Outputs {
    /// Nothing yet.
    pub fn new() -> Self {
        Outputs::default()
    }

    /// The state at the run's last sample.
    pub fn final_state(mut self) -> Self {
        self.final_state = true;
        self
    }

    /// The summary's figures.
    pub fn summary(mut self) -> Self {
        self.summary = true;
        self
    }

    /// The first time and the count of the event called `name`.
    pub fn event(mut self, name: impl Into<String>) -> Self {
        self.events.push(name.into());
        self
    }

    /// The state at sample time `t` (one of the run's sample times: t0 + k·Δ or the end).
    pub fn sample_at(mut self, t: f64) -> Self {
        self.times.push(t);
        self
    }

    /// The column names for a system `S`, in the order of [`Self::values`].
    pub fn names<S: HamelSystem>(&self) -> Vec<String> {
        let mut names = Vec::new();
        if self.final_state {
            names.extend(S::STATE.iter().map(|s| format!("final_{s}")));
        }
        if self.summary {
            names.extend(SUMMARY.iter().map(|s| (*s).to_string()));
        }
        for event in &self.events {
            names.push(format!("{event}_first"));
            names.push(format!("{event}_count"));
        }
        for t in &self.times {
            names.extend(S::STATE.iter().map(|s| format!("{s}@{t}")));
        }
        names
    }

    /// The values of a run of `S`, in the order of [`Self::names`]. A sample time the run
    /// does not have is an error naming it.
    pub fn values<S: HamelSystem>(&self, run: &Trajectory) -> Result<Vec<f64>, Error> {
        let mut values = Vec::new();
        if self.final_state {
            let last = run.len().checked_sub(1).ok_or_else(no_samples)?;
            values.extend(state_at::<S>(run, last)?);
        }
        if self.summary {
            let s = run.summary();
            let stopped_at = match &s.stopped {
                Some(Stopped::Event { t, .. } | Stopped::Cancelled { t }) => *t,
                None => f64::NAN,
            };
            values.extend([
                s.steps as f64,
                s.rejected as f64,
                s.evaluations as f64,
                s.samples as f64,
                s.energy_error(),
                s.max_constraint_residual,
                s.max_holonomic_residual,
                s.singular_crossings.len() as f64,
                stopped_at,
            ]);
        }
        for event in &self.events {
            let times = run.event_times(event);
            values.push(times.first().copied().unwrap_or(f64::NAN));
            values.push(times.len() as f64);
        }
        for &t in &self.times {
            let not_sampled = Error::InvalidSetting {
                name: "sample time",
                value: t,
                reason: "a study can keep the state only at one of the run's sample times",
            };
            let i = run
                .times()
                .iter()
                .position(|s| *s == t)
                .ok_or(not_sampled)?;
            values.extend(state_at::<S>(run, i)?);
        }
        Ok(values)
    }
}

fn no_samples() -> Error {
    Error::DimensionMismatch {
        what: "the run recorded no sample to keep".into(),
    }
}

/// The state components of sample i, by the names of `S`.
fn state_at<S: HamelSystem>(run: &Trajectory, i: usize) -> Result<Vec<f64>, Error> {
    S::STATE
        .iter()
        .map(|name| {
            run.column(name)
                .and_then(|c| c.get(i).copied())
                .ok_or_else(|| Error::UnknownName {
                    kind: "state",
                    name: (*name).to_string(),
                    known: run.names().join(", "),
                })
        })
        .collect()
}

/// The columns a linearization sweep keeps of each case's modes ([`crate::Linearization::
/// modes`], least stable first): `eig<k>_re` and `eig<k>_im` for each eigenvalue, and with
/// [`Self::vectors`] `mode<k>_<state>_re`/`_im` for each eigenvector's named components.
#[derive(Clone, Debug, PartialEq)]
pub struct ModeColumns {
    states: Vec<String>,
    vectors: bool,
}

impl ModeColumns {
    /// The modes of a linearization with these states (after `reduce`, if any).
    pub fn new(states: &[&str]) -> Self {
        ModeColumns {
            states: states.iter().map(|s| (*s).to_string()).collect(),
            vectors: false,
        }
    }

    /// The eigenvectors too, by their components' names.
    pub fn vectors(mut self) -> Self {
        self.vectors = true;
        self
    }

    /// The column names, in the order of [`Self::values`].
    pub fn names(&self) -> Vec<String> {
        let mut names = Vec::new();
        for k in 0..self.states.len() {
            names.push(format!("eig{k}_re"));
            names.push(format!("eig{k}_im"));
        }
        if self.vectors {
            for k in 0..self.states.len() {
                for s in &self.states {
                    names.push(format!("mode{k}_{s}_re"));
                    names.push(format!("mode{k}_{s}_im"));
                }
            }
        }
        names
    }

    /// The values of `modes` (one per state, as `modes()` gives them).
    pub fn values(&self, modes: &[Mode]) -> Result<Vec<f64>, Error> {
        if modes.len() != self.states.len() {
            return Err(Error::DimensionMismatch {
                what: format!("{} modes for {} states", modes.len(), self.states.len()),
            });
        }
        let mut values: Vec<f64> = modes
            .iter()
            .flat_map(|m| [m.value.re, m.value.im])
            .collect();
        if self.vectors {
            for mode in modes {
                for s in &self.states {
                    let c = mode.component(s)?;
                    values.extend([c.re, c.im]);
                }
            }
        }
        Ok(values)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Complex;

    #[test]
    fn mode_columns_name_eigenvalues_and_components() {
        let mode = |re: f64, im: f64| Mode {
            value: Complex::new(re, im),
            vector: vec![
                ("phi".into(), Complex::new(1.0, 0.0)),
                ("delta".into(), Complex::new(0.5, -0.25)),
            ],
        };
        let columns = ModeColumns::new(&["phi", "delta"]).vectors();
        assert_eq!(
            columns.names(),
            [
                "eig0_re",
                "eig0_im",
                "eig1_re",
                "eig1_im",
                "mode0_phi_re",
                "mode0_phi_im",
                "mode0_delta_re",
                "mode0_delta_im",
                "mode1_phi_re",
                "mode1_phi_im",
                "mode1_delta_re",
                "mode1_delta_im"
            ]
        );
        let values = columns.values(&[mode(0.1, 2.0), mode(0.1, -2.0)]).unwrap();
        assert_eq!(values.len(), 12);
        assert_eq!(&values[..6], [0.1, 2.0, 0.1, -2.0, 1.0, 0.0]);
        assert_eq!(&values[6..8], [0.5, -0.25]);
        assert!(columns.values(&[mode(0.0, 0.0)]).is_err());
    }
}
