//! The holonomic constraints f(t, q) = 0 solved for the dependent coordinates by Newton's
//! method: assembling a configuration from a guess, projecting a state back onto f = 0 after
//! an integrator step, and checking that a configuration satisfies them.
//!
//! Every test of a residual fᵢ is relative to its scale
//! sᵢ = Σⱼ |∂fᵢ/∂qⱼ| · max(|qⱼ|, 1): how much fᵢ changes when every coordinate moves by its
//! own size (by 1 for coordinates smaller than 1, whose units the model chose). It is in the
//! constraint's own units, whatever they are (a length, a squared length, an angle), and
//! rounding the coordinates to 16 digits, or evaluating f, whose terms are of that size,
//! leaves |fᵢ| at a few 10⁻¹⁶·sᵢ; so 10⁻¹⁴·sᵢ is reached by Newton's method with room to
//! spare, and nothing coarser is accepted.

use nalgebra::{DMatrix, DVector};

use crate::error::{AssemblyFailure, Error};
use crate::named::NamedValues;
use crate::system::HamelSystem;
use crate::vector::Vector;

/// Newton's method has converged when every |fᵢ| ≤ `ASSEMBLY_TOLERANCE` · sᵢ, with the scale
/// sᵢ = Σⱼ |∂fᵢ/∂qⱼ| · max(|qⱼ|, 1) (rounding leaves a few 10⁻¹⁶ of it).
pub const ASSEMBLY_TOLERANCE: f64 = 1e-14;

/// A configuration given to `state_from_velocities` or `state_from_speeds` may miss a
/// holonomic constraint by `HOLONOMIC_TOLERANCE` · sᵢ (scale as for [`ASSEMBLY_TOLERANCE`]):
/// coordinates written with ten digits pass, a wrong one does not.
pub const HOLONOMIC_TOLERANCE: f64 = 1e-10;

/// Newton's method converges quadratically from a reasonable guess (a handful of iterations);
/// this many means it is wandering.
const MAX_ITERATIONS: usize = 50;

/// Halvings of a Newton step before the iteration counts as stuck.
const MAX_HALVINGS: usize = 40;

/// Sufficient decrease (Armijo): a step of length α must reduce the largest scaled residual
/// by a factor 1 − σα, not merely by rounding.
const ARMIJO: f64 = 1e-4;

/// A pivot of the row-scaled Jacobian block below this is rounding of the row's largest entry
/// (which is 1): the dependent coordinates do not enter the constraints here.
const SINGULAR_PIVOT: f64 = 16.0 * f64::EPSILON;

/// Solves f(t, q) = 0 for the coordinates `S::DEPENDENT`, the others held, starting from
/// `start`. Returns `start` itself, bit for bit, when it satisfies the constraints exactly; one
/// within the tolerance gets one more (full) Newton step, which only polishes it.
/// The caller checks the parameters, t and `start` for finiteness.
pub(crate) fn newton<S: HamelSystem + ?Sized>(
    system: &S,
    t: f64,
    start: &S::Coordinates,
) -> Result<S::Coordinates, Error> {
    if S::K == 0 {
        return Ok(*start);
    }
    check_shape::<S>()?;
    let fail = |failure, row: usize, column: usize, residual: f64| {
        assembly_error::<S>(t, start, failure, row, column, residual)
    };
    let f = system.holonomic_residual(t, start);
    let mut point = Point::at(system, t, *start, f)
        .map_err(|row| fail(AssemblyFailure::NonFinite, row, row, f.as_ref()[row]))?;
    for iteration in 0..MAX_ITERATIONS {
        let (worst, merit) = point.worst();
        if merit <= ASSEMBLY_TOLERANCE {
            return Ok(point.polished(system, t));
        }
        let residual = point.f.as_ref()[worst];
        let step = point.newton_step().map_err(|(pivot, row, column)| {
            fail(AssemblyFailure::Singular { pivot }, row, column, residual)
        })?;
        point = match point.line_search(system, t, &step) {
            Search::Accepted(next) => next,
            Search::NonFinite { row, residual } => {
                return Err(fail(AssemblyFailure::NonFinite, row, row, residual));
            }
            Search::Stalled => {
                let failure = AssemblyFailure::Stalled {
                    iterations: iteration,
                };
                return Err(fail(failure, worst, worst, residual));
            }
        };
    }
    let (worst, merit) = point.worst();
    if merit <= ASSEMBLY_TOLERANCE {
        return Ok(point.polished(system, t));
    }
    let failure = AssemblyFailure::NoConvergence {
        iterations: MAX_ITERATIONS,
    };
    Err(fail(failure, worst, worst, point.f.as_ref()[worst]))
}

/// Checks that `q` satisfies every holonomic constraint to [`HOLONOMIC_TOLERANCE`]; the error
/// names the first one that it does not.
pub(crate) fn check<S: HamelSystem + ?Sized>(
    system: &S,
    t: f64,
    q: &S::Coordinates,
) -> Result<(), Error> {
    if S::K == 0 {
        return Ok(());
    }
    check_shape::<S>()?;
    let f = system.holonomic_residual(t, q);
    let jacobian = system.holonomic_jacobian(t, q);
    for (row, r) in f.as_ref().iter().enumerate() {
        let tolerance = HOLONOMIC_TOLERANCE * scale::<S>(&jacobian, q, row);
        // A NaN residual fails too, and so does an infinite or NaN tolerance (a huge
        // derivative times a huge coordinate), which would accept anything.
        if r.is_nan() || !tolerance.is_finite() || r.abs() > tolerance {
            return Err(Error::HolonomicViolation {
                constraint: constraint_name::<S>(row),
                coordinate: dependent_name::<S>(row),
                t,
                residual: *r,
                tolerance,
                configuration: NamedValues::new(S::COORDINATES, q.as_ref()),
            });
        }
    }
    Ok(())
}

/// A configuration with its residual, Jacobian and scales, all finite.
struct Point<S: HamelSystem + ?Sized> {
    q: S::Coordinates,
    f: S::Holonomic,
    jacobian: S::HolonomicJacobian,
    /// sᵢ, at least the smallest positive number (a row whose derivative vanishes everywhere
    /// is then only satisfied exactly, and its block is singular anyway).
    scales: S::Holonomic,
}

/// How a line search along a Newton step ended.
enum Search<P> {
    Accepted(P),
    /// The Jacobian at the accepted point is not finite in this row (whose residual is given).
    NonFinite {
        row: usize,
        residual: f64,
    },
    Stalled,
}

impl<S: HamelSystem + ?Sized> Point<S> {
    /// The point q with its residual f = f(t, q), or the first row whose residual or
    /// derivative is not finite.
    fn at(system: &S, t: f64, q: S::Coordinates, f: S::Holonomic) -> Result<Self, usize> {
        let jacobian = system.holonomic_jacobian(t, &q);
        let n = S::Coordinates::LEN;
        let mut scales = S::Holonomic::zeros();
        for (row, s) in scales.as_mut().iter_mut().enumerate() {
            let derivative = &jacobian.as_ref()[row * n..(row + 1) * n];
            // An infinite scale (a huge derivative times a huge coordinate) would accept any
            // residual.
            *s = scale::<S>(&jacobian, &q, row).max(f64::MIN_POSITIVE);
            if !f.as_ref()[row].is_finite()
                || derivative.iter().any(|d| !d.is_finite())
                || !s.is_finite()
            {
                return Err(row);
            }
        }
        Ok(Point {
            q,
            f,
            jacobian,
            scales,
        })
    }

    /// The row with the largest scaled residual |fᵢ|/sᵢ, and that residual.
    fn worst(&self) -> (usize, f64) {
        self.merit_of(&self.f)
    }

    /// The largest of |fᵢ|/sᵢ for residuals f (NaN if any is), with this point's scales.
    fn merit_of(&self, f: &S::Holonomic) -> (usize, f64) {
        let mut worst = (0, 0.0f64);
        for (row, (r, s)) in f.as_ref().iter().zip(self.scales.as_ref()).enumerate() {
            let scaled = r.abs() / s;
            if scaled.is_nan() {
                return (row, f64::NAN);
            }
            if scaled > worst.1 {
                worst = (row, scaled);
            }
        }
        worst
    }

    /// The Newton step δ for the dependent coordinates: J_d δ = −f, with J_d the k×k block of
    /// the Jacobian on the dependent columns, each row scaled by its largest entry over all
    /// columns so that the pivots compare with 1. A singular block is its pivot, the
    /// constraint row at that pivot and the pivot's column.
    fn newton_step(&self) -> Result<DVector<f64>, (f64, usize, usize)> {
        let (n, k) = (S::Coordinates::LEN, S::Holonomic::LEN);
        let jacobian = self.jacobian.as_ref();
        let mut block = DMatrix::zeros(k, k);
        let mut rhs = DVector::zeros(k);
        for row in 0..k {
            let derivative = &jacobian[row * n..(row + 1) * n];
            let largest = derivative.iter().fold(0.0f64, |m, d| m.max(d.abs()));
            if largest == 0.0 {
                return Err((0.0, row, row));
            }
            for (column, &d) in S::DEPENDENT.iter().enumerate() {
                block[(row, column)] = derivative[d] / largest;
            }
            rhs[row] = -self.f.as_ref()[row] / largest;
        }
        let lu = block.lu();
        let u = lu.u();
        // The constraint row that partial pivoting moved to each position.
        let mut rows = DVector::from_iterator(k, (0..k).map(|r| r as f64));
        lu.p().permute_rows(&mut rows);
        let singular = |c: usize| (u[(c, c)], rows[c] as usize, c);
        if let Some(column) =
            (0..k).find(|&c| u[(c, c)].is_nan() || u[(c, c)].abs() <= SINGULAR_PIVOT)
        {
            return Err(singular(column));
        }
        // With every pivot above the threshold the solve succeeds; a step that overflows
        // comes from a block too close to singular all the same.
        let step = lu
            .solve(&rhs)
            .unwrap_or_else(|| DVector::from_element(k, f64::NAN));
        match step.iter().position(|s| !s.is_finite()) {
            None => Ok(step),
            Some(column) => Err(singular(column)),
        }
    }

    /// The point after one more full Newton step, if that does not make the residual worse.
    /// Within the tolerance Newton's method is in its quadratic range, so one step leaves
    /// only rounding: a run projected after every step keeps f at that level rather than
    /// letting it grow up to the tolerance, which no single step's drift would reach. An
    /// exact root is left as it is, bit for bit.
    fn polished(self, system: &S, t: f64) -> S::Coordinates {
        let (_, merit) = self.worst();
        if merit == 0.0 {
            return self.q;
        }
        let Ok(step) = self.newton_step() else {
            return self.q;
        };
        let mut q = self.q;
        for (column, &d) in S::DEPENDENT.iter().enumerate() {
            q.as_mut()[d] += step[column];
        }
        let f = system.holonomic_residual(t, &q);
        match self.merit_of(&f) {
            (_, trial) if trial <= merit => q,
            _ => self.q,
        }
    }

    /// Backtracks along `step` from this point until the largest scaled residual decreases
    /// sufficiently: the full step near a root (quadratic convergence), a fraction of it far
    /// away, where the full step may overshoot or leave the constraint's domain.
    fn line_search(&self, system: &S, t: f64, step: &DVector<f64>) -> Search<Self> {
        let (_, merit) = self.worst();
        let mut alpha = 1.0;
        for _ in 0..=MAX_HALVINGS {
            let mut q = self.q;
            for (column, &d) in S::DEPENDENT.iter().enumerate() {
                q.as_mut()[d] += alpha * step[column];
            }
            let f = system.holonomic_residual(t, &q);
            let (_, trial) = self.merit_of(&f);
            // A NaN trial (outside the constraint's domain) fails the test and shortens the
            // step too.
            if trial <= (1.0 - ARMIJO * alpha) * merit {
                return match Point::at(system, t, q, f) {
                    Ok(point) => Search::Accepted(point),
                    Err(row) => Search::NonFinite {
                        row,
                        residual: f.as_ref()[row],
                    },
                };
            }
            alpha *= 0.5;
        }
        Search::Stalled
    }
}

/// sᵢ = Σⱼ |∂fᵢ/∂qⱼ| · max(|qⱼ|, 1) (see the module documentation).
fn scale<S: HamelSystem + ?Sized>(
    jacobian: &S::HolonomicJacobian,
    q: &S::Coordinates,
    row: usize,
) -> f64 {
    let n = S::Coordinates::LEN;
    jacobian.as_ref()[row * n..(row + 1) * n]
        .iter()
        .zip(q.as_ref())
        .map(|(d, v)| d.abs() * v.abs().max(1.0))
        .sum()
}

/// The sizes and indices a hand-written implementation could get wrong; checked so that they
/// are an error rather than an index out of bounds.
pub(crate) fn check_shape<S: HamelSystem + ?Sized>() -> Result<(), Error> {
    let (n, k) = (S::Coordinates::LEN, S::K);
    let inconsistent = |what: String| Err(Error::InconsistentModel { what });
    if S::Holonomic::LEN != k || S::HolonomicJacobian::LEN != k * n || S::DEPENDENT.len() != k {
        return inconsistent(format!(
            "K = {k} and N = {n}, but `Holonomic` has {} components, `HolonomicJacobian` {} \
             (should be K·N) and `DEPENDENT` lists {}",
            S::Holonomic::LEN,
            S::HolonomicJacobian::LEN,
            S::DEPENDENT.len()
        ));
    }
    for (i, &d) in S::DEPENDENT.iter().enumerate() {
        if d >= n || S::DEPENDENT[..i].contains(&d) {
            return inconsistent(format!(
                "`DEPENDENT` lists the coordinate index {d} {}",
                if d >= n { "beyond N" } else { "twice" }
            ));
        }
    }
    Ok(())
}

/// The name of holonomic constraint `row` (the last K of `CONSTRAINTS`).
pub(crate) fn constraint_name<S: HamelSystem + ?Sized>(row: usize) -> String {
    (S::P + row)
        .checked_sub(S::K)
        .and_then(|i| S::CONSTRAINTS.get(i))
        .map_or_else(
            || format!("holonomic constraint #{row}"),
            |n| (*n).to_string(),
        )
}

/// The name of the coordinate holonomic constraint `row` determines.
fn dependent_name<S: HamelSystem + ?Sized>(row: usize) -> String {
    S::DEPENDENT
        .get(row)
        .and_then(|&d| S::COORDINATES.get(d))
        .map_or_else(
            || format!("dependent coordinate #{row}"),
            |n| (*n).to_string(),
        )
}

fn assembly_error<S: HamelSystem + ?Sized>(
    t: f64,
    start: &S::Coordinates,
    failure: AssemblyFailure,
    row: usize,
    column: usize,
    residual: f64,
) -> Error {
    Error::Assembly {
        constraint: constraint_name::<S>(row),
        coordinate: dependent_name::<S>(column),
        t,
        failure,
        residual,
        configuration: NamedValues::new(S::COORDINATES, start.as_ref()),
    }
}
