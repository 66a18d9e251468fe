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
    /// The user's closed-form inverse: B row by row and Q₀ = Q(t, q, 0) = −B a, composed
    /// into L̃ = L(q, Bω + Q₀) by Hamel's route (and checked against A instead of having
    /// determinants checked).
    Given {
        b: Vec<Vec<NodeId>>,
        q0: Vec<NodeId>,
    },
    /// Derived from A with its diagonal blocks inverted in closed form, solved block by
    /// block; the blocks' determinants to check before use. The projected route takes it
    /// (composing a B that fills in, such as the N-trailer's, made its right-hand side 3×
    /// slower).
    Blocks {
        checks: Vec<PivotCheck>,
        solver: BlockSolver,
    },
    /// Through the LU of A at run time.
    Numeric(SparseLu),
}

impl Transformation {
    /// x = B·r: the solution of A x = r.
    pub fn solve(&self, g: &mut Graph, r: &[NodeId]) -> Vec<NodeId> {
        match self {
            Transformation::Given { b, .. } => b.iter().map(|row| dot(g, row, r)).collect(),
            Transformation::Blocks { solver, .. } => solver.solve(g, r),
            Transformation::Numeric(lu) => lu.solve(g, r).0,
        }
    }

    /// y = Bᵀ·r: the solution of Aᵀ y = r (y per row of A), by the blocks in reverse order.
    pub fn solve_transposed(&self, g: &mut Graph, r: &[NodeId]) -> Vec<NodeId> {
        match self {
            Transformation::Given { b, .. } => super::columns(b)
                .iter()
                .map(|column| dot(g, column, r))
                .collect(),
            Transformation::Blocks { solver, .. } => solver.solve_transposed(g, r),
            Transformation::Numeric(lu) => lu.solve_transposed(g, r),
        }
    }

    /// Q₀ = −B a, the velocity that affine rows impose: the user's own, or one more solve.
    pub fn drift(&self, g: &mut Graph, offset: &[NodeId]) -> Vec<NodeId> {
        match self {
            Transformation::Given { q0, .. } => q0.clone(),
            _ if offset.iter().all(|&a| g.is_zero(a)) => vec![g.zero(); offset.len()],
            _ => {
                let solved = self.solve(g, offset);
                solved.into_iter().map(|x| g.neg(x)).collect()
            }
        }
    }

    /// The columns B_k for k = `from` … n − 1, and what to check before using them: the
    /// LU's pivots (against A's scale) or the closed-form blocks' determinants. Each column
    /// solves A x = e_k; the solves share one factorization, because the graph is
    /// hash-consed and each is built from the same nodes. Only the columns asked for are
    /// built: the projected route needs the free ones, and a B that fills in has p·n
    /// entries in the constrained ones.
    pub fn columns(&self, g: &mut Graph, from: usize) -> (Vec<Vec<NodeId>>, Vec<PivotCheck>) {
        let n = match self {
            Transformation::Given { b, .. } => b.len(),
            Transformation::Blocks { solver, .. } => solver.len(),
            Transformation::Numeric(lu) => lu.len(),
        };
        let (zero, one) = (g.zero(), g.one());
        let unit =
            |k: usize| -> Vec<NodeId> { (0..n).map(|i| if i == k { one } else { zero }).collect() };
        match self {
            Transformation::Given { b, .. } => (super::columns(b).split_off(from), Vec::new()),
            Transformation::Blocks { checks, solver } => {
                let columns = (from..n).map(|k| solver.solve(g, &unit(k))).collect();
                (columns, checks.clone())
            }
            Transformation::Numeric(lu) => {
                let mut pivots = Vec::new();
                let columns = (from..n)
                    .map(|k| {
                        let (x, used) = lu.solve(g, &unit(k));
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
    Some((Transformation::Given { b, q0 }, Some(defect)))
}

/// B derived from the rows: in closed form if A's blocks allow it, else by the LU.
fn derived(g: &mut Graph, rows: &Rows, varying: &[NodeId]) -> Transformation {
    let Some(inverse) = rows.structure.closed_inverse(g, varying) else {
        return Transformation::Numeric(rows.structure.clone());
    };
    let checks = inverse
        .checks
        .into_iter()
        .map(|(value, scale, coordinate)| PivotCheck {
            value,
            scale,
            coordinate,
        })
        .collect();
    Transformation::Blocks {
        checks,
        solver: inverse.solver,
    }
}
