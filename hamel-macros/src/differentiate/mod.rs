//! `#[differentiate]`: derivative methods for every function of an impl block.
//!
//! The engine's direct interface. For each function `f(&self, x₁: T₁, …) -> R` whose
//! arguments are `f64` or arrays of `f64`, with the inputs flattened to x ∈ ℝᴺ (arguments in
//! order, arrays row-major) and the result to y ∈ ℝᴹ, it adds:
//!
//! | method | computes |
//! |---|---|
//! | `f_tangent(args, dir: &[f64; N]) -> [f64; M]` | F'(x)·dir |
//! | `f_gradient(args) -> [f64; N]` (M = 1) | ∇F(x) |
//! | `f_adjoint(args, weights: &[f64; M]) -> [f64; N]` (M > 1) | weightsᵀ·F'(x) |
//! | `f_jacobian(args) -> [[f64; N]; M]` | F'(x) |
//! | `f_hessian(args) -> [[f64; N]; N]` (M = 1; `weights` added for M > 1) | ∇²(wᵀF)(x) |
//! | `f_second(args, dir_u, dir_v: &[f64; N]) -> [f64; M]` | F''(x)[u, v] |
//! | `f_generic::<S: hamel::Scalar>(args over S) -> R over S` | F itself, over any scalar |
//! | `F_OPS: hamel::OpCounts` | operation counts of all of the above |
//!
//! Functions with integer arguments, or with values of the geometry vocabulary (`Vector3`,
//! `Rotation3`, ...) as arguments or result, are helpers: they can be called (and are
//! inlined) but get no derivative methods of their own.

mod derivatives;
mod methods;

use crate::engine::graph::Graph;
use crate::engine::lower::{ImplContext, Shape, Signature};
use proc_macro2::{Literal, TokenStream};
use quote::{format_ident, quote};
use syn::visit_mut::VisitMut;

pub fn expand(attr: TokenStream, item: TokenStream) -> TokenStream {
    let result = if attr.is_empty() {
        syn::parse2::<syn::ItemImpl>(item.clone()).and_then(|imp| expand_impl(&imp))
    } else {
        Err(syn::Error::new_spanned(
            attr,
            "`#[differentiate]` takes no arguments",
        ))
    };
    match result {
        Ok(tokens) => tokens,
        // Keep the user's code so that its own errors (and uses) still resolve.
        Err(e) => {
            let error = e.into_compile_error();
            quote!(#item #error)
        }
    }
}

fn expand_impl(imp: &syn::ItemImpl) -> syn::Result<TokenStream> {
    if let Some((path, _)) = &imp.trait_ {
        return Err(syn::Error::new_spanned(
            path,
            "`#[differentiate]` goes on an inherent impl block (`impl Model { .. }`), not a trait impl",
        ));
    }
    let ctx = ImplContext::new(&imp.items);
    let mut methods = Vec::new();
    let mut errors: Option<syn::Error> = None;
    for item in &imp.items {
        let syn::ImplItem::Fn(f) = item else { continue };
        match companions(&ctx, f) {
            Ok(tokens) => methods.push(tokens),
            Err(e) => match &mut errors {
                Some(all) => all.combine(e),
                None => errors = Some(e),
            },
        }
    }
    if let Some(e) = errors {
        return Err(e);
    }
    let (impl_generics, _, where_clause) = imp.generics.split_for_impl();
    let self_ty = &imp.self_ty;
    Ok(quote! {
        #imp
        impl #impl_generics #self_ty #where_clause {
            #(#methods)*
        }
    })
}

/// A generated method's argument: the user's argument, renamed if needed.
struct UserArg {
    name: syn::Ident,
    ty: syn::Type,
    shape: Shape,
}

/// Expression reading element `index` (row-major) of an argument.
fn element(arg: &UserArg, index: usize) -> TokenStream {
    let name = &arg.name;
    let mut path = Vec::new();
    let mut shape = &arg.shape;
    let mut rest = index;
    while let Shape::Array(_, inner) = shape {
        let stride = inner.len().max(1);
        path.push(rest / stride);
        rest %= stride;
        shape = inner;
    }
    let path: Vec<Literal> = path.into_iter().map(Literal::usize_unsuffixed).collect();
    if path.is_empty() {
        // A scalar, possibly behind references.
        let mut ty = &arg.ty;
        let mut derefs = 0;
        while let syn::Type::Reference(r) = ty {
            derefs += 1;
            ty = &r.elem;
        }
        let stars = (0..derefs).map(|_| quote!(*));
        quote!((#(#stars)* #name))
    } else {
        quote!(#name #([#path])*)
    }
}

/// Nested array expression of a shape from flat element expressions.
fn nest(shape: &Shape, flat: &mut impl Iterator<Item = TokenStream>) -> TokenStream {
    match shape {
        Shape::Array(n, inner) => {
            let items: Vec<TokenStream> = (0..*n).map(|_| nest(inner, flat)).collect();
            quote!([#(#items),*])
        }
        _ => flat
            .next()
            .unwrap_or_else(|| quote!(::core::compile_error!("hamel internal error: shape"))),
    }
}

/// Replace every `f64` in a type by the type parameter `S`.
struct ToGeneric(syn::Ident);

impl VisitMut for ToGeneric {
    fn visit_type_path_mut(&mut self, p: &mut syn::TypePath) {
        if p.qself.is_none() && p.path.is_ident("f64") {
            let s = &self.0;
            *p = syn::parse_quote!(#s);
        } else {
            syn::visit_mut::visit_type_path_mut(self, p);
        }
    }
}

/// The derivative methods of one function: the function lowered and differentiated once,
/// then one method per derivative kind, the function over any scalar, and the operation
/// counts.
fn companions(ctx: &ImplContext<'_>, f: &syn::ImplItemFn) -> syn::Result<TokenStream> {
    let mut graph = Graph::new();
    let Some(lowered) = derivatives::lower(ctx, &mut graph, f)? else {
        return Ok(TokenStream::new());
    };
    let derived = derivatives::derive(&mut graph, &lowered.x, &lowered.y);
    let writer = methods::Writer::new(&graph, f, &lowered, &derived);
    let mut out = TokenStream::new();
    out.extend(writer.tangent()?);
    out.extend(writer.gradient()?);
    out.extend(writer.jacobian()?);
    out.extend(writer.hessian()?);
    out.extend(writer.second()?);
    out.extend(writer.generic()?);
    out.extend(writer.op_counts()?);
    Ok(out)
}

/// Names for the generated methods' copies of the user's arguments: the user's own name when
/// it is a plain identifier that cannot clash with generated names, else `arg{i}`.
fn user_args(signature: &Signature) -> Vec<UserArg> {
    let reserved = |s: &str| {
        matches!(s, "dir" | "dir_u" | "dir_v" | "weights" | "self")
            || (s.starts_with('v') && s.len() > 1 && s[1..].chars().all(|c| c.is_ascii_digit()))
    };
    signature
        .args
        .iter()
        .enumerate()
        .map(|(i, a)| {
            let name = match &a.pat {
                syn::Pat::Ident(p) if p.subpat.is_none() && !reserved(&p.ident.to_string()) => {
                    p.ident.clone()
                }
                _ => format_ident!("arg{}", i),
            };
            UserArg {
                name,
                ty: a.ty.clone(),
                shape: a.shape.clone(),
            }
        })
        .collect()
}
