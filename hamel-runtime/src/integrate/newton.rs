//! The simplified Newton iteration that solves the stage equations of an implicit collocation
//! method, Zᵢ = h Σⱼ aᵢⱼ f(t + cⱼh, y + Zⱼ), on the Jacobian J = ∂f/∂x: every iteration solves
//! (I − h·A⊗J) ΔZ = −Z + h (A⊗I) F(Z) with one LU factorization of the iteration matrix,
//! formed once for a Jacobian and a step size and reused (Hairer & Wanner, *Solving Ordinary
//! Differential Equations II*, IV.8). The Jacobian is the [`Ode`]'s own ([`Ode::jacobian`]: for
//! a mechanical system the exact one, by dual numbers through its generated right-hand side),
//! or forward differences where it has none; the methods evaluate it afresh only when the
//! iteration stops converging fast.
//!
//! Two ways to stop: to rounding, for the symmetric methods (an iteration stopped early leaves
//! an error that is not symmetric, and over a long run it accumulates into a drift: Hairer,
//! McLachlan & Razakarivony, *BIT* 48 (2008)), and RADAU5's test on the predicted remaining
//! error, for the stiff method whose error control needs no more than the tolerance.

use nalgebra::{Complex, DMatrix, DVector, Dyn, LU};

use super::collocation::Tableau;
use super::differences::Jacobian;
use super::singular::{
    SUSPICIOUS_PIVOT, growing_mode, method_eigenvalues, relative_pivot, smallest_pivot,
};
use super::{Ode, Stats};
use crate::error::Error;
use crate::vector::Vector;

/// The most iterations a symmetric method spends converging its stages to rounding before it
/// evaluates the Jacobian afresh (and, with a fresh one, reports an error): from the
/// extrapolated start a contraction of 0.3 per iteration reaches rounding in about 25.
pub const NEWTON_MAX_ITERATIONS: usize = 50;

/// Scaled increments at most this small that stop decreasing are rounding: the iteration has
/// converged as far as `f64` allows.
const ROUNDING_FLOOR: f64 = 1e-12;

/// How to decide that the iteration has converged.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Criterion {
    /// To rounding: the scaled increment is at most one ulp, or the next one would be (the
    /// observed contraction times this one), or it has stopped decreasing below
    /// [`ROUNDING_FLOOR`]; diverging or too slow to get there in [`NEWTON_MAX_ITERATIONS`]
    /// is a failure.
    Rounding,
    /// Hairer's RADAU5 test: θ/(1 − θ)·‖ΔZ‖ ≤ `tolerance`, θ the observed contraction; at
    /// most `max_iterations`, and a failure as soon as Hairer & Wanner's prediction
    /// (θᵏᵐᵃˣ⁻ᵏ/(1 − θ)·‖ΔZ‖ > `tolerance`) says they will not do.
    Predicted {
        tolerance: f64,
        max_iterations: usize,
    },
}

/// How an iteration ended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Outcome {
    /// The stages are solved; `rate` is the largest contraction factor observed before
    /// rounding (0 when one iteration sufficed).
    Converged { iterations: usize, rate: f64 },
    /// Diverging, too slow, or a stage value where f is not finite. `shrink` is the factor
    /// by which RADAU5 would reduce the step; `increment` the last scaled increment.
    Failed {
        iterations: usize,
        rate: f64,
        increment: f64,
        shrink: f64,
    },
}

/// The stage slopes F_i = f(t + cᵢh, y + Zᵢ), counted.
pub(crate) fn stage_slopes<O: Ode, const S: usize>(
    ode: &mut O,
    c: &[f64; S],
    (t, y, h): (f64, &O::State, f64),
    z: &[O::State; S],
    f: &mut [O::State; S],
    stats: &mut Stats,
) -> Result<(), Error> {
    for (i, fi) in f.iter_mut().enumerate() {
        let mut yi = *y;
        for (v, dz) in yi.as_mut().iter_mut().zip(z[i].as_ref()) {
            *v += dz;
        }
        ode.rhs(t + c[i] * h, &yi, fi)?;
    }
    stats.evaluations += S;
    Ok(())
}

/// The bookkeeping of one iteration's convergence, whatever the linear algebra of its
/// corrections: the observed contraction, and when to stop ([`Criterion`]).
pub(crate) struct Convergence {
    criterion: Criterion,
    max_iterations: usize,
    /// The last scaled correction (NaN before the first).
    previous: f64,
    /// The contraction reported: the largest before rounding (to rounding), RADAU5's
    /// smoothed one (predicted).
    rate: f64,
    theta: f64,
    theta_old: f64,
    /// Whether `faccon` still awaits RADAU5's relaxation `faccon^0.8` ([`Self::relax`]).
    unrelaxed: bool,
}

impl Convergence {
    /// A new iteration; `faccon` is RADAU5's FACCON carried from the last step, which it
    /// relaxes (`faccon^0.8`) as RADAU5 does. The relaxed value counts only where the first
    /// iteration's test reads it, or where the iteration ends before the second overwrites
    /// it: its `powf` (some 125 instructions, a few per cent of a small system's step) waits
    /// until then ([`Self::relax`]), and most steps never take it.
    pub fn new(criterion: Criterion, faccon: &mut f64) -> Self {
        *faccon = faccon.max(f64::EPSILON);
        let max_iterations = match criterion {
            Criterion::Rounding => NEWTON_MAX_ITERATIONS,
            Criterion::Predicted { max_iterations, .. } => max_iterations,
        };
        let mut convergence = Convergence {
            criterion,
            max_iterations,
            previous: f64::NAN,
            rate: 0.0,
            theta: 0.0,
            theta_old: 0.0,
            unrelaxed: true,
        };
        // Only the predicted test at the first iteration can decide without it.
        if !matches!(criterion, Criterion::Predicted { .. }) || max_iterations < 2 {
            convergence.relax(faccon);
        }
        convergence
    }

    /// RADAU5's relaxation of FACCON, `faccon^0.8`, unless applied already.
    fn relax(&mut self, faccon: &mut f64) {
        if self.unrelaxed {
            *faccon = faccon.powf(0.8);
            self.unrelaxed = false;
        }
    }

    pub fn max_iterations(&self) -> usize {
        self.max_iterations
    }

    fn failed(&self, k: usize, rate: f64, increment: f64, shrink: f64) -> Outcome {
        Outcome::Failed {
            iterations: k,
            rate,
            increment,
            shrink,
        }
    }

    /// Judges the k-th correction, of scaled size `increment` (its solve having succeeded
    /// or not), before it is applied: a failure ends the iteration.
    #[inline]
    pub fn judge(
        &mut self,
        k: usize,
        increment: f64,
        solved: bool,
        faccon: &mut f64,
    ) -> Option<Outcome> {
        // A stage where f is not finite, or a solve that overflowed.
        if !(solved && increment.is_finite()) {
            self.relax(faccon);
            return Some(self.failed(k, f64::NAN, increment, 0.5));
        }
        self.theta = if k >= 2 {
            increment / self.previous
        } else {
            0.0
        };
        if let Criterion::Predicted {
            tolerance,
            max_iterations,
        } = self.criterion
        {
            if k >= 2 {
                // RADAU5: the geometric mean of the last two rates, once there are two.
                let smoothed = if k == 2 {
                    self.theta
                } else {
                    (self.theta * self.theta_old).sqrt()
                };
                self.theta_old = self.theta;
                self.rate = smoothed;
                if smoothed >= 0.99 {
                    self.relax(faccon);
                    return Some(self.failed(k, smoothed, increment, 0.5));
                }
                *faccon = smoothed / (1.0 - smoothed);
                self.unrelaxed = false;
                // Hairer & Wanner's test (IV.8; scipy's `Radau` too): the iteration will not
                // converge in the iterations left when θᵏᵐᵃˣ⁻ᵏ/(1 − θ)·‖ΔZ‖ > tolerance. The
                // error left after them would be θ times that; asking for one factor θ more
                // gives up on a slow iteration (θ ≈ 0.15) at its second iteration instead of
                // converging in six or seven, and the smaller step then converges in four.
                // Measured (`benches/work_precision`, rtol 10⁻³…10⁻¹⁰, with the halving
                // after a failure on a fresh Jacobian in `Radau5`): HIRES's late steps, which
                // the iteration limits, come out about 10 times more accurate for the same
                // evaluations, and its evaluations at equal error fall from 1.02 to 0.91
                // times scipy Radau's in the median (largest 1.26 to 1.15).
                let left = max_iterations - k;
                let predicted = increment * power(smoothed, left) / (1.0 - smoothed) / tolerance;
                if predicted >= 1.0 {
                    let q = predicted.clamp(1e-4, 20.0);
                    let shrink = 0.8 * q.powf(-1.0 / (4.0 + left as f64));
                    return Some(self.failed(k, smoothed, increment, shrink));
                }
            }
        }
        None
    }

    /// After the k-th correction is applied: converged, hopeless, or (`None`) on.
    pub fn settled(&mut self, k: usize, increment: f64, faccon: &mut f64) -> Option<Outcome> {
        let theta = self.theta;
        self.previous = increment.max(f64::MIN_POSITIVE);
        let converged = |rate| {
            Some(Outcome::Converged {
                iterations: k,
                rate,
            })
        };
        match self.criterion {
            Criterion::Rounding => {
                if k >= 2 && increment > ROUNDING_FLOOR {
                    self.rate = self.rate.max(theta);
                }
                let stalled = k >= 2 && theta >= 1.0;
                // What the next iteration would still change, θ/(1 − θ)·‖ΔZ‖, below an
                // ulp: the stages are at rounding already.
                let below_ulp = k >= 2 && theta < 0.5 && theta * increment <= 0.5 * f64::EPSILON;
                if increment <= f64::EPSILON
                    || below_ulp
                    || (stalled && increment <= ROUNDING_FLOOR)
                {
                    return converged(self.rate);
                }
                // Diverging, or so slow that rounding is out of reach in the iterations left.
                let left = (self.max_iterations - k) as f64;
                if stalled || (k >= 2 && increment * theta.powf(left) > ROUNDING_FLOOR) {
                    return Some(self.failed(k, theta, increment, 0.5));
                }
                None
            }
            Criterion::Predicted { tolerance, .. } => {
                if self.unrelaxed {
                    // faccon^0.8 ≥ min(faccon, 1): where that bound times the increment
                    // exceeds the tolerance by more than any rounding, so does the relaxed
                    // FACCON's, and the test fails without it.
                    if faccon.min(1.0) * increment > tolerance * (1.0 + 1e-12) {
                        return None;
                    }
                    self.relax(faccon);
                }
                (*faccon * increment <= tolerance)
                    .then_some(())
                    .and(converged(self.rate))
            }
        }
    }

    /// The failure after the last allowed iteration.
    pub fn exhausted(&self) -> Outcome {
        Outcome::Failed {
            iterations: self.max_iterations,
            rate: self.rate,
            increment: self.previous,
            shrink: 0.5,
        }
    }
}

/// The Jacobian, the factored iteration matrix and the iteration's workspace, for one
/// integration (allocated once; a factorization allocates its matrix).
pub(crate) struct Newton {
    n: usize,
    /// The Jacobian, the ODE's own or by differences; `jacobian.fresh` says whether it was
    /// evaluated at the start of the step being solved (a failure then cannot be blamed on an
    /// old Jacobian).
    pub jacobian: Jacobian,
    /// The LU factors of I − h·(A ⊗ J) and the h they are for.
    lu: Option<(f64, LU<f64, Dyn, Dyn>)>,
    residual: DVector<f64>,
    /// RADAU5's FACCON, carried from step to step: θ/(1 − θ) of the last iteration.
    faccon: f64,
    /// The leading components the convergence test measures (`Ode::controlled_components`):
    /// the others (the work done on a forced system) follow the state and do not act back
    /// on it, so they converge with it and must not hold it up.
    controlled: usize,
    /// The largest relative change of h for which the factorization is kept
    /// ([`Newton::with_reuse`]).
    reuse: f64,
}

/// The typical size of a component for the difference Jacobian of a fixed-step method, which
/// has no absolute tolerance to take it from: the step of column j is √ε·max(|xⱼ|, 1) at
/// first (Dennis & Schnabel's rule with a typical size of 1), then adapted
/// ([`super::differences`]).
pub(crate) const TYPICAL_SIZE: f64 = 1.0;

impl Newton {
    /// The machinery for an ODE with `n` components, of which the leading `controlled` are
    /// measured by the convergence test, and a method with `stages` stages.
    pub fn new(n: usize, controlled: usize, stages: usize) -> Self {
        Newton {
            n,
            jacobian: Jacobian::new(n, TYPICAL_SIZE),
            lu: None,
            residual: DVector::zeros(n * stages),
            faccon: 1.0,
            controlled: controlled.clamp(1, n.max(1)),
            reuse: 0.0,
        }
    }

    /// Keeps the factorization for a step h while |h/h_factored − 1| ≤ `ratio` (0: only for
    /// the same h). Simplified Newton converges to the same stages with an iteration matrix
    /// for a slightly different step, a little more slowly; a fixed-step method whose steps
    /// differ in their last bits between sample intervals would otherwise refactor an
    /// unchanged matrix.
    pub fn with_reuse(mut self, ratio: f64) -> Self {
        self.reuse = ratio;
        self
    }

    /// Whether a Jacobian has been evaluated yet.
    pub fn has_jacobian(&self) -> bool {
        self.jacobian.count() > 0
    }

    /// Evaluates the Jacobian at (t, x): the ODE's own, or forward differences; an entry that
    /// is not finite is an error naming it (or the rate that is not finite). Invalidates the
    /// factorization.
    pub fn evaluate<O: Ode>(
        &mut self,
        ode: &mut O,
        t: f64,
        x: &O::State,
        stats: &mut Stats,
    ) -> Result<(), Error> {
        self.lu = None;
        self.jacobian.evaluate(ode, t, x, None, stats)
    }

    /// Factors I − h·(A ⊗ J) unless it is factored for this h already (up to the reuse
    /// ratio); a singular matrix is an error naming t, h, the growing motion that makes it
    /// singular and the state x (where the step starts).
    pub fn factor<O: Ode, const S: usize>(
        &mut self,
        ode: &O,
        tableau: &Tableau<S>,
        (t, x, h): (f64, &O::State, f64),
        stats: &mut Stats,
    ) -> Result<(), Error> {
        if matches!(self.lu, Some((formed, _)) if (h / formed - 1.0).abs() <= self.reuse) {
            return Ok(());
        }
        let n = self.n;
        let jacobian = self.jacobian.matrix();
        let matrix = DMatrix::from_fn(S * n, S * n, |r, c| {
            let (i, p, j, q) = (r / n, r % n, c / n, c % n);
            let identity = if r == c { 1.0 } else { 0.0 };
            identity - h * tableau.a[i][j] * jacobian[(p, q)]
        });
        stats.factorizations += 1;
        let mus = || method_eigenvalues(&tableau.a);
        match factor_checked(matrix, &mut self.lu, h, jacobian, mus) {
            Some((growth, frequency)) => Err(Error::SingularIterationMatrix {
                t,
                h,
                growth,
                frequency,
                state: ode.describe(x),
            }),
            None => Ok(()),
        }
    }

    /// Solves the stage equations of a step of size h from (t, y), starting from `z` and
    /// leaving the solution there; the increments are measured component by component
    /// relative to `scale`. The factorization must be for this h ([`Newton::factor`]).
    #[allow(clippy::too_many_arguments)]
    pub fn iterate<O: Ode, const S: usize>(
        &mut self,
        ode: &mut O,
        tableau: &Tableau<S>,
        (t, y, h): (f64, &O::State, f64),
        z: &mut [O::State; S],
        criterion: Criterion,
        scale: &[f64],
        stats: &mut Stats,
    ) -> Result<Outcome, Error> {
        let n = self.n;
        let mut convergence = Convergence::new(criterion, &mut self.faccon);
        let mut f = [O::State::zeros(); S];
        for k in 1..=convergence.max_iterations() {
            stage_slopes(ode, &tableau.c, (t, y, h), z, &mut f, stats)?;
            for (i, (row, zi)) in tableau.a.iter().zip(z.iter()).enumerate() {
                for p in 0..n {
                    let sum: f64 = row.iter().zip(&f).map(|(a, fj)| a * fj.as_ref()[p]).sum();
                    self.residual[i * n + p] = h * sum - zi.as_ref()[p];
                }
            }
            let Some((_, lu)) = &self.lu else {
                unreachable!("the iteration matrix is factored before the iteration");
            };
            let solved = lu.solve_mut(&mut self.residual);
            let increment = self.scaled_norm(scale);
            if let Some(failed) = convergence.judge(k, increment, solved, &mut self.faccon) {
                return Ok(failed);
            }
            self.apply(z);
            if let Some(outcome) = convergence.settled(k, increment, &mut self.faccon) {
                return Ok(outcome);
            }
        }
        Ok(convergence.exhausted())
    }

    /// √(mean((ΔZ / scale)²)) over every stage and controlled component, ΔZ being in
    /// `residual`.
    fn scaled_norm(&self, scale: &[f64]) -> f64 {
        let (n, len) = (self.n, self.controlled);
        let sum: f64 = self
            .residual
            .iter()
            .enumerate()
            .filter(|(r, _)| r % n < len)
            .map(|(r, dz)| (dz / scale[r % n]).powi(2))
            .sum();
        let stages = self.residual.len() / n.max(1);
        (sum / (stages * len) as f64).sqrt()
    }

    /// Z += ΔZ.
    fn apply<V: Vector, const S: usize>(&self, z: &mut [V; S]) {
        let n = self.n;
        for (i, zi) in z.iter_mut().enumerate() {
            for (p, v) in zi.as_mut().iter_mut().enumerate() {
                *v += self.residual[i * n + p];
            }
        }
    }
}

/// Factors `matrix` = I − h·μ·J (for the eigenvalues μ of the method, `mus`, asked for only
/// when needed) into `slot`, with the h it is for; `Some(λ)` when it is singular, λ = (Re, Im)
/// the eigenvalue of J that makes it so (the slot then left empty). A tiny pivot alone is not
/// singular ([`super::singular`]): the LU is kept, and a solve that overflows fails the
/// iteration, which the adaptive method answers with a smaller step.
pub(crate) fn factor_checked(
    matrix: DMatrix<f64>,
    slot: &mut Option<(f64, LU<f64, Dyn, Dyn>)>,
    h: f64,
    jacobian: &DMatrix<f64>,
    mus: impl FnOnce() -> Vec<Complex<f64>>,
) -> Option<(f64, f64)> {
    let largest = matrix.amax();
    let lu = matrix.lu();
    let pivot = relative_pivot(smallest_pivot(&lu), largest);
    if pivot <= SUSPICIOUS_PIVOT {
        if let Some(mode) = growing_mode(jacobian, h, &mus()) {
            *slot = None;
            return Some(mode);
        }
    }
    *slot = Some((h, lu));
    None
}

/// x to the power k, as `x.powi(k)` computes it for an exponent unknown at compile time (the
/// `__powidf2` of compiler-rt and Rust's compiler-builtins: square-and-multiply from the
/// lowest bit, the product starting at 1), to the bit, but inline: the call, some 24
/// instructions for the few iterations left, was a few per cent of a small system's
/// iteration.
#[inline(always)]
fn power(mut x: f64, mut k: usize) -> f64 {
    let mut product = 1.0;
    loop {
        if k & 1 != 0 {
            product *= x;
        }
        k >>= 1;
        if k == 0 {
            return product;
        }
        x *= x;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn power_is_powi_to_the_bit() {
        // The exponent through `black_box`: `powi` with an exponent it cannot see, the
        // library's routine.
        for x in [
            0.0,
            -0.0,
            0.3,
            0.987654321,
            1.0 - 1e-9,
            0.1234567,
            7.5,
            -2.25,
            f64::NAN,
        ] {
            for k in 0..=40usize {
                let expected = x.powi(std::hint::black_box(k as i32));
                assert_eq!(power(x, k).to_bits(), expected.to_bits(), "{x}^{k}");
            }
        }
    }

    /// ẋ = A x with a fixed A: the iteration matrix is exact, so simplified Newton converges
    /// in one iteration (the second only confirms it).
    struct Linear;

    impl Ode for Linear {
        type State = [f64; 2];

        fn rhs(&mut self, _t: f64, x: &[f64; 2], dx: &mut [f64; 2]) -> Result<(), Error> {
            *dx = [x[1], -4.0 * x[0] - 0.5 * x[1]];
            Ok(())
        }

        fn jacobian(&mut self, _t: f64, _x: &[f64; 2], j: &mut [f64]) -> Result<bool, Error> {
            j.copy_from_slice(&[0.0, 1.0, -4.0, -0.5]);
            Ok(true)
        }
    }

    #[test]
    fn a_linear_problem_converges_at_once() {
        let tableau = Tableau::gauss2();
        let mut newton = Newton::new(2, 2, 2);
        let mut stats = Stats::default();
        let (t, y, h) = (0.0, [1.0, 0.0], 0.1);
        newton.evaluate(&mut Linear, t, &y, &mut stats).unwrap();
        newton
            .factor(&Linear, &tableau, (t, &y, h), &mut stats)
            .unwrap();
        let mut z = [[0.0; 2]; 2];
        let outcome = newton
            .iterate(
                &mut Linear,
                &tableau,
                (t, &y, h),
                &mut z,
                Criterion::Rounding,
                &[1.0, 1.0],
                &mut stats,
            )
            .unwrap();
        match outcome {
            Outcome::Converged { iterations, .. } => assert_eq!(iterations, 2, "{outcome:?}"),
            other => panic!("{other:?}"),
        }
        // A second factorization for the same h is skipped.
        newton
            .factor(&Linear, &tableau, (t, &y, h), &mut stats)
            .unwrap();
        assert_eq!((stats.jacobians, stats.factorizations), (1, 1));
    }

    /// The relaxation of FACCON left until needed changes neither the outcome nor the FACCON
    /// carried to the next step: RADAU5's eager `faccon^0.8` gives the same, to the bit.
    #[test]
    fn a_late_relaxation_is_radau5s() {
        let criterion = Criterion::Predicted {
            tolerance: 0.03,
            max_iterations: 7,
        };
        for f0 in [0.0, 1e-3, 0.2, 0.9999, 1.0, 3.0, 99.0] {
            for inc1 in [1e-6, 0.01, 0.0375, 0.3, 5.0, f64::NAN] {
                for inc2 in [1e-9, 0.002, 0.298, 4.9, f64::INFINITY] {
                    // RADAU5's order of things, written out.
                    let relaxed = f64::max(f0, f64::EPSILON).powf(0.8);
                    let expected = if !inc1.is_finite() || relaxed * inc1 <= 0.03 {
                        (relaxed, 1)
                    } else if !inc2.is_finite() || inc2 / inc1 >= 0.99 {
                        (relaxed, 2)
                    } else {
                        (inc2 / inc1 / (1.0 - inc2 / inc1), 2)
                    };
                    let mut faccon = f0;
                    let mut convergence = Convergence::new(criterion, &mut faccon);
                    let mut ended = None;
                    for (k, inc) in [(1, inc1), (2, inc2)] {
                        if convergence.judge(k, inc, true, &mut faccon).is_some()
                            || convergence.settled(k, inc, &mut faccon).is_some()
                        {
                            ended = Some(k);
                            break;
                        }
                    }
                    let case = (f0, inc1, inc2);
                    assert_eq!(faccon.to_bits(), expected.0.to_bits(), "{case:?}");
                    assert_eq!(ended.unwrap_or(2).min(2), expected.1, "{case:?}");
                }
            }
        }
    }

    #[test]
    fn a_singular_iteration_matrix_is_an_error() {
        // ẋ = x with the midpoint rule and h = 2: I − h·½·1 = 0.
        struct Growth;
        impl Ode for Growth {
            type State = [f64; 1];
            fn rhs(&mut self, _t: f64, x: &[f64; 1], dx: &mut [f64; 1]) -> Result<(), Error> {
                dx[0] = x[0];
                Ok(())
            }
        }
        let tableau = Tableau::gauss1();
        let mut newton = Newton::new(1, 1, 1);
        let mut stats = Stats::default();
        newton
            .evaluate(&mut Growth, 1.5, &[2.0], &mut stats)
            .unwrap();
        match newton.factor(&Growth, &tableau, (1.5, &[2.0], 2.0), &mut stats) {
            Err(Error::SingularIterationMatrix { t, h, state, .. }) => {
                assert_eq!((t, h), (1.5, 2.0));
                assert_eq!(state.get("x0"), Some(2.0));
            }
            other => panic!("{other:?}"),
        }
    }
}
