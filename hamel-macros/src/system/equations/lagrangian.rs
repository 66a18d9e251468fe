//! The Lagrangian from the energy roles: L(t, q, v) for the projected route, L̃(t, q, ω) for
//! Hamel's, and the energy a simulation monitors.

use super::rows::requires_velocities;
use super::transformation::Transformation;
use super::{array, bodies, dot, lower, pairs, subst};
use crate::engine::graph::{Graph, NodeId};
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

/// L = T − V or L as written, at the given velocities, with the bodies' energies added,
/// and the function to blame when it does not depend on them.
fn written<'a>(
    lowerer: &mut Lowerer<'a, '_>,
    spec: &Spec<'a>,
    t: NodeId,
    q: &[NodeId],
    velocities: &[NodeId],
) -> Option<(NodeId, &'a syn::ImplItemFn)> {
    let bodies = bodies::energies(lowerer, spec, t, q, velocities)?;
    let blame = spec.geometry.bodies.map(|(f, _)| f);
    let (l, f) = match &spec.energy {
        Energy::Lagrangian(f) => {
            let l = *lower(lowerer, spec, f, t, vec![array(q), array(velocities)])?.first()?;
            (Some(l), Some(*f))
        }
        Energy::Split { kinetic, potential } => {
            let kinetic_value = match kinetic {
                Some(f) => {
                    let args = vec![array(q), array(velocities)];
                    Some(*lower(lowerer, spec, f, t, args)?.first()?)
                }
                None => None,
            };
            let potential_value = match potential {
                Some(vf) => Some(*lower(lowerer, spec, vf, t, vec![array(q)])?.first()?),
                None => None,
            };
            let g = &mut *lowerer.graph;
            let l = match (kinetic_value, potential_value) {
                (Some(k), Some(v)) => Some(g.sub(k, v)),
                (Some(k), None) => Some(k),
                (None, Some(v)) => Some(g.neg(v)),
                (None, None) => None,
            };
            (l, *kinetic)
        }
        Energy::Quasi(_) => return None,
    };
    let g = &mut *lowerer.graph;
    let l = match (l, bodies) {
        (Some(l), Some((kinetic, potential))) => {
            let with = g.add(l, kinetic);
            g.sub(with, potential)
        }
        (None, Some((kinetic, potential))) => g.sub(kinetic, potential),
        (Some(l), None) => l,
        (None, None) => return None,
    };
    Some((l, f.or(blame)?))
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
    let bodies = bodies::energies(lowerer, spec, t, q, v)?;
    let written = match kinetic {
        Some(f) => Some(*lower(lowerer, spec, f, t, vec![array(q), array(v)])?.first()?),
        None => None,
    };
    let g = &mut *lowerer.graph;
    let at_v = match (written, bodies) {
        (Some(k), Some((b, _))) => g.add(k, b),
        (Some(k), None) => k,
        (None, Some((b, _))) => b,
        (None, None) => return Some(None),
    };
    // A homogeneous quadratic form: T(2v) = 4 T(v), with no part without velocities (which the
    // Legendre energy would count with the opposite sign).
    let zeros = vec![g.zero(); v.len()];
    let at_0 = subst(g, &[at_v], &pairs(v, &zeros))[0];
    let quadratic = g.is_zero(at_0) && quadratic_form(g, at_v, v);
    if !quadratic {
        return Some(None);
    }
    let kinetic_value = subst(g, &[at_v], &pairs(v, qd))[0];
    let mut energy = match bodies {
        Some((_, gravity)) => g.add(kinetic_value, gravity),
        None => kinetic_value,
    };
    if let Some(vf) = potential {
        let v_value = *lower(lowerer, spec, vf, t, vec![array(q)])?.first()?;
        energy = lowerer.graph.add(energy, v_value);
    }
    Some(Some(energy))
}

/// Whether `f` is a quadratic form in the velocity symbols `vars` plus a part without them,
/// f(2v) − f(0) = 4 (f(v) − f(0)), decided at generic points (outside the function's domain
/// there is no verdict against it).
pub fn quadratic_form(g: &mut Graph, f: NodeId, vars: &[NodeId]) -> bool {
    let (zero, two, four) = (g.zero(), g.constant(2.0), g.constant(4.0));
    let doubled: Vec<NodeId> = vars.iter().map(|&x| g.mul(two, x)).collect();
    let zeros = vec![zero; vars.len()];
    let at_2v = subst(g, &[f], &pairs(vars, &doubled))[0];
    let at_0 = subst(g, &[f], &pairs(vars, &zeros))[0];
    let grown = g.sub(at_2v, at_0);
    let part = g.sub(f, at_0);
    let expected = g.mul(four, part);
    let defect = g.sub(grown, expected);
    generic::points(3, g.input_count()).iter().all(|point| {
        let values = g.evaluate(&[defect, f], point);
        !values[0].is_finite() || values[0].abs() <= 1e-9 * (1.0 + values[1].abs())
    })
}

/// Whether the model's Lagrangian is a quadratic form in the velocities plus a part without
/// them (T quadratic, no gyroscopic term linear in the velocities): as written, L(t, q, v),
/// or in quasi-velocities, L̃(t, q, ω).
pub fn quadratic_in_velocities<'a>(
    lowerer: &mut Lowerer<'a, '_>,
    spec: &Spec<'a>,
    t: NodeId,
    q: &[NodeId],
    (v, omega): (&[NodeId], &[NodeId]),
) -> Option<bool> {
    let (l, vars) = match &spec.energy {
        Energy::Quasi(f) => (
            *lower(lowerer, spec, f, t, vec![array(q), array(omega)])?.first()?,
            omega,
        ),
        _ => (written(lowerer, spec, t, q, v)?.0, v),
    };
    Some(quadratic_form(lowerer.graph, l, vars))
}
