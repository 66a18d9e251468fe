//! Control from the model, on the graph of Hamel's equations: the control-affine form of the
//! reduced ODE, the outputs' Lie derivatives and the Lie brackets of its fields, each as
//! nested tangent sweeps of the engine (`hamel::docs::control` has the mathematics).
//!
//! With F(t, x, u) the right-hand side (q̇ and ω̇ in the state's inputs q, w and u):
//!
//! * the drift f(t, x) = F(t, x, 0) (u substituted by zeros) and the input fields
//!   g_j = ∂F/∂u_j (one tangent sweep each, seeded in u_j); F is affine in u exactly when no
//!   g_j depends on u, which the graph tells structurally;
//! * L_f^{k+1} h = ∂(L_f^k h)/∂t + ∂(L_f^k h)/∂x · f — a tangent sweep of L_f^k h with the
//!   state's inputs seeded by the nodes of f (which depend on x themselves: so the next
//!   sweep differentiates them too) and t by 1; L_{g_j} L_f^k h likewise along g_j, without t;
//! * [X, Y] = ∂Y/∂x · X − ∂X/∂x · Y, two sweeps at a frozen time; iterated brackets are
//!   right-nested, [X_{a₁}, [X_{a₂}, … [X_{a_{L−1}}, X_{a_L}]]] with a_{L−1} < a_L, whose span
//!   is the Lie algebra the fields generate.
//!
//! Nothing here is built for a model that does not ask (`spec.control` is `None`), so that
//! its expansion is exactly what it was.

pub mod emit;

use super::equations::{Equations, array, lower, subst};
use super::spec::Spec;
use super::spec::control::ControlRequest;
use crate::engine::diff::tangent;
use crate::engine::graph::{Graph, NodeId};
use crate::engine::lower::Lowerer;

/// An iterated Lie bracket of the drift and the input fields.
pub struct Bracket {
    /// As written in the generated documentation and `BRACKETS`: `[f, [f, g_tau1]]`.
    pub label: String,
    /// The number of brackets taken: 1 for [f, g_j].
    pub depth: usize,
    /// Its components over the state.
    pub nodes: Vec<NodeId>,
}

/// The control code's nodes.
pub struct ControlNodes {
    /// f(t, x) = F(t, x, 0), over the state.
    pub drift: Vec<NodeId>,
    /// g_j(t, x) = ∂F/∂u_j, one per input, over the state.
    pub fields: Vec<Vec<NodeId>>,
    /// The outputs' names (empty without `#[outputs]`).
    pub outputs: Vec<String>,
    /// L_f^k h_i, indexed [k][i] for k = 0 … order.
    pub lie: Vec<Vec<NodeId>>,
    /// L_{g_j} L_f^k h_i, indexed [k][i][j] for k < order.
    pub along: Vec<Vec<Vec<NodeId>>>,
    /// Which of them vanish identically (a constant zero on the graph), [k][i][j] flattened:
    /// what the relative degree is read from before any value.
    pub vanishing: Vec<bool>,
    pub brackets: Vec<Bracket>,
}

/// The nodes of the control code the model asks for, or `None` when it asks for none (or
/// after an error, reported: inputs that enter nonlinearly, a mistake in the outputs).
pub fn build<'a>(
    spec: &Spec<'a>,
    eq: &Equations,
    lowerer: &mut Lowerer<'a, '_>,
) -> Option<ControlNodes> {
    let request = spec.control.as_ref()?;
    let (drift, fields) = affine_form(spec, eq, lowerer)?;
    let (outputs, h) = match &request.outputs {
        Some(o) => {
            let mut args = vec![array(&eq.inputs.q)];
            if o.reads_speeds {
                args.push(array(&eq.inputs.w));
            }
            let h = lower(lowerer, spec, o.f, eq.inputs.t, args)?;
            (o.names.clone(), h)
        }
        None => (Vec::new(), Vec::new()),
    };
    let g = &mut *lowerer.graph;
    let state = state_inputs(eq);
    let (lie, along) = lie_derivatives(g, (&state, eq.inputs.t), (&drift, &fields), h, request);
    let brackets = brackets(g, &state, (&drift, &fields), &spec.inputs, request.brackets);
    let vanishing = along
        .iter()
        .flatten()
        .flatten()
        .map(|&id| g.is_zero(id))
        .collect();
    Some(ControlNodes {
        drift,
        fields,
        outputs,
        lie,
        along,
        vanishing,
        brackets,
    })
}

/// The state's inputs: the coordinates, then the free quasi-velocities.
fn state_inputs(eq: &Equations) -> Vec<NodeId> {
    eq.inputs.q.iter().chain(&eq.inputs.w).copied().collect()
}

/// f = F(t, x, 0) and g_j = ∂F/∂u_j; an error at the forces when some g_j depends on u.
fn affine_form(
    spec: &Spec<'_>,
    eq: &Equations,
    lowerer: &mut Lowerer<'_, '_>,
) -> Option<(Vec<NodeId>, Vec<Vec<NodeId>>)> {
    let g = &mut *lowerer.graph;
    let rhs: Vec<NodeId> = eq.qd.iter().chain(&eq.wdot).copied().collect();
    let zero = g.zero();
    let at_rest: Vec<(NodeId, NodeId)> = eq.inputs.u.iter().map(|&u| (u, zero)).collect();
    let drift = subst(g, &rhs, &at_rest);
    let one = g.one();
    let fields: Vec<Vec<NodeId>> = eq
        .inputs
        .u
        .iter()
        .map(|&u| tangent(g, &rhs, &[(u, one)]))
        .collect();
    let on_inputs = g.depends_on(&eq.inputs.u);
    let nonlinear = fields.iter().enumerate().find_map(|(j, field)| {
        field
            .iter()
            .position(|id| on_inputs[id.index()])
            .map(|row| (j, row))
    });
    if let Some((j, row)) = nonlinear {
        let state = spec.coordinates.iter().chain(&spec.speeds);
        let rate = state
            .clone()
            .nth(row)
            .map_or_else(String::new, ToString::to_string);
        let input = &spec.inputs[j];
        let message = format!(
            "the inputs enter the equations of motion nonlinearly: the rate of `{rate}` changes \
             with `{input}` at a rate that itself depends on the inputs, so the model is not \
             control-affine, ẋ = f(x) + Σ g_j(x) u_j, which `#[outputs]` and `control(..)` need: \
             make the forces affine in `u` (a motor's torque, not a function of it)"
        );
        let error = match spec.forces {
            Some(f) => syn::Error::new_spanned(&f.sig.ident, message),
            None => syn::Error::new(proc_macro2::Span::call_site(), message),
        };
        lowerer.push_error(error);
        return None;
    }
    Some((drift, fields))
}

/// The derivative of `roots` along the field `direction` over the state, and along the time
/// `t` (at rate 1) when given.
fn along(
    g: &mut Graph,
    roots: &[NodeId],
    state: &[NodeId],
    direction: &[NodeId],
    t: Option<NodeId>,
) -> Vec<NodeId> {
    let mut seeds: Vec<(NodeId, NodeId)> = state
        .iter()
        .copied()
        .zip(direction.iter().copied())
        .collect();
    if let Some(t) = t {
        let one = g.one();
        seeds.push((t, one));
    }
    tangent(g, roots, &seeds)
}

/// [X, Y] = ∂Y/∂x · X − ∂X/∂x · Y, at a frozen time.
fn bracket(g: &mut Graph, state: &[NodeId], x: &[NodeId], y: &[NodeId]) -> Vec<NodeId> {
    let dy_x = along(g, y, state, x, None);
    let dx_y = along(g, x, state, y, None);
    dy_x.iter().zip(&dx_y).map(|(&a, &b)| g.sub(a, b)).collect()
}

/// L_f^k h for k = 0 … order and L_{g_j} L_f^k h for k < order.
fn lie_derivatives(
    g: &mut Graph,
    (state, t): (&[NodeId], NodeId),
    (drift, fields): (&[NodeId], &[Vec<NodeId>]),
    h: Vec<NodeId>,
    request: &ControlRequest<'_>,
) -> (Vec<Vec<NodeId>>, Vec<Vec<Vec<NodeId>>>) {
    if h.is_empty() {
        return (Vec::new(), Vec::new());
    }
    let mut lie = vec![h];
    let mut inputs = Vec::new();
    for k in 0..request.order {
        let current = lie[k].clone();
        let by_input: Vec<Vec<NodeId>> = fields
            .iter()
            .map(|gj| along(g, &current, state, gj, None))
            .collect();
        // [i][j]: output by input.
        inputs.push(
            (0..current.len())
                .map(|i| by_input.iter().map(|col| col[i]).collect())
                .collect(),
        );
        lie.push(along(g, &current, state, drift, Some(t)));
    }
    (lie, inputs)
}

/// The right-nested brackets of the drift and the input fields to `depth`.
fn brackets(
    g: &mut Graph,
    state: &[NodeId],
    (drift, fields): (&[NodeId], &[Vec<NodeId>]),
    inputs: &[syn::Ident],
    depth: usize,
) -> Vec<Bracket> {
    let mut generators: Vec<(String, Vec<NodeId>)> = vec![("f".to_string(), drift.to_vec())];
    generators.extend(
        inputs
            .iter()
            .zip(fields)
            .map(|(name, field)| (format!("g_{name}"), field.clone())),
    );
    let mut all: Vec<Bracket> = Vec::new();
    if depth == 0 {
        return all;
    }
    for a in 0..generators.len() {
        for b in a + 1..generators.len() {
            all.push(Bracket {
                label: format!("[{}, {}]", generators[a].0, generators[b].0),
                depth: 1,
                nodes: bracket(g, state, &generators[a].1, &generators[b].1),
            });
        }
    }
    let mut level_start = 0;
    for d in 2..=depth {
        let level_end = all.len();
        for (name, x) in &generators {
            for w in level_start..level_end {
                let nodes = bracket(g, state, x, &all[w].nodes);
                let label = format!("[{name}, {}]", all[w].label);
                all.push(Bracket {
                    label,
                    depth: d,
                    nodes,
                });
            }
        }
        level_start = level_end;
    }
    all
}
