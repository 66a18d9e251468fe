//! `#[hamel_system]` on the parameter struct: every field must be an `f64`; the struct gets
//! an implementation of `hamel::Parameters` (names, doc comments, get and set by name).

use proc_macro2::TokenStream;
use quote::quote;
use syn::{Fields, ItemStruct};

/// The struct with its `Parameters` implementation; on mistakes, also their errors (the
/// implementation then covers the `f64` fields, so that the model's impl block does not
/// add an error of its own about a missing `Parameters`).
pub fn expand(attr: TokenStream, item: &ItemStruct) -> TokenStream {
    let mut errors = Vec::new();
    if !attr.is_empty() {
        errors.push(syn::Error::new_spanned(
            &attr,
            "on the parameter struct `#[hamel_system]` takes no arguments: the names of coordinates, \
             speeds and inputs go on the impl block, `#[hamel_system(coordinates(..), inputs(..))]`",
        ));
    }
    if !item.generics.params.is_empty() {
        errors.push(syn::Error::new_spanned(
            &item.generics,
            "a parameter struct cannot be generic: its fields are the model's `f64` parameters",
        ));
    }
    let fields: Vec<&syn::Field> = match &item.fields {
        Fields::Named(named) => named.named.iter().collect(),
        Fields::Unit => Vec::new(),
        Fields::Unnamed(unnamed) => {
            errors.push(syn::Error::new_spanned(
                unnamed,
                "parameters need names: use a struct with named `f64` fields, `struct Model { mass: f64 }`",
            ));
            Vec::new()
        }
    };
    let is_f64 = |field: &syn::Field| matches!(&field.ty, syn::Type::Path(p) if p.qself.is_none() && p.path.is_ident("f64"));
    for field in &fields {
        if !is_f64(field) {
            let name = field
                .ident
                .as_ref()
                .map(ToString::to_string)
                .unwrap_or_default();
            errors.push(syn::Error::new_spanned(
                &field.ty,
                format!(
                    "parameter `{name}` has type `{}`, but parameters are `f64`: hamel computes in `f64` \
                     (keep other data outside the parameter struct)",
                    crate::engine::lower::render_type(&field.ty)
                ),
            ));
        }
    }
    let mut errors = errors.into_iter();
    let error = errors.next().map(|mut first| {
        for e in errors {
            first.combine(e);
        }
        first.into_compile_error()
    });
    if error.is_some() && !item.generics.params.is_empty() {
        return quote!(#item #error);
    }

    let fields: Vec<&syn::Field> = fields.into_iter().filter(|f| is_f64(f)).collect();
    let ty = &item.ident;
    let idents: Vec<&syn::Ident> = fields.iter().filter_map(|f| f.ident.as_ref()).collect();
    let names: Vec<String> = idents.iter().map(ToString::to_string).collect();
    let docs: Vec<String> = fields.iter().map(|f| doc_comment(&f.attrs)).collect();
    quote! {
        #item
        #error

        impl ::hamel::Parameters for #ty {
            const NAMES: &'static [&'static str] = &[#(#names),*];
            const DOCS: &'static [&'static str] = &[#(#docs),*];

            fn get(&self, name: &str) -> ::core::option::Option<f64> {
                match name {
                    #(#names => ::core::option::Option::Some(self.#idents),)*
                    _ => ::core::option::Option::None,
                }
            }

            fn set(&mut self, name: &str, value: f64) -> ::core::result::Result<(), ::hamel::Error> {
                match name {
                    #(#names => {
                        self.#idents = value;
                        ::core::result::Result::Ok(())
                    })*
                    _ => ::core::result::Result::Err(::hamel::Error::UnknownParameter {
                        name: ::std::string::ToString::to_string(name),
                        known: <Self as ::hamel::Parameters>::NAMES.join(", "),
                    }),
                }
            }
        }
    }
}

/// The text of `///` comments, joined into one line.
fn doc_comment(attrs: &[syn::Attribute]) -> String {
    let lines: Vec<String> = attrs
        .iter()
        .filter(|a| a.path().is_ident("doc"))
        .filter_map(|a| match &a.meta {
            syn::Meta::NameValue(nv) => match &nv.value {
                syn::Expr::Lit(syn::ExprLit {
                    lit: syn::Lit::Str(s),
                    ..
                }) => Some(s.value().trim().to_string()),
                _ => None,
            },
            _ => None,
        })
        .collect();
    lines.join(" ").trim().to_string()
}
