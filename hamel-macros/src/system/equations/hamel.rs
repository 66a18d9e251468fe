//! Hamel's equations from the Lagrangian in quasi-velocities L̃(t, q, ω), for every column
//! B_k of B (`hamel::docs::design`, "Affine and time-dependent constraints"):
//!
//! ```text
//! Σ_{l>p} M_kl ω̇_l − rhs_k = λ_k (k < p), 0 (k ≥ p),   M_kl = ∂²L̃/∂ω_k∂ω_l,
//! rhs_k = f̃_k + B_kᵀ ∂L̃/∂q − (∂p_k/∂q)·q̇ − ∂p_k/∂t − (Φ''[q̇, B_k] − Φ''[B_k, q̇])
//!         − pᵀ(∂A/∂t) B_k + pᵀ (∂a/∂q) B_k,
//! ```
//!
//! p = ∂L̃/∂ω, Φ(t, q, v) = pᵀ r(t, q, v) with p held. The γ term never builds the n³
//! tensor: it is two bidirectional second derivatives of Φ per column. With homogeneous
//! rows that do not depend on t the last two terms vanish (the graph folds them away).

use super::{Assembled, Constrained, Vectors, dot, fresh, pairs, subst};
use crate::engine::diff;
use crate::engine::graph::{Graph, NodeId};

/// `omega` are the velocity symbols of `lt`; `b` every column of B; `p` the number of
/// constraints.
pub fn assemble(
    g: &mut Graph,
    lt: NodeId,
    omega: &[NodeId],
    b: &[Vec<NodeId>],
    x: &Vectors<'_>,
    p: usize,
) -> Assembled {
    let (t, q, qd) = (x.t, x.q, x.qd);
    let n = q.len();
    let one = g.one();
    let zero = g.zero();
    let wrt: Vec<NodeId> = q.iter().chain(omega).copied().collect();
    let gradient = diff::adjoint(g, &[lt], &[one], &wrt);
    let (grad_q, momenta) = gradient.split_at(n);

    // M_kl = ∂p_k/∂ω_l, one tangent sweep per free column.
    let mass_columns: Vec<Vec<NodeId>> = (p..n)
        .map(|l| diff::tangent(g, momenta, &[(omega[l], one)]))
        .collect();
    // (∂p_k/∂q)·q̇ with q̇ held as a symbol, and ∂p_k/∂t.
    let a_sym = fresh(g, "qd_direction", n);
    let hq = diff::tangent(g, momenta, &pairs(q, &a_sym));
    let ht = diff::tangent(g, momenta, &[(t, one)]);

    let p_sym = fresh(g, "momentum", n);
    let terms = RowTerms::new(g, p_sym.as_slice(), x);
    let rhs: Vec<NodeId> = b
        .iter()
        .enumerate()
        .map(|(k, bk)| {
            let f_tilde = dot(g, bk, x.forces);
            let b_grad = dot(g, bk, grad_q);
            let s = g.add(f_tilde, b_grad);
            let s = g.sub(s, hq[k]);
            let s = g.sub(s, ht[k]);
            let rows = terms.along(g, bk, qd);
            g.sub(s, rows)
        })
        .collect();

    // E = pᵀ(ω − a) − L̃, and ∂L/∂t = ∂L̃/∂t + pᵀ ∂r/∂t at v = q̇.
    let shifted: Vec<NodeId> = omega
        .iter()
        .zip(x.offset)
        .map(|(&w, &a)| g.sub(w, a))
        .collect();
    let legendre = dot(g, momenta, &shifted);
    let energy = g.sub(legendre, lt);
    let lt_rate = diff::tangent(g, &[lt], &[(t, one)])[0];
    let rows_rate = diff::tangent(g, x.rows, &[(t, one)]);
    let rows_rate = subst(g, &rows_rate, &pairs(x.v, qd));
    let carried = dot(g, momenta, &rows_rate);
    let lagrangian_rate = g.add(lt_rate, carried);

    // Evaluate at ω = (0, w); the symbols q̇ and p take their values.
    let mut at_state: Vec<(NodeId, NodeId)> = (0..p).map(|j| (omega[j], zero)).collect();
    at_state.extend(pairs(&omega[p..], x.w));
    let momenta_now = subst(g, momenta, &at_state);
    let mut all = at_state.clone();
    all.extend(pairs(&a_sym, qd));
    all.extend(pairs(&p_sym, &momenta_now));
    let mut roots: Vec<NodeId> = mass_columns.iter().flatten().copied().collect();
    roots.extend(&rhs);
    roots.push(energy);
    roots.push(lagrangian_rate);
    let done = subst(g, &roots, &all);
    let free = n - p;
    let (mass_flat, rest) = done.split_at(free * n);
    let by_column: Vec<&[NodeId]> = mass_flat.chunks(n).collect();
    let mut mass: Vec<Vec<NodeId>> = (0..n)
        .map(|k| by_column.iter().map(|c| c[k]).collect())
        .collect();
    let mut rhs = rest[..n].to_vec();
    Assembled {
        mass: mass.split_off(p),
        rhs: rhs.split_off(p),
        constrained: Constrained::Rows { mass, rhs },
        energy: rest[n],
        lagrangian_rate: rest[n + 1],
    }
}

/// The terms of the rows in Hamel's equations, from Φ(t, q, v) = Σ_j P_j r_j(t, q, v) with
/// the momenta P as symbols: the γ term (second derivatives in q and v), the explicit time
/// derivative of A, and the derivative of the affine part a along a direction.
struct RowTerms {
    /// Φ''[dq, dv].
    second: NodeId,
    /// ∂Φ/∂t (a function of v).
    rate: NodeId,
    /// D_qΦ[dq] (a function of v and dq).
    along_q: NodeId,
    dq: Vec<NodeId>,
    dv: Vec<NodeId>,
    v: Vec<NodeId>,
}

impl RowTerms {
    fn new(g: &mut Graph, p_sym: &[NodeId], x: &Vectors<'_>) -> RowTerms {
        let n = x.q.len();
        let one = g.one();
        let products: Vec<NodeId> = p_sym
            .iter()
            .zip(x.rows)
            .map(|(&pj, &r)| g.mul(pj, r))
            .collect();
        let phi = g.sum(&products);
        let dq = fresh(g, "q_direction", n);
        let dv = fresh(g, "v_direction", n);
        let second = diff::bidirectional(g, &[phi], &pairs(x.q, &dq), &pairs(x.v, &dv))[0];
        let rate = diff::tangent(g, &[phi], &[(x.t, one)])[0];
        let along_q = diff::tangent(g, &[phi], &pairs(x.q, &dq))[0];
        RowTerms {
            second,
            rate,
            along_q,
            dq,
            dv,
            v: x.v.to_vec(),
        }
    }

    /// Φ''[q̇, B_k] − Φ''[B_k, q̇] + pᵀ(∂A/∂t)B_k − pᵀ(∂a/∂q)B_k for one column B_k.
    fn along(&self, g: &mut Graph, bk: &[NodeId], qd: &[NodeId]) -> NodeId {
        let zero = g.zero();
        let zeros = vec![zero; bk.len()];
        let forward: Vec<NodeId> = self.dq.iter().chain(&self.dv).copied().collect();
        let qd_bk: Vec<NodeId> = qd.iter().chain(bk).copied().collect();
        let bk_qd: Vec<NodeId> = bk.iter().chain(qd).copied().collect();
        let d1 = subst(g, &[self.second], &pairs(&forward, &qd_bk))[0];
        let d2 = subst(g, &[self.second], &pairs(&forward, &bk_qd))[0];
        let gamma = g.sub(d1, d2);
        // pᵀ(∂A/∂t)B_k = ∂Φ/∂t at v = B_k minus at v = 0 (a's part).
        let rate_bk = subst(g, &[self.rate], &pairs(&self.v, bk))[0];
        let rate_0 = subst(g, &[self.rate], &pairs(&self.v, &zeros))[0];
        let time = g.sub(rate_bk, rate_0);
        // pᵀ(∂a/∂q)B_k = D_qΦ[B_k] at v = 0.
        let mut at_zero = pairs(&self.v, &zeros);
        at_zero.extend(pairs(&self.dq, bk));
        let affine = subst(g, &[self.along_q], &at_zero)[0];
        let s = g.add(gamma, time);
        g.sub(s, affine)
    }
}
