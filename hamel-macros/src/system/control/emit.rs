//! `impl hamel::ControlAffine for Model`: the control code's nodes as generated methods, with
//! the checks of the right-hand side (the solves they read), for a model that asks for it.

use super::ControlNodes;
use crate::engine::graph::NodeId;
use crate::system::generate::{ALL, Context, NONE, Source, vector};
use crate::system::interface::lit;
use proc_macro2::TokenStream;
use quote::quote;

/// The sizes of the generated arrays.
struct Sizes {
    state: usize,
    inputs: usize,
    outputs: usize,
    order: usize,
    brackets: usize,
}

/// The implementation of `hamel::ControlAffine`.
pub fn trait_impl(
    cx: &Context<'_>,
    imp: &syn::ItemImpl,
    nodes: &ControlNodes,
) -> syn::Result<TokenStream> {
    let sizes = Sizes {
        state: nodes.drift.len(),
        inputs: nodes.fields.len(),
        outputs: nodes.outputs.len(),
        order: nodes.along.len(),
        brackets: nodes.brackets.len(),
    };
    let types = types(&sizes);
    let consts = consts(nodes);
    let methods = methods(cx, nodes, &sizes)?;
    let ty = &imp.self_ty;
    let (impl_generics, _, where_clause) = imp.generics.split_for_impl();
    Ok(quote! {
        #[allow(clippy::all)]
        #[diagnostic::do_not_recommend]
        impl #impl_generics ::hamel::ControlAffine for #ty #where_clause {
            #types
            #consts
            #methods
        }
    })
}

/// The stand-in for a model with mistakes that asks for control code: the sizes as far as
/// the request tells them, every method unreachable (the crate does not build).
pub fn stand_in(
    imp: &syn::ItemImpl,
    state: usize,
    inputs: usize,
    request: &StandIn,
) -> TokenStream {
    let sizes = Sizes {
        state,
        inputs,
        outputs: request.outputs.len(),
        order: request.order,
        brackets: request.brackets,
    };
    let types = types(&sizes);
    let names = &request.outputs;
    let (order, along) = (lit(sizes.order), sizes.order * sizes.outputs * sizes.inputs);
    let labels = (0..sizes.brackets).map(|i| format!("bracket{i}"));
    let depths = (0..sizes.brackets).map(|_| lit(1));
    let vanishing = (0..along).map(|_| false);
    let never = quote!(::core::unreachable!(
        "hamel: the model has errors, reported at build time"
    ));
    let signatures = signatures(&sizes);
    let [outputs, affine, lie, brackets] = signatures;
    let ty = &imp.self_ty;
    let (impl_generics, _, where_clause) = imp.generics.split_for_impl();
    quote! {
        #[allow(clippy::all, unused_variables)]
        #[diagnostic::do_not_recommend]
        impl #impl_generics ::hamel::ControlAffine for #ty #where_clause {
            #types
            const OUTPUTS: &'static [&'static str] = &[#(#names),*];
            const ORDER: usize = #order;
            const BRACKETS: &'static [&'static str] = &[#(#labels),*];
            const BRACKET_DEPTHS: &'static [usize] = &[#(#depths),*];
            const VANISHING: &'static [bool] = &[#(#vanishing),*];
            #outputs { #never }
            #affine { #never }
            #lie { #never }
            #brackets { #never }
        }
    }
}

/// What a stand-in knows of the request: the outputs' names, the order and how many
/// brackets.
pub struct StandIn {
    pub outputs: Vec<String>,
    pub order: usize,
    pub brackets: usize,
}

fn types(s: &Sizes) -> TokenStream {
    let outputs = lit(s.outputs);
    let fields = lit(s.state * s.inputs);
    let lie = lit((s.order + 1) * s.outputs);
    let along = lit(s.order * s.outputs * s.inputs);
    let brackets = lit(s.brackets * s.state);
    quote! {
        type Outputs = [f64; #outputs];
        type InputFields = [f64; #fields];
        type LieDerivatives = [f64; #lie];
        type InputLieDerivatives = [f64; #along];
        type Brackets = [f64; #brackets];
    }
}

fn consts(nodes: &ControlNodes) -> TokenStream {
    let names = &nodes.outputs;
    let order = lit(nodes.along.len());
    let labels = nodes.brackets.iter().map(|b| &b.label);
    let depths = nodes.brackets.iter().map(|b| lit(b.depth));
    let vanishing = &nodes.vanishing;
    quote! {
        const OUTPUTS: &'static [&'static str] = &[#(#names),*];
        const ORDER: usize = #order;
        const BRACKETS: &'static [&'static str] = &[#(#labels),*];
        const BRACKET_DEPTHS: &'static [usize] = &[#(#depths),*];
        const VANISHING: &'static [bool] = &[#(#vanishing),*];
    }
}

/// The four methods' signatures, bodies to follow.
fn signatures(s: &Sizes) -> [TokenStream; 4] {
    let state = lit(s.state);
    let outputs = lit(s.outputs);
    let fields = lit(s.state * s.inputs);
    let lie = lit((s.order + 1) * s.outputs);
    let along = lit(s.order * s.outputs * s.inputs);
    let brackets = lit(s.brackets * s.state);
    let allow = quote!(#[inline] #[allow(clippy::all, clippy::pedantic, unused_parens, unused_variables, non_snake_case)]);
    let result = quote!(::core::result::Result);
    let singularity = quote!(::hamel::Singularity);
    [
        quote!(#allow fn output_values(&self, t: f64, x: &[f64; #state]) -> [f64; #outputs]),
        quote!(#allow fn control_affine_values(&self, t: f64, x: &[f64; #state]) -> #result<([f64; #state], [f64; #fields]), #singularity>),
        quote!(#allow fn lie_values(&self, t: f64, x: &[f64; #state]) -> #result<([f64; #lie], [f64; #along]), #singularity>),
        quote!(#allow fn bracket_values(&self, t: f64, x: &[f64; #state]) -> #result<[f64; #brackets], #singularity>),
    ]
}

fn methods(cx: &Context<'_>, nodes: &ControlNodes, s: &Sizes) -> syn::Result<TokenStream> {
    let [outputs_sig, affine_sig, lie_sig, brackets_sig] = signatures(s);
    let h: Vec<NodeId> = nodes.lie.first().cloned().unwrap_or_default();
    let outputs = cx.plain(Source::State, &h)?;
    // g row-major over the state: entry (i, j) is g_j's component i.
    let g: Vec<NodeId> = (0..s.state)
        .flat_map(|i| nodes.fields.iter().map(move |field| field[i]))
        .collect();
    let affine_roots: Vec<NodeId> = nodes.drift.iter().chain(&g).copied().collect();
    let affine = cx.method(Source::State, &affine_roots, ALL, &|c| {
        let (f, g) = (vector(c, &nodes.drift), vector(c, &g));
        quote!((#f, #g))
    })?;
    let lie: Vec<NodeId> = nodes.lie.iter().flatten().copied().collect();
    let along: Vec<NodeId> = nodes.along.iter().flatten().flatten().copied().collect();
    let lie_roots: Vec<NodeId> = lie.iter().chain(&along).copied().collect();
    let checks = if lie_roots.is_empty() { NONE } else { ALL };
    let lie_body = cx.method(Source::State, &lie_roots, checks, &|c| {
        let (l, a) = (vector(c, &lie), vector(c, &along));
        quote!((#l, #a))
    })?;
    let brackets: Vec<NodeId> = nodes
        .brackets
        .iter()
        .flat_map(|b| b.nodes.iter().copied())
        .collect();
    let checks = if brackets.is_empty() { NONE } else { ALL };
    let brackets_body = cx.method(Source::State, &brackets, checks, &|c| vector(c, &brackets))?;
    Ok(quote! {
        #outputs_sig { #outputs }
        #affine_sig { #affine }
        #lie_sig { #lie_body }
        #brackets_sig { #brackets_body }
    })
}
