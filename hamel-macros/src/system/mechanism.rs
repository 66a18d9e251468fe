//! `impl hamel::geometry::Mechanism for Model`, for a model stated from its bodies: the bodies,
//! contacts and gravity at run time, by calling the model's own role functions, so that a
//! scene or a picture shows exactly what the equations were derived from. A model with
//! mistakes gets a stand-in with the same names and unreachable methods (`fallback`), so that
//! the program's scenes of it add no errors of rustc's to the model's own.

use proc_macro2::TokenStream;
use quote::quote;

/// A role function, and whether it takes the time first.
pub struct Call<'a> {
    pub f: &'a syn::ImplItemFn,
    pub timed: bool,
}

impl Call<'_> {
    /// `Self::bodies(self, t, q)`, or without `t`; `args` are what follows `self` and `t`.
    fn tokens(&self, args: TokenStream) -> TokenStream {
        let ident = &self.f.sig.ident;
        match (self.timed, args.is_empty()) {
            (true, true) => quote!(Self::#ident(self, t)),
            (true, false) => quote!(Self::#ident(self, t, #args)),
            (false, _) => quote!(Self::#ident(self, #args)),
        }
    }
}

/// What the implementation calls.
pub struct Roles<'a> {
    pub bodies: Call<'a>,
    pub contacts: Option<Call<'a>>,
    pub gravity: Option<Call<'a>>,
}

/// The implementation: `roles` to call and the notes on the geometry, or `None` for the
/// stand-in of a model with mistakes.
pub fn mechanism_impl(
    imp: &syn::ItemImpl,
    n: usize,
    names: &[String],
    roles: Option<(&Roles<'_>, &[String])>,
) -> TokenStream {
    let ty = &imp.self_ty;
    let (impl_generics, _, where_clause) = imp.generics.split_for_impl();
    let n = proc_macro2::Literal::usize_unsuffixed(n);
    let geometry = quote!(::hamel::geometry);
    let never = quote!(::core::unreachable!(
        "hamel: the model has errors, reported at build time"
    ));
    let notes = roles.map_or(&[][..], |(_, notes)| notes);
    let notes_doc = notes
        .iter()
        .map(|note| format!(" {note}"))
        .collect::<Vec<_>>();
    let (bodies, contacts, gravity) = match roles.map(|(r, _)| r) {
        Some(r) => {
            let bodies = r.bodies.tokens(quote!(q));
            let contacts = r.contacts.as_ref().map_or_else(
                || quote!(::std::vec::Vec::new()),
                |c| {
                    let call = c.tokens(quote!(q));
                    quote!(::std::vec::Vec::from(#call))
                },
            );
            let gravity = r.gravity.as_ref().map_or_else(
                || quote!(::core::option::Option::None),
                |g| {
                    let call = g.tokens(TokenStream::new());
                    quote!(::core::option::Option::Some(#call))
                },
            );
            (quote!(::std::vec::Vec::from(#bodies)), contacts, gravity)
        }
        None => (never.clone(), never.clone(), never),
    };
    quote! {
        #[allow(clippy::all, unused_variables)]
        #[diagnostic::do_not_recommend]
        #(#[doc = #notes_doc])*
        impl #impl_generics #geometry::Mechanism for #ty #where_clause {
            const BODIES: &'static [&'static str] = &[#(#names),*];
            const NOTES: &'static [&'static str] = &[#(#notes),*];

            fn bodies_at(&self, t: f64, q: &[f64; #n]) -> ::std::vec::Vec<#geometry::Body> {
                #bodies
            }

            fn contacts_at(&self, t: f64, q: &[f64; #n]) -> ::std::vec::Vec<#geometry::Contact> {
                #contacts
            }

            fn gravity_vector(&self, t: f64) -> ::core::option::Option<#geometry::Vector3> {
                #gravity
            }
        }
    }
}
