//! The Jacobian ∂f/∂x an implicit or Rosenbrock method works with: the [`Ode`]'s own
//! ([`Ode::jacobian`]: for a simulation the system's exact one), or forward differences of its
//! right-hand side where it has none.
//!
//! The differences follow the rules scipy's `num_jac` publishes (scipy.integrate, used by its
//! `Radau`, `BDF` and `LSODA`), written here from its documentation: the step of column j is
//! hⱼ = factorⱼ·max(threshold, |xⱼ|), threshold = atol, directed as ẋⱼ points (away from a
//! boundary the solution moves away from), and factorⱼ, √ε at first, is carried from one
//! Jacobian to the next and adapted so that the difference stays well above its rounding
//! (about ε·|f|): a column whose largest difference is below ε^0.875 of the function's scale
//! is tried again with a step ten times larger and the better of the two kept; then factorⱼ
//! grows tenfold where the difference was below ε^0.75 of the scale and shrinks tenfold where
//! it was above ε^0.25, never below 1000ε.
//!
//! Why not Hairer's √(ε·max(10⁻⁵, |xⱼ|)): a step of the state's size alone ignores how small a
//! component may be against its tolerance. On Robertson's problem late in the run, y₂ ≈ 10⁻¹³
//! got steps of 4.7·10⁻¹¹, 200 times y₂ itself: one entry of the Jacobian was off by 10⁻³
//! relative, and y₁ at 4·10¹⁰ came out wrong by 2.6·10⁻³ of its value (scipy's `Radau`, by
//! `num_jac`: 4·10⁻⁷).
//!
//! One exception, in the first Jacobian of a run, at the components at or below the threshold:
//! there `num_jac`'s step is √ε·atol, with no history yet to correct it and no relation to the
//! size at which f changes. An initial state often has components that are exactly zero: HIRES
//! starts with six of its eight, and at atol = 10⁻¹⁰ their steps of 1.5·10⁻¹⁸ vanish in the
//! rows where f is about 1.7: ∂f₁/∂y₂ = 0.43, ∂f₂/∂y₂ = −8.75 and ∂f₁/∂y₃ = 8.32 came out 0
//! (scipy's own `num_jac` gives the same matrix). Its refinement does not see it: the
//! column's largest difference lies in a row where f is zero, whose difference is exact. So
//! such a column is tested against the largest |fᵢ| as well, and where its largest
//! difference is below ε^0.875 of that, it is differenced again by Hairer's step (one more
//! evaluation; the factor carried on stays `num_jac`'s). Radau5 converges on the lost matrix,
//! but slowly enough in y₂ that the error its stopping test allows (up to RADAU5's Newton
//! tolerance, far more than the iteration leaves on an exact Jacobian) is left at every step
//! until the Jacobian is renewed (t ≈ 0.28); it stayed in the slow components to the end, and
//! HIRES by differences came out 5 to 19 times less accurate than with the exact Jacobian at
//! rtol 10⁻⁶…10⁻⁸ for nearly the same steps (`benches/work_precision`, `once HIRES`).

use nalgebra::DMatrix;

use super::{NonFinite, Ode, Stats};
use crate::error::{Error, Num};
use crate::vector::Vector;

/// A difference below this fraction of the function's scale is rounding: the column is tried
/// again with a larger step.
const DIFF_REJECT: f64 = 2.0097183471152322e-14; // ε^0.875
/// Below this fraction the next step grows tenfold.
const DIFF_SMALL: f64 = 1.8189894035458565e-12; // ε^0.75
/// Above this fraction the next step shrinks tenfold (the difference is no longer small:
/// truncation error).
const DIFF_BIG: f64 = 1.220703125e-4; // ε^0.25
/// The smallest factor.
const MIN_FACTOR: f64 = 1e3 * f64::EPSILON;
const FACTOR_CHANGE: f64 = 10.0;
/// The size below which Hairer's RADAU5 does not shrink a step, √(ε·max(10⁻⁵, |xⱼ|)).
const HAIRER_FLOOR: f64 = 1e-5;

/// The Jacobian of an integration: evaluated afresh when the method asks, by the ODE or by
/// differences (whose per-column factors it carries from one evaluation to the next).
pub(crate) struct Jacobian {
    n: usize,
    /// Column-major, for the factorizations and the eigenvalues of the singularity test.
    matrix: DMatrix<f64>,
    /// Row by row, as the `Ode` writes it.
    rows: Vec<f64>,
    /// `num_jac`'s factor of each column (empty until the first differences).
    factors: Vec<f64>,
    /// The threshold below which |xⱼ| does not shrink a column's step (atol).
    threshold: f64,
    evaluations: usize,
    /// Whether the last Jacobian was formed by differences (n evaluations of the right-hand
    /// side: an expensive one, which a method keeps longer).
    differenced: bool,
    /// Whether the Jacobian was evaluated at the start of the step being solved: when it
    /// was, a failure cannot be blamed on an old Jacobian.
    pub fresh: bool,
}

/// Whether every entry of `entries` is finite. v·0 is NaN exactly for a v that is not
/// finite, and a sum of zeros stays zero in any order: one pass without a branch an entry,
/// summed in eight lanes (four vector registers) rather than one serial chain, which the
/// compiler may not reorder (the entry is looked for only when there is one).
#[inline(always)]
fn all_finite(entries: &[f64]) -> bool {
    let mut lanes = [0.0; 8];
    let chunks = entries.chunks_exact(lanes.len());
    let tail = chunks.remainder();
    for chunk in chunks {
        for (lane, v) in lanes.iter_mut().zip(chunk) {
            *lane += v * 0.0;
        }
    }
    let sum = lanes.iter().sum::<f64>();
    tail.iter().fold(sum, |sum, v| sum + v * 0.0) == 0.0
}

impl Jacobian {
    /// For an ODE of `n` components; `threshold` is the absolute tolerance (or the scale
    /// below which a component counts as zero).
    pub fn new(n: usize, threshold: f64) -> Self {
        Jacobian {
            n,
            matrix: DMatrix::zeros(n, n),
            rows: vec![0.0; n * n],
            factors: Vec::new(),
            threshold,
            evaluations: 0,
            differenced: false,
            fresh: false,
        }
    }

    /// Whether the last Jacobian was formed by differences.
    pub fn differenced(&self) -> bool {
        self.differenced
    }

    /// How many Jacobians have been evaluated: the identity of the current one.
    pub fn count(&self) -> usize {
        self.evaluations
    }

    /// The Jacobian last evaluated.
    pub fn matrix(&self) -> &DMatrix<f64> {
        &self.matrix
    }

    /// Evaluates the Jacobian at (t, x), where f is `f` if known (differences need it, and
    /// evaluate it when it is not given). An entry that is not finite is an error: naming the
    /// rate that is not finite itself, if one is (every derivative of a NaN is NaN, and the
    /// first would name a coordinate that has nothing to do with it), else the derivative.
    pub fn evaluate<O: Ode>(
        &mut self,
        ode: &mut O,
        t: f64,
        x: &O::State,
        f: Option<&O::State>,
        stats: &mut Stats,
    ) -> Result<(), Error> {
        let mut known = f.copied();
        self.differenced = !ode.jacobian(t, x, &mut self.rows)?;
        if self.differenced {
            let f0 = match known {
                Some(f0) => f0,
                None => {
                    let mut f0 = O::State::zeros();
                    ode.rhs(t, x, &mut f0)?;
                    stats.evaluations += 1;
                    known = Some(f0);
                    f0
                }
            };
            if let Some(found) = NonFinite::check(t, x, &f0) {
                return Err(found.error(ode));
            }
            self.differences(ode, t, x, &f0, stats)?;
        }
        stats.jacobians += 1;
        self.evaluations += 1;
        // The length n² known at compile time: a small Jacobian's check unrolled.
        let n = O::State::LEN;
        if !all_finite(&self.rows[..n * n]) {
            if let Some(k) = self.rows.iter().position(|v| !v.is_finite()) {
                return Err(self.non_finite(ode, t, x, known, k));
            }
        }
        self.transpose_rows::<O::State>();
        self.fresh = true;
        Ok(())
    }

    /// `rows` (J row by row) copied into `matrix` (column by column): nalgebra's
    /// `tr_copy_from` of `rows` read as Jᵀ, but with n the state's, known at compile time, so
    /// that a small matrix's copy is unrolled (with n read at run time it was two loops, some
    /// 90 instructions at n = 3, more than the exact Jacobian itself).
    fn transpose_rows<V: Vector>(&mut self) {
        let n = V::LEN;
        debug_assert_eq!(self.n, n);
        let rows = &self.rows[..n * n];
        let columns = &mut self.matrix.as_mut_slice()[..n * n];
        for (c, column) in columns.chunks_exact_mut(n.max(1)).enumerate() {
            for (entry, row) in column.iter_mut().zip(rows.chunks_exact(n.max(1))) {
                *entry = row[c];
            }
        }
    }

    /// The error for entry `k` of the Jacobian at (t, x), which is not finite.
    #[cold]
    fn non_finite<O: Ode>(
        &self,
        ode: &mut O,
        t: f64,
        x: &O::State,
        f: Option<O::State>,
        k: usize,
    ) -> Error {
        let f = f.or_else(|| {
            let mut f = O::State::zeros();
            ode.rhs(t, x, &mut f).ok().map(|()| f)
        });
        if let Some(found) = f.and_then(|f| NonFinite::check(t, x, &f)) {
            return found.error(ode);
        }
        let n = self.n;
        let names = ode.describe(x);
        let name = |i: usize| {
            names
                .0
                .get(i)
                .map_or_else(|| format!("x{i}"), |(n, _)| n.clone())
        };
        Error::NonFiniteDerivative {
            of: format!("the rate of `{}`", name(k / n)),
            by: name(k % n),
            value: self.rows[k],
            at: format!("at t = {}, in the state {names}", Num(t)),
        }
    }

    /// The Jacobian by forward differences into `rows`, with `num_jac`'s steps (module
    /// documentation): n evaluations, and one more for each column refined.
    fn differences<O: Ode>(
        &mut self,
        ode: &mut O,
        t: f64,
        x: &O::State,
        f0: &O::State,
        stats: &mut Stats,
    ) -> Result<(), Error> {
        let n = O::State::LEN;
        let first = self.factors.len() != n;
        if first {
            self.factors = vec![f64::EPSILON.sqrt(); n];
        }
        let (xs, fs) = (x.as_ref(), f0.as_ref());
        // The rounding of the largest rate bounds what any column can resolve.
        let largest_rate = fs.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for j in 0..n {
            // Directed as ẋⱼ points.
            let direction = if fs[j] >= 0.0 { 1.0 } else { -1.0 };
            let scale = direction * self.threshold.max(xs[j].abs());
            let mut factor = self.factors[j];
            let mut step = (xs[j] + factor * scale) - xs[j];
            while step == 0.0 {
                factor *= FACTOR_CHANGE;
                step = (xs[j] + factor * scale) - xs[j];
            }
            let mut column = self.column(ode, t, x, f0, j, step, stats)?;
            if column.largest < DIFF_REJECT * column.scale {
                let larger = FACTOR_CHANGE * factor;
                let retry_step = (xs[j] + larger * scale) - xs[j];
                let retry = self.column(ode, t, x, f0, j, retry_step, stats)?;
                // The retry is better when its difference is larger relative to its scale.
                if column.largest * retry.scale < retry.largest * column.scale {
                    (column, factor, step) = (retry, larger, retry_step);
                }
            }
            self.set_column(j, &column.difference, step);
            if column.largest < DIFF_SMALL * column.scale {
                factor *= FACTOR_CHANGE;
            }
            if column.largest > DIFF_BIG * column.scale {
                factor /= FACTOR_CHANGE;
            }
            self.factors[j] = factor.max(MIN_FACTOR);
            let lost = column.largest < DIFF_REJECT * largest_rate;
            if first && lost && xs[j].abs() <= self.threshold {
                if let Some(hairer) = hairer_step(xs[j], direction * step.abs()) {
                    let column = self.column(ode, t, x, f0, j, hairer, stats)?;
                    self.set_column(j, &column.difference, hairer);
                }
            }
        }
        Ok(())
    }

    /// Column j of the Jacobian: the `difference` over the `step` it was taken with. Sized by
    /// the state's type, so that n is known at compile time, as where the loop was written
    /// out in place (with the slice's length, read at run time, and an index check an entry,
    /// the differenced runs took about 1 % more instructions).
    fn set_column<V: Vector>(&mut self, j: usize, difference: &V, step: f64) {
        let n = V::LEN;
        assert!(j < n, "column {j} of {n}");
        for (row, d) in self.rows[..n * n]
            .chunks_exact_mut(n)
            .zip(difference.as_ref())
        {
            row[j] = d / step;
        }
    }

    /// f(t, x + step·eⱼ) − f(t, x), its largest entry in modulus and the function's scale
    /// there, max(|f₀ᵢ|, |fᵢ|) at that entry.
    #[allow(clippy::too_many_arguments)]
    fn column<O: Ode>(
        &self,
        ode: &mut O,
        t: f64,
        x: &O::State,
        f0: &O::State,
        j: usize,
        step: f64,
        stats: &mut Stats,
    ) -> Result<Column<O::State>, Error> {
        let mut shifted = *x;
        shifted.as_mut()[j] += step;
        let mut f = O::State::zeros();
        ode.rhs(t, &shifted, &mut f)?;
        stats.evaluations += 1;
        // A NaN there is the right-hand side's, at the state it was evaluated at (every
        // entry of the column would be NaN, blamed on the derivative).
        if let Some(found) = NonFinite::check(t, &shifted, &f) {
            return Err(found.error(ode));
        }
        let mut difference = f;
        let (mut largest, mut at) = (-1.0f64, 0);
        for (i, (d, f0i)) in difference.as_mut().iter_mut().zip(f0.as_ref()).enumerate() {
            *d -= f0i;
            // An infinite difference is the largest: it fails the Jacobian's check, by name.
            let size = if d.is_nan() { f64::INFINITY } else { d.abs() };
            if size > largest {
                (largest, at) = (size, i);
            }
        }
        let scale = f0.as_ref()[at].abs().max(f.as_ref()[at].abs());
        Ok(Column {
            difference,
            largest: largest.max(0.0),
            scale,
        })
    }
}

/// One column's difference and what decides its step.
struct Column<V> {
    difference: V,
    largest: f64,
    scale: f64,
}

/// Hairer's step √(ε·max(10⁻⁵, |xⱼ|)) at xⱼ, directed as `step`, if it is longer than `step`
/// (module documentation).
fn hairer_step(xj: f64, step: f64) -> Option<f64> {
    let hairer = step.signum() * (f64::EPSILON * HAIRER_FLOOR.max(xj.abs())).sqrt();
    let hairer = (xj + hairer) - xj;
    (hairer.abs() > step.abs()).then_some(hairer)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `all_finite` is `is_finite` of every entry: each kind of non-finite value at each
    /// place of slices of every length around the eight lanes', among zeros of either sign,
    /// the largest finite values and subnormal ones (whose products by 0 are zeros).
    #[test]
    fn finiteness_is_that_of_every_entry() {
        let finite = [0.0, -0.0, f64::MAX, -f64::MAX, 5e-324, -1.5, 1e300];
        for len in 0..=19 {
            let base: Vec<f64> = (0..len).map(|k| finite[k % finite.len()]).collect();
            assert!(all_finite(&base), "{base:?}");
            for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
                for k in 0..len {
                    let mut entries = base.clone();
                    entries[k] = bad;
                    assert!(!all_finite(&entries), "{entries:?}");
                }
            }
        }
        // +∞ and −∞ in different lanes: their products by 0 are NaN, not a cancelling pair.
        let mut entries = vec![1.0; 16];
        entries[3] = f64::INFINITY;
        entries[12] = f64::NEG_INFINITY;
        assert!(!all_finite(&entries));
    }

    /// ẋ = A x + (0, 10³ x₀²): a linear part and a nonlinear one.
    struct Scaled;

    impl Ode for Scaled {
        type State = [f64; 2];

        fn rhs(&mut self, _t: f64, x: &[f64; 2], dx: &mut [f64; 2]) -> Result<(), Error> {
            *dx = [x[1], -4.0 * x[0] - 0.5 * x[1] + 1e3 * x[0] * x[0]];
            Ok(())
        }
    }

    fn exact(x: &[f64; 2]) -> [f64; 4] {
        [0.0, 1.0, -4.0 + 2e3 * x[0], -0.5]
    }

    /// The largest error of an entry, relative to the entry (absolute below 1).
    fn error(jacobian: &Jacobian, x: &[f64; 2]) -> f64 {
        let want = exact(x);
        jacobian
            .rows
            .iter()
            .zip(want)
            .map(|(got, want)| (got - want).abs() / want.abs().max(1.0))
            .fold(0.0, f64::max)
    }

    #[test]
    fn differences_approximate_the_jacobian() {
        for x in [[0.3, -1.2], [0.0, 0.0], [0.01, 0.5]] {
            let mut jacobian = Jacobian::new(2, 1e-10);
            let mut stats = Stats::default();
            jacobian
                .evaluate(&mut Scaled, 0.0, &x, None, &mut stats)
                .unwrap();
            // Forward differences: rounding ε·|f|/h plus truncation h·|f″|/2, about 10⁻⁶.
            assert!(error(&jacobian, &x) < 1e-5, "at {x:?}: {:?}", jacobian.rows);
            // f at x, then one evaluation per column (none refined here).
            assert_eq!(stats.evaluations, 3, "at {x:?}");
            assert_eq!(stats.jacobians, 1);
        }
    }

    /// A component a billion times smaller than the rate it moves: its first step, √ε of it,
    /// changes that rate by less than an ulp (the entry is refined, and still 25 % off); the
    /// factor carried to the next evaluations grows tenfold each time, as scipy's `num_jac`
    /// does from step to step, and two evaluations later the entry is 2000 times closer.
    #[test]
    fn the_carried_factor_corrects_a_step_lost_in_rounding() {
        let x = [1e-9, 3.0];
        let mut jacobian = Jacobian::new(2, 1e-10);
        let mut stats = Stats::default();
        jacobian
            .evaluate(&mut Scaled, 0.0, &x, None, &mut stats)
            .unwrap();
        assert!(error(&jacobian, &x) > 0.1, "{:?}", jacobian.rows);
        for _ in 0..2 {
            jacobian
                .evaluate(&mut Scaled, 0.0, &x, None, &mut stats)
                .unwrap();
        }
        assert!(error(&jacobian, &x) < 1e-3, "{:?}", jacobian.rows);
    }

    /// A component far below its tolerance's threshold: the step is the threshold's, not
    /// the component's own size (Hairer's rule gave √(ε·10⁻⁵) ≈ 5·10⁻¹¹, 500 times the
    /// component, and an entry wrong by 100 %).
    #[test]
    fn a_tiny_component_gets_a_step_from_its_threshold() {
        // ẋ₁ = −3·10⁷ x₁² (Robertson's): ∂/∂x₁ = −6·10⁷ x₁ at x₁ = 10⁻¹³ is −6·10⁻⁶.
        struct Square;
        impl Ode for Square {
            type State = [f64; 1];
            fn rhs(&mut self, _: f64, x: &[f64; 1], dx: &mut [f64; 1]) -> Result<(), Error> {
                dx[0] = -3e7 * x[0] * x[0];
                Ok(())
            }
        }
        let mut jacobian = Jacobian::new(1, 1e-20);
        let mut stats = Stats::default();
        let x = [1e-13];
        jacobian
            .evaluate(&mut Square, 0.0, &x, None, &mut stats)
            .unwrap();
        let want = -6e7 * x[0];
        assert!(
            (jacobian.rows[0] - want).abs() < 1e-6 * want.abs(),
            "{} against {want}",
            jacobian.rows[0]
        );
    }

    /// A column whose difference is lost in rounding is refined with a larger step, and the
    /// factor carried to the next evaluation.
    #[test]
    fn a_difference_lost_in_rounding_is_refined() {
        // f = 10³ + 10⁻⁹·x₀: the change is far below an ulp of f at √ε steps.
        struct Flat;
        impl Ode for Flat {
            type State = [f64; 1];
            fn rhs(&mut self, _: f64, x: &[f64; 1], dx: &mut [f64; 1]) -> Result<(), Error> {
                dx[0] = 1e3 + 1e-9 * x[0];
                Ok(())
            }
        }
        let mut jacobian = Jacobian::new(1, 1e-6);
        let mut stats = Stats::default();
        jacobian
            .evaluate(&mut Flat, 0.0, &[1.0], None, &mut stats)
            .unwrap();
        // f, the first column and its retry.
        assert_eq!(stats.evaluations, 3);
        assert!(jacobian.factors[0] > f64::EPSILON.sqrt());
    }

    /// HIRES's first rows at its initial state, where y₂ = y₃ = 0 and atol = 10⁻¹⁰: `num_jac`'s
    /// steps of √ε·atol for them are lost in the rows where f ≈ 1.7 (∂f₁/∂y₂ and ∂f₂/∂y₂ came
    /// out 0), unseen by its refinement (the largest difference is in the third row, where f
    /// is zero). The first Jacobian differences those columns again by Hairer's steps.
    #[test]
    fn the_first_jacobian_at_zero_components_is_not_lost_in_rounding() {
        struct Hires3;
        impl Ode for Hires3 {
            type State = [f64; 3];
            fn rhs(&mut self, _: f64, y: &[f64; 3], f: &mut [f64; 3]) -> Result<(), Error> {
                *f = [
                    -1.71 * y[0] + 0.43 * y[1] + 8.32 * y[2] + 0.0007,
                    1.71 * y[0] - 8.75 * y[1],
                    8.32 * y[1] + 1.71 * y[2],
                ];
                Ok(())
            }
        }
        let want = [-1.71, 0.43, 8.32, 1.71, -8.75, 0.0, 0.0, 8.32, 1.71];
        let mut jacobian = Jacobian::new(3, 1e-10);
        let mut stats = Stats::default();
        jacobian
            .evaluate(&mut Hires3, 0.0, &[1.0, 0.0, 0.0], None, &mut stats)
            .unwrap();
        for (k, (got, want)) in jacobian.rows.iter().zip(want).enumerate() {
            assert!((got - want).abs() < 1e-5, "entry {k}: {got} against {want}");
        }
        // f, one evaluation per column, and the two lost columns again.
        assert_eq!(stats.evaluations, 6);
    }

    /// The copy into column-major storage is nalgebra's transpose of the rows, entry by
    /// entry, zeros of both signs included.
    #[test]
    fn the_matrix_is_the_transpose_of_the_rows() {
        fn check<const N: usize>() {
            let mut jacobian = Jacobian::new(N, 1e-10);
            for (k, v) in jacobian.rows.iter_mut().enumerate() {
                *v = match k % 4 {
                    0 => -0.0,
                    1 => 0.0,
                    _ => k as f64 * 1.5 - 7.0,
                };
            }
            jacobian.transpose_rows::<[f64; N]>();
            let rows = DMatrix::from_row_slice(N, N, &jacobian.rows);
            let bits = |m: &DMatrix<f64>| m.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&jacobian.matrix), bits(&rows));
        }
        check::<1>();
        check::<3>();
        check::<8>();
        check::<20>();
    }

    #[test]
    fn the_thresholds_are_powers_of_epsilon() {
        let e = f64::EPSILON;
        assert_eq!(DIFF_REJECT, e.powf(0.875));
        assert_eq!(DIFF_SMALL, e.powf(0.75));
        assert_eq!(DIFF_BIG, e.powf(0.25));
    }

    #[test]
    fn a_nan_rate_is_named_not_a_derivative() {
        // f₁ is NaN; the Jacobian by differences would be NaN in every column.
        struct NanRate;
        impl Ode for NanRate {
            type State = [f64; 2];
            fn rhs(&mut self, _: f64, x: &[f64; 2], dx: &mut [f64; 2]) -> Result<(), Error> {
                *dx = [x[1], (x[0] - 2.0).sqrt()];
                Ok(())
            }
        }
        let mut jacobian = Jacobian::new(2, 1e-6);
        let error = jacobian
            .evaluate(&mut NanRate, 0.5, &[1.0, 0.0], None, &mut Stats::default())
            .unwrap_err();
        match &error {
            Error::NonFiniteRate { t, rate, .. } => {
                assert_eq!((*t, rate.as_str()), (0.5, "x1"));
            }
            other => panic!("{other:?}"),
        }
        assert!(
            error.to_string().contains("NaN for the rate of `x1`"),
            "{error}"
        );
    }
}
