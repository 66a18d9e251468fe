//! Stability along a parameter: the modes of a linearization followed along a sweep of one
//! parameter (a speed, a stiffness) by the continuity of their eigenvectors
//! ([`crate::tracking`]), the parameter values where a mode's real part crosses zero, found
//! by Brent's method ([`crate::roots::brent`]) to [`CROSSING_TOLERANCE`], and the ranges of
//! the parameter where every mode decays. A [`ModeSweep`] also gives its eigenvalues against
//! the parameter as a `Table` (feature `ensemble`) with the modes' names (and
//! `hamel::plot::modes_figure` draws them).
//!
//! A crossing is located on the mode itself, not on the largest real part: between two steps
//! of the sweep, the mode at a parameter p is the one that matches the mode at the step below
//! (as [`crate::ModeTracker`] matches steps), and its real part is the function whose root
//! Brent's method finds. A mode's real part that jumps between two steps — the sweep too
//! coarse for the tracker to follow it there — is an error ([`Error::RootNotFound`]), never a
//! crossing placed at the jump. A mode that crosses zero and back between two steps is not
//! seen: the sweep must be fine enough to resolve what it is asked to find.
//!
//! ```
//! use hamel_runtime::{Error, Linearization, ModeSweep};
//! use nalgebra::DMatrix;
//!
//! // ẍ − (p − 1) ẋ + x = 0 beside ż = (p − 2) z: the oscillator grows for p > 1, the real
//! // mode for p > 2, so the system is stable for p < 1 only.
//! let linearize = |p: f64| {
//!     let a = DMatrix::from_row_slice(3, 3, &[0.0, 1.0, 0.0, -1.0, p - 1.0, 0.0, 0.0, 0.0, p - 2.0]);
//!     Linearization::new(&["x", "v", "z"], &[], a, DMatrix::zeros(3, 0))
//! };
//! let steps = (0..=30).map(|i| 0.1 * f64::from(i));
//! let sweep = ModeSweep::track("p", steps, &linearize)?;
//! let crossings = sweep.crossings(&linearize)?;
//! // The oscillator's pair crosses at p = 1 (both branches), the real mode at p = 2.
//! assert_eq!(crossings.len(), 3);
//! assert!((crossings[0].parameter - 1.0).abs() < 1e-12 && crossings[0].destabilizing);
//! assert!((crossings[2].parameter - 2.0).abs() < 1e-12);
//! let stable = sweep.stable_ranges(&linearize)?;
//! assert_eq!(stable.len(), 1);
//! assert!(stable[0].opens.is_none() && (stable[0].end - 1.0).abs() < 1e-12);
//! # Ok::<(), Error>(())
//! ```

use nalgebra::Complex;

#[cfg(feature = "ensemble")]
use crate::ensemble::Table;
use crate::error::Error;
use crate::linearization::Linearization;
use crate::modes::Mode;
use crate::roots::brent;
use crate::tracking::{ModeBranch, ModeTracker};

/// How close to the parameter where a mode's real part is zero a crossing is located
/// (absolute, in the parameter's unit): Brent's method stops within this, the result is
/// within 10⁻¹² of the crossing.
pub const CROSSING_TOLERANCE: f64 = 1e-13;

/// A located root is a crossing only if the mode's real part there is this small relative
/// to the largest |λ| (or 1): far above the rounding of a root found to
/// [`CROSSING_TOLERANCE`], far below any jump from one mode to another.
const CROSSING_RESIDUAL: f64 = 1e-8;

/// The modes of a linearization at each value of a parameter, each followed along the sweep
/// on a [`ModeBranch`] of its own and named (`mode_1`, `mode_2`, … until named otherwise).
#[derive(Clone, Debug, PartialEq)]
pub struct ModeSweep {
    parameter: String,
    branches: Vec<ModeBranch>,
    names: Vec<String>,
}

/// Where a mode's real part crosses zero.
#[derive(Clone, Debug, PartialEq)]
pub struct Crossing {
    /// The parameter value, within [`CROSSING_TOLERANCE`].
    pub parameter: f64,
    /// The branch (its index in [`ModeSweep::branches`]) and its name.
    pub branch: usize,
    pub name: String,
    /// Whether the mode grows above the crossing (and decays below it).
    pub destabilizing: bool,
    /// |Im λ| at the crossing: the frequency of the motion that starts or stops growing
    /// there (0 for a real mode).
    pub frequency: f64,
}

/// A range of the parameter, within the sweep, where no mode grows (every real part ≤ 0).
#[derive(Clone, Debug, PartialEq)]
pub struct StableRange {
    /// Its ends.
    pub start: f64,
    pub end: f64,
    /// The crossing that opens it; `None` when the sweep's first value is stable already.
    pub opens: Option<Crossing>,
    /// The crossing that closes it; `None` when the sweep's last value is still stable.
    pub closes: Option<Crossing>,
}

impl ModeSweep {
    /// The modes of `linearize(p)` at each `p` of `values` (in the order given, typically
    /// increasing), followed by [`crate::track_modes`]; `parameter` names the parameter in
    /// tables and errors. A linearization that fails is the error, naming its parameter.
    pub fn track<F>(
        parameter: &str,
        values: impl IntoIterator<Item = f64>,
        linearize: &F,
    ) -> Result<ModeSweep, Error>
    where
        F: Fn(f64) -> Result<Linearization, Error>,
    {
        let mut tracker = ModeTracker::new();
        for p in values {
            tracker.push(p, linearize(p)?.modes()?)?;
        }
        Ok(ModeSweep::from_branches(parameter, tracker.into_branches()))
    }

    /// A sweep of branches tracked already ([`crate::track_modes`]).
    pub fn from_branches(parameter: &str, branches: Vec<ModeBranch>) -> ModeSweep {
        let names = (1..=branches.len()).map(|k| format!("mode_{k}")).collect();
        ModeSweep {
            parameter: parameter.to_string(),
            branches,
            names,
        }
    }

    /// Names branch `branch` (a conjugate pair's two branches may share a name); an index
    /// beyond the branches is an error.
    pub fn name(mut self, branch: usize, name: &str) -> Result<ModeSweep, Error> {
        let count = self.branches.len();
        let slot = self
            .names
            .get_mut(branch)
            .ok_or_else(|| Error::DimensionMismatch {
                what: format!("branch {branch} named `{name}` in a sweep of {count} branches"),
            })?;
        *slot = name.to_string();
        Ok(self)
    }

    /// The parameter's name.
    pub fn parameter(&self) -> &str {
        &self.parameter
    }

    /// The parameter's values, in the sweep's order.
    pub fn values(&self) -> &[f64] {
        self.branches.first().map_or(&[], |b| b.parameters())
    }

    /// The branches, in the order of the first step's modes (least stable first).
    pub fn branches(&self) -> &[ModeBranch] {
        &self.branches
    }

    /// Each branch's name.
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// The first branch called `name`.
    pub fn branch(&self, name: &str) -> Option<&ModeBranch> {
        let k = self.names.iter().position(|n| n == name)?;
        self.branches.get(k)
    }

    /// Every crossing of every branch, by parameter (a conjugate pair's two branches each
    /// have theirs); `linearize` must be the function the sweep was tracked with.
    pub fn crossings<F>(&self, linearize: &F) -> Result<Vec<Crossing>, Error>
    where
        F: Fn(f64) -> Result<Linearization, Error>,
    {
        let mut all = Vec::new();
        for k in 0..self.branches.len() {
            for i in 0..self.values().len().saturating_sub(1) {
                if self.changes_sign(k, i) {
                    all.push(self.locate(k, i, linearize)?);
                }
            }
        }
        all.sort_by(|a, b| {
            a.parameter
                .total_cmp(&b.parameter)
                .then(a.branch.cmp(&b.branch))
        });
        Ok(all)
    }

    /// The ranges of the sweep where no mode grows, each end located on the mode that
    /// crosses there: of the modes that cross between the two steps around an end, the last
    /// to decay opens a range and the first to grow closes it (what the largest real part
    /// does). `linearize` must be the function the sweep was tracked with.
    pub fn stable_ranges<F>(&self, linearize: &F) -> Result<Vec<StableRange>, Error>
    where
        F: Fn(f64) -> Result<Linearization, Error>,
    {
        let values = self.values();
        let stable: Vec<bool> = (0..values.len())
            .map(|i| self.branches.iter().all(|b| b.modes()[i].value.re <= 0.0))
            .collect();
        let mut ranges = Vec::new();
        let mut i = 0;
        while i < values.len() {
            if !stable[i] {
                i += 1;
                continue;
            }
            let first = i;
            while i + 1 < values.len() && stable[i + 1] {
                i += 1;
            }
            let opens = match first {
                0 => None,
                _ => self.last_of(first - 1, false, linearize)?,
            };
            let closes = match i + 1 < values.len() {
                true => self.last_of(i, true, linearize)?,
                false => None,
            };
            ranges.push(StableRange {
                start: opens.as_ref().map_or(values[first], |c| c.parameter),
                end: closes.as_ref().map_or(values[i], |c| c.parameter),
                opens,
                closes,
            });
            i += 1;
        }
        Ok(ranges)
    }

    /// The eigenvalues against the parameter: a column named after the parameter, then
    /// `<name>_re` and `<name>_im` for each branch (a name shared by several branches numbered,
    /// `weave_1_re`, `weave_2_re`), one row per step. With the feature `ensemble`.
    #[cfg(feature = "ensemble")]
    pub fn table(&self) -> Result<Table, Error> {
        let mut columns = vec![self.parameter.clone()];
        for k in 0..self.branches.len() {
            let label = self.label(k);
            columns.push(format!("{label}_re"));
            columns.push(format!("{label}_im"));
        }
        let mut table = Table::new(columns)?;
        for (i, &p) in self.values().iter().enumerate() {
            let mut row = vec![p];
            for b in &self.branches {
                row.extend([b.modes()[i].value.re, b.modes()[i].value.im]);
            }
            table.push(i as u64, Ok(row))?;
        }
        Ok(table)
    }

    /// Branch k's name, numbered when another branch shares it.
    pub fn label(&self, k: usize) -> String {
        let name = &self.names[k];
        if self.names.iter().filter(|n| *n == name).count() > 1 {
            let number = self.names[..=k].iter().filter(|n| *n == name).count();
            format!("{name}_{number}")
        } else {
            name.clone()
        }
    }

    /// Whether branch k grows at one of steps i and i + 1 and not at the other.
    fn changes_sign(&self, k: usize, i: usize) -> bool {
        let re = |i: usize| self.branches[k].modes()[i].value.re;
        (re(i) > 0.0) != (re(i + 1) > 0.0)
    }

    /// Of the branches that cross between steps i and i + 1 towards growing (`growing`) or
    /// decaying, the crossing that decides the largest real part: the first to grow, or the
    /// last to decay.
    fn last_of<F>(&self, i: usize, growing: bool, linearize: &F) -> Result<Option<Crossing>, Error>
    where
        F: Fn(f64) -> Result<Linearization, Error>,
    {
        let mut found: Option<Crossing> = None;
        for k in 0..self.branches.len() {
            let grows = self.branches[k].modes()[i + 1].value.re > 0.0;
            if !self.changes_sign(k, i) || grows != growing {
                continue;
            }
            let c = self.locate(k, i, linearize)?;
            let better = match &found {
                None => true,
                Some(f) if growing => c.parameter < f.parameter,
                Some(f) => c.parameter > f.parameter,
            };
            if better {
                found = Some(c);
            }
        }
        Ok(found)
    }

    /// The crossing of branch k between steps i and i + 1.
    fn locate<F>(&self, k: usize, i: usize, linearize: &F) -> Result<Crossing, Error>
    where
        F: Fn(f64) -> Result<Linearization, Error>,
    {
        let values = self.values();
        let (a, b) = (values[i], values[i + 1]);
        let reference: Vec<Mode> = self
            .branches
            .iter()
            .map(|br| br.modes()[i].clone())
            .collect();
        let known = |p: f64| {
            [(a, i), (b, i + 1)]
                .into_iter()
                .find(|&(q, _)| q == p)
                .map(|(_, j)| self.branches[k].modes()[j].value)
        };
        let mode_at = |p: f64| -> Result<(Complex<f64>, f64), Error> {
            let modes = linearize(p)?.modes()?;
            let scale = modes.iter().map(|m| m.value.norm()).fold(1.0, f64::max);
            let mut tracker = ModeTracker::new();
            tracker.push(a, reference.clone())?;
            tracker.push(p, modes)?;
            let value = tracker.branches()[k].modes().last().map(|m| m.value);
            Ok((value.unwrap_or(Complex::new(f64::NAN, 0.0)), scale))
        };
        let what = "a tracked mode's real part";
        let root = brent(
            what,
            |p| match known(p) {
                Some(l) => Ok(l.re),
                None => Ok(mode_at(p)?.0.re),
            },
            a,
            b,
            CROSSING_TOLERANCE,
        )?;
        let (value, scale) = match known(root) {
            Some(l) => (l, 1.0f64.max(l.norm())),
            None => mode_at(root)?,
        };
        if value.re.abs() > CROSSING_RESIDUAL * scale {
            return Err(Error::RootNotFound {
                what,
                near: root,
                residual: value.re,
            });
        }
        Ok(Crossing {
            parameter: root,
            branch: k,
            name: self.names[k].clone(),
            destabilizing: self.branches[k].modes()[i + 1].value.re > 0.0,
            frequency: value.im.abs(),
        })
    }
}

#[cfg(test)]
mod tests;
