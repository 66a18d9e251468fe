//! `#[hamel_system]`: on the parameter struct, parameter reflection; on the model's impl
//! block, Hamel's equations as generated Rust.
//!
//! Phases, one file each: `model` (names and roles as written), `spec` (checks on the
//! signatures), `equations` (the graph of Hamel's equations, with the checks that need it:
//! linearity of the rows, a Lagrangian that depends on the velocities), `ldlt` (the unrolled
//! solve), `linearity`, `generate` (the Rust that comes out), `fallback` (what comes out
//! instead when the model has mistakes), `parameters` (the struct).

mod control;
mod equations;
// The exported functions' derivatives (`hamel-export`): compiled into the macro only with the
// feature `export`, so that a program that exports nothing neither builds this code nor
// runs it.
#[cfg(feature = "export")]
mod export;
#[cfg(not(feature = "export"))]
mod export {
    /// Without the feature `export` there is nothing to export: no value of this type exists.
    pub enum ExportNodes {}

    pub mod emit {
        use super::super::generate::Context;
        use super::ExportNodes;

        pub fn emit(_: &Context<'_>, nodes: &ExportNodes) -> syn::Result<proc_macro2::TokenStream> {
            match *nodes {}
        }
    }
}
mod fallback;
mod generate;
mod generic;
mod helpers_stand_in;
mod interface;
mod ldlt;
mod linearity;
mod mechanism;
mod model;
mod notes;
mod orientations;
mod parameters;
mod parametric;
mod rank;
mod rate_bodies;
mod reserved;
mod sparse_lu;
mod spec;

use crate::engine::graph::Graph;
use crate::engine::hash::HashSet;
use crate::engine::lower::{ImplContext, Lowerer, Shape, Value};
use fallback::{Sketch, fallback};
use proc_macro2::TokenStream;
use quote::{ToTokens, quote};
use syn::spanned::Spanned;

pub fn expand(attr: TokenStream, item: TokenStream) -> TokenStream {
    match syn::parse2::<syn::Item>(item.clone()) {
        Ok(syn::Item::Struct(s)) => parameters::expand(attr, &s),
        // A model that calls shared helpers first gathers their source (`helpers`), and
        // stands in for itself if a set's macro is missing (`helpers_stand_in`).
        Ok(syn::Item::Impl(imp)) if !helper_sets(&attr).is_empty() => {
            let sets = helper_sets(&attr);
            let gather = crate::helpers::start(&sets, &attr, &item);
            let stand_in = helpers_stand_in::stand_in(&attr, &imp, &sets);
            quote!(#gather #stand_in)
        }
        Ok(syn::Item::Impl(imp)) => expand_impl(attr, &imp, &[]),
        Ok(other) => {
            let error = syn::Error::new_spanned(
                &other,
                "`#[hamel_system]` goes on the model's parameter struct and on its impl block",
            );
            parameters::not_a_struct(&other, error)
        }
        Err(e) => {
            let error = e.into_compile_error();
            quote!(#item #error)
        }
    }
}

/// The last step of gathering a model's shared helpers (`hamel::__hamel_with_helpers!`):
/// the next helper set's macro, or the model expanded with every helper known.
pub fn expand_with_helpers(input: TokenStream) -> TokenStream {
    // A stand-in's call (`helpers_stand_in`): the set's macro exists.
    if crate::helpers::is_stand_in_call(&input) {
        return quote!(0);
    }
    let gathered = match crate::helpers::parse(input) {
        Ok(g) => g,
        Err(e) => return e.into_compile_error(),
    };
    if let Some(next) = crate::helpers::next(&gathered) {
        return next;
    }
    let imp = match syn::parse2::<syn::ItemImpl>(gathered.item.clone()) {
        Ok(imp) => imp,
        Err(e) => return e.into_compile_error(),
    };
    let sets: Vec<syn::ItemImpl> = gathered
        .helpers
        .iter()
        .filter_map(|h| syn::parse2(h.clone()).ok())
        .collect();
    let at = imp.impl_token.span;
    crate::helpers::self_resolved_at(expand_impl(gathered.attr, &imp, &sets), at)
}

/// The helper sets named in `helpers(..)`, read without checking the rest of the arguments.
fn helper_sets(attr: &TokenStream) -> Vec<syn::Path> {
    let mut errors = Vec::new();
    model::parse_names(attr.clone(), &mut errors).helpers
}

fn expand_impl(
    attr: TokenStream,
    imp: &syn::ItemImpl,
    helper_sets: &[syn::ItemImpl],
) -> TokenStream {
    if let Some((path, _)) = &imp.trait_ {
        let error = syn::Error::new_spanned(
            path,
            "`#[hamel_system]` goes on the model's inherent impl block (`impl Model { .. }`)",
        );
        return on_trait_impl(attr, imp, error);
    }
    let mut errors = Vec::new();
    let names = model::parse_names(attr, &mut errors);
    let roles = model::Roles::find(&imp.items, &mut errors);

    // Bodies may index with the generated constants: `q[Self::ALPHA]`.
    let sketch = Sketch::new(&names, &roles);
    let mut ctx = ImplContext::new(&imp.items);
    for (name, i) in &sketch.index_consts {
        ctx.define_index(name.clone(), *i as i64);
    }
    for set in helper_sets {
        if let syn::Type::Path(p) = &*set.self_ty
            && let Some(last) = p.path.segments.last()
        {
            ctx.add_helpers(last.ident.to_string(), &set.items);
        }
    }

    let mut graph = Graph::new();
    let mut lowerer = Lowerer::new(&mut graph, &ctx);
    for e in errors {
        lowerer.push_error(e);
    }
    let (impl_token, self_ty) = (imp.impl_token, &imp.self_ty);
    let at = quote!(#impl_token #self_ty);
    let spec = spec::check(names, &roles, &mut lowerer, &at);
    let equations = spec
        .as_ref()
        .and_then(|s| equations::build_cheaper(s, &mut lowerer));
    let control = match (&spec, &equations) {
        (Some(s), Some(eq)) if !lowerer.has_errors() => control::build(s, eq, &mut lowerer),
        _ => None,
    };
    if lowerer.has_errors() {
        check_unreached_bodies(&roles, &mut lowerer);
    }
    let replaced = if lowerer.has_errors() {
        Vec::new()
    } else {
        rate_bodies::lower(&roles, &mut lowerer)
    };
    if let Err(e) = lowerer.take_errors() {
        let faulty = lowerer.faulty_functions().clone();
        return fallback(imp, &faulty, &sketch, e);
    }
    let externals = lowerer.externals.items.clone();
    let arrays = std::mem::take(&mut lowerer.parameter_arrays);
    drop(lowerer);
    let (Some(spec), Some(equations)) = (spec, equations) else {
        let error = syn::Error::new(
            imp.impl_token.span(),
            "hamel internal error: model not built, but no error reported",
        );
        return fallback(imp, &HashSet::default(), &sketch, error);
    };
    let mut stripped = model::strip_role_attributes(imp);
    if let Err(e) = rate_bodies::emit(&graph, &externals, &replaced, &mut stripped) {
        return fallback(imp, &HashSet::default(), &sketch, e);
    }
    // The exported functions' derivatives, for `hamel-export` (feature `export`).
    #[cfg(feature = "export")]
    let exported = Some(export::build(
        &mut graph,
        &equations,
        control.as_ref(),
        &externals,
    ));
    #[cfg(not(feature = "export"))]
    let exported: Option<export::ExportNodes> = None;
    let read = generate::Read {
        externals: &externals,
        arrays: &arrays,
    };
    generate::generate(
        &spec,
        (&equations, control.as_ref()),
        exported.as_ref(),
        &graph,
        &read,
        &stripped,
    )
    .unwrap_or_else(|e| fallback(imp, &HashSet::default(), &sketch, e))
}

/// `#[hamel_system]` on a trait impl (`impl HamelSystem for Model`): the error, and the block
/// as the inherent impl it should be, with the stand-ins of a model with mistakes. Emitted as
/// written, its functions would each be "not a member of the trait", and the program's uses of
/// the model would each miss its `impl HamelSystem`.
fn on_trait_impl(attr: TokenStream, imp: &syn::ItemImpl, error: syn::Error) -> TokenStream {
    let inherent = as_inherent(imp);
    let mut ignored = Vec::new();
    let names = model::parse_names(attr, &mut ignored);
    let roles = model::Roles::find(&inherent.items, &mut ignored);
    let sketch = Sketch::new(&names, &roles);
    fallback(&inherent, &HashSet::default(), &sketch, error)
}

/// The impl block `imp` as an inherent impl: without its trait, and with only the items an
/// inherent impl can hold, functions and constants (associated types cannot be inherent).
pub(crate) fn as_inherent(imp: &syn::ItemImpl) -> syn::ItemImpl {
    let mut inherent = imp.clone();
    inherent.trait_ = None;
    inherent.unsafety = None;
    inherent
        .items
        .retain(|item| matches!(item, syn::ImplItem::Fn(_) | syn::ImplItem::Const(_)));
    inherent
}

/// When the model has a mistake, the bodies the equations did not reach (the model could not
/// be assembled, or assembling stopped at an earlier mistake) are still lowered, each on the
/// arguments its role needs, so that one build reports every independent mistake.
fn check_unreached_bodies<'a>(roles: &model::Roles<'a>, lowerer: &mut Lowerer<'a, '_>) {
    for rf in roles.by_role.values() {
        let name = rf.f.sig.ident.to_string();
        if lowerer.was_lowered(&name) {
            continue;
        }
        let Some(signature) = lowerer.signature(rf.f) else {
            continue;
        };
        // On the arguments the role needs, when the signature has them in the wrong shape
        // (its error is reported): `q[2]` is no mistake in a body whose `q` should have three.
        // Each argument is what its name says it is, when the name is the role's (a misplaced
        // argument is reported): in `fn(&self, qd, q)` the body reads `q[2]` as a coordinate.
        let shapes: Vec<Shape> = match lowerer.expected_arguments.get(&name) {
            Some(expected) if expected.len() == signature.args.len() => signature
                .args
                .iter()
                .enumerate()
                .map(|(i, arg)| {
                    let named = spec::argument_name(&arg.pat)
                        .and_then(|n| expected.iter().position(|(e, _)| *e == n));
                    expected[named.unwrap_or(i)].1.clone()
                })
                .collect(),
            _ => signature.args.iter().map(|a| a.shape.clone()).collect(),
        };
        let args: Option<Vec<Value>> = signature
            .args
            .iter()
            .zip(&shapes)
            .map(|(arg, shape)| {
                let label = arg.pat.to_token_stream().to_string();
                shape
                    .fresh_inputs(lowerer.graph, &label)
                    .map(|(value, _)| value)
            })
            .collect();
        if let Some(args) = args {
            lowerer.check_body(rf.f, args);
        }
    }
}
