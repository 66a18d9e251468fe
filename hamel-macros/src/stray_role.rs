//! The role attributes (`#[kinetic_energy]`, `#[constraints]`, ..) as macros of their own.
//!
//! Inside an impl block with `#[hamel_system]` they never run: that macro reads and removes
//! them before rustc resolves them. So when one runs, it is outside such a block (the block
//! lacks the attribute, or the role is in a second impl block of the model), and instead of
//! rustc's "cannot find attribute", it says where the role belongs.

use proc_macro2::{Span, TokenStream};
use quote::quote;

/// The marked item unchanged, with one error at the attribute.
pub fn expand(role: &str, item: TokenStream) -> TokenStream {
    // At the attribute, but resolved as the user's code: rustc then does not add that the
    // error "originates in the attribute macro", which the user can do nothing about.
    let at = match item.clone().into_iter().next() {
        Some(first) => Span::call_site().resolved_at(first.span()),
        None => Span::call_site(),
    };
    let error = syn::Error::new(
        at,
        format!(
            "`#[{role}]` is outside an impl block with `#[hamel_system]`, the only place where \
             it is read: all the roles of a model go in one impl block, which carries \
             `#[hamel_system(coordinates(..))]`; move this function into that block, or put the \
             attribute on this one if the model has none"
        ),
    )
    .into_compile_error();
    // The function is unused without the model around it: rustc should not say so too.
    quote!(#[allow(dead_code)] #item #error)
}
