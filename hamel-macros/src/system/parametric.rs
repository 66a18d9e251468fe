//! The right-hand side (and the outputs) with the parameters as arguments: the same graph as
//! `rhs_generic`, emitted once more with every parameter `self.m0` (or `self.m[2]`) read from an
//! array of scalars `p`, in the order `__HAMEL_PARAMETRIC_NAMES` lists them (the parameters
//! the graph reads; `hamel-export` maps them from `Parameters::NAMES`). With dual numbers in `p` it gives
//! ∂F/∂p exactly, which a solver that treats parameters as unknowns needs (`hamel-export`'s
//! CasADi functions). Generic and `#[doc(hidden)]`: a program that never calls it does not
//! compile it past type checking.
//!
//! Beside it, which inputs each result depends on, read from the graph (every operand of every
//! node, both arms of a `Select`: a superset of what any point's values can make nonzero): the
//! sparsity of the Jacobians that a solver exploits.

use super::equations::Equations;
use super::generate::{ALL, Context, NONE, Source, vector};
use super::interface::{Dims, lit};
use crate::engine::emit::Scalar;
use crate::engine::graph::{Graph, Node, NodeId};
use proc_macro2::{Ident, Span, TokenStream};
use quote::quote;

/// `self.m0` gives `m0`, `self.m[2]` gives `m2` (the names `Parameters` gives array entries);
/// anything else (a constant, `Self::G`) is not a parameter.
pub(super) fn parameter_name(label: &str) -> Option<String> {
    let field = label.strip_prefix("self.")?;
    match field.split_once('[') {
        Some((base, index)) => Some(format!("{base}{}", index.strip_suffix(']')?)),
        None => Some(field.to_string()),
    }
}

/// The parameters the graph reads, with their names.
fn parameters(cx: &Context<'_>) -> Vec<(NodeId, String)> {
    cx.externals
        .iter()
        .filter_map(|ext| match cx.graph.node(ext.node) {
            Node::Input(slot) => {
                parameter_name(cx.graph.input_label(slot)).map(|name| (ext.node, name))
            }
            _ => None,
        })
        .collect()
}

/// Each parameter read as `p[i]`, `i` its position among the parameters the graph reads
/// (`__HAMEL_PARAMETRIC_NAMES`). Not the struct's order: the struct is another item, which
/// this macro does not see, and naming its `Parameters` here would add an error of its own
/// where the struct lacks `#[hamel_system]`.
fn parameter_bindings(parameters: &[(NodeId, String)]) -> Vec<(NodeId, TokenStream)> {
    parameters
        .iter()
        .enumerate()
        .map(|(i, (node, _))| {
            let i = lit(i);
            (*node, quote!(p[#i]))
        })
        .collect()
}

/// For each root, the indices of the inputs among `columns` it depends on (increasing).
///
/// One pass over the roots' cone, in topological order, carrying for each node the set of
/// columns it reads as a bit set: a pass over the whole graph for each column instead cost
/// the catalogue's build about a second of the macro's time (the models' graphs have tens of
/// thousands of nodes, and tens of columns: the state, the inputs and the parameters).
pub(super) fn dependencies(graph: &Graph, roots: &[NodeId], columns: &[NodeId]) -> Vec<Vec<usize>> {
    let words = columns.len().div_ceil(64);
    let cone = graph.live_set(roots);
    // Each cone node's row in `bits`; `NOT_IN_CONE` for the others.
    const NOT_IN_CONE: u32 = u32::MAX;
    let mut row_of = vec![NOT_IN_CONE; graph.len()];
    for (k, id) in cone.iter().enumerate() {
        row_of[id.index()] = k as u32;
    }
    let mut bits = vec![0u64; cone.len() * words];
    for (j, column) in columns.iter().enumerate() {
        let k = row_of[column.index()];
        if k != NOT_IN_CONE {
            bits[k as usize * words + j / 64] |= 1 << (j % 64);
        }
    }
    for (k, id) in cone.iter().enumerate() {
        for operand in graph.node(*id).operands().as_slice() {
            // Operands precede their users, and a cone holds its nodes' operands.
            let from = row_of[operand.index()] as usize;
            for w in 0..words {
                bits[k * words + w] |= bits[from * words + w];
            }
        }
    }
    roots
        .iter()
        .map(|root| {
            let row = &bits[row_of[root.index()] as usize * words..][..words];
            (0..columns.len())
                .filter(|j| row[j / 64] & (1 << (j % 64)) != 0)
                .collect()
        })
        .collect()
}

/// A table of dependencies: for each result, the state and input columns (indices into
/// x, then u) and the parameters (by name) it depends on.
fn dependency_table(
    cx: &Context<'_>,
    roots: &[NodeId],
    parameters: &[(NodeId, String)],
) -> (TokenStream, TokenStream) {
    let inputs = &cx.eq.inputs;
    let columns: Vec<NodeId> = inputs
        .q
        .iter()
        .chain(&inputs.w)
        .chain(&inputs.u)
        .copied()
        .collect();
    let state_rows = dependencies(cx.graph, roots, &columns)
        .into_iter()
        .map(|row| {
            let row = row.into_iter().map(lit);
            quote!(&[#(#row),*])
        });
    let nodes: Vec<NodeId> = parameters.iter().map(|(n, _)| *n).collect();
    let parameter_rows = dependencies(cx.graph, roots, &nodes)
        .into_iter()
        .map(|row| {
            let row = row.into_iter().map(|j| &parameters[j].1);
            quote!(&[#(#row),*])
        });
    (quote!(&[#(#state_rows),*]), quote!(&[#(#parameter_rows),*]))
}

/// `__hamel_rhs_parametric`, `__hamel_outputs_parametric` (no outputs for a model without
/// `#[outputs]`), their dependency tables, and the parameter lookup they compile with.
/// `outputs` are the outputs' names and nodes.
pub(super) fn emit(
    cx: &Context<'_>,
    dims: Dims,
    outputs: (&[String], &[NodeId]),
    exported: Option<&super::export::ExportNodes>,
) -> syn::Result<TokenStream> {
    let eq: &Equations = cx.eq;
    let s = Ident::new("S", Span::call_site());
    let parameters = parameters(cx);
    let bindings = parameter_bindings(&parameters);
    let roots: Vec<NodeId> = eq.qd.iter().chain(&eq.wdot).copied().collect();
    let (code, checks) = cx.emit_bound(
        Source::State,
        Scalar::Generic(s.clone()),
        &roots,
        ALL,
        &bindings,
    )?;
    let stmts = &code.stmts;
    let writes = roots.iter().enumerate().map(|(i, &id)| {
        let v = code.value(id);
        let i = lit(i);
        quote!(dx[#i] = #v;)
    });
    let (state, m) = (lit(2 * dims.n - dims.p), lit(dims.m));
    let (rhs_columns, rhs_parameters) = dependency_table(cx, &roots, &parameters);
    let time = cx.graph.depends_on(&[eq.inputs.t]);
    let time_dependent = roots.iter().any(|r| time[r.index()]);
    let outputs = outputs_parametric(cx, outputs, &bindings, &parameters)?;
    let parameter_names = parameters.iter().map(|(_, name)| name);
    let np = lit(parameters.len());
    let allow = quote!(#[allow(clippy::all, clippy::pedantic, unused_parens, unused_variables, non_snake_case)]);
    let exported = match exported {
        Some(nodes) => super::export::emit::emit(cx, nodes)?,
        None => TokenStream::new(),
    };
    Ok(quote! {
        #exported

        /// The parameters the parametric methods read, in the order of their argument `p`
        /// (each a field of the struct, or an entry `m2` of an array field `m`). Generated
        /// by `#[hamel_system]`.
        #[doc(hidden)]
        pub const __HAMEL_PARAMETRIC_NAMES: &'static [&'static str] = &[#(#parameter_names),*];

        /// The right-hand side ẋ = F(t, x, u; p) with the parameters `p` of
        /// `__HAMEL_PARAMETRIC_NAMES`, over any `hamel::Scalar`: with `p` read from `self` it
        /// is `rhs_generic`, value for value; with dual numbers in `p` it differentiates with
        /// respect to them. Generated by `#[hamel_system]`.
        #[doc(hidden)]
        #allow
        #[inline]
        pub fn __hamel_rhs_parametric<S: ::hamel::Scalar>(
            p: &[S; #np],
            t: S,
            x: &[S; #state],
            u: &[S; #m],
            dx: &mut [S; #state],
        ) -> ::core::result::Result<(), ::hamel::Singularity> {
            #stmts
            #checks
            #(#writes)*
            ::core::result::Result::Ok(())
        }

        /// For each component of the right-hand side, the state and input components it
        /// depends on (indices into x, then u: m inputs after the state's), as the graph of
        /// the generated code says (a superset of the nonzero entries of ∂F/∂(x, u) at any
        /// point). Generated by `#[hamel_system]`.
        #[doc(hidden)]
        pub const __HAMEL_RHS_COLUMNS: &'static [&'static [usize]] = #rhs_columns;

        /// For each component of the right-hand side, the parameters it depends on, by name.
        /// Generated by `#[hamel_system]`.
        #[doc(hidden)]
        pub const __HAMEL_RHS_PARAMETERS: &'static [&'static [&'static str]] = #rhs_parameters;

        /// Whether the right-hand side depends on the time explicitly. Generated by
        /// `#[hamel_system]`.
        #[doc(hidden)]
        pub const __HAMEL_RHS_TIME: bool = #time_dependent;

        #outputs
    })
}

/// The outputs y = h(t, x; p) with the parameters from `p`, their names and dependency
/// tables.
fn outputs_parametric(
    cx: &Context<'_>,
    (names, h): (&[String], &[NodeId]),
    bindings: &[(NodeId, TokenStream)],
    parameters: &[(NodeId, String)],
) -> syn::Result<TokenStream> {
    let s = Ident::new("S", Span::call_site());
    let (code, _) = cx.emit_bound(Source::State, Scalar::Generic(s), h, NONE, bindings)?;
    let stmts = &code.stmts;
    let value = vector(&code, h);
    let state = lit(cx.eq.inputs.q.len() + cx.eq.inputs.w.len());
    let r = lit(h.len());
    let np = lit(parameters.len());
    let (columns, params) = dependency_table(cx, h, parameters);
    Ok(quote! {
        /// The outputs y = h(t, x; p) with the parameters `p` of `__HAMEL_PARAMETRIC_NAMES`,
        /// over any `hamel::Scalar`. Generated by `#[hamel_system]`.
        #[doc(hidden)]
        #[allow(clippy::all, clippy::pedantic, unused_parens, unused_variables, non_snake_case)]
        #[inline]
        pub fn __hamel_outputs_parametric<S: ::hamel::Scalar>(
            p: &[S; #np],
            t: S,
            x: &[S; #state],
        ) -> [S; #r] {
            #stmts
            #value
        }

        /// The outputs' names (those of `ControlAffine::OUTPUTS`, for a model with
        /// outputs). Generated by `#[hamel_system]`.
        #[doc(hidden)]
        pub const __HAMEL_OUTPUT_NAMES: &'static [&'static str] = &[#(#names),*];

        /// For each output, the state components it depends on. Generated by
        /// `#[hamel_system]`.
        #[doc(hidden)]
        pub const __HAMEL_OUTPUT_COLUMNS: &'static [&'static [usize]] = #columns;

        /// For each output, the parameters it depends on, by name. Generated by
        /// `#[hamel_system]`.
        #[doc(hidden)]
        pub const __HAMEL_OUTPUT_PARAMETERS: &'static [&'static [&'static str]] = #params;
    })
}

#[cfg(test)]
mod tests {
    use super::parameter_name;

    #[test]
    fn parameters_are_named_as_the_struct_names_them() {
        assert_eq!(parameter_name("self.m0").as_deref(), Some("m0"));
        assert_eq!(parameter_name("self.m[2]").as_deref(), Some("m2"));
        assert_eq!(parameter_name("G"), None);
        assert_eq!(parameter_name("Self::RADIUS"), None);
    }
}
