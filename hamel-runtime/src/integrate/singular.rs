//! Whether an implicit method's iteration matrix is singular, and why.
//!
//! The matrices an implicit step factors are I − h·(A ⊗ J) for its stage equations and
//! (u₁/h) I − J = (u₁/h)(I − (h/u₁) J) for Radau5's error estimate: I − h·μ·J for each
//! eigenvalue μ of A (or μ = 1/u₁). Such a matrix is singular exactly when h·μ·λ = 1 for an
//! eigenvalue λ of J. For an A-stable method every μ has a positive real part and
//! Re(1/μ) > 0, so that needs Re λ > 0: a motion that grows as e^(λt), with a time scale near
//! the step. For a stable system (every Re λ ≤ 0) the matrix is never singular, however large
//! h·‖J‖.
//!
//! The cheap test, a smallest LU pivot tiny beside the matrix's largest entry, is not
//! scale-invariant: at a step of 10⁹ on Robertson's problem the identity's entries are 10⁻¹³
//! of h·J's, and the pivots they leave look like rounding although the matrix is far from
//! singular (its eigenvalues 1 − hμλ are all at least 1 in size). So a tiny pivot is only a
//! suspicion; the verdict is taken on the eigenvalues λ of J, which no scaling of the state or
//! of h changes: singular when some 1 − hμλ is small.

use nalgebra::{Complex, ComplexField, DMatrix, Dyn, LU};

/// How close to 0 some |1 − hμλ| must be, relative to 1 (the identity's eigenvalue), for
/// the matrix to be singular: its LU is then no better than rounding.
const NEAR_SINGULAR: f64 = 1e-6;

/// Relative LU pivots at most this small raise the suspicion (then checked on the
/// eigenvalues): the smallest pivot over the matrix's largest entry.
pub(crate) const SUSPICIOUS_PIVOT: f64 = 1e-13;

/// The smallest LU pivot of a matrix relative to its largest entry (0 for a zero matrix).
pub(crate) fn relative_pivot(smallest: f64, largest: f64) -> f64 {
    if largest > 0.0 {
        smallest / largest
    } else {
        0.0
    }
}

/// The smallest pivot of an LU factorization in modulus: U's diagonal, read in place in the
/// packed factors (`LU::u` would copy U to read it; `lu_internal` is nalgebra's accessor for
/// them, hidden from its docs). Infinite for an empty matrix, whose largest entry is 0.
pub(crate) fn smallest_pivot<T>(lu: &LU<T, Dyn, Dyn>) -> f64
where
    T: ComplexField<RealField = f64>,
{
    let factors = lu.lu_internal();
    (0..factors.nrows())
        .map(|i| factors[(i, i)].clone().modulus())
        .fold(f64::INFINITY, f64::min)
}

/// The eigenvalue λ = (Re, Im) of `jacobian` that makes I − h·μ·J singular for one of the
/// eigenvalues μ of the method (`mus`), if one does: the growing motion to blame.
pub(crate) fn growing_mode(
    jacobian: &DMatrix<f64>,
    h: f64,
    mus: &[Complex<f64>],
) -> Option<(f64, f64)> {
    if jacobian.iter().any(|v| !v.is_finite()) {
        return None;
    }
    let lambdas = jacobian.clone().complex_eigenvalues();
    lambdas
        .iter()
        .filter(|l| l.re > 0.0)
        .map(|l| {
            let nearest = mus
                .iter()
                .map(|mu| (Complex::new(1.0, 0.0) - mu * l * h).norm())
                .fold(f64::INFINITY, f64::min);
            (nearest, (l.re, l.im))
        })
        .filter(|(nearest, _)| *nearest <= NEAR_SINGULAR)
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, l)| l)
}

/// The eigenvalues μ of a method's matrix A.
pub(crate) fn method_eigenvalues<const S: usize>(a: &[[f64; S]; S]) -> Vec<Complex<f64>> {
    DMatrix::from_fn(S, S, |i, j| a[i][j])
        .complex_eigenvalues()
        .iter()
        .copied()
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_a_growing_mode_at_the_step_makes_the_matrix_singular() {
        // The midpoint rule (μ = ½): J = 1 at h = 2 gives 1 − 2·½·1 = 0.
        let mus = [Complex::new(0.5, 0.0)];
        let growth = DMatrix::from_element(1, 1, 1.0);
        assert_eq!(growing_mode(&growth, 2.0, &mus), Some((1.0, 0.0)));
        assert_eq!(growing_mode(&growth, 1.0, &mus), None);
        // A stiff, stable J at a huge step: far from singular, however small its pivots.
        let stiff = DMatrix::from_row_slice(2, 2, &[-1e12, 0.0, 0.0, -1.0]);
        assert_eq!(growing_mode(&stiff, 1e9, &mus), None);
    }
}
