//! The modes of a linearization: the eigenvalues of A with their eigenvectors, the state
//! names attached. Both come from nalgebra's decompositions — the eigenvalues from the real
//! Schur form, each eigenvector as the right singular vector of A − λI for its smallest
//! singular value (nalgebra's SVD, on complex matrices for complex λ) — not from an
//! eigen-solver of this crate's own.

use core::fmt;

use nalgebra::{Complex, ComplexField, DMatrix, DVector, SVD, Schur};

use crate::error::{Error, Num};
use crate::linearization::Linearization;

/// Relative to ‖A‖ (Frobenius): eigenvalues closer than this are one repeated eigenvalue, and
/// singular values of A − λI below it are zero. Rounding in nalgebra's decompositions is a
/// few 10⁻¹⁶ of ‖A‖; distinct eigenvalues of a matrix that is not close to defective are far
/// further apart.
pub const EIGEN_TOLERANCE: f64 = 1e-12;

/// Iterations per state that nalgebra's Schur and singular value decompositions may take
/// before they count as not converging (a handful per eigenvalue is usual).
const ITERATIONS_PER_STATE: usize = 100;

/// Eigenvectors of one eigenvalue, normalized.
type Eigenvectors = Vec<DVector<Complex<f64>>>;

/// The eigenvalues of A/σ for a power of two σ (see [`Linearization::spectrum`]).
struct Spectrum {
    /// A/σ.
    scaled: DMatrix<f64>,
    /// σ.
    factor: f64,
    /// The eigenvalues of A/σ, sorted.
    values: Vec<Complex<f64>>,
}

/// A mode of a linearization: an eigenvalue λ of A and an eigenvector, each component with the
/// name of its state. The vector is scaled so that its largest component (the first of those
/// equal to rounding, 10⁻⁹ relative) is exactly 1; for a real λ it is real, and the vector of
/// λ̄ is the conjugate of λ's.
#[derive(Clone, Debug, PartialEq)]
pub struct Mode {
    /// The eigenvalue λ: the mode evolves as e^{λt}.
    pub value: Complex<f64>,
    /// The eigenvector v, A v = λ v, in the order of the linearization's states.
    pub vector: Vec<(String, Complex<f64>)>,
}

impl Mode {
    /// The component of the eigenvector for the state `name`; an unknown name is
    /// [`Error::UnknownName`], listing the states.
    pub fn component(&self, name: &str) -> Result<Complex<f64>, Error> {
        self.vector
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| *v)
            .ok_or_else(|| Error::UnknownName {
                kind: "state",
                name: name.to_string(),
                known: self
                    .vector
                    .iter()
                    .map(|(n, _)| n.as_str())
                    .collect::<Vec<_>>()
                    .join(", "),
            })
    }

    /// The natural frequency ωₙ = |λ|, as python-control's `damp` has it.
    pub fn natural_frequency(&self) -> f64 {
        self.value.norm()
    }

    /// The damping ratio ζ = −Re λ/|λ| (negative for a growing mode); `None` for λ = 0, where
    /// it is not defined.
    pub fn damping_ratio(&self) -> Option<f64> {
        let frequency = self.natural_frequency();
        // + 0.0: an undamped mode has ζ = 0, not −0.
        (frequency > 0.0).then(|| -self.value.re / frequency + 0.0)
    }
}

impl fmt::Display for Mode {
    /// `λ = -0.1 + 0.995i (ωn = 1, ζ = 0.1): x = 1, v = -0.1 + 0.995i`, four significant
    /// digits.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "λ = {} (ωn = {}",
            Cx(self.value),
            Num(self.natural_frequency())
        )?;
        if let Some(zeta) = self.damping_ratio() {
            write!(f, ", ζ = {}", Num(zeta))?;
        }
        f.write_str("):")?;
        for (i, (name, value)) in self.vector.iter().enumerate() {
            let separator = if i > 0 { "," } else { "" };
            write!(f, "{separator} {name} = {}", Cx(*value))?;
        }
        Ok(())
    }
}

/// A complex number with four significant digits: `2`, `-0.5i`, `-0.1 - 0.995i`.
struct Cx(Complex<f64>);

impl fmt::Display for Cx {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        // + 0.0 prints a negative zero as 0.
        let (re, im) = (self.0.re + 0.0, self.0.im + 0.0);
        match (re == 0.0, im == 0.0) {
            (_, true) => write!(f, "{}", Num(re)),
            (true, false) => write!(f, "{}i", Num(im)),
            (false, false) => {
                let sign = if im < 0.0 { '-' } else { '+' };
                write!(f, "{} {sign} {}i", Num(re), Num(im.abs()))
            }
        }
    }
}

impl Linearization {
    /// The eigenvalues of A (nalgebra's real Schur form), in the order of [`Self::modes`].
    ///
    /// Errors: [`Error::EigenAnalysis`] when the decomposition does not converge or an
    /// eigenvalue overflows (entries near the largest `f64`).
    pub fn eigenvalues(&self) -> Result<Vec<Complex<f64>>, Error> {
        let spectrum = self.spectrum()?;
        let factor = spectrum.factor;
        Ok(spectrum.values.into_iter().map(|mu| mu * factor).collect())
    }

    /// A/σ for a power of two σ near its largest entry, σ, and the eigenvalues of A/σ, sorted.
    /// The decompositions work on A/σ, whose entries are at most 2 (unless they are all tiny),
    /// because nalgebra's do not guard against overflow: on entries near 10³⁰⁸ they return
    /// wrong finite eigenvalues rather than infinite ones. Dividing by σ is exact, and so is
    /// multiplying the eigenvalues by it, unless that overflows, which is the error.
    fn spectrum(&self) -> Result<Spectrum, Error> {
        let a = self.a_matrix();
        let largest = a.amax();
        if largest == 0.0 || a.is_empty() {
            return Ok(Spectrum {
                scaled: a.clone(),
                factor: 1.0,
                values: vec![Complex::new(0.0, 0.0); a.nrows()],
            });
        }
        // Clamped to the exponents of normal numbers, so that σ is one.
        let exponent = largest.log2().floor().clamp(-1022.0, 1023.0) as i32;
        let factor = 2f64.powi(exponent);
        let scaled = a / factor;
        let budget = ITERATIONS_PER_STATE * a.nrows();
        let schur = Schur::try_new(scaled.clone(), f64::EPSILON, budget).ok_or_else(|| {
            Error::EigenAnalysis {
                reason: format!(
                    "nalgebra's Schur decomposition did not converge in {budget} iterations"
                ),
            }
        })?;
        // + 0.0 turns negative zeros into zeros, which sort with them.
        let mut values: Vec<Complex<f64>> = schur
            .complex_eigenvalues()
            .iter()
            .map(|v| Complex::new(v.re + 0.0, v.im + 0.0))
            .collect();
        let overflow = |v: &&Complex<f64>| !(*v * factor).is_finite();
        if let Some(v) = values.iter().find(overflow) {
            return Err(Error::EigenAnalysis {
                reason: format!(
                    "an eigenvalue, ({})·2^{exponent}, is too large for an `f64`: the entries of \
                     A (up to {}) are too large to compute with; change the units",
                    Cx(*v),
                    Num(largest)
                ),
            });
        }
        // Least stable first (largest real part), the upper of a conjugate pair first: a
        // total order on the values, so the same matrix always lists its modes alike.
        values.sort_by(|x, y| y.re.total_cmp(&x.re).then(y.im.total_cmp(&x.im)));
        Ok(Spectrum {
            scaled,
            factor,
            values,
        })
    }

    /// The modes: every eigenvalue of A ([`Self::eigenvalues`]: largest real part first,
    /// then largest imaginary part) with an eigenvector, the right singular vector of A − λI
    /// for its smallest singular value (nalgebra's SVD), normalized as [`Mode`] says. The
    /// second of a complex conjugate pair gets the conjugate of the first's vector.
    ///
    /// A repeated eigenvalue (values within [`EIGEN_TOLERANCE`]·‖A‖ of the first) gets as
    /// many orthogonal vectors as A − λI has zero singular values, the right singular vectors
    /// of one decomposition; a defective one, with fewer eigenvectors than its multiplicity,
    /// repeats the last.
    ///
    /// A linearization's entries are finite (its constructors check), so the errors are
    /// those of [`Self::eigenvalues`] and a singular value decomposition that does not
    /// converge ([`Error::EigenAnalysis`]).
    pub fn modes(&self) -> Result<Vec<Mode>, Error> {
        let Spectrum {
            scaled: a,
            factor,
            values,
        } = self.spectrum()?;
        let tolerance = EIGEN_TOLERANCE * a.norm();
        // Per distinct eigenvalue (of A/σ): its eigenvectors and how many modes took one.
        let mut leaders: Vec<(Complex<f64>, Eigenvectors, usize)> = Vec::new();
        // Per mode so far: its eigenvalue of A/σ, and whether its conjugate took its vector.
        let mut done: Vec<(Complex<f64>, bool)> = Vec::with_capacity(values.len());
        let mut modes: Vec<Mode> = Vec::with_capacity(values.len());
        for mu in values {
            // The Schur form gives a complex pair as exact conjugates, the upper one first.
            let partner = (mu.im < 0.0)
                .then(|| done.iter().position(|&(m, taken)| !taken && m == mu.conj()))
                .flatten();
            let vector: Vec<Complex<f64>> = match partner {
                Some(j) => {
                    done[j].1 = true;
                    modes[j].vector.iter().map(|(_, c)| c.conj()).collect()
                }
                None => {
                    let close = |(m, ..): &(Complex<f64>, _, _)| (m - mu).norm() <= tolerance;
                    let leader = match leaders.iter().position(close) {
                        Some(leader) => leader,
                        None => {
                            leaders.push((mu, null_vectors(&a, mu, tolerance)?, 0));
                            leaders.len() - 1
                        }
                    };
                    let (_, vectors, taken) = &mut leaders[leader];
                    let vector = &vectors[(*taken).min(vectors.len() - 1)];
                    *taken += 1;
                    vector.iter().copied().collect()
                }
            };
            done.push((mu, false));
            let names = self.states().iter().cloned();
            modes.push(Mode {
                value: mu * factor,
                vector: names.zip(vector).collect(),
            });
        }
        Ok(modes)
    }
}

/// The normalized right singular vectors of A − μI for its zero singular values (at most
/// `tolerance`), smallest first, and the smallest in any case. For a real μ the
/// decomposition is real, so that the vectors are.
fn null_vectors(a: &DMatrix<f64>, mu: Complex<f64>, tolerance: f64) -> Result<Eigenvectors, Error> {
    let s = a.nrows();
    if mu.im == 0.0 {
        let shifted = a - DMatrix::from_diagonal_element(s, s, mu.re);
        right_null_vectors(shifted, tolerance)
    } else {
        let shifted = a.map(|v| Complex::new(v, 0.0)) - DMatrix::from_diagonal_element(s, s, mu);
        right_null_vectors(shifted, tolerance)
    }
}

fn right_null_vectors<T: ComplexField<RealField = f64>>(
    matrix: DMatrix<T>,
    tolerance: f64,
) -> Result<Eigenvectors, Error> {
    let budget = ITERATIONS_PER_STATE * matrix.nrows();
    let failed = || Error::EigenAnalysis {
        reason: format!(
            "nalgebra's singular value decomposition of A − λI did not converge in {budget} \
             iterations"
        ),
    };
    let svd = SVD::try_new(matrix, false, true, f64::EPSILON, budget).ok_or_else(failed)?;
    let v_t = svd.v_t.ok_or_else(failed)?;
    let sigma = &svd.singular_values;
    let mut order: Vec<usize> = (0..sigma.len()).collect();
    order.sort_by(|&i, &j| sigma[i].total_cmp(&sigma[j]));
    Ok(order
        .iter()
        .enumerate()
        .take_while(|&(rank, &i)| rank == 0 || sigma[i] <= tolerance)
        // Row i of Vᴴ is vᵢᴴ.
        .map(|(_, &i)| {
            let v = v_t.row(i).adjoint();
            normalized(v.map(|c| Complex::new(c.clone().real(), c.imaginary())))
        })
        .collect())
}

/// `v` divided by its largest component — the first within 10⁻⁹ of the largest modulus, so
/// that rounding does not decide between components equal in theory — which becomes exactly
/// 1. A singular vector has norm 1, so that component is not zero.
fn normalized(v: DVector<Complex<f64>>) -> DVector<Complex<f64>> {
    let largest = v.iter().map(|c| c.norm()).fold(0.0, f64::max);
    let Some(pivot) = v.iter().position(|c| c.norm() >= largest * (1.0 - 1e-9)) else {
        return v;
    };
    let scale = v[pivot];
    let mut w = v / scale;
    w[pivot] = Complex::new(1.0, 0.0);
    w
}
