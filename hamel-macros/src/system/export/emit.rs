//! The exported functions as Rust: per family (`rhs`, `outputs`, `lie`) its values, its
//! Jacobian, forward and adjoint derivatives and weighted second derivatives, each a
//! `#[doc(hidden)]` associated function of the model, with the tables of their sparse
//! entries; and `__hamel_export_prepare`, the values of all of them that depend on the
//! parameters alone.
//!
//! Every function has a type parameter it does not use: a generic function is compiled to
//! machine code only in a crate that calls it (the model's own crate, the catalogue, only
//! type-checks it), in release and debug builds alike.

use super::sweeps::{Columns, Derivatives, Entry, Staged};
use super::{ExportNodes, Family};
use crate::engine::emit::Scalar;
use crate::engine::graph::{Graph, Node, NodeId};
use crate::system::generate::{Context, NONE, Source};
use crate::system::interface::lit;
use proc_macro2::{Ident, TokenStream};
use quote::{format_ident, quote};

/// The lengths the signatures are written with.
struct Sizes {
    prepared: usize,
    parameters: usize,
    state: usize,
    inputs: usize,
    columns: usize,
}

/// Every item of the export.
pub fn emit(cx: &Context<'_>, nodes: &ExportNodes) -> syn::Result<TokenStream> {
    let roots: Vec<NodeId> = nodes
        .families
        .iter()
        .flat_map(|f| cx.checked_roots(&emitted(&f.derivatives), f.checks))
        .collect();
    let prepared = prepared_nodes(cx.graph, &nodes.varying, &roots);
    let sizes = Sizes {
        prepared: prepared.len(),
        parameters: nodes.parameters.len(),
        state: cx.eq.inputs.q.len() + cx.eq.inputs.w.len(),
        inputs: cx.eq.inputs.u.len(),
        columns: nodes.columns.nodes.len(),
    };
    let parameters: Vec<(NodeId, TokenStream)> = nodes
        .parameters
        .iter()
        .enumerate()
        .map(|(i, (node, _))| {
            let i = lit(i);
            (*node, quote!(p[#i]))
        })
        .collect();
    let mut bindings = parameters.clone();
    bindings.extend(prepared.iter().enumerate().map(|(k, &node)| {
        let k = lit(k);
        (node, quote!(prepared[#k]))
    }));
    for f in &nodes.families {
        let d = &f.derivatives;
        bindings.extend(d.directions.iter().enumerate().map(|(c, &node)| {
            let c = lit(c);
            (node, quote!(direction[#c]))
        }));
        bindings.extend(d.weights.iter().enumerate().map(|(r, &node)| {
            let r = lit(r);
            (node, quote!(weights[#r]))
        }));
    }
    let prepare = prepare(cx, &prepared, &parameters, &sizes)?;
    let mut items = vec![prepare];
    for f in &nodes.families {
        items.push(family(
            cx,
            f,
            &nodes.columns,
            (&bindings, &parameters),
            &sizes,
        )?);
    }
    Ok(quote!(#(#items)*))
}

/// Every node a family's code may compute: its values and the stages that were built.
fn emitted(d: &Derivatives) -> Vec<NodeId> {
    let stages = |s: &Staged<Vec<Entry>>| {
        s.states
            .iter()
            .chain(&s.parameters)
            .flatten()
            .map(|e| e.2)
            .collect::<Vec<_>>()
    };
    let mut all = d.roots.clone();
    all.extend(stages(&d.jacobian));
    all.extend(stages(&d.second));
    all.extend(&d.forward);
    all.extend(&d.forward_states);
    all.extend(&d.adjoint);
    all
}

/// The values of `roots`' code that depend on the parameters alone: those an operation that
/// varies reads, and the roots that do not vary (a Jacobian entry 1/r), except constants,
/// inputs and conditions.
fn prepared_nodes(g: &Graph, varying: &[NodeId], roots: &[NodeId]) -> Vec<NodeId> {
    let active = g.depends_on(varying);
    let live = g.live_set(roots);
    let mut wanted = vec![false; g.len()];
    for &r in roots {
        wanted[r.index()] = true;
    }
    for &id in &live {
        if active[id.index()] {
            for &o in g.node(id).operands().as_slice() {
                wanted[o.index()] = true;
            }
        }
    }
    live.into_iter()
        .filter(|&id| {
            let node = g.node(id);
            wanted[id.index()]
                && !active[id.index()]
                && !node.is_bool()
                && !matches!(node, Node::Const(_) | Node::Input(_))
        })
        .collect()
}

const ALLOW: &str =
    "clippy::all, clippy::pedantic, unused_parens, unused_variables, unused_mut, non_snake_case";

fn allow() -> TokenStream {
    let lints: TokenStream = ALLOW.parse().unwrap_or_default();
    quote!(#[allow(#lints)])
}

/// `__hamel_export_prepare` and the number of values it prepares.
fn prepare(
    cx: &Context<'_>,
    prepared: &[NodeId],
    parameters: &[(NodeId, TokenStream)],
    s: &Sizes,
) -> syn::Result<TokenStream> {
    let (code, _) = cx.emit_bound(Source::State, Scalar::F64, prepared, NONE, parameters)?;
    let stmts = &code.stmts;
    let values = prepared.iter().map(|&id| code.value(id));
    let (count, np) = (lit(s.prepared), lit(s.parameters));
    let allow = allow();
    Ok(quote! {
        /// How many values `__hamel_export_prepare` computes. Generated by `#[hamel_system]`.
        #[doc(hidden)]
        pub const __HAMEL_EXPORT_PREPARED: usize = #count;

        /// The values of the exported functions that depend on the parameters alone (the
        /// parameters in the order of `__HAMEL_PARAMETRIC_NAMES`), computed once per parameter
        /// set. Generated by `#[hamel_system]`.
        #[doc(hidden)]
        #allow
        #[inline]
        pub fn __hamel_export_prepare<E>(p: &[f64; #np]) -> [f64; #count] {
            #stmts
            [#(#values),*]
        }
    })
}

/// The arguments every function of a family starts with.
fn arguments(s: &Sizes) -> TokenStream {
    let (count, np, nx, nu) = (
        lit(s.prepared),
        lit(s.parameters),
        lit(s.state),
        lit(s.inputs),
    );
    quote! {
        prepared: &[f64; #count],
        p: &[f64; #np],
        t: f64,
        x: &[f64; #nx],
        u: &[f64; #nu],
    }
}

/// Each input node of the exported code and the expression it reads.
type Bindings<'a> = &'a [(NodeId, TokenStream)];

/// A family's functions and tables.
fn family(
    cx: &Context<'_>,
    f: &Family,
    columns: &Columns,
    (bindings, parameters): (Bindings<'_>, Bindings<'_>),
    s: &Sizes,
) -> syn::Result<TokenStream> {
    let d = &f.derivatives;
    let name = |suffix: &str| format_ident!("__hamel_export_{}{}", f.name, suffix);
    let args = arguments(s);
    let allow = allow();
    let result = quote!(::core::result::Result);
    let singularity = quote!(::hamel::Singularity);
    let emit = |stages: &[&[NodeId]]| {
        cx.emit_bound_stages(Source::State, Scalar::F64, stages, f.checks, bindings)
    };
    let (no, nc) = (lit(d.roots.len()), lit(s.columns));
    let value_body = value_body(&emit, d)?;
    let jacobian_body = staged_body(&emit, &d.jacobian, &[], "out")?;
    let second_body = staged_body(&emit, &d.second, &[(&d.jacobian, "jacobian")], "second")?;
    let forward_body = forward_body(&emit, d)?;
    let adjoint_body = adjoint_body(&emit, d, columns)?;
    let (nj, nh) = (
        lit(staged_entries(&d.jacobian).0.len()),
        lit(staged_entries(&d.second).0.len()),
    );
    let (value, jacobian_fn, forward_fn, adjoint_fn, second_fn) = (
        name(""),
        name("_jacobian"),
        name("_forward"),
        name("_adjoint"),
        name("_second"),
    );
    let tables = tables(cx, f, columns);
    let generic = generic_value(cx, f, parameters, s)?;
    let doc = |what: &str| {
        format!(
            "{what} of the exported `{}`. Generated by `#[hamel_system]`.",
            f.name
        )
    };
    let (value_doc, jacobian_doc, forward_doc, adjoint_doc, second_doc) = (
        doc("The values"),
        doc(
            "The Jacobian's entries (`_JACOBIAN`: row, column), those by the parameters only if `parameters` (false: not compiled, nothing written)",
        ),
        doc(
            "The derivative along `direction` (over the columns x, u, p, t), with the parameters' part only if `parameters`",
        ),
        doc(
            "The adjoint derivative with `weights` (over the columns x, u, p, t), the parameters' part only if `parameters`",
        ),
        doc(
            "The weighted second derivatives' entries (`_SECOND`: row ≥ column) and the Jacobian's, by the parameters only if `parameters` (false: not compiled)",
        ),
    );
    Ok(quote! {
        #[doc = #value_doc]
        #[doc(hidden)]
        #allow
        #[inline]
        pub fn #value<E>(#args out: &mut [f64; #no]) -> #result<(), #singularity> {
            #value_body
        }

        #[doc = #jacobian_doc]
        #[doc(hidden)]
        #allow
        #[inline]
        pub fn #jacobian_fn<E>(#args parameters: bool, out: &mut [f64; #nj]) -> #result<bool, #singularity> {
            #jacobian_body
        }

        #[doc = #forward_doc]
        #[doc(hidden)]
        #allow
        #[inline]
        pub fn #forward_fn<E>(#args direction: &[f64; #nc], parameters: bool, out: &mut [f64; #no]) -> #result<(), #singularity> {
            #forward_body
        }

        #[doc = #adjoint_doc]
        #[doc(hidden)]
        #allow
        #[inline]
        pub fn #adjoint_fn<E>(#args weights: &[f64; #no], parameters: bool, out: &mut [f64; #nc]) -> #result<(), #singularity> {
            #adjoint_body
        }

        #[doc = #second_doc]
        #[doc(hidden)]
        #allow
        #[inline]
        pub fn #second_fn<E>(#args weights: &[f64; #no], parameters: bool, second: &mut [f64; #nh], jacobian: &mut [f64; #nj]) -> #result<bool, #singularity> {
            #second_body
        }

        #tables

        #generic
    })
}

/// The body of the values' function.
fn value_body(emit: &Emit<'_>, d: &Derivatives) -> syn::Result<TokenStream> {
    let (codes, checks) = emit(&[&d.roots])?;
    let [code] = exactly(codes)?;
    let stmts = &code.stmts;
    let out = writes(&code, "out", d.roots.iter().copied().enumerate());
    Ok(quote! {
        #stmts
        #checks
        #out
        ::core::result::Result::Ok(())
    })
}

/// The body of the forward derivative: along every column, or (`parameters` false) along
/// the state, inputs and time only, a smaller code.
fn forward_body(emit: &Emit<'_>, d: &Derivatives) -> syn::Result<TokenStream> {
    let (all, all_checks) = emit(&[&d.forward])?;
    let (states, states_checks) = emit(&[&d.forward_states])?;
    let ([all], [states]) = (exactly(all)?, exactly(states)?);
    let (all_stmts, states_stmts) = (&all.stmts, &states.stmts);
    let all_writes = writes(&all, "out", d.forward.iter().copied().enumerate());
    let states_writes = writes(&states, "out", d.forward_states.iter().copied().enumerate());
    Ok(quote! {
        if parameters {
            #all_stmts
            #all_checks
            #all_writes
        } else {
            #states_stmts
            #states_checks
            #states_writes
        }
        ::core::result::Result::Ok(())
    })
}

/// The body of the adjoint derivative: its columns by the state, inputs and time, then
/// (`parameters`) those by the parameters.
fn adjoint_body(emit: &Emit<'_>, d: &Derivatives, columns: &Columns) -> syn::Result<TokenStream> {
    let (by_parameters, by_states): (Vec<_>, Vec<_>) = d
        .adjoint
        .iter()
        .copied()
        .enumerate()
        .partition(|(c, _)| columns.is_parameter(*c));
    let nodes = |entries: &[(usize, NodeId)]| entries.iter().map(|e| e.1).collect::<Vec<_>>();
    let (codes, checks) = emit(&[&nodes(&by_states), &nodes(&by_parameters)])?;
    let [first, second] = exactly(codes)?;
    let (first_stmts, second_stmts) = (&first.stmts, &second.stmts);
    let first_writes = writes(&first, "out", by_states.iter().copied());
    let second_writes = writes(&second, "out", by_parameters.iter().copied());
    Ok(quote! {
        #first_stmts
        #checks
        #first_writes
        if parameters {
            #second_stmts
            #second_writes
        }
        ::core::result::Result::Ok(())
    })
}

/// The tables of a family's sparse entries, stages and dependencies.
fn tables(cx: &Context<'_>, f: &Family, columns: &Columns) -> TokenStream {
    let d = &f.derivatives;
    let table = |suffix: &str| format_ident!("__HAMEL_EXPORT_{}_{}", f.name.to_uppercase(), suffix);
    let (jacobian, second) = (staged_entries(&d.jacobian), staged_entries(&d.second));
    let compiled = [
        d.jacobian.states.is_some(),
        d.jacobian.parameters.is_some(),
        d.second.states.is_some(),
        d.second.parameters.is_some(),
    ];
    let (jacobian_entries, jacobian_states) = (&jacobian.0, lit(jacobian.1));
    let (second_entries, second_states) = (&second.0, lit(second.1));
    let (jacobian_table, second_table, compiled_table, states_table, depends_table) = (
        table("JACOBIAN"),
        table("SECOND"),
        table("COMPILED"),
        table("STATES"),
        table("DEPENDS"),
    );
    let depends = crate::system::parametric::dependencies(cx.graph, &d.roots, &columns.nodes)
        .into_iter()
        .map(|row| {
            let row = row.into_iter().map(lit);
            quote!(&[#(#row),*])
        });
    quote! {
        /// The Jacobian's entries (row, column over x, u, p, t), by the state, inputs and
        /// time first, then by the parameters. Generated by `#[hamel_system]`.
        #[doc(hidden)]
        pub const #jacobian_table: &'static [(usize, usize)] = &[#(#jacobian_entries),*];
        /// The weighted second derivatives' entries (row ≥ column), likewise ordered.
        /// Generated by `#[hamel_system]`.
        #[doc(hidden)]
        pub const #second_table: &'static [(usize, usize)] = &[#(#second_entries),*];
        /// Which stages are compiled: the Jacobian by the state, by the parameters; the second
        /// derivatives likewise. Generated by `#[hamel_system]`.
        #[doc(hidden)]
        pub const #compiled_table: [bool; 4] = [#(#compiled),*];
        /// How many entries of each table are by the state, inputs and time (the rest are by
        /// the parameters). Generated by `#[hamel_system]`.
        #[doc(hidden)]
        pub const #states_table: [usize; 2] = [#jacobian_states, #second_states];
        /// For each output component, the columns (x, u, p, t) it depends on, as the graph
        /// says. Generated by `#[hamel_system]`.
        #[doc(hidden)]
        pub const #depends_table: &'static [&'static [usize]] = &[#(#depends),*];
    }
}

/// The values over any `hamel::Scalar`, for the stages `hamel-export` computes by dual
/// numbers; only for the Lie derivatives (the right-hand side and the outputs have theirs,
/// `__hamel_rhs_parametric` and `__hamel_outputs_parametric`).
fn generic_value(
    cx: &Context<'_>,
    f: &Family,
    parameters: Bindings<'_>,
    s: &Sizes,
) -> syn::Result<TokenStream> {
    if f.name != "lie" {
        return Ok(TokenStream::new());
    }
    let d = &f.derivatives;
    let scalar = Ident::new("S", proc_macro2::Span::call_site());
    // The parameters read from `p` (no prepared values: they are `f64`, this code is in S).
    let (code, checks) = cx.emit_bound(
        Source::State,
        Scalar::Generic(scalar),
        &d.roots,
        f.checks,
        parameters,
    )?;
    let stmts = &code.stmts;
    let out = writes(&code, "out", d.roots.iter().copied().enumerate());
    let (np, nx, nu, no) = (
        lit(s.parameters),
        lit(s.state),
        lit(s.inputs),
        lit(d.roots.len()),
    );
    let allow = allow();
    Ok(quote! {
        /// The Lie derivatives over any `hamel::Scalar` (dual numbers: their derivatives).
        /// Generated by `#[hamel_system]`.
        #[doc(hidden)]
        #allow
        #[inline]
        pub fn __hamel_export_lie_generic<S: ::hamel::Scalar>(
            p: &[S; #np],
            t: S,
            x: &[S; #nx],
            u: &[S; #nu],
            out: &mut [S; #no],
        ) -> ::core::result::Result<(), ::hamel::Singularity> {
            #stmts
            #checks
            #out
            ::core::result::Result::Ok(())
        }
    })
}

/// A staged table's entries as `(row, column)` tokens, and how many are in the first stage.
fn staged_entries(staged: &Staged<Vec<Entry>>) -> (Vec<TokenStream>, usize) {
    let first = staged.states.as_deref().unwrap_or_default();
    let second = staged.parameters.as_deref().unwrap_or_default();
    let tokens = first
        .iter()
        .chain(second)
        .map(|&(r, c, _)| {
            let (r, c) = (lit(r), lit(c));
            quote!((#r, #c))
        })
        .collect();
    (tokens, first.len())
}

/// The code of each of `N` stages (`emit_stages` gives one per stage asked for; anything
/// else is an internal error, reported, never a panic).
fn exactly<const N: usize>(
    codes: Vec<crate::engine::emit::Code>,
) -> syn::Result<[crate::engine::emit::Code; N]> {
    codes.try_into().map_err(|_| {
        syn::Error::new(
            proc_macro2::Span::call_site(),
            "hamel internal error: a stage of the exported code was not emitted",
        )
    })
}

/// `out[i] = value;` for each (index, node).
fn writes(
    code: &crate::engine::emit::Code,
    array: &str,
    entries: impl Iterator<Item = (usize, NodeId)>,
) -> TokenStream {
    let array = Ident::new(array, proc_macro2::Span::call_site());
    entries
        .map(|(i, id)| {
            let v = code.value(id);
            let i = lit(i);
            quote!(#array[#i] = #v;)
        })
        .collect()
}

type Emit<'a> =
    dyn Fn(&[&[NodeId]]) -> syn::Result<(Vec<crate::engine::emit::Code>, TokenStream)> + 'a;

/// The body of a staged function writing `staged` into `array` (and each of `also`, the
/// same stages of another table, into its array): `Ok(false)` when a stage asked for is not
/// compiled.
fn staged_body(
    emit: &Emit<'_>,
    staged: &Staged<Vec<Entry>>,
    also: &[(&Staged<Vec<Entry>>, &str)],
    array: &str,
) -> syn::Result<TokenStream> {
    let result = quote!(::core::result::Result);
    let Some(first) = &staged.states else {
        return Ok(quote!(#result::Ok(false)));
    };
    let stage_nodes = |s: &[Entry], others: &[&[Entry]]| -> Vec<NodeId> {
        s.iter()
            .chain(others.iter().flat_map(|o| o.iter()))
            .map(|e| e.2)
            .collect()
    };
    let also_first: Vec<&[Entry]> = also
        .iter()
        .map(|(s, _)| s.states.as_deref().unwrap_or_default())
        .collect();
    let also_second: Vec<&[Entry]> = also
        .iter()
        .map(|(s, _)| s.parameters.as_deref().unwrap_or_default())
        .collect();
    let roots_first = stage_nodes(first, &also_first);
    let second = staged.parameters.as_deref();
    let roots_second = stage_nodes(second.unwrap_or_default(), &also_second);
    let (codes, checks) = emit(&[&roots_first, &roots_second])?;
    let [code_first, code_second] = exactly(codes)?;
    let write_stage =
        |code: &crate::engine::emit::Code, own: &[Entry], others: &[&[Entry]], offset: &[usize]| {
            let start = |k: usize| offset.get(k).copied().unwrap_or(0);
            let mut tokens = writes(
                code,
                array,
                own.iter().enumerate().map(|(i, e)| (start(0) + i, e.2)),
            );
            for (k, ((_, name), entries)) in also.iter().zip(others).enumerate() {
                tokens.extend(writes(
                    code,
                    name,
                    entries
                        .iter()
                        .enumerate()
                        .map(|(i, e)| (start(k + 1) + i, e.2)),
                ));
            }
            tokens
        };
    let zero = vec![0; also.len() + 1];
    let first_writes = write_stage(&code_first, first, &also_first, &zero);
    let offsets: Vec<usize> = std::iter::once(first.len())
        .chain(also_first.iter().map(|e| e.len()))
        .collect();
    let (first_stmts, second_stmts) = (&code_first.stmts, &code_second.stmts);
    let parameters = match second {
        Some(second) => {
            let second_writes = write_stage(&code_second, second, &also_second, &offsets);
            quote! {
                if parameters {
                    #second_stmts
                    #second_writes
                }
            }
        }
        None => TokenStream::new(),
    };
    let refuse = second
        .is_none()
        .then(|| quote!(if parameters { return #result::Ok(false); }));
    Ok(quote! {
        #refuse
        #first_stmts
        #checks
        #first_writes
        #parameters
        #result::Ok(true)
    })
}
