//! Radau IIA's stage equations solved as RADAU5 solves them (Hairer & Wanner, *Solving
//! Ordinary Differential Equations II*, IV.8, "Transformation to block diagonal form"): with
//! A⁻¹ = T Λ T⁻¹, Λ = diag(γ, [[α, −β], [β, α]]), the simplified Newton iteration for
//! W = (T⁻¹ ⊗ I) Z decouples into one real system (γ/h I − J) ΔW₁ = … and one complex system
//! ((α + iβ)/h I − J)(ΔW₂ + iΔW₃) = … of size n, instead of one real system of size 3n: two
//! factorizations of about (1 + 4)·n³/3 operations instead of 9n³, and solves to match — on
//! the 20 species of the pollution problem the difference between a fast stiff solver and a
//! slow one. The real matrix is also that of RADAU5's error estimate, which shares its LU.
//!
//! T is computed here from the eigenvectors of A⁻¹, normalized as RADAU5's T (the iterates
//! are those in Z, transformed, but the convergence test measures the corrections of W, so
//! its scaling matters); the test checks it against RADAU5's constants.

use nalgebra::{Complex, DMatrix, Matrix3};

use super::collocation::Tableau;
use super::dense::{SQUARE_FLOOR, SQUARE_MARGIN, SquareLu};
use super::newton::{Convergence, Criterion, Outcome, stage_slopes};
use super::singular::{SUSPICIOUS_PIVOT, growing_mode, method_eigenvalues, relative_pivot};
use super::{Ode, Stats};
use crate::error::Error;
use crate::vector::Vector;

/// The block diagonalization of A⁻¹ for Radau IIA with three stages.
#[derive(Clone, Debug)]
pub(crate) struct Transformation {
    /// A⁻¹'s real eigenvalue γ (RADAU5's U1 inverted back: 3.6378…).
    pub gamma: f64,
    /// Its complex pair α ± iβ (β > 0).
    pub alpha: f64,
    pub beta: f64,
    /// T and T⁻¹, with A⁻¹ T = T Λ.
    pub t: [[f64; 3]; 3],
    pub t_inv: [[f64; 3]; 3],
}

impl Transformation {
    pub fn new(tableau: &Tableau<3>) -> Self {
        let a = Matrix3::from_fn(|i, j| tableau.a[i][j]);
        let a_inv = a.try_inverse().expect("Radau IIA's A is invertible");
        let eigen = a_inv.complex_eigenvalues();
        let real = eigen
            .iter()
            .min_by(|x, y| x.im.abs().total_cmp(&y.im.abs()))
            .copied()
            .expect("three eigenvalues");
        let pair = eigen
            .iter()
            .find(|l| l.im > 0.0)
            .copied()
            .expect("a complex pair");
        // The real eigenvector: the null space of A⁻¹ − γ I.
        // RADAU5's normalization, which its convergence test (on the corrections of W)
        // depends on: the real eigenvector of unit length with a positive last component, the
        // complex one with last component 1.
        let v1 = null_vector(&a_inv.map(Complex::from), Complex::from(real.re));
        let length = v1.iter().map(|c| c.norm_sqr()).sum::<f64>().sqrt();
        let sign = v1[2].re.signum();
        let v1 = v1.map(|c| c * (sign / length));
        // The complex one for α − iβ (RADAU5's): A⁻¹ (vr + i vi) = (α − iβ)(vr + i vi), so
        // that A⁻¹ [vr vi] = [vr vi] [[α, −β], [β, α]].
        let v = null_vector(&a_inv.map(Complex::from), pair.conj());
        let last = v[2];
        let v = v.map(|c| c / last);
        let t = Matrix3::from_fn(|i, j| match j {
            0 => v1[i].re,
            1 => v[i].re,
            _ => v[i].im,
        });
        let t_inv = t.try_inverse().expect("T is invertible");
        Transformation {
            gamma: real.re,
            alpha: pair.re,
            beta: pair.im,
            t: core::array::from_fn(|i| core::array::from_fn(|j| t[(i, j)])),
            t_inv: core::array::from_fn(|i| core::array::from_fn(|j| t_inv[(i, j)])),
        }
    }
}

/// A vector spanning the null space of m − λ I (3 × 3, λ an eigenvalue): the cross product
/// of two of its rows, the pair with the largest product.
fn null_vector(m: &nalgebra::Matrix3<Complex<f64>>, lambda: Complex<f64>) -> [Complex<f64>; 3] {
    let shifted = m - nalgebra::Matrix3::from_diagonal_element(lambda);
    let row = |i: usize| [shifted[(i, 0)], shifted[(i, 1)], shifted[(i, 2)]];
    let cross = |a: [Complex<f64>; 3], b: [Complex<f64>; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let size = |v: &[Complex<f64>; 3]| v.iter().map(|c| c.norm_sqr()).sum::<f64>();
    [
        cross(row(0), row(1)),
        cross(row(0), row(2)),
        cross(row(1), row(2)),
    ]
    .into_iter()
    .max_by(|a, b| size(a).total_cmp(&size(b)))
    .expect("three candidates")
}

/// The two factored matrices of a step size and Jacobian, and the iteration's workspace,
/// allocated with the integration and reused by every factorization.
pub(crate) struct TransformedStages<V: Vector> {
    controlled: usize,
    pub transformation: Transformation,
    /// The LU factors of γ/h I − J (the error estimate's matrix too) and of (α + iβ)/h I − J,
    /// valid for the h and Jacobian in `formed`, if any.
    real: V::Lu,
    complex: V::ComplexLu,
    /// The h and the Jacobian (by its count) the factors are for: none before the first
    /// factorization and after a singular one.
    formed: Option<(f64, usize)>,
    /// The right-hand sides of the two systems, solved in place: ΔW₁, and ΔW₂ + iΔW₃.
    real_rhs: V,
    complex_rhs: Vec<Complex<f64>>,
    /// RADAU5's FACCON, carried from step to step.
    faccon: f64,
    /// The eigenvalues of the tableau's A, for the singularity test: computed (a Schur
    /// decomposition) at the first suspicious pivot, then kept.
    method_eigenvalues: Option<Vec<Complex<f64>>>,
}

impl<V: Vector> TransformedStages<V> {
    pub fn new(controlled: usize, tableau: &Tableau<3>) -> Self {
        let n = V::LEN;
        TransformedStages {
            controlled: controlled.clamp(1, n.max(1)),
            transformation: Transformation::new(tableau),
            real: V::Lu::new(),
            complex: V::ComplexLu::new(),
            formed: None,
            real_rhs: V::zeros(),
            complex_rhs: vec![Complex::new(0.0, 0.0); n],
            faccon: 1.0,
            method_eigenvalues: None,
        }
    }

    /// Solves (γ/h I − J) x = b in place with the current factorization (the error
    /// estimate's).
    pub fn solve_real(&self, b: &mut V) {
        debug_assert!(self.formed.is_some(), "factored before use");
        self.real.solve(b.as_mut());
    }

    /// Factors both matrices for step h and the Jacobian `jacobian` (number `id` of the
    /// integration), unless done already; two LU factorizations, counted as two (as scipy's
    /// `Radau` counts them). `Some(λ)` when one is singular: the eigenvalue of J that makes
    /// it so (a growing mode at the step: [`super::singular`]).
    pub fn factor(
        &mut self,
        jacobian: &DMatrix<f64>,
        (h, id): (f64, usize),
        tableau: &Tableau<3>,
        stats: &mut Stats,
    ) -> Option<(f64, f64)> {
        if self.formed == Some((h, id)) {
            return None;
        }
        let tr = &self.transformation;
        let (g, s) = (tr.gamma / h, Complex::new(tr.alpha / h, tr.beta / h));
        let (real, complex) = factor_pair::<V>(&mut self.real, &mut self.complex, jacobian, g, s);
        stats.factorizations += 2;
        self.formed = None;
        let suspicious = relative_pivot(real.smallest, real.largest) <= SUSPICIOUS_PIVOT
            || complex.suspicious(&self.complex, jacobian);
        if suspicious {
            let mus = self
                .method_eigenvalues
                .get_or_insert_with(|| method_eigenvalues(&tableau.a));
            if let Some(mode) = growing_mode(jacobian, h, mus) {
                return Some(mode);
            }
        }
        self.formed = Some((h, id));
        None
    }

    /// Solves the stage equations of the step h from (t, y) from the starting values `z`,
    /// leaving the solution there: RADAU5's iteration in W = (T⁻¹ ⊗ I) Z, its corrections
    /// measured relative to `scale` over the controlled components.
    #[allow(clippy::too_many_arguments)]
    pub fn iterate<O: Ode<State = V>>(
        &mut self,
        ode: &mut O,
        tableau: &Tableau<3>,
        (t, y, h): (f64, &V, f64),
        z: &mut [V; 3],
        criterion: Criterion,
        scale: &V,
        stats: &mut Stats,
    ) -> Result<Outcome, Error> {
        let tr = self.transformation.clone();
        let mut w = transform(&tr.t_inv, z);
        let mut f = [V::zeros(); 3];
        let mut convergence = Convergence::new(criterion, &mut self.faccon);
        for k in 1..=convergence.max_iterations() {
            stage_slopes(ode, &tableau.c, (t, y, h), z, &mut f, stats)?;
            // G = (T⁻¹ ⊗ I) F.
            let gt = transform(&tr.t_inv, &f);
            let solved = self.solve_corrections(&w, &gt, h);
            // The corrections measured and added in one pass (W is not read again when the
            // iteration fails).
            let increment = self.correct(&mut w, scale);
            if let Some(failed) = convergence.judge(k, increment, solved, &mut self.faccon) {
                return Ok(failed);
            }
            *z = transform(&tr.t, &w);
            if let Some(outcome) = convergence.settled(k, increment, &mut self.faccon) {
                return Ok(outcome);
            }
        }
        Ok(convergence.exhausted())
    }

    /// The corrections ΔW₁ and ΔW₂ + iΔW₃ of the step h from the iterate `w` and
    /// G = (T⁻¹ ⊗ I) F, in `real_rhs` and `complex_rhs`: the two systems solved with the
    /// right-hand sides −(Λ/h ⊗ I) W + G. Whether the solves succeeded.
    fn solve_corrections(&mut self, w: &[V; 3], gt: &[V; 3], h: f64) -> bool {
        debug_assert!(self.formed.is_some(), "factored before the iteration");
        let tr = &self.transformation;
        let (g, a, b) = (tr.gamma / h, tr.alpha / h, tr.beta / h);
        let real = self.real_rhs.as_mut();
        for (p, (r, c)) in real.iter_mut().zip(&mut self.complex_rhs).enumerate() {
            let (w1, w2, w3) = (w[0].as_ref()[p], w[1].as_ref()[p], w[2].as_ref()[p]);
            *r = gt[0].as_ref()[p] - g * w1;
            let r2 = gt[1].as_ref()[p] - (a * w2 - b * w3);
            let r3 = gt[2].as_ref()[p] - (b * w2 + a * w3);
            *c = Complex::new(r2, r3);
        }
        self.real.solve(self.real_rhs.as_mut()) && self.complex.solve(&mut self.complex_rhs)
    }

    /// Adds the corrections ΔW (in `real_rhs` and `complex_rhs`) to `w`, and returns
    /// RADAU5's norm of them: √(mean((ΔWᵢ / scale)²)) over the three stages and the
    /// controlled components (the first `controlled`).
    #[inline(always)]
    fn correct(&self, w: &mut [V; 3], scale: &V) -> f64 {
        let len = self.controlled;
        let [w1, w2, w3] = w;
        let (real, complex) = (self.real_rhs.as_ref(), &self.complex_rhs[..]);
        let (w1, w2, w3) = (w1.as_mut(), w2.as_mut(), w3.as_mut());
        // The controlled components, measured, then the others: zipped slices, no index
        // checks and no branch in the loops. The sum of squares starts at +0 (`Sum` starts
        // at −0: its first term is +0 or more, so the sums are the same).
        let mut sum = 0.0;
        if len == V::LEN {
            // Every component controlled (the usual case): loops of a length known at
            // compile time, unrolled for a small system.
            for ((((r, c), s), w1), (w2, w3)) in real
                .iter()
                .zip(complex)
                .zip(scale.as_ref())
                .zip(w1.iter_mut())
                .zip(w2.iter_mut().zip(w3.iter_mut()))
            {
                sum += (r / s).powi(2) + (c.re / s).powi(2) + (c.im / s).powi(2);
                *w1 += r;
                *w2 += c.re;
                *w3 += c.im;
            }
            return (sum / (3 * len) as f64).sqrt();
        }
        for ((((r, c), s), w1), (w2, w3)) in real[..len]
            .iter()
            .zip(&complex[..len])
            .zip(&scale.as_ref()[..len])
            .zip(&mut w1[..len])
            .zip(w2[..len].iter_mut().zip(&mut w3[..len]))
        {
            sum += (r / s).powi(2) + (c.re / s).powi(2) + (c.im / s).powi(2);
            *w1 += r;
            *w2 += c.re;
            *w3 += c.im;
        }
        for (((r, c), w1), (w2, w3)) in real[len..]
            .iter()
            .zip(&complex[len..])
            .zip(&mut w1[len..])
            .zip(w2[len..].iter_mut().zip(&mut w3[len..]))
        {
            *w1 += r;
            *w2 += c.re;
            *w3 += c.im;
        }
        (sum / (3 * len) as f64).sqrt()
    }
}

/// A factored matrix's smallest pivot and largest entry, in modulus.
struct Pivots {
    smallest: f64,
    largest: f64,
}

/// Forms and factors γ/h I − J (`g` = γ/h) and (α + iβ)/h I − J (`s`) from the Jacobian,
/// read column by column (its storage order). Off the diagonal both hold −J, written as
/// `0.0 - j` and `zero - j` (not −j: the sign of a zero, as the matrices were always formed),
/// the complex entries with a zero imaginary part, whose modulus is |j| exactly: only the n
/// diagonal entries of the complex matrix need a modulus of their own for the largest entry,
/// and of those only the ones whose squared modulus is within 10⁻¹² of the largest one's.
fn factor_pair<V: Vector>(
    real: &mut V::Lu,
    complex: &mut V::ComplexLu,
    jacobian: &DMatrix<f64>,
    g: f64,
    s: Complex<f64>,
) -> (Pivots, ComplexEntries) {
    let zero = Complex::new(0.0, 0.0);
    let n = V::LEN;
    debug_assert_eq!((jacobian.nrows(), jacobian.ncols()), (n, n));
    let js = jacobian.as_slice();
    // Column by column (the storage order of both), as slices: no index checks. The complex
    // column is written whole, then its diagonal entry over it: no branch an entry (for the
    // real one, splitting the column around its diagonal cost more on n = 3 than it saved).
    let (mut off_diagonal, mut real_diagonal, mut diagonal_square) = (0.0f64, 0.0f64, 0.0f64);
    let real_smallest = real.factor(|m| {
        if V::LEN >= SPLIT_FROM {
            // The column around its diagonal, the maxima the closure's own (see `negated`).
            let (mut off, mut diagonal) = (0.0f64, 0.0f64);
            for (c, (column, js)) in square::<V, _>(m, js).enumerate() {
                let ((above, rest), (j_above, j_rest)) = (column.split_at_mut(c), js.split_at(c));
                off = negated(above, j_above, off);
                rest[0] = g - j_rest[0];
                diagonal = larger(diagonal, rest[0].abs());
                off = negated(&mut rest[1..], &j_rest[1..], off);
            }
            (off_diagonal, real_diagonal) = (off, diagonal);
            return;
        }
        for (c, (column, js)) in square::<V, _>(m, js).enumerate() {
            for (r, (v, &j)) in column.iter_mut().zip(js).enumerate() {
                if r == c {
                    *v = g - j;
                    real_diagonal = larger(real_diagonal, v.abs());
                } else {
                    *v = 0.0 - j;
                    off_diagonal = larger(off_diagonal, j.abs());
                }
            }
        }
    });
    // The complex diagonal's running maximum is the closure's own, handed out at the end:
    // kept in a register (a captured one is stored back after every column, as the matrix
    // might alias it; for the real matrix's two maxima that cost less than what the
    // compiler did with them as locals, not unrolling the columns at n = 8).
    complex.form(|m| {
        let mut square_max = 0.0f64;
        for (c, (column, js)) in square::<V, _>(m, js).enumerate() {
            for (v, &j) in column.iter_mut().zip(js) {
                *v = zero - j;
            }
            column[c] = s - js[c];
            square_max = larger(square_max, column[c].norm_sqr());
        }
        diagonal_square = square_max;
    });
    (
        Pivots {
            smallest: real_smallest,
            largest: real_diagonal.max(off_diagonal),
        },
        ComplexEntries {
            s,
            diagonal_square,
            off_diagonal,
        },
    )
}

/// What forming the complex matrix (α + iβ)/h I − J measured of its entries: the largest
/// |j| off the diagonal and the largest squared modulus on it, from which its pivots are
/// judged.
struct ComplexEntries {
    s: Complex<f64>,
    diagonal_square: f64,
    off_diagonal: f64,
}

impl ComplexEntries {
    /// The factored matrix's smallest pivot and largest entry, in modulus: `hypot`s, the
    /// largest diagonal entry's taken only of the entries that can be the largest (as
    /// `dense::smallest_modulus` takes the smallest pivot's).
    fn pivots<C: SquareLu<Complex<f64>>>(&self, complex: &C, jacobian: &DMatrix<f64>) -> Pivots {
        let (s, diagonal_square) = (self.s, self.diagonal_square);
        let diagonal = || (0..jacobian.nrows()).map(|c| s - jacobian[(c, c)]);
        let complex_diagonal = if diagonal_square.is_finite() && diagonal_square > SQUARE_FLOOR {
            let bound = diagonal_square * (1.0 - SQUARE_MARGIN);
            diagonal()
                .filter(|d| d.norm_sqr() >= bound)
                .fold(0.0, |m, d| larger(m, d.norm()))
        } else {
            diagonal().fold(0.0, |m, d| larger(m, d.norm()))
        };
        Pivots {
            smallest: complex.smallest_pivot(),
            largest: complex_diagonal.max(self.off_diagonal),
        }
    }

    /// Whether the smallest pivot relative to the largest entry is at most
    /// [`SUSPICIOUS_PIVOT`], as [`Self::pivots`] would tell, settled on their squared moduli
    /// where that ratio is not a near-tie ([`settled_by_squares`]): no `hypot` then, some
    /// 100 instructions a factorization at n = 3.
    fn suspicious<C: SquareLu<Complex<f64>>>(&self, complex: &C, jacobian: &DMatrix<f64>) -> bool {
        let largest_square = self
            .diagonal_square
            .max(self.off_diagonal * self.off_diagonal);
        let settled = complex
            .smallest_pivot_square()
            .and_then(|smallest| settled_by_squares(smallest, largest_square));
        settled.unwrap_or_else(|| {
            let pivots = self.pivots(complex, jacobian);
            relative_pivot(pivots.smallest, pivots.largest) <= SUSPICIOUS_PIVOT
        })
    }
}

/// `relative_pivot(smallest, largest) <= SUSPICIOUS_PIVOT` from the squares of the two
/// moduli (each within a few ulps of the exact square), where their ratio differs from
/// SUSPICIOUS_PIVOT² by more than a relative [`SQUARE_MARGIN`]: far beyond any rounding of
/// the squares, of the moduli (`hypot`, within an ulp) and of their quotient, so the answer
/// is the one the moduli give. `None` for a near-tie, or squares that are not finite, normal
/// numbers above [`SQUARE_FLOOR`].
fn settled_by_squares(smallest_square: f64, largest_square: f64) -> Option<bool> {
    let normal = |q: f64| q.is_finite() && q > SQUARE_FLOOR;
    if !(normal(smallest_square) && normal(largest_square)) {
        return None;
    }
    let ratio = smallest_square / largest_square;
    let threshold = SUSPICIOUS_PIVOT * SUSPICIOUS_PIVOT;
    if ratio > threshold * (1.0 + SQUARE_MARGIN) {
        Some(false)
    } else if ratio < threshold * (1.0 - SQUARE_MARGIN) {
        Some(true)
    } else {
        None
    }
}

/// The columns of a matrix's storage `m` and of the Jacobian `js`, paired, both sliced to n²
/// entries with n = `V::LEN`: lengths known at compile time inside the closures that fill the
/// matrices (not the n they would capture from outside, read at run time), so
/// that a small matrix's loops are unrolled (with the lengths they are called with, read at
/// run time, they were loops with a division for their trip count: some 90 instructions more
/// a factorization at n = 3).
#[inline(always)]
fn square<'a, 'b, V: Vector, T>(
    m: &'a mut [T],
    js: &'b [f64],
) -> impl Iterator<Item = (&'a mut [T], &'b [f64])> {
    let n = V::LEN;
    let (m, js) = (&mut m[..n * n], &js[..n * n]);
    m.chunks_exact_mut(n.max(1)).zip(js.chunks_exact(n.max(1)))
}

/// The least n whose real matrix is filled a column around its diagonal at a time, with its
/// maxima in registers: at n = 20 the entry-by-entry loop, a branch on the diagonal and both
/// maxima stored back to memory an entry, took some 14 instructions an entry (POLLU's Radau5
/// spent 6 % of its instructions there, 24 % fewer split); at n = 8 (HIRES) the split cost
/// 0.6 % more of the whole run, and at n = 3 more too.
const SPLIT_FROM: usize = 12;

/// Writes `0.0 - j` of each `j` of `js` to `v` (as the matrices were always formed, see
/// `factor_pair`) and returns the running maximum `m` of the |j| (by `larger`).
#[inline(always)]
fn negated(v: &mut [f64], js: &[f64], mut m: f64) -> f64 {
    for (v, &j) in v.iter_mut().zip(js) {
        *v = 0.0 - j;
        m = larger(m, j.abs());
    }
    m
}

/// The larger of a running maximum `m` (never NaN: it starts at 0) and `x`, and `m` when `x`
/// is NaN: what `m.max(x)` gives, by one comparison (`f64::max` also handles a NaN `m`, some
/// three instructions more for each entry of the matrices).
#[inline(always)]
fn larger(m: f64, x: f64) -> f64 {
    if x > m { x } else { m }
}

/// (M ⊗ I) applied to three stage vectors: each output entry m_i0·x0 + m_i1·x1 + m_i2·x2,
/// summed left to right (what `Iterator::sum` from −0 gives, −0 + a being a for every a),
/// written in place component by component: no closure per stage and no copy of a stage
/// vector out of one, whose inlining varied from build to build (at n = 8 a third of the
/// iteration's instructions went to `array::from_fn`'s machinery and copies).
#[inline(always)]
fn transform<V: Vector>(m: &[[f64; 3]; 3], x: &[V; 3]) -> [V; 3] {
    let mut out = [V::zeros(); 3];
    let [o0, o1, o2] = &mut out;
    let (x0, x1, x2) = (x[0].as_ref(), x[1].as_ref(), x[2].as_ref());
    let row = |i: usize, a: f64, b: f64, c: f64| m[i][0] * a + m[i][1] * b + m[i][2] * c;
    for ((((o0, o1), o2), x0), (x1, x2)) in o0
        .as_mut()
        .iter_mut()
        .zip(o1.as_mut())
        .zip(o2.as_mut())
        .zip(x0)
        .zip(x1.iter().zip(x2))
    {
        *o0 = row(0, *x0, *x1, *x2);
        *o1 = row(1, *x0, *x1, *x2);
        *o2 = row(2, *x0, *x1, *x2);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A Jacobian with entries of every sign and size, zeros of both signs among them.
    fn mixed_jacobian(n: usize) -> DMatrix<f64> {
        DMatrix::from_fn(n, n, |r, c| match (r * n + c) % 5 {
            0 => 0.0,
            1 => -0.0,
            k => (k as f64 - 3.5) * 10f64.powi((r as i32 - c as i32) * 3) / (1.0 + c as f64),
        })
    }

    /// Another, of full rank at n = 20 (where `mixed_jacobian`'s columns are multiples of one
    /// vector or zero): sizes 10⁻⁶ to 10⁶ scattered, zeros of both signs.
    fn scattered_jacobian(n: usize) -> DMatrix<f64> {
        DMatrix::from_fn(n, n, |r, c| match (r * 7 + c * 3) % 5 {
            0 => 0.0,
            1 => -0.0,
            k => {
                let exponent = ((r * 5 + c * 11) % 7) as i32 * 2 - 6;
                (k as f64 - 3.5) * 10f64.powi(exponent) / (1.0 + c as f64)
            }
        })
    }

    /// At n = 6 the real matrix is filled entry by entry, at n = 20 a column around its
    /// diagonal at a time (`SPLIT_FROM`): both as written, to the bit.
    #[test]
    fn the_matrices_are_formed_as_written_and_their_largest_entries_exactly() {
        const { assert!(6 < SPLIT_FROM && 20 >= SPLIT_FROM) };
        formed_as_written::<6>(mixed_jacobian(6));
        formed_as_written::<20>(scattered_jacobian(20));
    }

    fn formed_as_written<const N: usize>(jacobian: DMatrix<f64>) {
        let tableau = Tableau::radau_iia();
        let stages = TransformedStages::<[f64; N]>::new(N, &tableau);
        let bits = |v: f64| v.to_bits();
        // At 1e-20 the diagonal of the complex matrix is its largest entry (|(α + iβ)/h|
        // ≈ 4e20 over |J| ≤ 1e15), at the others an entry of J is.
        for h in [1e-20, 1e-9, 0.3, 7e4] {
            let tr = &stages.transformation;
            let (g, s) = (tr.gamma / h, Complex::new(tr.alpha / h, tr.beta / h));
            let (mut real, mut complex) = (
                <[f64; N] as Vector>::Lu::new(),
                <[f64; N] as Vector>::ComplexLu::new(),
            );
            let (real_pivots, complex_entries) =
                factor_pair::<[f64; N]>(&mut real, &mut complex, &jacobian, g, s);
            let complex_pivots = complex_entries.pivots(&complex, &jacobian);
            // The screened test tells what the moduli tell.
            assert_eq!(
                complex_entries.suspicious(&complex, &jacobian),
                relative_pivot(complex_pivots.smallest, complex_pivots.largest) <= SUSPICIOUS_PIVOT,
                "h = {h}"
            );
            // The definitions: each entry as written, the largest by a modulus of each.
            let zero = Complex::new(0.0, 0.0);
            let expected_real = DMatrix::from_fn(N, N, |r, c| {
                (if r == c { g } else { 0.0 }) - jacobian[(r, c)]
            });
            let expected_complex = DMatrix::from_fn(N, N, |r, c| {
                (if r == c { s } else { zero }) - jacobian[(r, c)]
            });
            assert_eq!(
                bits(real_pivots.largest),
                bits(expected_real.amax()),
                "h = {h}"
            );
            let complex_largest = expected_complex
                .iter()
                .map(|z| z.norm())
                .fold(0.0, f64::max);
            assert_eq!(
                bits(complex_pivots.largest),
                bits(complex_largest),
                "h = {h}"
            );
            // The factors solve as nalgebra's LU of the matrices as written, to the bit.
            let b: [f64; N] = core::array::from_fn(|i| 1.0 - 0.3 * i as f64);
            let mut x = b;
            assert!(real.solve(&mut x));
            let mut y = nalgebra::DVector::from_column_slice(&b);
            assert!(expected_real.lu().solve_mut(&mut y));
            assert_eq!(x.map(bits).to_vec(), y.map(bits).as_slice());
            let bc: Vec<Complex<f64>> = b.iter().map(|v| Complex::new(*v, -v)).collect();
            let mut xc = bc.clone();
            assert!(complex.solve(&mut xc));
            let mut yc = nalgebra::DVector::from_vec(bc);
            assert!(expected_complex.lu().solve_mut(&mut yc));
            for (a, b) in xc.iter().zip(yc.iter()) {
                assert_eq!(
                    (bits(a.re), bits(a.im)),
                    (bits(b.re), bits(b.im)),
                    "h = {h}"
                );
            }
        }
    }

    /// The test on squared moduli answers as the moduli do wherever it answers, on pairs of
    /// complex numbers around the threshold (a relative 10⁻⁶ to 10⁻¹⁵ from it, and exactly
    /// at it), of every size from 10⁻¹²⁰ to 10¹²⁰ and direction; and it answers away from
    /// the threshold.
    #[test]
    fn the_squares_settle_the_singularity_test_as_the_moduli_do() {
        let (mut answered, mut ties) = (0, 0);
        for k in 0..4000u32 {
            let angle = |j: u32| 0.61 * f64::from(j) + 0.1;
            let size = 10f64.powi((k % 241) as i32 - 120);
            let large = Complex::from_polar(size, angle(k));
            let offset = match k % 5 {
                0 => 0.0,
                1 => 1e-6,
                2 => -1e-12,
                3 => 1e-15 * f64::from(k % 7),
                _ => -1e-13 * f64::from(k % 11),
            };
            let small = Complex::from_polar(
                large.norm() * SUSPICIOUS_PIVOT * (1.0 + offset),
                angle(k / 3 + 1),
            );
            let exact = relative_pivot(small.norm(), large.norm()) <= SUSPICIOUS_PIVOT;
            match settled_by_squares(small.norm_sqr(), large.norm_sqr()) {
                Some(screened) => {
                    assert_eq!(screened, exact, "{small} against {large}");
                    answered += 1;
                }
                None => ties += 1,
            }
        }
        assert!(
            answered > 1500 && ties > 1500,
            "{answered} answered, {ties} ties"
        );
        assert_eq!(settled_by_squares(1.0, 1e20), Some(false));
        assert_eq!(settled_by_squares(1e-20, 1e20), Some(true));
        assert_eq!(settled_by_squares(1.0, 0.0), None);
        assert_eq!(settled_by_squares(f64::NAN, 1.0), None);
        assert_eq!(settled_by_squares(1.0, f64::INFINITY), None);
    }

    /// The transform is (M ⊗ I) x as `Iterator::sum` adds it, to the bit, zeros of both
    /// signs included.
    #[test]
    fn the_transform_is_the_summed_products() {
        let tr = Transformation::new(&Tableau::radau_iia());
        let value = |k: usize| match k % 6 {
            0 => 0.0,
            1 => -0.0,
            _ => (k as f64 * 0.37).sin() * 10f64.powi(k as i32 % 9 - 4),
        };
        let x: [[f64; 5]; 3] = core::array::from_fn(|i| core::array::from_fn(|p| value(5 * i + p)));
        for m in [
            &tr.t,
            &tr.t_inv,
            &[[0.0, -0.0, 1.0], [-0.0, -0.0, -0.0], [2.0, 0.5, -3.0]],
        ] {
            let ours = transform(m, &x);
            for (i, row) in ours.iter().enumerate() {
                for (p, v) in row.iter().enumerate() {
                    let summed: f64 = (0..3).map(|j| m[i][j] * x[j][p]).sum();
                    assert_eq!(v.to_bits(), summed.to_bits(), "({i}, {p})");
                }
            }
        }
    }

    /// The test binary's allocator: the system's, counting the blocks each thread asks for,
    /// so that a test can tell that a call allocated nothing.
    #[global_allocator]
    static ALLOCATOR: Counting = Counting;

    struct Counting;

    std::thread_local! {
        static BLOCKS: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
    }

    fn count() {
        // `try_with`: allocations while the thread's storage is torn down go uncounted.
        let _ = BLOCKS.try_with(|blocks| blocks.set(blocks.get() + 1));
    }

    // SAFETY: every call is forwarded to the system allocator unchanged.
    unsafe impl std::alloc::GlobalAlloc for Counting {
        unsafe fn alloc(&self, layout: std::alloc::Layout) -> *mut u8 {
            count();
            unsafe { std::alloc::System.alloc(layout) }
        }
        unsafe fn alloc_zeroed(&self, layout: std::alloc::Layout) -> *mut u8 {
            count();
            unsafe { std::alloc::System.alloc_zeroed(layout) }
        }
        unsafe fn realloc(
            &self,
            ptr: *mut u8,
            layout: std::alloc::Layout,
            new_size: usize,
        ) -> *mut u8 {
            count();
            unsafe { std::alloc::System.realloc(ptr, layout, new_size) }
        }
        unsafe fn dealloc(&self, ptr: *mut u8, layout: std::alloc::Layout) {
            unsafe { std::alloc::System.dealloc(ptr, layout) }
        }
    }

    #[test]
    fn refactoring_allocates_nothing() {
        let tableau = Tableau::radau_iia();
        const N: usize = 6;
        let mut stages = TransformedStages::<[f64; N]>::new(N, &tableau);
        // Well conditioned (a step's matrices with a suspicious pivot would be examined for a
        // growing mode, which allocates).
        let jacobian = DMatrix::from_fn(N, N, |r, c| ((r * N + c) % 7) as f64 - 3.0)
            - DMatrix::identity(N, N) * 1e3;
        let mut stats = Stats::default();
        let mut factor = |stages: &mut TransformedStages<[f64; N]>, key| {
            assert_eq!(stages.factor(&jacobian, key, &tableau, &mut stats), None);
        };
        // A new h, a new Jacobian, and the same h and Jacobian again (nothing to do): not one
        // block allocated, the matrices and their permutations being statically sized.
        BLOCKS.with(|blocks| blocks.set(0));
        for key in [(0.1, 1), (0.2, 1), (0.2, 2), (0.2, 2)] {
            factor(&mut stages, key);
        }
        assert_eq!(BLOCKS.with(|blocks| blocks.get()), 0);
        // Two LUs (the real and the complex system) for each of three factorizations.
        assert_eq!(stats.factorizations, 6);
    }

    // RADAU5's constants below with the digits its source gives.
    #[allow(clippy::excessive_precision)]
    #[test]
    fn the_transformation_block_diagonalizes_the_inverse_of_a() {
        let tableau = Tableau::radau_iia();
        let tr = Transformation::new(&tableau);
        // RADAU5's constants: γ = 1/U1 with U1 = (6 + 81^(1/3) − 9^(1/3))/30, and α ± iβ from
        // ALPH = (12 − 81^(1/3) + 9^(1/3))/60, BETA = (81^(1/3) + 9^(1/3))·√3/60 over
        // ALPH² + BETA².
        let (c81, c9) = (81f64.cbrt(), 9f64.cbrt());
        let gamma = 30.0 / (6.0 + c81 - c9);
        let (alph, beta) = ((12.0 - c81 + c9) / 60.0, (c81 + c9) * 3f64.sqrt() / 60.0);
        let cno = alph * alph + beta * beta;
        assert!((tr.gamma - gamma).abs() < 1e-12);
        assert!((tr.alpha - alph / cno).abs() < 1e-12 && (tr.beta - beta / cno).abs() < 1e-12);
        // T⁻¹ A⁻¹ T = Λ.
        let a = Matrix3::from_fn(|i, j| tableau.a[i][j]);
        let t = Matrix3::from_fn(|i, j| tr.t[i][j]);
        let t_inv = Matrix3::from_fn(|i, j| tr.t_inv[i][j]);
        let lambda = t_inv * a.try_inverse().unwrap() * t;
        let expected = Matrix3::new(
            tr.gamma, 0.0, 0.0, 0.0, tr.alpha, -tr.beta, 0.0, tr.beta, tr.alpha,
        );
        assert!((lambda - expected).amax() < 1e-12, "{lambda}");
        // RADAU5's T (its T11 … T31; T32 = 1, T33 = 0).
        let radau5 = [
            [
                9.1232394870892942792e-2,
                -0.14125529502095420843,
                -3.0029194105147424492e-2,
            ],
            [
                0.24171793270710701896,
                0.20412935229379993199,
                0.38294211275726193779,
            ],
            [0.96604818261509293619, 1.0, 0.0],
        ];
        for (i, (ours, theirs)) in tr.t.iter().zip(&radau5).enumerate() {
            for (j, (a, b)) in ours.iter().zip(theirs).enumerate() {
                assert!((a - b).abs() < 1e-12, "T{i}{j} = {a}");
            }
        }
    }
}
