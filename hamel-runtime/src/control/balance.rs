//! The Riccati equation A'P + PA − PGP + Q = 0 (G = BR⁻¹B') solved on matrices of norm near
//! one, and, when it has no stabilizing solution, why: the inputs do not reach an unstable
//! mode, Q does not weight a mode on the imaginary axis, or — the system stabilizable and
//! every such mode weighted — weights too far in scale from the system for double precision.
//!
//! The equation is unchanged by P = σ P̃ and by dividing it through by τ: with Ã = A/τ,
//! B̃ = B·√(σ/τ) (so G̃ = σG/τ) and Q̃ = Q/(στ), P̃ solves Ã'P̃ + P̃Ã − P̃G̃P̃ + Q̃ = 0 and the
//! gain is K = √(στ) K̃. σ and τ are powers of two (the scaled matrices are exact) that make
//! ‖G̃‖ = ‖Q̃‖ and max(‖Ã‖, ‖G̃‖) ≈ 1: Q = 10³⁰⁰ I (or R = 10⁻³⁰⁰) no longer overflows in the
//! Hamiltonian matrix, and Q and R scaled alike give the same gain.

use nalgebra::{Complex, DMatrix, SVD, Schur};

use super::riccati::Riccati;
use crate::error::{Error, Num};

/// The powers of two of a balanced equation: τ = 2^t, σ = 2^(t + 2b), B̃ = 2^b B.
pub(super) struct Balance {
    t: i32,
    b: i32,
    /// ‖A‖, ‖G‖ and ‖Q‖ (largest entries) of the equation as given.
    norms: [f64; 3],
}

/// 2^k, for |k| within the range of `f64` exponents.
fn two_to(k: i32) -> f64 {
    2f64.powi(k.clamp(-1022, 1023))
}

/// log₂ of a positive finite number, rounded; `None` otherwise.
fn exponent(x: f64) -> Option<i32> {
    (x.is_finite() && x > 0.0).then(|| x.log2().round() as i32)
}

impl Balance {
    pub(super) fn of(a: &DMatrix<f64>, g: &DMatrix<f64>, q: &DMatrix<f64>) -> Balance {
        let norms = [a.amax(), g.amax(), q.amax()];
        let [na, ng, nq] = norms;
        let (t, b) = match (exponent(ng), exponent(nq)) {
            (Some(eg), Some(eq)) => {
                // √(‖Q‖‖G‖) in powers of two, against ‖A‖.
                let coupling = (eg + eq) / 2;
                let t = exponent(na).map_or(coupling, |ea| ea.max(coupling));
                // 2^(2b) ‖G‖ = 2^(−2t−2b) ‖Q‖.
                let b = ((eq - eg - 2 * t) as f64 / 4.0).round() as i32;
                (t, b)
            }
            _ => (exponent(na).unwrap_or(0), 0),
        };
        Balance { t, b, norms }
    }

    /// Ã, B̃ and Q̃.
    pub(super) fn apply(
        &self,
        a: &DMatrix<f64>,
        b: &DMatrix<f64>,
        q: &DMatrix<f64>,
    ) -> (DMatrix<f64>, DMatrix<f64>, DMatrix<f64>) {
        (
            a * two_to(-self.t),
            b * two_to(self.b),
            q * two_to(-2 * self.t - 2 * self.b),
        )
    }

    /// The solution of the equation as given, from the balanced one's.
    pub(super) fn undo(&self, scaled: Riccati) -> Result<Riccati, Error> {
        let solution = scaled.solution * two_to(self.t + 2 * self.b);
        let gain = scaled.gain * two_to(self.t + self.b);
        if !solution.iter().chain(gain.iter()).all(|v| v.is_finite()) {
            return Err(Error::InvalidWeights {
                matrix: "Q",
                reason: format!(
                    "is so large against R (‖Q‖ = {}, ‖BR⁻¹B'‖ = {}) that the solution P or the \
                     gain K overflows: scale Q and R nearer each other (K depends only on their \
                     ratio)",
                    Num(self.norms[2]),
                    Num(self.norms[1])
                ),
            });
        }
        Ok(Riccati {
            solution,
            gain,
            ..scaled
        })
    }

    /// √(‖Q‖‖G‖)/‖A‖: how strongly the weights couple the Hamiltonian's blocks, against the
    /// system's own rates.
    fn coupling(&self) -> f64 {
        let [na, ng, nq] = self.norms;
        (nq.sqrt() * ng.sqrt()) / na
    }
}

/// Relative size below which a singular value of a rank test counts as zero.
const RANK_TOLERANCE: f64 = 1e-10;
/// Real parts within this fraction of ‖A‖ of zero count as on the imaginary axis.
const AXIS_TOLERANCE: f64 = 1e-10;

/// Why the equation (`a`, `b`, `q`, as given) has no stabilizing solution, for the error
/// `found` that the solver gave: an unstable mode the inputs do not reach, a mode on the
/// imaginary axis Q does not weight (the Popov–Belevitch–Hautus tests, each block scaled to
/// norm 1, which leaves their ranks as they are) — or neither, and then weights out of scale
/// with the system (the equation has a solution, beyond double precision), or `found` itself.
pub(super) fn why_not(
    a: &DMatrix<f64>,
    b: &DMatrix<f64>,
    q: &DMatrix<f64>,
    scaling: &Balance,
    found: Error,
) -> Error {
    let n = a.nrows();
    let Some(schur) = Schur::try_new(a.clone(), f64::EPSILON, 100 * n.max(1)) else {
        return found;
    };
    let unit = |m: &DMatrix<f64>| {
        let norm = m.amax();
        let scale = if norm > 0.0 { 1.0 / norm } else { 1.0 };
        m.map(|v| Complex::new(v * scale, 0.0))
    };
    let size = a.amax().max(f64::MIN_POSITIVE);
    let (ca, cb, cq) = (unit(a), unit(b), unit(q));
    let identity = DMatrix::<Complex<f64>>::identity(n, n);
    for lambda in schur.complex_eigenvalues().iter() {
        if lambda.re < -AXIS_TOLERANCE * size {
            continue;
        }
        let shifted = &ca - &identity * (*lambda / size);
        let mode = format!(
            "{} {} {}i",
            Num(lambda.re),
            if lambda.im < 0.0 { "-" } else { "+" },
            Num(lambda.im.abs())
        );
        if !full_rank(&concat_columns(&shifted, &cb)) {
            return Error::NoStabilizingSolution {
                reason: format!(
                    "the mode {mode} of A is not stable and the inputs do not reach it ([A - λI, \
                     B] is rank deficient there): (A, B) is not stabilizable"
                ),
            };
        }
        if lambda.re.abs() <= AXIS_TOLERANCE * size && !full_rank(&concat_rows(&shifted, &cq)) {
            return Error::NoStabilizingSolution {
                reason: format!(
                    "the mode {mode} of A lies on the imaginary axis and Q does not weight it \
                     ([A - λI; Q] is rank deficient there): weight it in Q"
                ),
            };
        }
    }
    let coupling = scaling.coupling();
    if !(1e-4..=1e4).contains(&coupling) {
        let [na, ng, nq] = scaling.norms;
        let (matrix, other) = if nq.log2().abs() >= ng.log2().abs() {
            ("Q", "R")
        } else {
            ("R", "Q")
        };
        return Error::InvalidWeights {
            matrix,
            reason: format!(
                "is too far in scale from {other} and the system to solve in double precision: \
                 ‖Q‖ = {}, ‖BR⁻¹B'‖ = {} and ‖A‖ = {}, so √(‖Q‖‖BR⁻¹B'‖)/‖A‖ = {}, though (A, \
                 B) is stabilizable and Q weights every mode on the imaginary axis (the \
                 equation has a solution, which rounding hides); bring the weights nearer the \
                 system's scale (the gain depends on Q and R only through their ratio)",
                Num(nq),
                Num(ng),
                Num(na),
                Num(coupling)
            ),
        };
    }
    found
}

fn full_rank(m: &DMatrix<Complex<f64>>) -> bool {
    let rank = m.nrows().min(m.ncols());
    let values = SVD::new(m.clone(), false, false).singular_values;
    let largest = values.max();
    values
        .iter()
        .filter(|&&v| v > RANK_TOLERANCE * largest)
        .count()
        == rank
}

fn concat_columns(a: &DMatrix<Complex<f64>>, b: &DMatrix<Complex<f64>>) -> DMatrix<Complex<f64>> {
    let mut m = DMatrix::zeros(a.nrows(), a.ncols() + b.ncols());
    m.view_mut((0, 0), a.shape()).copy_from(a);
    m.view_mut((0, a.ncols()), b.shape()).copy_from(b);
    m
}

fn concat_rows(a: &DMatrix<Complex<f64>>, b: &DMatrix<Complex<f64>>) -> DMatrix<Complex<f64>> {
    let mut m = DMatrix::zeros(a.nrows() + b.nrows(), a.ncols());
    m.view_mut((0, 0), a.shape()).copy_from(a);
    m.view_mut((a.nrows(), 0), b.shape()).copy_from(b);
    m
}

#[cfg(test)]
mod tests {
    use super::super::riccati::solve_care;
    use super::*;

    fn double_integrator() -> (DMatrix<f64>, DMatrix<f64>) {
        (
            DMatrix::from_row_slice(2, 2, &[0.0, 1.0, 0.0, 0.0]),
            DMatrix::from_row_slice(2, 1, &[0.0, 1.0]),
        )
    }

    fn care(q: f64, r: f64) -> Result<DMatrix<f64>, Error> {
        let (a, b) = double_integrator();
        let i = DMatrix::identity(2, 2);
        solve_care(&a, &b, &(i * q), &(DMatrix::identity(1, 1) * r)).map(|s| s.gain)
    }

    /// For x'' = u with Q = diag(q₁, q₂) and R = 1, K = [√q₁, √(q₂ + 2√q₁)] (the double
    /// integrator's LQR in closed form). Before, Q and R both 10³⁰⁰ overflowed the
    /// Hamiltonian matrix and Q = 10⁻³⁰ I lost its modes in rounding: both were called
    /// unstabilizable.
    #[test]
    fn weights_of_any_common_scale_give_the_closed_form_gain() {
        for (q, r) in [
            (1.0, 1.0),
            (1e300, 1e300),
            (1e-300, 1e-300),
            (1e-30, 1.0),
            (1e30, 1.0),
        ] {
            let k = care(q, r).unwrap();
            let e = q / r;
            let exact = [e.sqrt(), (e + 2.0 * e.sqrt()).sqrt()];
            for j in 0..2 {
                assert!(
                    (k[j] - exact[j]).abs() <= 1e-13 * exact[j],
                    "{q:e} {r:e}: {k}"
                );
            }
        }
    }

    /// Before, Q = 10³⁰⁰ I (or R = 10⁻³⁰⁰) was called "not stabilizable"; the double
    /// integrator is. Now the message says the weights are out of scale, and which.
    #[test]
    fn weights_out_of_scale_are_called_so_not_unstabilizable() {
        for (q, r, matrix) in [
            (1e300, 1.0, "Q"),
            (1e-300, 1.0, "Q"),
            (1.0, 1e-300, "R"),
            (1.0, 1e300, "R"),
        ] {
            let e = care(q, r).unwrap_err();
            assert!(
                matches!(e, Error::InvalidWeights { matrix: m, .. } if m == matrix),
                "{q:e} {r:e}: {e}"
            );
            let message = e.to_string();
            assert!(message.contains("too far in scale"), "{message}");
            assert!(message.contains("(A, B) is stabilizable"), "{message}");
        }
        // What is not stabilizable, or not weighted on the axis, is still called so, with
        // the mode.
        let a = DMatrix::from_row_slice(2, 2, &[1.0, 0.0, 0.0, -1.0]);
        let b = DMatrix::from_row_slice(2, 1, &[0.0, 1.0]);
        let e = solve_care(&a, &b, &DMatrix::identity(2, 2), &DMatrix::identity(1, 1));
        let e = e.unwrap_err().to_string();
        assert!(
            e.contains("the mode 1 + 0i of A is not stable and the inputs do not reach"),
            "{e}"
        );
        let a = DMatrix::from_row_slice(2, 2, &[0.0, 1.0, -1.0, 0.0]);
        let e = solve_care(&a, &b, &DMatrix::zeros(2, 2), &DMatrix::identity(1, 1));
        let e = e.unwrap_err().to_string();
        assert!(
            e.contains("lies on the imaginary axis and Q does not weight it"),
            "{e}"
        );
    }
}
