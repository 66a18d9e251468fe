//! Modes followed along a parameter: which eigenvalue at one step is which at the next.
//!
//! [`Linearization::modes`](crate::Linearization::modes) lists a linearization's modes least
//! stable first. Along a parameter — a speed, a stiffness — that order changes whenever two
//! real parts cross, so "the first mode" at one speed and at the next can be different
//! motions. A [`ModeTracker`] matches each step's modes to the previous step's by the
//! continuity of their eigenvectors instead, and keeps each motion on a [`ModeBranch`] of its
//! own; [`track_modes`] does it for a whole sweep.
//!
//! The matching, step to step: for every pair of a previous mode u and a new mode v, the
//! similarity |⟨u, v⟩| / (‖u‖ ‖v‖) — 1 for the same direction, whatever the scale or phase
//! of either vector. The pair with the largest similarity is matched first, then the
//! largest among the modes left, and so on. Similarities within [`TRACKING_TIE_TOLERANCE`] of the
//! largest count as equal, and among those the pair whose eigenvalues are closest wins (then
//! the earlier modes, so that the result never depends on rounding). Ties are not rare: a
//! real eigenvector is exactly as similar to a complex vector as to its conjugate, so a real
//! pair that merges into a complex one, or a complex pair whose vectors are nearly real, is
//! told apart by the eigenvalues alone.
//!
//! The steps must be close enough that each mode's vector changes less between them than
//! the vectors of different modes differ. [`ModeTracker::push`] returns the weakest
//! similarity of its matching, which says how safe it was: near 1, each mode found itself;
//! well below it, a finer step there would be safer.
//!
//! ```
//! use hamel_runtime::{Error, Linearization, Mode, track_modes};
//! use nalgebra::DMatrix;
//!
//! // Two uncoupled states whose eigenvalues p and 0.95 − p cross at p = 0.475.
//! let modes = |p: f64| -> Result<Vec<Mode>, Error> {
//!     let a = DMatrix::from_row_slice(2, 2, &[p, 0.0, 0.0, 0.95 - p]);
//!     Linearization::new(&["x", "y"], &[], a, DMatrix::zeros(2, 0))?.modes()
//! };
//! let steps = (0..=10)
//!     .map(|i| {
//!         let p = 0.1 * f64::from(i);
//!         Ok((p, modes(p)?))
//!     })
//!     .collect::<Result<Vec<_>, Error>>()?;
//! // Sorted least stable first, the first mode is y's below the crossing and x's above it.
//! assert_eq!(steps[0].1[0].component("y")?.re, 1.0);
//! assert_eq!(steps[10].1[0].component("x")?.re, 1.0);
//!
//! // Tracked, each branch keeps its state: the first is y's throughout, its eigenvalue
//! // 0.95 − p.
//! let branches = track_modes(steps)?;
//! let y = &branches[0];
//! assert!(y.modes().iter().all(|m| m.component("y").unwrap().re == 1.0));
//! let values: Vec<f64> = y.eigenvalues().map(|l| l.re).collect();
//! assert!((values[0] - 0.95).abs() < 1e-12 && (values[10] + 0.05).abs() < 1e-12);
//! # Ok::<(), Error>(())
//! ```

use nalgebra::Complex;

use crate::error::Error;
use crate::modes::Mode;

/// Similarities closer than this count as equal (see the [module's documentation](self)),
/// and the eigenvalues decide: well above the rounding of eigenvectors from nalgebra's
/// decompositions (a few 10⁻¹⁶ relative, more near repeated eigenvalues), well below the
/// change of a vector over any step a tracker can follow.
pub const TRACKING_TIE_TOLERANCE: f64 = 1e-9;

/// One mode followed along a parameter: its parameter values and its mode at each.
#[derive(Clone, Debug, PartialEq)]
pub struct ModeBranch {
    parameters: Vec<f64>,
    modes: Vec<Mode>,
}

impl ModeBranch {
    /// The parameter at each step, in the order the steps were given.
    pub fn parameters(&self) -> &[f64] {
        &self.parameters
    }

    /// The branch's mode at each step.
    pub fn modes(&self) -> &[Mode] {
        &self.modes
    }

    /// The branch's eigenvalue at each step.
    pub fn eigenvalues(&self) -> impl Iterator<Item = Complex<f64>> + '_ {
        self.modes.iter().map(|m| m.value)
    }

    /// The number of steps.
    pub fn len(&self) -> usize {
        self.modes.len()
    }

    /// Whether the branch has no step yet.
    pub fn is_empty(&self) -> bool {
        self.modes.is_empty()
    }

    /// The mode at the step whose parameter is nearest `parameter` (the first of equally
    /// near ones); `None` for an empty branch or a NaN parameter.
    pub fn nearest(&self, parameter: f64) -> Option<(f64, &Mode)> {
        let distance = |p: f64| (p - parameter).abs();
        let i = (0..self.len())
            .filter(|&i| !distance(self.parameters[i]).is_nan())
            .min_by(|&i, &j| {
                distance(self.parameters[i]).total_cmp(&distance(self.parameters[j]))
            })?;
        Some((self.parameters[i], &self.modes[i]))
    }
}

/// Follows the modes of a sequence of linearizations along a parameter, one step at a
/// time (see the [module's documentation](self)). The first step starts one [`ModeBranch`] per
/// mode, in its order; every later step extends each branch by the mode matched to it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ModeTracker {
    branches: Vec<ModeBranch>,
    steps: usize,
}

impl ModeTracker {
    /// A tracker with no step yet.
    pub fn new() -> Self {
        ModeTracker::default()
    }

    /// Adds the modes at the next parameter value and returns the weakest similarity among
    /// the matches (1 for the first step, or for steps without modes): how safely each mode
    /// was told from the others.
    ///
    /// Errors, leaving the tracker as it was: [`Error::InvalidSetting`] for a parameter or a
    /// mode (eigenvalue or vector component) that is not a finite number;
    /// [`Error::DimensionMismatch`] for a step with another number of modes than the first,
    /// or modes whose vectors are of other states.
    pub fn push(&mut self, parameter: f64, modes: Vec<Mode>) -> Result<f64, Error> {
        self.check(parameter, &modes)?;
        self.steps += 1;
        if self.steps == 1 {
            self.branches = modes
                .into_iter()
                .map(|mode| ModeBranch {
                    parameters: vec![parameter],
                    modes: vec![mode],
                })
                .collect();
            return Ok(1.0);
        }
        let previous: Vec<&Mode> = self
            .branches
            .iter()
            .filter_map(|b| b.modes.last())
            .collect();
        let (matching, weakest) = match_modes(&previous, &modes);
        let mut modes: Vec<Option<Mode>> = modes.into_iter().map(Some).collect();
        for (branch, new) in self.branches.iter_mut().zip(matching) {
            if let Some(mode) = modes[new].take() {
                branch.parameters.push(parameter);
                branch.modes.push(mode);
            }
        }
        Ok(weakest)
    }

    /// The branches so far, in the order of the first step's modes.
    pub fn branches(&self) -> &[ModeBranch] {
        &self.branches
    }

    /// The branches, in the order of the first step's modes.
    pub fn into_branches(self) -> Vec<ModeBranch> {
        self.branches
    }

    /// A step that can be matched to the steps before: a finite parameter, finite modes, as
    /// many as before, with vectors of the same states.
    fn check(&self, parameter: f64, modes: &[Mode]) -> Result<(), Error> {
        if !parameter.is_finite() {
            return Err(Error::InvalidSetting {
                name: "the tracked parameter",
                value: parameter,
                reason: "each step's parameter must be a finite number",
            });
        }
        let finite = |c: &Complex<f64>| c.re.is_finite() && c.im.is_finite();
        for mode in modes {
            let bad = std::iter::once(&mode.value)
                .chain(mode.vector.iter().map(|(_, c)| c))
                .find(|c| !finite(c));
            if let Some(c) = bad {
                return Err(Error::InvalidSetting {
                    name: "a tracked mode",
                    value: if c.re.is_finite() { c.im } else { c.re },
                    reason: "eigenvalues and eigenvector components must be finite numbers",
                });
            }
        }
        let names = |m: &Mode| m.vector.iter().map(|(n, _)| n.clone()).collect::<Vec<_>>();
        let reference = self
            .branches
            .first()
            .and_then(|b| b.modes.first())
            .or(modes.first())
            .map(names)
            .unwrap_or_default();
        if let Some(m) = modes.iter().find(|m| names(m) != reference) {
            return Err(Error::DimensionMismatch {
                what: format!(
                    "a mode at parameter {parameter} has a vector of the states ({}), the \
                     others of ({}): the modes tracked must be of the same linearization's \
                     states",
                    names(m).join(", "),
                    reference.join(", ")
                ),
            });
        }
        let before = self.branches.len();
        if self.steps > 0 && modes.len() != before {
            return Err(Error::DimensionMismatch {
                what: format!(
                    "{} modes at parameter {parameter}, {before} at the steps before: every \
                     step needs one mode per branch",
                    modes.len()
                ),
            });
        }
        Ok(())
    }
}

/// Follows the modes of `steps`, each a parameter value and the modes of the linearization
/// there, in order: one [`ModeBranch`] per mode of the first step, in its order. See the
/// [module's documentation](self) for how modes are matched, and [`ModeTracker::push`] for
/// the errors (a step that fails names its parameter).
pub fn track_modes(
    steps: impl IntoIterator<Item = (f64, Vec<Mode>)>,
) -> Result<Vec<ModeBranch>, Error> {
    let mut tracker = ModeTracker::new();
    for (parameter, modes) in steps {
        tracker.push(parameter, modes)?;
    }
    Ok(tracker.into_branches())
}

/// |⟨u, v⟩| / (‖u‖ ‖v‖): 1 when the vectors are parallel, whatever their complex scale.
fn similarity(u: &Mode, v: &Mode) -> f64 {
    let (mut dot, mut uu, mut vv) = (Complex::new(0.0, 0.0), 0.0, 0.0);
    for ((_, a), (_, b)) in u.vector.iter().zip(&v.vector) {
        dot += a.conj() * b;
        uu += a.norm_sqr();
        vv += b.norm_sqr();
    }
    let norms = (uu * vv).sqrt();
    if norms > 0.0 { dot.norm() / norms } else { 0.0 }
}

/// For each previous mode, the index of the new mode matched to it, greedily by similarity
/// (ties by eigenvalue distance, then by order), and the weakest similarity matched.
fn match_modes(previous: &[&Mode], new: &[Mode]) -> (Vec<usize>, f64) {
    let n = previous.len();
    let scores: Vec<Vec<f64>> = previous
        .iter()
        .map(|u| new.iter().map(|v| similarity(u, v)).collect())
        .collect();
    let (mut taken_old, mut taken_new) = (vec![false; n], vec![false; n]);
    let mut matching = vec![0; n];
    let mut weakest = 1.0f64;
    for _ in 0..n {
        let open = || {
            (0..n)
                .filter(|&i| !taken_old[i])
                .flat_map(|i| (0..n).filter(|&j| !taken_new[j]).map(move |j| (i, j)))
        };
        let best = open()
            .map(|(i, j)| scores[i][j])
            .fold(f64::NEG_INFINITY, f64::max);
        let distance = |(i, j): (usize, usize)| (previous[i].value - new[j].value).norm();
        let Some((i, j)) = open()
            .filter(|&(i, j)| scores[i][j] >= best - TRACKING_TIE_TOLERANCE)
            .min_by(|&a, &b| distance(a).total_cmp(&distance(b)))
        else {
            break;
        };
        taken_old[i] = true;
        taken_new[j] = true;
        matching[i] = j;
        weakest = weakest.min(scores[i][j]);
    }
    (matching, weakest)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Linearization;
    use nalgebra::DMatrix;

    fn modes_of(a: &[f64], states: &[&str]) -> Vec<Mode> {
        let s = states.len();
        Linearization::new(
            states,
            &[],
            DMatrix::from_row_slice(s, s, a),
            DMatrix::zeros(s, 0),
        )
        .unwrap()
        .modes()
        .unwrap()
    }

    /// A damped oscillator ẍ + c ẋ + x = 0 beside a real mode −r: as c grows from 0 to 3 the
    /// oscillator's complex pair meets on the real axis at c = 2 and splits into two real
    /// modes, one of which crosses −r; the real mode's vector (z) never changes.
    fn oscillator(c: f64, r: f64) -> Vec<Mode> {
        modes_of(
            &[0.0, 1.0, 0.0, -1.0, -c, 0.0, 0.0, 0.0, -r],
            &["x", "v", "z"],
        )
    }

    #[test]
    fn a_mode_keeps_its_vector_where_sorting_would_swap_it() {
        let steps: Vec<(f64, Vec<Mode>)> = (0..=300)
            .map(|i| {
                let c = f64::from(i) * 0.01;
                (c, oscillator(c, 0.45))
            })
            .collect();
        let branches = track_modes(steps.clone()).unwrap();
        assert_eq!(branches.len(), 3);
        // The real mode −0.45 is last (least stable first) at c = 0, where the oscillator's
        // modes have real part 0; it stays on its branch, its vector along z, throughout.
        let z = branches
            .iter()
            .find(|b| (b.modes()[0].component("z").unwrap().norm() - 1.0).abs() < 1e-12)
            .unwrap();
        for mode in z.modes() {
            assert!((mode.value - Complex::new(-0.45, 0.0)).norm() < 1e-12);
            assert!((mode.component("z").unwrap() - Complex::new(1.0, 0.0)).norm() < 1e-12);
        }
        assert_eq!(z.parameters().len(), 301);
        // The oscillator's two branches: a conjugate pair up to c = 2 (λ = −c/2 ± i√(1 − c²/4)),
        // then the two real roots (−c ± √(c² − 4))/2, each continuing one of the pair.
        let others: Vec<&ModeBranch> = branches.iter().filter(|b| !std::ptr::eq(*b, z)).collect();
        for (k, (c, _)) in steps.iter().enumerate() {
            let mut values: Vec<Complex<f64>> = others.iter().map(|b| b.modes()[k].value).collect();
            let disc = c * c - 4.0;
            let expected = if disc < 0.0 {
                [
                    Complex::new(-c / 2.0, (-disc).sqrt() / 2.0),
                    Complex::new(-c / 2.0, -(-disc).sqrt() / 2.0),
                ]
            } else {
                [
                    Complex::new((-c + disc.sqrt()) / 2.0, 0.0),
                    Complex::new((-c - disc.sqrt()) / 2.0, 0.0),
                ]
            };
            values.sort_by(|a, b| b.re.total_cmp(&a.re).then(b.im.total_cmp(&a.im)));
            for (got, want) in values.iter().zip(expected) {
                assert!(
                    (got - want).norm() < 1e-6,
                    "at c = {c}: {got} against {want}"
                );
            }
        }
        // Past c = 2 each oscillator branch is real and moves monotonically: the slow root
        // rises towards 0, the fast one falls, and the slow one crosses −0.45 (at c = 0.45 + 1/0.45)
        // without taking the real mode's branch.
        let last: Vec<f64> = others.iter().map(|b| b.modes()[300].value.re).collect();
        assert!(last.iter().any(|&v| v > -0.45) && last.iter().any(|&v| v < -2.0));
        for b in &others {
            let re: Vec<f64> = b.eigenvalues().skip(201).map(|l| l.re).collect();
            let rising = re[1] > re[0];
            assert!(
                re.windows(2).all(|w| (w[1] > w[0]) == rising),
                "monotonic past the split"
            );
        }
    }

    #[test]
    fn a_conjugate_pair_keeps_its_signs() {
        // ẍ + 0.2 ẋ + ω² x = 0 with ω from 1 to 3: the upper eigenvalue stays upper.
        let steps = (0..=40).map(|i| {
            let w = 1.0 + 0.05 * f64::from(i);
            (w, modes_of(&[0.0, 1.0, -w * w, -0.2], &["x", "v"]))
        });
        let branches = track_modes(steps).unwrap();
        assert!(branches[0].eigenvalues().all(|l| l.im > 0.0));
        assert!(branches[1].eigenvalues().all(|l| l.im < 0.0));
        let (p, mode) = branches[0].nearest(2.02).unwrap();
        assert_eq!(p, 2.0);
        assert!((mode.value.im - (4.0f64 - 0.01).sqrt()).abs() < 1e-12);
    }

    #[test]
    fn the_weakest_similarity_says_how_safe_a_step_was() {
        let mut tracker = ModeTracker::new();
        assert_eq!(tracker.push(0.0, oscillator(0.5, 3.0)).unwrap(), 1.0);
        let small = tracker.push(0.01, oscillator(0.51, 3.0)).unwrap();
        assert!(small > 0.999_99, "{small}");
        let large = tracker.push(2.0, oscillator(2.5, 3.0)).unwrap();
        assert!(large < 0.99, "{large}");
        assert_eq!(tracker.branches()[0].len(), 3);
    }

    #[test]
    fn steps_that_cannot_be_matched_are_errors_and_change_nothing() {
        let mut tracker = ModeTracker::new();
        tracker.push(0.0, oscillator(0.5, 3.0)).unwrap();
        let err = tracker.push(f64::NAN, oscillator(0.5, 3.0)).unwrap_err();
        assert!(matches!(
            err,
            Error::InvalidSetting {
                name: "the tracked parameter",
                ..
            }
        ));
        let two = modes_of(&[0.0, 1.0, -1.0, -0.2], &["x", "v"]);
        let err = tracker.push(0.1, two).unwrap_err();
        assert!(err.to_string().contains("states (x, v)"), "{err}");
        let other = modes_of(
            &[0.0, 1.0, 0.0, -1.0, -0.5, 0.0, 0.0, 0.0, -3.0],
            &["a", "b", "c"],
        );
        let err = tracker.push(0.1, other).unwrap_err();
        assert!(err.to_string().contains("(a, b, c)"), "{err}");
        let mut bad = oscillator(0.5, 3.0);
        bad[0].vector[1].1 = Complex::new(f64::INFINITY, 0.0);
        assert!(matches!(
            tracker.push(0.1, bad),
            Err(Error::InvalidSetting { .. })
        ));
        assert_eq!(tracker.branches()[0].len(), 1);
        assert!(track_modes(Vec::new()).unwrap().is_empty());
    }
}
