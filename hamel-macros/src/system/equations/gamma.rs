//! The coefficients γʲ_{l,k} of Hamel's equations, for inspection (the right-hand side never
//! builds this n³ tensor): γʲ_{l,k} = Aⱼ''[B_l, B_k] − Aⱼ''[B_k, B_l] with
//! Aⱼ''[a, c] = Σ ∂A^j_ν/∂q^σ a^σ c^ν.

use super::{fresh, pairs, subst};
use crate::engine::diff;
use crate::engine::graph::{Graph, NodeId};

/// γ indexed [j][l − p][k − p], from the rows r(t, q, v) and the free columns of B.
pub fn gamma(
    g: &mut Graph,
    rows: &[NodeId],
    q: &[NodeId],
    v: &[NodeId],
    b_free: &[Vec<NodeId>],
) -> Vec<Vec<Vec<NodeId>>> {
    let n = q.len();
    let dq = fresh(g, "gamma_q_direction", n);
    let dv = fresh(g, "gamma_v_direction", n);
    let second = diff::bidirectional(g, rows, &pairs(q, &dq), &pairs(v, &dv));
    let directions: Vec<NodeId> = dq.iter().chain(&dv).copied().collect();
    // Aⱼ''[a, c] for every row j at once: one substitution per ordered pair of columns, each
    // rebuilding the cone of all the rows (substituting row by row rebuilt it n times).
    let along = |g: &mut Graph, a: &[NodeId], c: &[NodeId]| -> Vec<NodeId> {
        let ac: Vec<NodeId> = a.iter().chain(c).copied().collect();
        subst(g, &second, &pairs(&directions, &ac))
    };
    let free = b_free.len();
    let mut gamma = vec![vec![vec![g.zero(); free]; free]; rows.len()];
    for (l, bl) in b_free.iter().enumerate() {
        for (k, bk) in b_free.iter().enumerate() {
            let lk = along(g, bl, bk);
            let kl = along(g, bk, bl);
            for (j, (&x, &y)) in lk.iter().zip(&kl).enumerate() {
                gamma[j][l][k] = g.sub(x, y);
            }
        }
    }
    gamma
}
