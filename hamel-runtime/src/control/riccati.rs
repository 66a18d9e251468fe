//! The continuous algebraic Riccati equation A'P + PA − PBR⁻¹B'P + Q = 0, its stabilizing
//! solution by the matrix sign function of the Hamiltonian matrix (Roberts 1980; Byers 1987,
//! with determinant scaling — the method of Drake's `ContinuousAlgebraicRiccatiEquation`),
//! refined to rounding by Newton–Kleinman steps (Kleinman 1968), each a Lyapunov equation
//! solved as its Kronecker-product linear system. Every factorization is nalgebra's.

use core::cmp::Ordering;

use nalgebra::{Cholesky, DMatrix, SVD, Schur};

use super::balance::{Balance, why_not};
use crate::error::{Error, Num};

/// The sign iteration has converged when a step changes the iterate by at most this much
/// of its norm (1-norm).
const SIGN_TOLERANCE: f64 = 1e-13;
/// Steps of the sign iteration before it counts as not converging (it converges
/// quadratically once the scaled iterate's eigenvalues are near ±1: about 10 for the
/// bicycle).
const MOST_SIGN_STEPS: usize = 100;
/// Newton–Kleinman steps at most, after the sign function (each at least doubles the correct
/// digits; two are usual).
const MOST_NEWTON_STEPS: usize = 8;
/// Above this many states the Lyapunov equations of the Newton steps (a dense system of
/// n² unknowns) are not solved, and the sign function's solution is returned as it is.
pub const MOST_REFINED_STATES: usize = 40;
/// Relative to the largest singular value, the smallest of the stable subspace's basis below
/// which that subspace is not the graph of a matrix: no stabilizing solution.
const GRAPH_TOLERANCE: f64 = 1e-12;

/// The stabilizing solution P of a Riccati equation and the optimal gain K = R⁻¹B'P.
#[derive(Clone, Debug, PartialEq)]
pub struct Riccati {
    /// P, symmetric positive semi-definite; A − BK is stable.
    pub solution: DMatrix<f64>,
    /// K = R⁻¹B'P.
    pub gain: DMatrix<f64>,
    /// max |A'P + PA − PBR⁻¹B'P + Q| over max(|Q|, |A'P|, |PGP|): what is left of the
    /// equation, relative to its terms.
    pub residual: f64,
    /// The sign iteration's steps and the Newton–Kleinman steps taken.
    pub steps: (usize, usize),
}

/// The stabilizing solution of A'P + PA − PBR⁻¹B'P + Q = 0 (the continuous algebraic Riccati
/// equation of LQR), with Q symmetric positive semi-definite and R symmetric positive
/// definite: scipy's `solve_continuous_are(A, B, Q, R)`, python-control's `care`, Drake's
/// `ContinuousAlgebraicRiccatiEquation`.
///
/// Errors: [`Error::DimensionMismatch`] for sizes that do not fit;
/// [`Error::InvalidWeights`] for a Q or R that is not symmetric, not semi-definite (Q) or
/// not definite (R), or not finite; [`Error::NoStabilizingSolution`] when (A, B) is not
/// stabilizable or the Hamiltonian matrix has eigenvalues on the imaginary axis (a mode of A
/// on the axis that Q does not see).
///
/// ```
/// use hamel_runtime::control::solve_care;
/// use nalgebra::DMatrix;
///
/// // The double integrator x'' = u with Q = I, R = 1: P = [[√3, 1], [1, √3]], K = [1, √3].
/// let a = DMatrix::from_row_slice(2, 2, &[0.0, 1.0, 0.0, 0.0]);
/// let b = DMatrix::from_row_slice(2, 1, &[0.0, 1.0]);
/// let riccati = solve_care(&a, &b, &DMatrix::identity(2, 2), &DMatrix::identity(1, 1))?;
/// let k = &riccati.gain;
/// assert!((k[(0, 0)] - 1.0).abs() < 1e-14 && (k[(0, 1)] - 3f64.sqrt()).abs() < 1e-14);
/// # Ok::<(), hamel_runtime::Error>(())
/// ```
pub fn solve_care(
    a: &DMatrix<f64>,
    b: &DMatrix<f64>,
    q: &DMatrix<f64>,
    r: &DMatrix<f64>,
) -> Result<Riccati, Error> {
    check_sizes(a, b, q, r)?;
    let cholesky = check_weights(q, r)?;
    let g = b * cholesky.solve(&b.transpose());
    // The equation solved on matrices of norm near 1, so that weights of any magnitude
    // neither overflow nor vanish in the Hamiltonian matrix (`balance`).
    let scaling = Balance::of(a, &g, q);
    let (sa, sb, sq) = scaling.apply(a, b, q);
    match solve_balanced(&sa, &sb, &sq, &cholesky) {
        Ok(riccati) => scaling.undo(riccati),
        Err(e @ Error::NoStabilizingSolution { .. }) => Err(why_not(a, b, q, &scaling, e)),
        Err(e) => Err(e),
    }
}

/// [`solve_care`] on a balanced problem.
fn solve_balanced(
    a: &DMatrix<f64>,
    b: &DMatrix<f64>,
    q: &DMatrix<f64>,
    cholesky: &Cholesky<f64, nalgebra::Dyn>,
) -> Result<Riccati, Error> {
    let r_inv_bt = cholesky.solve(&b.transpose());
    let g = b * &r_inv_bt;
    let (p, sign_steps) = sign_solution(a, &g, q)?;
    let (p, newton_steps) = refine(a, b, &g, q, &r_inv_bt, p)?;
    let gain = &r_inv_bt * &p;
    let closed = a - b * &gain;
    check_stable(&closed)?;
    let residual = residual(a, &g, q, &p);
    if residual.partial_cmp(&1e-6) != Some(Ordering::Less) {
        return Err(Error::NoStabilizingSolution {
            reason: format!(
                "the solution found leaves {} of the equation's terms (relative), so the \
                 problem is too ill-conditioned to solve to rounding or has no solution",
                Num(residual)
            ),
        });
    }
    Ok(Riccati {
        solution: p,
        gain,
        residual,
        steps: (sign_steps, newton_steps),
    })
}

fn check_sizes(
    a: &DMatrix<f64>,
    b: &DMatrix<f64>,
    q: &DMatrix<f64>,
    r: &DMatrix<f64>,
) -> Result<(), Error> {
    let (n, m) = (a.nrows(), b.ncols());
    let fits = a.is_square()
        && b.nrows() == n
        && q.shape() == (n, n)
        && r.shape() == (m, m)
        && n > 0
        && m > 0;
    if !fits {
        return Err(Error::DimensionMismatch {
            what: format!(
                "A is {} × {}, B {} × {}, Q {} × {}, R {} × {}: A must be n × n, B n × m, Q n × n \
                 and R m × m, with n and m at least 1",
                a.nrows(),
                a.ncols(),
                b.nrows(),
                b.ncols(),
                q.nrows(),
                q.ncols(),
                r.nrows(),
                r.ncols()
            ),
        });
    }
    for (name, matrix) in [("A", a), ("B", b)] {
        if let Some(v) = matrix.iter().find(|v| !v.is_finite()) {
            return Err(Error::InvalidSetting {
                name,
                value: *v,
                reason: "every entry of the system's matrices must be a finite number",
            });
        }
    }
    for (name, matrix) in [("Q", q), ("R", r)] {
        if let Some(v) = matrix.iter().find(|v| !v.is_finite()) {
            return Err(Error::InvalidWeights {
                matrix: name,
                reason: format!(
                    "has the entry {}: every entry must be a finite number",
                    Num(*v)
                ),
            });
        }
    }
    Ok(())
}

/// Q symmetric positive semi-definite, R symmetric positive definite (its Cholesky factor).
fn check_weights(
    q: &DMatrix<f64>,
    r: &DMatrix<f64>,
) -> Result<Cholesky<f64, nalgebra::Dyn>, Error> {
    for (name, m) in [("Q", q), ("R", r)] {
        let scale = m.amax().max(f64::MIN_POSITIVE);
        let asymmetry = (m - m.transpose()).amax();
        if asymmetry > 1e-12 * scale {
            return Err(Error::InvalidWeights {
                matrix: name,
                reason: format!(
                    "is not symmetric (its largest asymmetry is {}): weight x'Qx and u'Ru with \
                     symmetric matrices",
                    Num(asymmetry)
                ),
            });
        }
    }
    let least = q.clone().symmetric_eigen().eigenvalues.min();
    if least < -1e-12 * q.amax() {
        return Err(Error::InvalidWeights {
            matrix: "Q",
            reason: format!(
                "is not positive semi-definite (it has the eigenvalue {}): a state weight may \
                 not reward a deviation",
                Num(least)
            ),
        });
    }
    Cholesky::new(r.clone()).ok_or_else(|| Error::InvalidWeights {
        matrix: "R",
        reason: "is not positive definite: every input needs a positive weight, or the \
                 optimal input is unbounded"
            .to_string(),
    })
}

/// P from the matrix sign function of the Hamiltonian H = [[A, −G], [−Q, −A']]: its stable
/// invariant subspace is the span of [I; P], the null space of sign(H) + I.
fn sign_solution(
    a: &DMatrix<f64>,
    g: &DMatrix<f64>,
    q: &DMatrix<f64>,
) -> Result<(DMatrix<f64>, usize), Error> {
    let n = a.nrows();
    let mut z = DMatrix::zeros(2 * n, 2 * n);
    z.view_mut((0, 0), (n, n)).copy_from(a);
    z.view_mut((0, n), (n, n)).copy_from(&(-g));
    z.view_mut((n, 0), (n, n)).copy_from(&(-q));
    z.view_mut((n, n), (n, n)).copy_from(&(-a.transpose()));
    let on_axis = || Error::NoStabilizingSolution {
        reason: "the Hamiltonian matrix [[A, -BR^-1B'], [-Q, -A']] is singular or has \
                 eigenvalues on the imaginary axis: A has a mode on the axis that Q does not \
                 weight, or one that the inputs do not reach"
            .to_string(),
    };
    let mut steps = 0;
    loop {
        steps += 1;
        let lu = z.clone().lu();
        let det = lu.determinant();
        let inverse = lu.try_inverse().ok_or_else(on_axis)?;
        if !(det.is_finite() && det != 0.0) {
            return Err(on_axis());
        }
        // Byers' determinant scaling: c = |det Z|^(1/2n) brings the eigenvalues near ±1.
        let c = det.abs().powf(1.0 / (2 * n) as f64);
        let next = (&z / c + &inverse * c) * 0.5;
        let change = (&next - &z).lp_norm(1);
        let size = z.lp_norm(1);
        z = next;
        if !z.iter().all(|v| v.is_finite()) {
            return Err(on_axis());
        }
        if change <= SIGN_TOLERANCE * size {
            break;
        }
        if steps >= MOST_SIGN_STEPS {
            return Err(Error::NoStabilizingSolution {
                reason: format!(
                    "the matrix sign iteration did not converge in {MOST_SIGN_STEPS} steps: the \
                     Hamiltonian matrix has eigenvalues on or near the imaginary axis"
                ),
            });
        }
    }
    // (W + I)[I; P] = 0: [W12; W22 + I] P = −[W11 + I; W21], by least squares.
    let mut lhs = DMatrix::zeros(2 * n, n);
    lhs.view_mut((0, 0), (n, n))
        .copy_from(&z.view((0, n), (n, n)));
    lhs.view_mut((n, 0), (n, n))
        .copy_from(&(z.view((n, n), (n, n)) + DMatrix::identity(n, n)));
    let mut rhs = DMatrix::zeros(2 * n, n);
    rhs.view_mut((0, 0), (n, n))
        .copy_from(&(-(z.view((0, 0), (n, n)) + DMatrix::identity(n, n))));
    rhs.view_mut((n, 0), (n, n))
        .copy_from(&(-z.view((n, 0), (n, n))));
    let svd = SVD::new(lhs, true, true);
    let largest = svd.singular_values.max();
    let smallest = svd.singular_values.min();
    if smallest.partial_cmp(&(GRAPH_TOLERANCE * largest)) != Some(Ordering::Greater) {
        return Err(Error::NoStabilizingSolution {
            reason: format!(
                "the stable invariant subspace of the Hamiltonian matrix is not the graph of a \
                 matrix (its basis has the singular values {} and {}): (A, B) is not \
                 stabilizable, or a mode on the imaginary axis is not weighted by Q",
                Num(largest),
                Num(smallest)
            ),
        });
    }
    let p = svd
        .solve(&rhs, 0.0)
        .map_err(|reason| Error::NoStabilizingSolution {
            reason: reason.to_string(),
        })?;
    Ok(((&p + p.transpose()) * 0.5, steps))
}

/// Newton–Kleinman steps from P: K = R⁻¹B'P, then (A − BK)'X + X(A − BK) = −(Q + K'RK) for the
/// next P, while they reduce the residual (none above [`MOST_REFINED_STATES`] states).
fn refine(
    a: &DMatrix<f64>,
    b: &DMatrix<f64>,
    g: &DMatrix<f64>,
    q: &DMatrix<f64>,
    r_inv_bt: &DMatrix<f64>,
    mut p: DMatrix<f64>,
) -> Result<(DMatrix<f64>, usize), Error> {
    let n = a.nrows();
    if n > MOST_REFINED_STATES {
        return Ok((p, 0));
    }
    let mut current = residual(a, g, q, &p);
    let mut steps = 0;
    while steps < MOST_NEWTON_STEPS && current > 4.0 * f64::EPSILON {
        let k = r_inv_bt * &p;
        let closed = a - b * &k;
        // Q + K'RK = Q + P G P (K'RK = P B R⁻¹ R R⁻¹ B' P).
        let c = q + &p * g * &p;
        let Some(next) = lyapunov(&closed, &c) else {
            break;
        };
        let next = (&next + next.transpose()) * 0.5;
        let after = residual(a, g, q, &next);
        if after.partial_cmp(&current) != Some(Ordering::Less) {
            break;
        }
        p = next;
        current = after;
        steps += 1;
    }
    Ok((p, steps))
}

/// X with A'X + XA = −C, from the Kronecker form (I ⊗ A' + A' ⊗ I) vec X = −vec C (columns
/// stacked); `None` when that system is singular (A and −A share an eigenvalue).
fn lyapunov(a: &DMatrix<f64>, c: &DMatrix<f64>) -> Option<DMatrix<f64>> {
    let n = a.nrows();
    let identity = DMatrix::<f64>::identity(n, n);
    let at = a.transpose();
    let system = identity.kronecker(&at) + at.kronecker(&identity);
    let rhs = nalgebra::DVector::from_column_slice((-c).as_slice());
    let x = system.lu().solve(&rhs)?;
    Some(DMatrix::from_column_slice(n, n, x.as_slice()))
}

/// max |A'P + PA − PGP + Q| relative to the largest of the terms.
fn residual(a: &DMatrix<f64>, g: &DMatrix<f64>, q: &DMatrix<f64>, p: &DMatrix<f64>) -> f64 {
    let atp = a.transpose() * p;
    let pgp = p * g * p;
    let r = &atp + atp.transpose() - &pgp + q;
    let scale = q
        .amax()
        .max(atp.amax())
        .max(pgp.amax())
        .max(f64::MIN_POSITIVE);
    r.amax() / scale
}

/// Every eigenvalue of the closed loop A − BK must have a negative real part.
fn check_stable(closed: &DMatrix<f64>) -> Result<(), Error> {
    let n = closed.nrows();
    let schur = Schur::try_new(closed.clone(), f64::EPSILON, 100 * n.max(1)).ok_or_else(|| {
        Error::EigenAnalysis {
            reason: "nalgebra's Schur decomposition of the closed loop did not converge"
                .to_string(),
        }
    })?;
    if let Some(l) = schur
        .complex_eigenvalues()
        .iter()
        .find(|l| l.re.partial_cmp(&0.0) != Some(Ordering::Less))
    {
        return Err(Error::NoStabilizingSolution {
            reason: format!(
                "the closed loop A - BK has the eigenvalue {} {} {}i, not in the left half \
                 plane: (A, B) is not stabilizable (a mode the inputs do not reach is not \
                 stable)",
                Num(l.re),
                if l.im < 0.0 { "-" } else { "+" },
                Num(l.im.abs())
            ),
        });
    }
    Ok(())
}
