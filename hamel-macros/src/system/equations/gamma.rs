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
    second
        .iter()
        .map(|&d| {
            b_free
                .iter()
                .map(|bl| {
                    b_free
                        .iter()
                        .map(|bk| {
                            let lk: Vec<NodeId> = bl.iter().chain(bk).copied().collect();
                            let kl: Vec<NodeId> = bk.iter().chain(bl).copied().collect();
                            let x = subst(g, &[d], &pairs(&directions, &lk))[0];
                            let y = subst(g, &[d], &pairs(&directions, &kl))[0];
                            g.sub(x, y)
                        })
                        .collect()
                })
                .collect()
        })
        .collect()
}
