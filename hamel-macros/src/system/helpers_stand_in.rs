//! The stand-in of a model that names shared helpers, for when a name in `helpers(..)` holds
//! none (its impl lacks `#[hamel::helpers]`).
//!
//! Such a model is expanded by its helper sets' macros (`crate::helpers`): when one of them
//! does not exist, rustc reports "cannot find macro" at the name and nothing of the model is
//! emitted, so each use of the model in the program would be an error of its own ("`Coin` is
//! not a hamel model", no `Coin::THETA`). The model's first expansion therefore also emits
//! the stand-in of a model with mistakes (`fallback`), made inert unless a set's macro is
//! missing. Whether a macro exists is known to rustc alone, so each stand-in item reads it
//! through a call of every set's macro in an array length, `[(); 0 + Wheels!{..}]`:
//!
//! * when every set's macro exists, each call gives `0`; the trait impls are then for
//!   `<[(); 0] as Select>::Model`, a hidden type of their own, and the inherent items are
//!   under `where [&'h (); 0]: Never`, a bound no type meets: neither reaches the model, whose
//!   own expansion emits the real items;
//! * when one does not, the call is rustc's error (the same diagnostic as the model's call of
//!   that macro, reported once) and the array length an erroneous constant: the projection is
//!   then rustc's error type, which the trait impls' self type matches as any type, and the
//!   bound holds as erroneous bounds do, so that every use of the model type-checks behind
//!   the one error. (While that error stands, any other type passes for a model too: a
//!   program's use of a type that is not one is reported once the name holds helpers.)

use super::fallback::{self, Sketch};
use super::{model, parameters};
use proc_macro2::TokenStream;
use quote::{format_ident, quote};
use syn::spanned::Spanned;

/// The stand-in items of the model `imp` with the attribute `attr`, naming the helper sets
/// `sets`; nothing if its pieces do not parse (they are made of the user's tokens, which
/// parse as a model already).
pub fn stand_in(attr: &TokenStream, imp: &syn::ItemImpl, sets: &[syn::Path]) -> TokenStream {
    build(attr, imp, sets).unwrap_or_default()
}

fn build(attr: &TokenStream, imp: &syn::ItemImpl, sets: &[syn::Path]) -> Option<TokenStream> {
    let mut ignored = Vec::new();
    let names = model::parse_names(attr.clone(), &mut ignored);
    let roles = model::Roles::find(&imp.items, &mut ignored);
    let sketch = Sketch::new(&names, &roles);

    // The marker at the name too: should the name hold a macro other than a set's, what it
    // makes of the marker is reported there.
    let calls = sets.iter().map(|set| {
        let marker = format_ident!("{}", crate::helpers::STAND_IN_MARKER, span = set.span());
        crate::helpers::invoke(set, quote!(#marker))
    });
    let length = quote!(0 #(+ #calls)*);

    // The user's functions and constants, under the bound that no type meets; the functions'
    // bodies are left out, so that a mistake in one is reported by the model's expansion only.
    // On a trait impl, which is its own mistake (`on_trait_impl`): the inherent block it
    // should be.
    let mut inherent = super::as_inherent(imp);
    inherent.attrs.push(syn::parse_quote!(#[doc(hidden)]));
    inherent
        .generics
        .params
        .insert(0, syn::parse_quote!('__hamel));
    inherent
        .generics
        .make_where_clause()
        .predicates
        .push(syn::parse2(quote!([&'__hamel (); #length]: __HamelNever)).ok()?);

    // The trait impls, for the hidden type (a generic model's parameters would be
    // unconstrained there: it gets none).
    let traits = if imp.generics.params.is_empty() {
        let mut traits = imp.clone();
        traits.self_ty =
            Box::new(syn::parse2(quote!(<[(); #length] as __HamelSelect>::Model)).ok()?);
        Some(traits)
    } else {
        None
    };
    let model = fallback::stand_in(&inherent, traits.as_ref(), &|_| true, &sketch);
    let hidden = format_ident!("__HamelUnusedStandIn");
    let parameters = parameters::stand_in(&hidden, &syn::Generics::default());
    Some(quote! {
        #[allow(dead_code, private_bounds, non_local_definitions, clippy::all)]
        const _: () = {
            #[doc(hidden)]
            pub trait __HamelNever {}
            #[doc(hidden)]
            pub trait __HamelSelect {
                type Model;
            }
            #[doc(hidden)]
            pub struct #hidden;
            impl __HamelSelect for [(); 0] {
                type Model = #hidden;
            }
            #parameters
            #model
        };
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use quote::ToTokens as _;

    fn items(tokens: TokenStream) -> Vec<syn::Item> {
        let file: syn::File = syn::parse2(tokens).expect("the stand-in parses");
        let [syn::Item::Const(c)] = &file.items[..] else {
            panic!("one `const _` block, not {:?}", file.items.len());
        };
        let syn::Expr::Block(block) = &*c.expr else {
            panic!("a block");
        };
        block
            .block
            .stmts
            .iter()
            .filter_map(|s| match s {
                syn::Stmt::Item(item) => Some(item.clone()),
                _ => None,
            })
            .collect()
    }

    fn impls(items: &[syn::Item]) -> Vec<(Option<String>, syn::ItemImpl)> {
        items
            .iter()
            .filter_map(|item| match item {
                syn::Item::Impl(imp) => {
                    let t = imp.trait_.as_ref().map(|(path, _)| {
                        let last = path.segments.last().expect("a trait path");
                        last.ident.to_string()
                    });
                    Some((t, imp.clone()))
                }
                _ => None,
            })
            .collect()
    }

    /// Every set's macro, called at the name the user wrote with the stand-in's marker.
    fn calls_every_set(tokens: &TokenStream) -> bool {
        let text = tokens.to_string();
        text.contains("Wheels ! { __hamel_stand_in }")
            && text.contains("shapes :: Frames ! { __hamel_stand_in }")
    }

    #[test]
    fn the_stand_in_reads_every_set_and_reaches_the_model_only_without_one() {
        let attr = quote!(coordinates(x, y, theta), helpers(Wheels, shapes::Frames));
        let imp: syn::ItemImpl = syn::parse_quote! {
            impl Sleigh {
                #[kinetic_energy]
                fn t(&self, q: &[f64; 3], qd: &[f64; 3]) -> f64 { Wheels::energy(self.m, qd) }
                #[constraints]
                fn c(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] { [qd[1]] }
            }
        };
        let sets: Vec<syn::Path> =
            vec![syn::parse_quote!(Wheels), syn::parse_quote!(shapes::Frames)];
        let items = items(stand_in(&attr, &imp, &sets));
        let impls = impls(&items);
        // The trait impls are for the projection, never for the model by name.
        let system = impls
            .iter()
            .find(|(t, _)| t.as_deref() == Some("HamelSystem"))
            .map(|(_, imp)| imp)
            .expect("a stand-in `impl HamelSystem`");
        let syn::Type::Path(projection) = &*system.self_ty else {
            panic!("the self type is a path");
        };
        assert!(projection.qself.is_some(), "the self type is a projection");
        assert!(calls_every_set(&system.self_ty.to_token_stream()));
        // The model's own items, behind the bound no type meets, with their bodies left out.
        let own = impls
            .iter()
            .filter(|(t, imp)| t.is_none() && imp.self_ty.to_token_stream().to_string() == "Sleigh")
            .map(|(_, imp)| imp)
            .collect::<Vec<_>>();
        assert!(!own.is_empty());
        for imp in &own {
            let bound = imp.generics.where_clause.to_token_stream();
            assert!(calls_every_set(&bound), "{bound}");
            assert!(bound.to_string().contains("__HamelNever"));
        }
        let text = quote!(#(#own)*).to_string();
        assert!(text.contains("const THETA"), "{text}");
        assert!(!text.contains("Wheels :: energy"), "{text}");
    }

    #[test]
    fn a_generic_model_gets_no_stand_in_trait_impls() {
        let attr = quote!(coordinates(x, y, theta), helpers(Wheels));
        let imp: syn::ItemImpl = syn::parse_quote! {
            impl<const N: usize> Sleigh<N> {
                #[constraints]
                fn c(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] { [qd[1]] }
            }
        };
        let sets: Vec<syn::Path> = vec![syn::parse_quote!(Wheels)];
        let items = items(stand_in(&attr, &imp, &sets));
        let impls = impls(&items);
        assert!(
            impls
                .iter()
                .all(|(t, _)| matches!(t.as_deref(), None | Some("__HamelSelect" | "Parameters")))
        );
    }

    #[test]
    fn a_sets_macro_answers_the_stand_in_with_zero() {
        let call = quote!(__hamel_stand_in { impl Wheels { fn f() {} } });
        assert_eq!(super::super::expand_with_helpers(call).to_string(), "0");
    }
}
