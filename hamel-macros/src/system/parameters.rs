//! `#[hamel_system]` on the parameter struct: every field must be an `f64`; the struct gets
//! an implementation of `hamel::Parameters` (names, doc comments, get and set by name).

use proc_macro2::TokenStream;
use quote::{ToTokens, quote};
use syn::{Fields, ItemStruct};

pub fn expand(attr: TokenStream, item: &ItemStruct) -> syn::Result<TokenStream> {
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
    for field in &fields {
        let is_f64 =
            matches!(&field.ty, syn::Type::Path(p) if p.qself.is_none() && p.path.is_ident("f64"));
        if !is_f64 {
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
                    field.ty.to_token_stream()
                ),
            ));
        }
    }
    if let Some(mut first) = errors.pop() {
        for e in errors {
            first.combine(e);
        }
        return Err(first);
    }

    let ty = &item.ident;
    let idents: Vec<&syn::Ident> = fields.iter().filter_map(|f| f.ident.as_ref()).collect();
    let names: Vec<String> = idents.iter().map(ToString::to_string).collect();
    let docs: Vec<String> = fields.iter().map(|f| doc_comment(&f.attrs)).collect();
    Ok(quote! {
        #item

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
    })
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
