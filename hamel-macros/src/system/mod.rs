//! `#[hamel_system]`: on the parameter struct, parameter reflection; on the model's impl
//! block, Hamel's equations as generated Rust.
//!
//! Phases, one file each: `model` (names and roles as written), `spec` (checks on the
//! signatures), `equations` (the graph of Hamel's equations, with the checks that need it:
//! linearity of the rows, a Lagrangian that depends on the velocities), `ldlt` (the unrolled
//! solve), `linearity`, `generate` (the Rust that comes out), `parameters` (the struct).

mod equations;
mod generate;
mod ldlt;
mod linearity;
mod model;
mod parameters;
mod sparse_lu;
mod spec;

use crate::engine::graph::Graph;
use crate::engine::lower::{ImplContext, Lowerer};
use proc_macro2::TokenStream;
use quote::quote;
use syn::ext::IdentExt;
use syn::spanned::Spanned;

pub fn expand(attr: TokenStream, item: TokenStream) -> TokenStream {
    match syn::parse2::<syn::Item>(item.clone()) {
        Ok(syn::Item::Struct(s)) => parameters::expand(attr, &s).unwrap_or_else(|e| {
            let error = e.into_compile_error();
            quote!(#s #error)
        }),
        Ok(syn::Item::Impl(imp)) => expand_impl(attr, &imp).unwrap_or_else(|e| {
            // Keep the user's functions (without our role attributes, which rustc would not
            // know), so that the rest of their code still resolves.
            let stripped = model::strip_role_attributes(&imp);
            let error = e.into_compile_error();
            quote!(#stripped #error)
        }),
        Ok(other) => {
            let error = syn::Error::new_spanned(
                &other,
                "`#[hamel_system]` goes on the model's parameter struct and on its impl block",
            )
            .into_compile_error();
            quote!(#other #error)
        }
        Err(e) => {
            let error = e.into_compile_error();
            quote!(#item #error)
        }
    }
}

fn expand_impl(attr: TokenStream, imp: &syn::ItemImpl) -> syn::Result<TokenStream> {
    if let Some((path, _)) = &imp.trait_ {
        return Err(syn::Error::new_spanned(
            path,
            "`#[hamel_system]` goes on the model's inherent impl block (`impl Model { .. }`)",
        ));
    }
    let mut errors = Vec::new();
    let names = model::parse_names(attr, &mut errors);
    let roles = model::Roles::find(&imp.items, &mut errors);

    // Bodies may index with the generated constants: `q[Self::ALPHA]`.
    let mut ctx = ImplContext::new(&imp.items);
    let lists = [
        names.coordinates.as_ref().map(|(_, l)| l),
        names.speeds.as_ref().map(|(_, l)| l),
        Some(&names.inputs),
    ];
    for list in lists.into_iter().flatten() {
        for (i, ident) in list.iter().enumerate() {
            ctx.define_index(ident.unraw().to_string().to_uppercase(), i as i64);
        }
    }

    let mut graph = Graph::new();
    let mut lowerer = Lowerer::new(&mut graph, &ctx);
    for e in errors {
        lowerer.push_error(e);
    }
    let spec = spec::check(names, &roles, &mut lowerer, imp.impl_token.span());
    let equations = spec
        .as_ref()
        .and_then(|s| equations::build(s, &mut lowerer));
    lowerer.take_errors()?;
    let externals = lowerer.externals.items.clone();
    drop(lowerer);
    let (Some(spec), Some(equations)) = (spec, equations) else {
        return Err(syn::Error::new(
            imp.impl_token.span(),
            "hamel internal error: model not built, but no error reported",
        ));
    };
    let stripped = model::strip_role_attributes(imp);
    generate::generate(&spec, &equations, &graph, &externals, &stripped)
}
