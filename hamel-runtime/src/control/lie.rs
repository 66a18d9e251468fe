//! The outputs' Lie derivatives at a state, and what input–output linearization reads from
//! them: each output's relative degree and the decoupling matrix.

use core::fmt;

use nalgebra::{DMatrix, DVector};

use super::{ControlAffine, index_of, owned};
use crate::error::{Error, Num};
use crate::named::NamedValues;
use crate::vector::Vector;

/// An L_{g_j} L_f^k h_i counts as zero when it vanishes identically (the macro knows which
/// do) or is at most this fraction of the largest |L_{g_j} L_f^k h_i| of the same output over
/// every k and j: what is left of cancelling terms is rounding of that order.
pub const LIE_ZERO_TOLERANCE: f64 = 1e-12;

/// L_f^k h (k ≤ K) and L_{g_j} L_f^k h (k < K) at a state, from
/// [`ControlAffine::lie_derivatives`].
#[derive(Clone, PartialEq)]
pub struct LieDerivatives {
    outputs: Vec<String>,
    inputs: Vec<String>,
    /// R × (K + 1): (i, k) is L_f^k h_i.
    drift: DMatrix<f64>,
    /// K matrices of R × M: [k] (i, j) is L_{g_j} L_f^k h_i.
    along: Vec<DMatrix<f64>>,
    /// Which of `along` vanish identically, [k][i][j] flattened.
    vanishing: Vec<bool>,
    t: f64,
    state: NamedValues,
}

impl LieDerivatives {
    pub(super) fn new<S: ControlAffine + ?Sized>(
        t: f64,
        x: &S::State,
        lie: &[f64],
        along: &[f64],
    ) -> Self {
        let (r, m, k) = (S::OUTPUTS.len(), S::Inputs::LEN, S::ORDER);
        let drift = if r == 0 {
            DMatrix::zeros(0, k + 1)
        } else {
            // lie is [k][i]: the transpose of the R × (K + 1) matrix.
            DMatrix::from_row_slice(k + 1, r, lie).transpose()
        };
        let along = (0..k)
            .map(|order| DMatrix::from_row_slice(r, m, &along[order * r * m..(order + 1) * r * m]))
            .collect();
        LieDerivatives {
            outputs: owned(S::OUTPUTS),
            inputs: owned(S::INPUTS),
            drift,
            along,
            vanishing: S::VANISHING.to_vec(),
            t,
            state: S::named_state(x),
        }
    }

    /// The outputs' names.
    pub fn outputs(&self) -> &[String] {
        &self.outputs
    }

    /// The inputs' names.
    pub fn inputs(&self) -> &[String] {
        &self.inputs
    }

    /// K: L_f^k h is here for k ≤ K, L_{g_j} L_f^k h for k < K.
    pub fn order(&self) -> usize {
        self.along.len()
    }

    /// L_f^k h of the output named `output` (k = 0 is the output itself).
    ///
    /// Errors: an unknown output ([`Error::UnknownName`]); k beyond the order
    /// ([`Error::InvalidSetting`]).
    pub fn drift(&self, output: &str, k: usize) -> Result<f64, Error> {
        let i = index_of(&self.outputs, "output", output)?;
        self.check_order(k, self.order())?;
        Ok(self.drift[(i, k)])
    }

    /// L_{g_j} L_f^k h of the output named `output` along the field of the input `input`.
    ///
    /// Errors: an unknown output or input ([`Error::UnknownName`]); k not below the order
    /// ([`Error::InvalidSetting`]).
    pub fn along_input(&self, input: &str, output: &str, k: usize) -> Result<f64, Error> {
        let i = index_of(&self.outputs, "output", output)?;
        let j = index_of(&self.inputs, "input", input)?;
        self.check_order(k, self.order().saturating_sub(1))?;
        Ok(self.along[k][(i, j)])
    }

    /// The matrix of L_f^k h: output i in row i, order k in column k (R × (K + 1)).
    pub fn drift_matrix(&self) -> &DMatrix<f64> {
        &self.drift
    }

    /// The matrix of L_{g_j} L_f^k h for one k < K: outputs by inputs (R × M).
    pub fn input_matrix(&self, k: usize) -> Option<&DMatrix<f64>> {
        self.along.get(k)
    }

    fn check_order(&self, k: usize, most: usize) -> Result<(), Error> {
        if k > most {
            return Err(Error::InvalidSetting {
                name: "order of the Lie derivative",
                value: k as f64,
                reason: "it is beyond the order the model generates (`control(order = ..)`)",
            });
        }
        Ok(())
    }

    /// Whether L_{g_j} L_f^k h_i counts as zero ([`LIE_ZERO_TOLERANCE`]).
    fn is_zero(&self, k: usize, i: usize, j: usize) -> bool {
        let m = self.inputs.len();
        let r = self.outputs.len();
        if self.vanishing.get((k * r + i) * m + j) == Some(&true) {
            return true;
        }
        let scale = self
            .along
            .iter()
            .flat_map(|a| a.row(i).iter().copied().collect::<Vec<_>>())
            .fold(0.0f64, |s, v| s.max(v.abs()));
        self.along[k][(i, j)].abs() <= LIE_ZERO_TOLERANCE * scale
    }

    /// Each output's relative degree at this state: r_i = 1 + the least k for which some
    /// L_{g_j} L_f^k h_i is not zero ([`LIE_ZERO_TOLERANCE`]), so that the inputs first
    /// appear in the r_i-th derivative of y_i.
    ///
    /// Errors: [`Error::RelativeDegree`] naming an output no input acts on within the order.
    pub fn relative_degrees(&self) -> Result<Vec<usize>, Error> {
        (0..self.outputs.len())
            .map(|i| {
                (0..self.order())
                    .find(|&k| (0..self.inputs.len()).any(|j| !self.is_zero(k, i, j)))
                    .map(|k| k + 1)
                    .ok_or_else(|| Error::RelativeDegree {
                        output: self.outputs[i].clone(),
                        order: self.order(),
                        t: self.t,
                        state: self.state.clone(),
                    })
            })
            .collect()
    }

    /// The decoupling matrix A(x) = (L_{g_j} L_f^{r_i − 1} h_i) and the drift terms
    /// b_i(x) = L_f^{r_i} h_i, so that y_i^{(r_i)} = b_i + Σ_j A_ij u_j.
    ///
    /// Errors: as [`Self::relative_degrees`].
    pub fn decoupling(&self) -> Result<Decoupling, Error> {
        let degrees = self.relative_degrees()?;
        let (r, m) = (self.outputs.len(), self.inputs.len());
        let matrix = DMatrix::from_fn(r, m, |i, j| self.along[degrees[i] - 1][(i, j)]);
        let drift = DVector::from_fn(r, |i, _| self.drift[(i, degrees[i])]);
        Ok(Decoupling {
            outputs: self.outputs.clone(),
            inputs: self.inputs.clone(),
            relative_degrees: degrees,
            matrix,
            drift,
        })
    }
}

impl fmt::Debug for LieDerivatives {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("LieDerivatives")
            .field("outputs", &self.outputs)
            .field("inputs", &self.inputs)
            .field("drift", &self.drift)
            .field("along", &self.along)
            .finish()
    }
}

impl fmt::Display for LieDerivatives {
    /// One line per output and order: `L_f^1 px = 0.3`, then `L_g L_f^0 px = [0, 0]`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, name) in self.outputs.iter().enumerate() {
            for k in 0..self.drift.ncols() {
                writeln!(f, "L_f^{k} {name} = {}", Num(self.drift[(i, k)]))?;
            }
            for (k, a) in self.along.iter().enumerate() {
                let values: Vec<String> = a.row(i).iter().map(|v| Num(*v).to_string()).collect();
                writeln!(
                    f,
                    "L_g L_f^{k} {name} = [{}] ({})",
                    values.join(", "),
                    self.inputs.join(", ")
                )?;
            }
        }
        Ok(())
    }
}

/// What input–output linearization needs at a state: the relative degrees r_i, the
/// decoupling matrix A(x) = (L_{g_j} L_f^{r_i − 1} h_i) and b(x) = (L_f^{r_i} h_i), so that
/// y_i^{(r_i)} = b_i(x) + Σ_j A_ij(x) u_j.
#[derive(Clone, Debug, PartialEq)]
pub struct Decoupling {
    /// The outputs' names: the rows.
    pub outputs: Vec<String>,
    /// The inputs' names: the columns.
    pub inputs: Vec<String>,
    /// r_i for each output.
    pub relative_degrees: Vec<usize>,
    /// A(x), R × M.
    pub matrix: DMatrix<f64>,
    /// b(x), R.
    pub drift: DVector<f64>,
}
