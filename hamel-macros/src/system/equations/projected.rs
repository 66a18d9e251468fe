//! Lagrange's equations projected on the columns of B, for a B derived from A (by the LU at
//! run time, where L̃ cannot be differentiated in q, or in closed form, where composing
//! L(q, Bω) would cost more):
//!
//! ```text
//! Σ_{l>p} (B_kᵀ H_vv B_l) ω̇_l − B_kᵀ (f + ∇_q L − H_vq q̇ − ∂_t∇_v L − H_vv c) = λ_k or 0,
//! q̈ = Σ_{l>p} B_l ω̇_l + c,   c = −B (D_q r[q̇] + ∂r/∂t) at v = q̇,
//! ```
//!
//! from differentiating ω = r(t, q, q̇) along the motion (the constrained ω stay zero).
//! Only the free columns are projected here; λ is B_cᵀ R for Lagrange's residual R in q,
//! found by one solve with Aᵀ (`Constrained::Residual`).

use super::transformation::Transformation;
use super::{Assembled, Constrained, Vectors, dot, fresh, pairs, subst};
use crate::engine::diff;
use crate::engine::graph::{Graph, NodeId};

/// `l` is L(t, q, v) in the velocity symbols of `x.v`.
pub fn assemble(
    g: &mut Graph,
    l: NodeId,
    transformation: &Transformation,
    x: &Vectors<'_>,
) -> Assembled {
    let (t, q, qd, v, b_free) = (x.t, x.q, x.qd, x.v, x.b_free);
    let n = q.len();
    let p = n - x.w.len();
    let one = g.one();
    let wrt: Vec<NodeId> = q.iter().chain(v).copied().collect();
    let gradient = diff::adjoint(g, &[l], &[one], &wrt);
    let (grad_q, grad_v) = gradient.split_at(n);

    // B_kᵀ H_vv B_l: one tangent of ∇_v L per free direction (B entries are inputs here).
    let h_b: Vec<Vec<NodeId>> = b_free
        .iter()
        .map(|bl| diff::tangent(g, grad_v, &pairs(v, bl)))
        .collect();
    let mass: Vec<Vec<NodeId>> = b_free
        .iter()
        .map(|bk| h_b.iter().map(|hl| dot(g, bk, hl)).collect())
        .collect();

    // c = −B (D_q r[q̇] + ∂r/∂t) at v = q̇.
    let a_sym = fresh(g, "qd_direction", n);
    let along = diff::tangent(g, x.rows, &pairs(q, &a_sym));
    let rate = diff::tangent(g, x.rows, &[(t, one)]);
    let along: Vec<NodeId> = along
        .iter()
        .zip(&rate)
        .map(|(&a, &r)| g.add(a, r))
        .collect();
    let mut at_qd = pairs(v, qd);
    at_qd.extend(pairs(&a_sym, qd));
    let along = subst(g, &along, &at_qd);
    let solved = transformation.solve(g, &along);
    let c: Vec<NodeId> = solved.into_iter().map(|d| g.neg(d)).collect();

    // d/dt ∂L/∂q̇ − H_vv·(B_free ω̇) = H_vq q̇ + H_vv c + ∂_t∇_v L: one tangent.
    let c_sym = fresh(g, "acceleration_drift", n);
    let mut seeds = pairs(q, &a_sym);
    seeds.extend(pairs(v, &c_sym));
    seeds.push((t, one));
    let drift = diff::tangent(g, grad_v, &seeds);
    let terms: Vec<NodeId> = (0..n)
        .map(|i| {
            let s = g.add(x.forces[i], grad_q[i]);
            g.sub(s, drift[i])
        })
        .collect();
    let rhs: Vec<NodeId> = b_free.iter().map(|bk| dot(g, bk, &terms)).collect();
    let legendre = dot(g, grad_v, v);
    let energy = g.sub(legendre, l);
    let lagrangian_rate = diff::tangent(g, &[l], &[(t, one)])[0];

    let mut all = pairs(v, qd);
    all.extend(pairs(&a_sym, qd));
    all.extend(pairs(&c_sym, &c));
    let free = n - p;
    let mut roots: Vec<NodeId> = mass.iter().flatten().copied().collect();
    roots.extend(h_b.iter().flatten());
    roots.extend(&rhs);
    roots.extend(&terms);
    roots.push(energy);
    roots.push(lagrangian_rate);
    let done = subst(g, &roots, &all);
    let (mass_flat, rest) = done.split_at(free * free);
    let (coupling, rest) = rest.split_at(free * n);
    let (rhs, rest) = rest.split_at(free);
    let (terms, rest) = rest.split_at(n);
    Assembled {
        mass: mass_flat.chunks(free).map(<[NodeId]>::to_vec).collect(),
        rhs: rhs.to_vec(),
        constrained: Constrained::Residual {
            coupling: coupling.chunks(n).map(<[NodeId]>::to_vec).collect(),
            terms: terms.to_vec(),
        },
        energy: rest[0],
        lagrangian_rate: rest[1],
    }
}
