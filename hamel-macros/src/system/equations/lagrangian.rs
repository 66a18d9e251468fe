//! The Lagrangian from the energy roles: L(t, q, v) for the projected route, L̃(t, q, ω) for
//! Hamel's, and the energy a simulation monitors.

use super::rows::requires_velocities;
use super::transformation::Transformation;
use super::{array, dot, lower, pairs, subst};
use crate::engine::graph::NodeId;
use crate::engine::lower::Lowerer;
use crate::system::generic;
use crate::system::spec::{Energy, Spec};

/// L̃(t, q, ω) where Hamel's route can have it: as written (`#[quasi_lagrangian]`), or
/// L(t, q, Q(t, q, ω)) with a closed-form inverse Q. `Some(None)` when B is known only
/// numerically (the projected route then needs L itself); `None` after an error.
pub fn quasi<'a>(
    lowerer: &mut Lowerer<'a, '_>,
    spec: &Spec<'a>,
    transformation: &Transformation,
    t: NodeId,
    q: &[NodeId],
    omega: &[NodeId],
) -> Option<Option<NodeId>> {
    let (lt, f) = match (&spec.energy, transformation) {
        (Energy::Quasi(f), _) => {
            let lt = *lower(lowerer, spec, f, t, vec![array(q), array(omega)])?.first()?;
            (lt, *f)
        }
        (_, Transformation::Given { b, q0 }) => {
            let g = &mut *lowerer.graph;
            let velocities: Vec<NodeId> = b
                .iter()
                .zip(q0)
                .map(|(row, &q0_i)| {
                    let s = dot(g, row, omega);
                    g.add(s, q0_i)
                })
                .collect();
            written(lowerer, spec, t, q, &velocities)?
        }
        (_, Transformation::Blocks { .. } | Transformation::Numeric(_)) => return Some(None),
    };
    requires_velocities(lowerer, f, lt, omega, "the Lagrangian").then_some(Some(lt))
}

/// L(t, q, v) in the velocity symbols `v`, checked to depend on them.
pub fn lagrangian<'a>(
    lowerer: &mut Lowerer<'a, '_>,
    spec: &Spec<'a>,
    t: NodeId,
    q: &[NodeId],
    v: &[NodeId],
) -> Option<NodeId> {
    let (l, f) = written(lowerer, spec, t, q, v)?;
    requires_velocities(lowerer, f, l, v, "the Lagrangian").then_some(l)
}

/// L = T − V or L as written, at the given velocities, with the function to blame when it
/// does not depend on them.
fn written<'a>(
    lowerer: &mut Lowerer<'a, '_>,
    spec: &Spec<'a>,
    t: NodeId,
    q: &[NodeId],
    velocities: &[NodeId],
) -> Option<(NodeId, &'a syn::ImplItemFn)> {
    match &spec.energy {
        Energy::Lagrangian(f) => {
            let l = *lower(lowerer, spec, f, t, vec![array(q), array(velocities)])?.first()?;
            Some((l, f))
        }
        Energy::Split { kinetic, potential } => {
            let args = vec![array(q), array(velocities)];
            let kinetic_value = *lower(lowerer, spec, kinetic, t, args)?.first()?;
            let l = match potential {
                Some(vf) => {
                    let v = *lower(lowerer, spec, vf, t, vec![array(q)])?.first()?;
                    lowerer.graph.sub(kinetic_value, v)
                }
                None => kinetic_value,
            };
            Some((l, kinetic))
        }
        Energy::Quasi(_) => None,
    }
}

/// The energy as T + V, where that is the energy q̇·∂L/∂q̇ − L: for a kinetic energy that is
/// a quadratic form in q̇ (decided at generic points: T(t, q, 2v) = 4 T(t, q, v)), as it is in
/// an inertial frame. T + V is the physical energy and avoids the Legendre transform's
/// rounding. `Some(None)` when the Legendre energy must be used; `None` after an error.
pub fn split_energy<'a>(
    lowerer: &mut Lowerer<'a, '_>,
    spec: &Spec<'a>,
    t: NodeId,
    q: &[NodeId],
    v: &[NodeId],
    qd: &[NodeId],
) -> Option<Option<NodeId>> {
    let Energy::Split { kinetic, potential } = &spec.energy else {
        return Some(None);
    };
    let at_v = *lower(lowerer, spec, kinetic, t, vec![array(q), array(v)])?.first()?;
    let g = &mut *lowerer.graph;
    let two = g.constant(2.0);
    let doubled: Vec<NodeId> = v.iter().map(|&x| g.mul(two, x)).collect();
    let at_2v = subst(g, &[at_v], &pairs(v, &doubled))[0];
    let four = g.constant(4.0);
    let expected = g.mul(four, at_v);
    let defect = g.sub(at_2v, expected);
    let quadratic = generic::points(3, g.input_count()).iter().all(|point| {
        let values = g.evaluate(&[defect, at_v], point);
        // Outside the function's domain there is no verdict against it.
        !values[0].is_finite() || values[0].abs() <= 1e-9 * (1.0 + values[1].abs())
    });
    if !quadratic {
        return Some(None);
    }
    let kinetic_value = subst(g, &[at_v], &pairs(v, qd))[0];
    Some(Some(match potential {
        Some(vf) => {
            let v_value = *lower(lowerer, spec, vf, t, vec![array(q)])?.first()?;
            lowerer.graph.add(kinetic_value, v_value)
        }
        None => kinetic_value,
    }))
}
