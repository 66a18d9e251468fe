//! The small dense linear algebra generated right-hand sides call: the inverse of A(q) by
//! LU with partial pivoting, for models that give no closed-form inverse. (The reduced mass
//! matrix is factored by LDLᵀ code the macro unrolls into the right-hand side itself.)
//!
//! Generic over [`Scalar`] so that dual numbers can flow through a generated right-hand
//! side; pivoting compares value parts only. Fixed sizes, no heap.

use crate::error::Singularity;
use crate::scalar::Scalar;

/// Relative size below which a pivot counts as zero: a few units of rounding.
fn negligible<S: Scalar, const N: usize>(a: &[[S; N]; N]) -> f64 {
    let scale = a
        .iter()
        .map(|row| row.iter().map(|x| x.re().abs()).sum::<f64>())
        .fold(0.0, f64::max);
    (N as f64) * f64::EPSILON * scale
}

/// The inverse of `a`, or the pivot at which it is (numerically) singular.
pub fn invert<S: Scalar, const N: usize>(a: &[[S; N]; N]) -> Result<[[S; N]; N], Singularity> {
    let tiny = negligible(a);
    let mut lu = *a;
    let mut perm = [0usize; N];
    for (i, p) in perm.iter_mut().enumerate() {
        *p = i;
    }
    for k in 0..N {
        let mut best = k;
        for r in k + 1..N {
            if lu[r][k].re().abs() > lu[best][k].re().abs() {
                best = r;
            }
        }
        let pivot = lu[best][k].re();
        if !(pivot.abs() > tiny) {
            return Err(Singularity::Transformation { pivot: k, value: pivot });
        }
        lu.swap(k, best);
        perm.swap(k, best);
        let inv = S::from_f64(1.0) / lu[k][k];
        for r in k + 1..N {
            let factor = lu[r][k] * inv;
            lu[r][k] = factor;
            for c in k + 1..N {
                lu[r][c] = lu[r][c] - factor * lu[k][c];
            }
        }
    }
    // Solve L U x = P e_j for every column j.
    let zero = S::from_f64(0.0);
    let mut inverse = [[zero; N]; N];
    for j in 0..N {
        let mut x = [zero; N];
        for i in 0..N {
            let mut s = if perm[i] == j { S::from_f64(1.0) } else { zero };
            for c in 0..i {
                s = s - lu[i][c] * x[c];
            }
            x[i] = s;
        }
        for i in (0..N).rev() {
            let mut s = x[i];
            for c in i + 1..N {
                s = s - lu[i][c] * x[c];
            }
            x[i] = s / lu[i][i];
        }
        for i in 0..N {
            inverse[i][j] = x[i];
        }
    }
    Ok(inverse)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inverse_of_a_permuted_matrix() {
        let a = [[0.0, 2.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 4.0]];
        let b = invert(&a).unwrap();
        for i in 0..3 {
            for j in 0..3 {
                let p: f64 = (0..3).map(|k| a[i][k] * b[k][j]).sum();
                assert!((p - if i == j { 1.0 } else { 0.0 }).abs() < 1e-15);
            }
        }
    }

    #[test]
    fn singular_matrix_names_the_pivot() {
        let a = [[1.0, 2.0], [2.0, 4.0]];
        match invert(&a) {
            Err(Singularity::Transformation { pivot, .. }) => assert_eq!(pivot, 1),
            other => panic!("expected a singular pivot, got {other:?}"),
        }
    }

    #[test]
    fn nan_is_singular_not_propagated() {
        let a = [[f64::NAN, 0.0], [0.0, 1.0]];
        assert!(invert(&a).is_err());
    }
}
