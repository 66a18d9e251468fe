//! The functions `hamel-export` exports, with their derivatives as straight-line code: built
//! on the model's graph by the engine's sweeps (`sweeps`) and emitted (`emit`) as
//! `#[doc(hidden)]` associated functions beside `__hamel_rhs_parametric`. Only with the
//! feature `export` of this crate, which `hamel-export`'s feature `compiled` turns on: a
//! program that does not export a model neither builds these graphs nor type-checks their
//! code.
//!
//! Three families, each a function of (t, x, u; p) with its derivatives: the right-hand side
//! F (`rhs`), the outputs h (`outputs`, for a model with `#[outputs]`) and their Lie
//! derivatives (`lie`: L_f^k h for k = 0 … order, then L_{g_j} L_f^k h for k < order, for a
//! model with `control(..)`). Every value that depends on the parameters alone, in any of
//! them, is computed once per parameter set (`__hamel_export_prepare`).

pub mod emit;
pub mod sweeps;

use super::control::ControlNodes;
use super::equations::Equations;
use super::generate::{ALL, Checks, NONE};
use crate::engine::graph::{Graph, Node, NodeId};
use crate::engine::lower::External;
use sweeps::{Budget, Budgets, Columns, Derivatives, derivatives};

/// The largest stages compiled, in operations of their code: past them, `hamel-export`
/// computes a stage by dual numbers through the values' code. The paper's robot needs about
/// 200 operations for its Jacobian by the state and inputs and 350 for its second
/// derivatives; the Whipple bicycle 24,000 and 63,000 (its right-hand side has 2,800); the
/// 24-trailer train's Jacobian alone 57,000. By the parameters, which a solver asks for
/// only when it estimates them, the stages are kept small; the Lie derivatives, whose
/// derivatives are of third and fourth order in the model's functions, get smaller budgets.
const RHS: Budgets = Budgets {
    jacobian_states: Budget::operations(30_000),
    jacobian_parameters: Budget::operations(6_000),
    second_states: Budget::operations(70_000),
    second_parameters: Budget::operations(6_000),
};
const LIE: Budgets = Budgets {
    jacobian_states: Budget::operations(10_000),
    jacobian_parameters: Budget::operations(3_000),
    second_states: Budget::operations(10_000),
    second_parameters: Budget::operations(3_000),
};

/// One exported function and what its code needs.
pub struct Family {
    /// The suffix of its generated items: `rhs`, `outputs`, `lie`.
    pub name: &'static str,
    /// The checks of the solves it reads (none for the outputs, which solve nothing).
    pub checks: Checks,
    pub derivatives: Derivatives,
}

/// Everything the export emits.
pub struct ExportNodes {
    pub columns: Columns,
    /// The parameters the graph reads, in the order of the columns' parameter block.
    pub parameters: Vec<(NodeId, String)>,
    pub families: Vec<Family>,
    /// The inputs that vary from call to call: t, x, u and every seed and weight.
    pub varying: Vec<NodeId>,
}

/// The parameters the graph reads (`self.m0`, `self.m[2]`), with their names.
pub fn parameter_nodes(graph: &Graph, externals: &[External]) -> Vec<(NodeId, String)> {
    externals
        .iter()
        .filter_map(|ext| match graph.node(ext.node) {
            Node::Input(slot) => super::parametric::parameter_name(graph.input_label(slot))
                .map(|name| (ext.node, name)),
            _ => None,
        })
        .collect()
}

/// The families' derivative nodes, added to the model's graph.
pub fn build(
    graph: &mut Graph,
    eq: &Equations,
    control: Option<&ControlNodes>,
    externals: &[External],
) -> ExportNodes {
    let parameters = parameter_nodes(graph, externals);
    let i = &eq.inputs;
    let mut nodes: Vec<NodeId> = i.q.iter().chain(&i.w).chain(&i.u).copied().collect();
    let start = nodes.len();
    nodes.extend(parameters.iter().map(|(n, _)| *n));
    let end = nodes.len();
    nodes.push(i.t);
    let columns = Columns {
        nodes,
        parameters: start..end,
    };
    let rhs: Vec<NodeId> = eq.qd.iter().chain(&eq.wdot).copied().collect();
    let mut families = vec![Family {
        name: "rhs",
        checks: ALL,
        derivatives: derivatives(graph, &rhs, &columns, "rhs", RHS),
    }];
    // A model without outputs exports them too, with none: `hamel-export` names the same
    // items for every model.
    let h = control
        .and_then(|c| c.lie.first().cloned())
        .unwrap_or_default();
    families.push(Family {
        name: "outputs",
        checks: NONE,
        derivatives: derivatives(graph, &h, &columns, "outputs", RHS),
    });
    let lie: Vec<NodeId> = control
        .map(|c| {
            c.lie
                .iter()
                .flatten()
                .chain(c.along.iter().flatten().flatten())
                .copied()
                .collect()
        })
        .unwrap_or_default();
    families.push(Family {
        name: "lie",
        checks: ALL,
        derivatives: derivatives(graph, &lie, &columns, "lie", LIE),
    });
    let mut varying = i.varying();
    for f in &families {
        varying.extend(&f.derivatives.directions);
        varying.extend(&f.derivatives.weights);
    }
    ExportNodes {
        columns,
        parameters,
        families,
        varying,
    }
}
