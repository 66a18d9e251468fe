//! Procedural macros of [`hamel`](https://docs.rs/hamel). Use them through the `hamel` crate.
//!
//! The macros are thin entry points; the work is in `engine` (compile-time differentiation)
//! and in the expansion modules. Every entry point returns errors as `compile_error!` with the
//! span of the user's code, and never panics.

mod differentiate;
mod engine;
mod system;

use proc_macro::TokenStream;

/// Generate derivative methods for every function of an impl block; see the `hamel` crate.
#[proc_macro_attribute]
pub fn differentiate(attr: TokenStream, item: TokenStream) -> TokenStream {
    guarded(|| differentiate::expand(attr.into(), item.into())).into()
}

/// Turn a model into a simulator; see the `hamel` crate.
#[proc_macro_attribute]
pub fn hamel_system(attr: TokenStream, item: TokenStream) -> TokenStream {
    guarded(|| system::expand(attr.into(), item.into())).into()
}

/// Run an expansion; should it ever panic, report an error instead of "proc macro panicked".
fn guarded(expand: impl FnOnce() -> proc_macro2::TokenStream) -> proc_macro2::TokenStream {
    match std::panic::catch_unwind(std::panic::AssertUnwindSafe(expand)) {
        Ok(tokens) => tokens,
        Err(_) => syn::Error::new(
            proc_macro2::Span::call_site(),
            "hamel internal error: the macro failed on this input; please report it with the model",
        )
        .into_compile_error(),
    }
}
