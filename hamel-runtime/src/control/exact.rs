//! Exact input–output linearization (Isidori, *Nonlinear Control Systems*, 3rd ed., §5.2):
//! for outputs with relative degrees r_i and a nonsingular decoupling matrix A(x),
//! u = A(x)⁻¹ (v − b(x)) makes y_i^{(r_i)} = v_i, and v_i = y_{d,i}^{(r_i)} −
//! Σ_k c_k (L_f^k h_i − y_{d,i}^{(k)}) gives each tracking error the linear dynamics with
//! the characteristic polynomial (s + λ)^{r_i}.

use core::cmp::Ordering;

use nalgebra::{DVector, SVD};

use super::{ControlAffine, Controller};
use crate::error::Error;
use crate::vector::Vector;

/// The decoupling matrix counts as singular when its smallest singular value is at most
/// this fraction of its largest: its inverse would amplify rounding beyond any use.
pub const DECOUPLING_TOLERANCE: f64 = 1e-10;

/// A reference trajectory for the outputs: at time t, for each output i, its value and its
/// derivatives up to the output's relative degree, `[y, ẏ, …, y^(r_i)]`. A closure
/// `|t| -> Vec<Vec<f64>>` is one.
pub trait Reference {
    /// The reference values at `t`, one list per output, in the order of
    /// [`ControlAffine::OUTPUTS`].
    fn at(&self, t: f64) -> Vec<Vec<f64>>;
}

impl<F: Fn(f64) -> Vec<Vec<f64>>> Reference for F {
    fn at(&self, t: f64) -> Vec<Vec<f64>> {
        self(t)
    }
}

/// The tracking controller of exact input–output linearization for a square system (as
/// many outputs as inputs): a [`Controller`] for [`crate::Simulation::run_controlled`].
pub struct ExactLinearization<'s, S, R> {
    system: &'s S,
    rate: f64,
    reference: R,
}

impl<'s, S: ControlAffine, R: Reference> ExactLinearization<'s, S, R> {
    /// The controller that drives the outputs of `system` to `reference`, each error
    /// decaying as the linear system with all its poles at −`rate`.
    ///
    /// Errors: a `rate` that is not a positive finite number, or whose gains rate^r overflow
    /// ([`Error::InvalidSetting`]); a system with another number of outputs than inputs
    /// ([`Error::DimensionMismatch`]).
    pub fn new(system: &'s S, rate: f64, reference: R) -> Result<Self, Error> {
        if !(rate.is_finite() && rate > 0.0) {
            return Err(Error::InvalidSetting {
                name: "rate",
                value: rate,
                reason: "the tracking errors decay as exp(-rate t): give a positive number",
            });
        }
        // The gains c_k = C(r, k) rate^(r − k) for the largest relative degree the model
        // generates (`control(order = ..)`): past `f64`, every input would be NaN.
        let gains = coefficients(rate, S::ORDER.max(1));
        if !gains.iter().all(|c| c.is_finite()) {
            return Err(Error::InvalidSetting {
                name: "rate",
                value: rate,
                reason: "the feedback gains, rate^r for the outputs' relative degrees r, are \
                         beyond the range of f64 (every input would be NaN): give a smaller \
                         rate",
            });
        }
        let (r, m) = (S::OUTPUTS.len(), S::Inputs::LEN);
        if r != m || r == 0 {
            return Err(Error::DimensionMismatch {
                what: format!(
                    "exact input-output linearization needs as many outputs as inputs (a square \
                     decoupling matrix); the model has {r} outputs ({}) and {m} inputs ({})",
                    S::OUTPUTS.join(", "),
                    S::INPUTS.join(", ")
                ),
            });
        }
        Ok(ExactLinearization {
            system,
            rate,
            reference,
        })
    }

    /// The coefficients c_0 … c_{r−1} of (s + λ)^r = s^r + c_{r−1} s^{r−1} + … + c_0.
    fn coefficients(&self, r: usize) -> Vec<f64> {
        coefficients(self.rate, r)
    }
}

/// The coefficients c_0 … c_{r−1} of (s + λ)^r = s^r + c_{r−1} s^{r−1} + … + c_0, binomial:
/// c_k = C(r, k) λ^(r − k).
fn coefficients(rate: f64, r: usize) -> Vec<f64> {
    let mut c = Vec::with_capacity(r);
    let mut binomial = 1.0;
    for k in 0..r {
        c.push(binomial * rate.powi((r - k) as i32));
        binomial = binomial * (r - k) as f64 / (k + 1) as f64;
    }
    c
}

impl<S: ControlAffine, R: Reference> Controller<S> for ExactLinearization<'_, S, R> {
    /// u = A(x)⁻¹ (v − b(x)).
    ///
    /// Errors: those of [`ControlAffine::lie_derivatives`] and
    /// [`super::LieDerivatives::decoupling`]; a reference of the wrong shape
    /// ([`Error::InvalidReference`]); a decoupling matrix singular at this state
    /// ([`Error::SingularDecoupling`], with its singular values, the time and the state).
    fn control(&self, t: f64, x: &S::State) -> Result<S::Inputs, Error> {
        let lie = self.system.lie_derivatives(t, x)?;
        let decoupling = lie.decoupling()?;
        let reference = self.reference.at(t);
        let outputs = &decoupling.outputs;
        if reference.len() > outputs.len() {
            return Err(Error::DimensionMismatch {
                what: format!(
                    "the reference gives {} lists of values at t = {}, for the {} outputs ({}): \
                     one list per output, in their order",
                    reference.len(),
                    crate::error::Num(t),
                    outputs.len(),
                    outputs.join(", ")
                ),
            });
        }
        let mut v = DVector::zeros(outputs.len());
        for (i, name) in outputs.iter().enumerate() {
            let r = decoupling.relative_degrees[i];
            // An output the reference has no list for gets none: it is the one named.
            let wanted = reference.get(i).map_or(0, Vec::len);
            if wanted != r + 1 {
                return Err(Error::InvalidReference {
                    output: name.clone(),
                    expected: r + 1,
                    given: wanted,
                    t,
                });
            }
            let yd = &reference[i];
            let feedback: f64 = self
                .coefficients(r)
                .iter()
                .enumerate()
                .map(|(k, c)| c * (lie.drift_matrix()[(i, k)] - yd[k]))
                .sum();
            v[i] = yd[r] - feedback - decoupling.drift[i];
        }
        let svd = SVD::new(decoupling.matrix.clone(), true, true);
        let mut singular_values: Vec<f64> = svd.singular_values.iter().copied().collect();
        singular_values.sort_by(|a, b| b.total_cmp(a));
        let largest = singular_values.first().copied().unwrap_or(0.0);
        let smallest = singular_values.last().copied().unwrap_or(0.0);
        if smallest.partial_cmp(&(DECOUPLING_TOLERANCE * largest)) != Some(Ordering::Greater) {
            return Err(Error::SingularDecoupling {
                t,
                state: S::named_state(x),
                singular_values,
                tolerance: DECOUPLING_TOLERANCE,
            });
        }
        let u = svd.solve(&v, 0.0).map_err(|reason| Error::EigenAnalysis {
            reason: reason.to_string(),
        })?;
        S::Inputs::from_slice(u.as_slice()).ok_or_else(|| Error::DimensionMismatch {
            what: "the decoupling matrix's columns are not the model's inputs".to_string(),
        })
    }
}
