//! The derivatives of one exported function, built on the model's graph by the engine's
//! sweeps, so that they share every subexpression with the function's values and with each
//! other: the Jacobian column by column (a tangent sweep per argument), a forward derivative
//! (one tangent sweep along fresh direction inputs), an adjoint derivative (one adjoint sweep
//! with fresh weight inputs), and the weighted second derivatives Σ_r λ_r ∂²F_r/∂z_a∂z_b (a
//! tangent sweep of that adjoint per argument: forward over reverse, whose tangents of the
//! function's own nodes are the Jacobian's).
//!
//! The Jacobian and the second derivatives come in two stages: by the arguments that vary
//! in a solver (the state, the inputs, the time) and by the parameters, which a solver asks
//! for only when it estimates them. Each stage is built only while the graph grows by less
//! than a budget, and kept only if its code stays under a size: a model too large for
//! straight-line second derivatives (the 24-trailer train) keeps what fits, and `hamel-export`
//! computes the rest by dual numbers.

use crate::engine::diff::{adjoint, tangent};
use crate::engine::graph::{Graph, Node, NodeId};

/// The arguments of an exported function, as graph inputs, in the order of its local
/// columns: the state, the inputs, the parameters the graph reads, the time.
pub struct Columns {
    pub nodes: Vec<NodeId>,
    /// Where the parameters are among the columns.
    pub parameters: std::ops::Range<usize>,
}

impl Columns {
    pub fn is_parameter(&self, c: usize) -> bool {
        self.parameters.contains(&c)
    }
}

/// The two stages of a derivative: by the varying arguments, then by the parameters. `None`
/// where the stage was not built or is too large to emit.
#[derive(Clone, Copy)]
pub struct Staged<T> {
    pub states: Option<T>,
    pub parameters: Option<T>,
}

/// An entry of a sparse derivative: (row, column, node).
pub type Entry = (usize, usize, NodeId);

/// One exported function and its derivative nodes.
pub struct Derivatives {
    /// The values, one per output component.
    pub roots: Vec<NodeId>,
    /// ∂root_r/∂column_c for the entries that are not a constant zero on the graph, in
    /// column-major order.
    pub jacobian: Staged<Vec<Entry>>,
    /// The forward derivative's seeds, one fresh input per column; its result per row, with
    /// every seed (`forward`) and with those of the varying arguments only (`forward_states`).
    pub directions: Vec<NodeId>,
    pub forward: Vec<NodeId>,
    pub forward_states: Vec<NodeId>,
    /// The adjoint derivative's weights, one fresh input per row, and its result per column.
    pub weights: Vec<NodeId>,
    pub adjoint: Vec<NodeId>,
    /// Σ_r weight_r ∂²root_r/∂column_a∂column_b for a ≥ b, the entries that are not a
    /// constant zero, in column-major order of the lower triangle (a, b, node). The parameter
    /// stage holds the entries with a parameter among a, b.
    pub second: Staged<Vec<Entry>>,
}

/// How many operations the code of a stage may have, and so how far building it may grow
/// the graph (a few nodes per operation: `NODES_PER_OPERATION`).
#[derive(Clone, Copy)]
pub struct Budget {
    pub nodes: usize,
    pub operations: usize,
}

/// The graph grows by about 2.5–4 nodes per operation of a stage's code (the Whipple
/// bicycle's second derivatives: 229,000 nodes for 63,000 operations).
const NODES_PER_OPERATION: usize = 5;

impl Budget {
    pub const fn operations(operations: usize) -> Budget {
        Budget {
            nodes: NODES_PER_OPERATION * operations,
            operations,
        }
    }
}

/// The budget of each stage.
#[derive(Clone, Copy)]
pub struct Budgets {
    pub jacobian_states: Budget,
    pub jacobian_parameters: Budget,
    pub second_states: Budget,
    pub second_parameters: Budget,
}

/// The derivatives of `roots` by `columns`; `label` names the fresh inputs (for the
/// generated code's comments and errors).
pub fn derivatives(
    g: &mut Graph,
    roots: &[NodeId],
    columns: &Columns,
    label: &str,
    budgets: Budgets,
) -> Derivatives {
    let n = columns.nodes.len();
    let (states_columns, parameters): (Vec<usize>, Vec<usize>) =
        (0..n).partition(|&c| !columns.is_parameter(c));
    let states = &states_columns;
    let jacobian = Staged {
        states: jacobian_columns(g, roots, columns, states, budgets.jacobian_states),
        parameters: jacobian_columns(g, roots, columns, &parameters, budgets.jacobian_parameters),
    };
    let directions: Vec<NodeId> = (0..n)
        .map(|c| g.new_input(format!("{label}.direction[{c}]")))
        .collect();
    let seeds = |only: &[usize]| -> Vec<(NodeId, NodeId)> {
        only.iter()
            .map(|&c| (columns.nodes[c], directions[c]))
            .collect()
    };
    let all: Vec<usize> = (0..n).collect();
    let forward = tangent(g, roots, &seeds(&all));
    let forward_states = tangent(g, roots, &seeds(states));
    let weights: Vec<NodeId> = (0..roots.len())
        .map(|r| g.new_input(format!("{label}.weight[{r}]")))
        .collect();
    let adjoint = adjoint(g, roots, &weights, &columns.nodes);
    // Second derivatives only where the first are: the Jacobian entries are among their
    // nodes (the transposed blocks of CasADi's `jac_adj1_f`).
    let second_states = jacobian.states.as_ref().and_then(|jacobian| {
        let budget = budgets.second_states;
        let entries = second_columns(
            g,
            &adjoint,
            columns,
            states,
            |a| !columns.is_parameter(a),
            budget,
        )?;
        within(g, &entries, jacobian, budget).then_some(entries)
    });
    let second_parameters = match (&second_states, &jacobian.parameters) {
        (Some(states), Some(jacobian_p)) => {
            let budget = budgets.second_parameters;
            let rows = by_rows(g, &adjoint, columns, (&states_columns, &parameters), budget);
            let only = by_parameter_columns(g, &adjoint, columns, &parameters, budget);
            // Two ways to the same entries (`by_rows`, `by_parameter_columns`): the one whose
            // code, with stage 1's (which stage 2 reads), has fewer operations. The paper's
            // robot: 2,049 against 2,186 by the parameter columns; its variant from the paper
            // 1,459 by rows against 1,541.
            let first: Vec<Entry> = states
                .iter()
                .chain(jacobian.states.as_deref().unwrap_or_default())
                .copied()
                .collect();
            let added = |entries: &Option<Vec<Entry>>| {
                entries.as_ref().map(|e| {
                    let all: Vec<Entry> =
                        first.iter().chain(e).chain(jacobian_p).copied().collect();
                    operations(g, &all.iter().map(|e| e.2).collect::<Vec<_>>())
                })
            };
            // Only where the first way fits its budget: the stages compiled stay those the
            // budgets chose, the code only smaller.
            let rows = rows.filter(|e| within(g, e, jacobian_p, budget));
            match (added(&rows), added(&only)) {
                (Some(a), Some(b)) if b < a => only,
                _ => rows,
            }
        }
        _ => None,
    };
    Derivatives {
        roots: roots.to_vec(),
        jacobian,
        directions,
        forward,
        forward_states,
        weights,
        adjoint,
        second: Staged {
            states: second_states,
            parameters: second_parameters,
        },
    }
}

/// The second derivatives with a parameter among a, b (a ≥ b): the parameter columns in
/// full, and the rows a that are parameters in the columns of the state (`which`: the state's
/// columns, the parameters'); `None` past the budget.
fn by_rows(
    g: &mut Graph,
    adjoint: &[NodeId],
    columns: &Columns,
    (states, parameters): (&[usize], &[usize]),
    budget: Budget,
) -> Option<Vec<Entry>> {
    let mut entries = second_columns(g, adjoint, columns, parameters, |_| true, budget)?;
    let rows = second_columns(
        g,
        adjoint,
        columns,
        states,
        |a| columns.is_parameter(a),
        budget,
    )?;
    entries.extend(rows);
    Some(entries)
}

/// The same entries from the parameter columns alone: a tangent sweep along each parameter
/// gives its column of the second derivatives in full, the rows of the state too, which are
/// the entries (parameter, state) by symmetry. Fewer sweeps than [`by_rows`] (the parameters
/// against the parameters and the state), and they share more: which is the smaller code
/// depends on the model.
fn by_parameter_columns(
    g: &mut Graph,
    adjoint: &[NodeId],
    columns: &Columns,
    parameters: &[usize],
    budget: Budget,
) -> Option<Vec<Entry>> {
    let keep = |a: usize, b: usize| a >= b || !columns.is_parameter(a);
    let entries = tangent_columns(g, adjoint, columns, parameters, keep, budget)?;
    Some(
        entries
            .into_iter()
            .map(|(a, b, node)| if a >= b { (a, b, node) } else { (b, a, node) })
            .collect(),
    )
}

/// The Jacobian's entries in `which` columns, or `None` past the budget.
fn jacobian_columns(
    g: &mut Graph,
    roots: &[NodeId],
    columns: &Columns,
    which: &[usize],
    budget: Budget,
) -> Option<Vec<Entry>> {
    let entries = tangent_columns(g, roots, columns, which, |_, _| true, budget)?;
    within(g, &entries, &[], budget).then_some(entries)
}

/// The second derivatives in `which` columns b, rows a ≥ b where `row` holds; `None` past the
/// budget.
fn second_columns(
    g: &mut Graph,
    adjoint: &[NodeId],
    columns: &Columns,
    which: &[usize],
    row: impl Fn(usize) -> bool,
    budget: Budget,
) -> Option<Vec<Entry>> {
    tangent_columns(g, adjoint, columns, which, |a, b| a >= b && row(a), budget)
}

/// The nonzero derivatives of `roots` along each of `which` columns, as (row, column, node)
/// where `keep(row, column)` holds, by one forward sweep a column; `None` when the sweeps add
/// more nodes than the budget allows.
fn tangent_columns(
    g: &mut Graph,
    roots: &[NodeId],
    columns: &Columns,
    which: &[usize],
    keep: impl Fn(usize, usize) -> bool,
    budget: Budget,
) -> Option<Vec<Entry>> {
    if budget.operations == 0 && !which.is_empty() {
        return None;
    }
    let start = g.len();
    let one = g.one();
    let mut entries = Vec::new();
    for &c in which {
        let tangents = tangent(g, roots, &[(columns.nodes[c], one)]);
        if g.len() - start > budget.nodes {
            return None;
        }
        entries.extend(
            tangents
                .into_iter()
                .enumerate()
                .filter(|&(r, node)| keep(r, c) && !g.is_zero(node))
                .map(|(r, node)| (r, c, node)),
        );
    }
    Some(entries)
}

/// Whether the code of `entries` (with `also`) has at most the budget's operations.
fn within(g: &Graph, entries: &[Entry], also: &[Entry], budget: Budget) -> bool {
    let roots: Vec<NodeId> = entries.iter().chain(also).map(|e| e.2).collect();
    operations(g, &roots) <= budget.operations
}

/// The operations (not constants or inputs) the code of `roots` computes.
pub fn operations(g: &Graph, roots: &[NodeId]) -> usize {
    g.live_set(roots)
        .into_iter()
        .filter(|&id| !matches!(g.node(id), Node::Const(_) | Node::Input(_) | Node::Bool(_)))
        .count()
}
