//! Role functions that use `rate!`: the macro knows what `rate!(e)` is (the derivative of
//! `e` along the motion), rustc does not, so the generated impl gives such a function a
//! body of straight-line code that computes what the written one means. The function can
//! then still be called at run time (`model.rolling(&q, &qd)`), with the rates evaluated.

use super::model::Roles;
use crate::engine::emit::{Emitter, Scalar};
use crate::engine::graph::{Graph, NodeId};
use crate::engine::lower::{External, Lowerer, Value, uses_rate};
use proc_macro2::TokenStream;
use quote::quote;

/// A role function's value on inputs of its own, and the expressions that read them.
pub struct Replaced {
    name: String,
    inputs: Vec<(NodeId, TokenStream)>,
    value: Value,
}

/// Each role function that uses `rate!`, lowered again on inputs bound to its own arguments.
pub fn lower<'a>(roles: &Roles<'a>, lowerer: &mut Lowerer<'a, '_>) -> Vec<Replaced> {
    let mut replaced = Vec::new();
    for rf in roles.by_role.values().filter(|rf| uses_rate(rf.f)) {
        let name = rf.f.sig.ident.to_string();
        let Some(expected) = lowerer.expected_arguments.get(&name).cloned() else {
            continue;
        };
        let typed = rf.f.sig.inputs.iter().filter_map(|a| match a {
            syn::FnArg::Typed(pt) => Some(&*pt.pat),
            syn::FnArg::Receiver(_) => None,
        });
        let mut inputs = Vec::new();
        let mut args = Vec::new();
        for ((label, shape), pat) in expected.iter().zip(typed) {
            let syn::Pat::Ident(ident) = pat else {
                lowerer.push_error(syn::Error::new_spanned(
                    pat,
                    "a role that uses `rate!` takes its arguments by name (`q`, `qd`): the \
                     generated code reads them",
                ));
                return Vec::new();
            };
            let Some((value, nodes)) = shape.fresh_inputs(lowerer.graph, label) else {
                return Vec::new();
            };
            let ident = &ident.ident;
            match nodes.as_slice() {
                [one] if matches!(value, Value::Real(_)) => inputs.push((*one, quote!(#ident))),
                _ => inputs.extend(nodes.iter().enumerate().map(|(i, &node)| {
                    let i = proc_macro2::Literal::usize_unsuffixed(i);
                    (node, quote!(#ident[#i]))
                })),
            }
            args.push(value);
        }
        let value = lowerer.call_role(rf.f, args);
        if !value.is_poison() {
            replaced.push(Replaced {
                name,
                inputs,
                value,
            });
        }
    }
    replaced
}

/// The impl with the bodies of the functions in `replaced` generated.
pub fn emit(
    graph: &Graph,
    externals: &[External],
    replaced: &[Replaced],
    imp: &mut syn::ItemImpl,
) -> syn::Result<()> {
    for r in replaced {
        let mut emitter = Emitter::new(graph, Scalar::F64);
        for (node, tokens) in &r.inputs {
            emitter.bind(*node, tokens.clone());
        }
        for ext in externals {
            emitter.bind(ext.node, ext.tokens.clone());
        }
        let Some(roots) = r.value.flatten() else {
            continue;
        };
        let code = emitter.emit(&roots)?;
        let stmts = &code.stmts;
        let result = shaped(&r.value, &mut roots.iter().map(|&id| code.value(id)));
        for item in &mut imp.items {
            if let syn::ImplItem::Fn(f) = item
                && f.sig.ident == r.name
            {
                f.block = syn::parse_quote!({
                    #stmts
                    #result
                });
                f.attrs
                    .push(syn::parse_quote!(#[allow(clippy::all, unused_parens, non_snake_case)]));
            }
        }
    }
    Ok(())
}

/// The expression of a value of the shape of `like`, from its reals' expressions in order.
fn shaped(like: &Value, reals: &mut impl Iterator<Item = TokenStream>) -> TokenStream {
    match like {
        Value::Array(items) => {
            let items = items.iter().map(|i| shaped(i, reals));
            quote!([#(#items),*])
        }
        _ => reals.next().unwrap_or_default(),
    }
}
