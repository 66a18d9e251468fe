//! The Lie brackets of the drift and the input fields at a state, and the accessibility rank
//! they span (Sussmann and Jurdjevic's accessibility algebra: the fields and all their
//! iterated brackets; for a driftless system, Chow's theorem).

use core::fmt;

use nalgebra::{DMatrix, DVector};

use super::{ControlAffine, ControlAffineForm, index_of, owned};
use crate::error::Error;
use crate::vector::Vector;

/// A singular value of the matrix of fields (each scaled to unit length) counts towards the
/// rank when it exceeds this fraction of the largest: rounding in fields that are dependent
/// leaves singular values of about 10⁻¹⁵.
pub const ACCESSIBILITY_TOLERANCE: f64 = 1e-8;

/// The drift, the input fields and their brackets at a state, from
/// [`ControlAffine::lie_brackets`].
#[derive(Clone, Debug, PartialEq)]
pub struct LieBrackets {
    form: ControlAffineForm,
    labels: Vec<String>,
    depths: Vec<usize>,
    /// S × B: bracket b in column b.
    brackets: DMatrix<f64>,
    /// The dimension of the state manifold: the state's, less one per holonomic constraint.
    dimension: usize,
}

impl LieBrackets {
    pub(super) fn new<S: ControlAffine + ?Sized>(form: ControlAffineForm, values: &[f64]) -> Self {
        let s = S::State::LEN;
        let b = S::BRACKETS.len();
        LieBrackets {
            form,
            labels: owned(S::BRACKETS),
            depths: S::BRACKET_DEPTHS.to_vec(),
            brackets: DMatrix::from_column_slice(s, b, values),
            dimension: s - S::K,
        }
    }

    /// The drift and the input fields.
    pub fn form(&self) -> &ControlAffineForm {
        &self.form
    }

    /// The brackets' labels, `[f, g_tau1]`, in the order of their columns.
    pub fn labels(&self) -> &[String] {
        &self.labels
    }

    /// The bracket labelled `label` (`"[f, g_tau1]"`); an unknown label is
    /// [`Error::UnknownName`], listing those there are.
    pub fn bracket(&self, label: &str) -> Result<DVector<f64>, Error> {
        let b = index_of(&self.labels, "bracket", label)?;
        Ok(self.brackets.column(b).into_owned())
    }

    /// The brackets as the columns of an S × B matrix.
    pub fn matrix(&self) -> &DMatrix<f64> {
        &self.brackets
    }

    /// The rank of the span of the drift, the input fields and the brackets, depth by depth
    /// (each field scaled to unit length; [`ACCESSIBILITY_TOLERANCE`]).
    ///
    /// Errors: [`Error::EigenAnalysis`] should the singular value decomposition not converge.
    pub fn accessibility(&self) -> Result<Accessibility, Error> {
        let deepest = self.depths.iter().copied().max().unwrap_or(0);
        let mut ranks = Vec::with_capacity(deepest + 1);
        let mut singular_values = Vec::new();
        for depth in 0..=deepest {
            let (rank, values) = self.rank_to(depth)?;
            ranks.push(rank);
            singular_values = values;
        }
        let rank = ranks.last().copied().unwrap_or(0);
        Ok(Accessibility {
            dimension: self.dimension,
            rank,
            depth: ranks.iter().position(|&r| r >= self.dimension),
            ranks,
            singular_values,
        })
    }

    /// The rank of the fields and the brackets of at most `depth`, with the singular values.
    fn rank_to(&self, depth: usize) -> Result<(usize, Vec<f64>), Error> {
        let mut columns: Vec<DVector<f64>> = vec![self.form.drift().clone()];
        columns.extend(self.form.fields().column_iter().map(|c| c.into_owned()));
        columns.extend(
            self.brackets
                .column_iter()
                .zip(&self.depths)
                .filter(|(_, d)| **d <= depth)
                .map(|(c, _)| c.into_owned()),
        );
        let unit: Vec<DVector<f64>> = columns
            .into_iter()
            .filter_map(|c| {
                let norm = c.norm();
                (norm > 0.0 && norm.is_finite()).then(|| c / norm)
            })
            .collect();
        let s = self.form.states().len();
        if unit.is_empty() {
            return Ok((0, Vec::new()));
        }
        let matrix = DMatrix::from_columns(&unit);
        // The rank of M equals that of M Mᵀ's square root; the SVD of the S × C matrix.
        let svd = nalgebra::SVD::try_new(matrix, false, false, f64::EPSILON, 100 * s.max(1))
            .ok_or_else(|| Error::EigenAnalysis {
                reason: "nalgebra's singular value decomposition of the fields did not converge"
                    .to_string(),
            })?;
        let mut values: Vec<f64> = svd.singular_values.iter().copied().collect();
        values.sort_by(|a, b| b.total_cmp(a));
        let largest = values.first().copied().unwrap_or(0.0);
        let rank = values
            .iter()
            .filter(|&&v| v > ACCESSIBILITY_TOLERANCE * largest)
            .count();
        Ok((rank, values))
    }
}

/// The accessibility rank at a state: the dimension of the span of the drift f, the input
/// fields g_j and their brackets to each depth. Full rank (= [`Self::dimension`], 2n − p less
/// the holonomic constraints) means the system is locally accessible there (Sussmann and
/// Jurdjevic); for a driftless one, locally controllable (Chow).
#[derive(Clone, Debug, PartialEq)]
pub struct Accessibility {
    /// The dimension of the state manifold.
    pub dimension: usize,
    /// The rank with every bracket generated.
    pub rank: usize,
    /// The rank with the brackets of depth at most d, for d = 0 (the fields alone) … the
    /// deepest generated.
    pub ranks: Vec<usize>,
    /// The least depth at which the rank is full, if it is.
    pub depth: Option<usize>,
    /// The singular values with every bracket (each field scaled to unit length), largest
    /// first.
    pub singular_values: Vec<f64>,
}

impl Accessibility {
    /// Whether the rank is full.
    pub fn is_full(&self) -> bool {
        self.rank >= self.dimension
    }
}

impl fmt::Display for Accessibility {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let ranks: Vec<String> = self.ranks.iter().map(ToString::to_string).collect();
        write!(
            f,
            "accessibility rank {} of {} (by bracket depth 0, 1, …: {})",
            self.rank,
            self.dimension,
            ranks.join(", ")
        )?;
        match self.depth {
            Some(d) => write!(f, "; full at depth {d}"),
            None => f.write_str("; not full at the depth generated"),
        }
    }
}
