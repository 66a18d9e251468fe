//! The inverse of the rows, q̇ = Q(t, q, ω) = B(q, t)(ω − a(q, t)): from the user's
//! `#[velocities]` in closed form (checked to be the inverse by `inverse`), or by an LU
//! factorization of A with partial pivoting unrolled into the generated code.

use super::rows::{Rows, check_affine, coefficients};
use super::{array, inverse, lower};
use crate::engine::graph::{Graph, NodeId};
use crate::engine::lower::Lowerer;
use crate::system::sparse_lu::SparseLu;
use crate::system::spec::Spec;

/// How B is known.
pub enum Transformation {
    /// In closed form: B row by row, and Q₀ = Q(t, q, 0) = −B a.
    Closed {
        b: Vec<Vec<NodeId>>,
        q0: Vec<NodeId>,
    },
    /// Through the LU of A at run time.
    Numeric(SparseLu),
}

impl Transformation {
    /// Every column of B, and (for the LU) the pivots the solves divide by, each with the
    /// coordinate it solves for. The columns share one factorization: the graph is
    /// hash-consed, and each solve is built from the same nodes.
    pub fn columns(&self, g: &mut Graph, n: usize) -> (Vec<Vec<NodeId>>, Vec<(NodeId, usize)>) {
        match self {
            Transformation::Closed { b, .. } => (super::columns(b), Vec::new()),
            Transformation::Numeric(lu) => {
                let (zero, one) = (g.zero(), g.one());
                let mut pivots = Vec::new();
                let columns = (0..n)
                    .map(|k| {
                        let unit: Vec<NodeId> =
                            (0..n).map(|i| if i == k { one } else { zero }).collect();
                        let (x, used) = lu.solve(g, &unit);
                        pivots = used;
                        x
                    })
                    .collect();
                (columns, pivots)
            }
        }
    }
}

/// The transformation, and for a closed-form one the defect that checks it at run time.
pub fn build<'a>(
    lowerer: &mut Lowerer<'a, '_>,
    spec: &Spec<'a>,
    rows: &Rows,
    t: NodeId,
    q: &[NodeId],
    omega: &[NodeId],
) -> Option<(Transformation, Option<Vec<NodeId>>)> {
    let Some(f) = spec.velocities else {
        return Some((Transformation::Numeric(rows.structure.clone()), None));
    };
    let out = lower(lowerer, spec, f, t, vec![array(q), array(omega)])?;
    if !check_affine(lowerer, f, &out, omega, "velocity", "w") {
        return None;
    }
    let (b, q0) = coefficients(lowerer.graph, &out, omega);
    let defect = inverse::check(lowerer, spec, f, rows, &b, &q0)?;
    Some((Transformation::Closed { b, q0 }, Some(defect)))
}
