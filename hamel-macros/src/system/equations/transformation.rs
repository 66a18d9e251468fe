//! The inverse of the rows, q̇ = Q(t, q, ω) = B(q, t)(ω − a(q, t)): from the user's
//! `#[velocities]` in closed form (checked to be the inverse by `inverse`), or by an LU
//! factorization of A with partial pivoting unrolled into the generated code.

use super::rows::{Rows, check_affine, coefficients};
use super::{PivotCheck, array, dot, inverse, lower};
use crate::engine::graph::{Graph, NodeId};
use crate::engine::lower::Lowerer;
use crate::system::sparse_lu::{BlockSolver, SparseLu};
use crate::system::spec::Spec;

/// How B is known.
pub enum Transformation {
    /// In closed form: B row by row, Q₀ = Q(t, q, 0) = −B a, and the determinants to check
    /// before B is used (none for the user's own inverse, which is checked against A
    /// instead).
    Closed {
        b: Vec<Vec<NodeId>>,
        q0: Vec<NodeId>,
        checks: Vec<PivotCheck>,
        /// `None` for the user's inverse, which Hamel's route composes into
        /// L̃ = L(q, Bω + Q₀). For a B derived from A, the solves by substitution with the
        /// blocks' inverses, and the projected route (composing a B that fills in, such as
        /// the N-trailer's, made its right-hand side 3× slower).
        solver: Option<BlockSolver>,
    },
    /// Through the LU of A at run time.
    Numeric(SparseLu),
}

impl Transformation {
    /// x = B·r: the solution of A x = r, by the LU or with the closed form.
    pub fn solve(&self, g: &mut Graph, r: &[NodeId]) -> Vec<NodeId> {
        match self {
            Transformation::Closed {
                solver: Some(solver),
                ..
            } => solver.solve(g, r),
            Transformation::Closed { b, .. } => b.iter().map(|row| dot(g, row, r)).collect(),
            Transformation::Numeric(lu) => lu.solve(g, r).0,
        }
    }

    /// y = Bᵀ·r: the solution of Aᵀ y = r (y per row of A), by the blocks in reverse order.
    pub fn solve_transposed(&self, g: &mut Graph, r: &[NodeId]) -> Vec<NodeId> {
        match self {
            Transformation::Closed {
                solver: Some(solver),
                ..
            } => solver.solve_transposed(g, r),
            Transformation::Closed { b, .. } => super::columns(b)
                .iter()
                .map(|column| dot(g, column, r))
                .collect(),
            Transformation::Numeric(lu) => lu.solve_transposed(g, r),
        }
    }

    /// Every column of B, and what to check before using them: the LU's pivots (against
    /// A's scale) or the closed form's determinants. The LU's columns share one
    /// factorization: the graph is hash-consed, and each solve is built from the same nodes.
    pub fn columns(&self, g: &mut Graph, n: usize) -> (Vec<Vec<NodeId>>, Vec<PivotCheck>) {
        match self {
            Transformation::Closed { b, checks, .. } => (super::columns(b), checks.clone()),
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
                let scale = lu.scale(g);
                let checks = pivots
                    .into_iter()
                    .map(|(value, coordinate)| PivotCheck {
                        value,
                        scale,
                        coordinate,
                    })
                    .collect();
                (columns, checks)
            }
        }
    }
}

/// The transformation, and for the user's closed-form one the defect that checks it at run
/// time. Without one, B is derived in closed form when A's diagonal blocks are small
/// ([`SparseLu::closed_inverse`]), and otherwise left to the LU at run time.
pub fn build<'a>(
    lowerer: &mut Lowerer<'a, '_>,
    spec: &Spec<'a>,
    rows: &Rows,
    t: NodeId,
    q: &[NodeId],
    omega: &[NodeId],
) -> Option<(Transformation, Option<Vec<NodeId>>)> {
    let Some(f) = spec.velocities else {
        let varying: Vec<NodeId> = std::iter::once(t).chain(q.iter().copied()).collect();
        return Some((derived(lowerer.graph, rows, &varying), None));
    };
    let out = lower(lowerer, spec, f, t, vec![array(q), array(omega)])?;
    if !check_affine(lowerer, f, &out, omega, "velocity", "w") {
        return None;
    }
    let (b, q0) = coefficients(lowerer.graph, &out, omega);
    let defect = inverse::check(lowerer, spec, f, rows, &b, &q0)?;
    let checks = Vec::new();
    let solver = None;
    Some((
        Transformation::Closed {
            b,
            q0,
            checks,
            solver,
        },
        Some(defect),
    ))
}

/// B derived from the rows: in closed form if A's blocks allow it, else by the LU.
fn derived(g: &mut Graph, rows: &Rows, varying: &[NodeId]) -> Transformation {
    let Some(inverse) = rows.structure.closed_inverse(g, varying) else {
        return Transformation::Numeric(rows.structure.clone());
    };

    // Q₀ = −B a.
    let q0 = inverse
        .b
        .iter()
        .map(|row| {
            let drift = dot(g, row, &rows.offset);
            g.neg(drift)
        })
        .collect();
    let checks = inverse
        .checks
        .into_iter()
        .map(|(value, scale, coordinate)| PivotCheck {
            value,
            scale,
            coordinate,
        })
        .collect();
    Transformation::Closed {
        b: inverse.b,
        q0,
        checks,
        solver: Some(inverse.solver),
    }
}
