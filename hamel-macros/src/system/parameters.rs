//! `#[hamel_system]` on the parameter struct: every field must be an `f64` or an array of
//! them (`m: [f64; 3]`, per-body data, read as `self.m[i]`); the struct gets an
//! implementation of `hamel::Parameters` (names, doc comments, get and set by name). An
//! array's entries are named like an indexed group of coordinates: `m0`, `m1`, `m2`.

use proc_macro2::TokenStream;
use quote::quote;
use syn::{Fields, ItemStruct};

/// The struct with its `Parameters` implementation; on mistakes, also their errors. Whatever
/// the mistakes, the struct gets an implementation, so that the model's impl block and the
/// program add no error of their own about a missing `Parameters`: for a generic struct one
/// whose methods are never reached, and a field of type `f32` is emitted as `f64`, so that the
/// model's functions read it without an error at each use.
pub fn expand(attr: TokenStream, item: &ItemStruct) -> TokenStream {
    let errors = errors(&attr, item);
    let error = combined(errors);
    if !item.generics.params.is_empty() {
        let stand_in = stand_in(&item.ident, &item.generics);
        return quote!(#item #error #stand_in);
    }
    let mut emitted = item.clone();
    for field in emitted.fields.iter_mut() {
        if let Some(ty) = as_f64(&field.ty) {
            field.ty = ty;
        }
    }
    let fields: Vec<&syn::Field> = match &emitted.fields {
        Fields::Named(named) => named
            .named
            .iter()
            .filter(|f| kind(&f.ty).is_some())
            .collect(),
        _ => Vec::new(),
    };
    let ty = &item.ident;
    let entries = entries(&fields);
    let error = match duplicates(&entries, &fields) {
        Some(e) => {
            let e = e.into_compile_error();
            Some(quote!(#error #e))
        }
        None => error,
    };
    let names: Vec<&String> = entries.iter().map(|(n, _, _)| n).collect();
    let reads: Vec<&TokenStream> = entries.iter().map(|(_, r, _)| r).collect();
    let docs: Vec<&String> = entries.iter().map(|(_, _, d)| d).collect();
    let doc = doc_lines(&item.attrs);
    quote! {
        #emitted
        #error

        // Not listed under "`Parameters` is not implemented for `Other`" (see `interface`).
        #[diagnostic::do_not_recommend]
        impl ::hamel::Parameters for #ty {
            const NAMES: &'static [&'static str] = &[#(#names),*];
            const DOCS: &'static [&'static str] = &[#(#docs),*];
            const DOC: &'static str = #doc;

            fn get(&self, name: &str) -> ::core::option::Option<f64> {
                match name {
                    #(#names => ::core::option::Option::Some(#reads),)*
                    _ => ::core::option::Option::None,
                }
            }

            // A struct without parameters has only the unknown-name arm, after which the rest
            // is unreachable.
            #[allow(unreachable_code)]
            fn set(&mut self, name: &str, value: f64) -> ::core::result::Result<(), ::hamel::Error> {
                let field: &mut f64 = match name {
                    #(#names => &mut #reads,)*
                    _ => return ::core::result::Result::Err(::hamel::Error::UnknownParameter {
                        name: ::std::string::ToString::to_string(name),
                        known: <Self as ::hamel::Parameters>::NAMES.join(", "),
                    }),
                };
                // Refused here, where the caller still knows where the value came from,
                // rather than by `validate` when a state is built; the field keeps its value.
                if !value.is_finite() {
                    return ::core::result::Result::Err(::hamel::Error::InvalidParameter {
                        name: ::std::string::ToString::to_string(name),
                        value,
                    });
                }
                *field = value;
                ::core::result::Result::Ok(())
            }
        }
    }
}

/// `#[hamel_system]` on an item that cannot be a parameter struct (an enum, a union): the
/// error, the item, and an implementation of `Parameters` never reached, for the same reason
/// as a generic struct's.
pub fn not_a_struct(item: &syn::Item, error: syn::Error) -> TokenStream {
    let error = error.into_compile_error();
    let stand_in = match item {
        syn::Item::Enum(e) => stand_in(&e.ident, &e.generics),
        syn::Item::Union(u) => stand_in(&u.ident, &u.generics),
        _ => TokenStream::new(),
    };
    quote!(#item #error #stand_in)
}

/// `impl Parameters` for a parameter struct with mistakes that leave its fields unknown: its
/// methods are never reached, since the errors keep the crate from building.
pub fn stand_in(ident: &syn::Ident, generics: &syn::Generics) -> TokenStream {
    let (impl_generics, ty_generics, where_clause) = generics.split_for_impl();
    let never = quote!(::core::unreachable!(
        "hamel: the parameter struct has errors, reported at build time"
    ));
    quote! {
        #[diagnostic::do_not_recommend]
        #[allow(unused_variables)]
        impl #impl_generics ::hamel::Parameters for #ident #ty_generics #where_clause {
            const NAMES: &'static [&'static str] = &[];
            const DOCS: &'static [&'static str] = &[];
            fn get(&self, name: &str) -> ::core::option::Option<f64> { #never }
            fn set(&mut self, name: &str, value: f64) -> ::core::result::Result<(), ::hamel::Error> { #never }
        }
    }
}

fn combined(errors: Vec<syn::Error>) -> Option<TokenStream> {
    let mut errors = errors.into_iter();
    errors.next().map(|mut first| {
        for e in errors {
            first.combine(e);
        }
        first.into_compile_error()
    })
}

/// Every mistake in the attribute, the struct or a field's type. A field whose type is one of
/// the struct's generic parameters (`m: T`) is the generic struct's mistake, reported once.
fn errors(attr: &TokenStream, item: &ItemStruct) -> Vec<syn::Error> {
    let mut errors = Vec::new();
    if !attr.is_empty() {
        errors.push(syn::Error::new_spanned(
            attr,
            "on the parameter struct `#[hamel_system]` takes no arguments: the names of coordinates, \
             speeds and inputs go on the impl block, `#[hamel_system(coordinates(..), inputs(..))]`",
        ));
    }
    if !item.generics.params.is_empty() {
        errors.push(syn::Error::new_spanned(
            &item.generics,
            "a parameter struct cannot be generic: its fields are the model's parameters, each an \
             `f64` (`m: f64`) or an array of them with a literal length (`m: [f64; 3]`)",
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
    let generic = generic_names(&item.generics);
    for field in fields.iter().filter(|f| kind(&f.ty).is_none()) {
        if mentions(&field.ty, &generic) {
            continue;
        }
        let name = field
            .ident
            .as_ref()
            .map(ToString::to_string)
            .unwrap_or_default();
        errors.push(syn::Error::new_spanned(
            &field.ty,
            format!(
                "parameter `{name}` has type `{}`, but parameters are `f64` or arrays of them \
                 (`[f64; 3]`, with a literal length): hamel computes in `f64` (keep other data \
                 outside the parameter struct)",
                crate::engine::lower::render_type(&field.ty)
            ),
        ));
    }
    errors
}

/// The names of a struct's generic parameters: types, lifetimes and constants.
fn generic_names(generics: &syn::Generics) -> Vec<String> {
    generics
        .params
        .iter()
        .map(|p| match p {
            syn::GenericParam::Type(t) => t.ident.to_string(),
            syn::GenericParam::Lifetime(l) => l.lifetime.to_string(),
            syn::GenericParam::Const(c) => c.ident.to_string(),
        })
        .collect()
}

/// Whether a type names one of these generic parameters anywhere (`T`, `[f64; N]`, `&'a f64`).
fn mentions(ty: &syn::Type, generic: &[String]) -> bool {
    fn walk(tokens: TokenStream, generic: &[String]) -> bool {
        let mut after_quote = false;
        for tree in tokens {
            match tree {
                proc_macro2::TokenTree::Group(g) => {
                    if walk(g.stream(), generic) {
                        return true;
                    }
                    after_quote = false;
                }
                proc_macro2::TokenTree::Punct(p) => after_quote = p.as_char() == '\'',
                proc_macro2::TokenTree::Ident(i) => {
                    let name = if after_quote {
                        format!("'{i}")
                    } else {
                        i.to_string()
                    };
                    if generic.contains(&name) {
                        return true;
                    }
                    after_quote = false;
                }
                proc_macro2::TokenTree::Literal(_) => after_quote = false,
            }
        }
        false
    }
    walk(quote::ToTokens::to_token_stream(ty), generic)
}

/// `f64` in place of `f32` (and `[f64; 3]` of `[f32; 3]`): the parameter is a number in
/// another precision, reported, and read by the model's functions, which compute in `f64`.
fn as_f64(ty: &syn::Type) -> Option<syn::Type> {
    match ty {
        syn::Type::Path(p) if p.qself.is_none() && p.path.is_ident("f32") => {
            let span = syn::spanned::Spanned::span(ty);
            Some(syn::Type::Verbatim(quote::quote_spanned!(span=> f64)))
        }
        syn::Type::Group(g) => as_f64(&g.elem),
        syn::Type::Array(a) => {
            let elem = as_f64(&a.elem)?;
            let mut a = a.clone();
            *a.elem = elem;
            Some(syn::Type::Array(a))
        }
        _ => None,
    }
}

/// `Some(None)` for `f64`, `Some(Some(len))` for `[f64; len]` with a literal length.
fn kind(ty: &syn::Type) -> Option<Option<usize>> {
    match ty {
        syn::Type::Path(p) if p.qself.is_none() && p.path.is_ident("f64") => Some(None),
        // A type or length substituted by `macro_rules!` (`[f64; $len]` with `$len:literal`)
        // arrives wrapped in an invisible group: look through it.
        syn::Type::Group(g) => kind(&g.elem),
        syn::Type::Array(a) if kind(&a.elem) == Some(None) => match ungrouped(&a.len) {
            syn::Expr::Lit(syn::ExprLit {
                lit: syn::Lit::Int(i),
                ..
            }) => i.base10_parse().ok().map(Some),
            _ => None,
        },
        _ => None,
    }
}

/// An expression without the invisible groups `macro_rules!` wraps its fragments in.
fn ungrouped(e: &syn::Expr) -> &syn::Expr {
    match e {
        syn::Expr::Group(g) => ungrouped(&g.expr),
        other => other,
    }
}

/// One entry per scalar parameter: its name, how it is read, its doc comment (an array's
/// entries each get the array's comment with their index).
fn entries(fields: &[&syn::Field]) -> Vec<(String, TokenStream, String)> {
    let mut entries = Vec::new();
    for field in fields {
        let Some(ident) = &field.ident else { continue };
        let doc = doc_comment(&field.attrs);
        match kind(&field.ty) {
            Some(None) => entries.push((ident.to_string(), quote!(self.#ident), doc)),
            Some(Some(len)) => {
                for i in 0..len {
                    let index = proc_macro2::Literal::usize_unsuffixed(i);
                    let doc = match doc.as_str() {
                        "" => String::new(),
                        d => format!("{d} [{i}]"),
                    };
                    entries.push((format!("{ident}{i}"), quote!(self.#ident[#index]), doc));
                }
            }
            None => {}
        }
    }
    entries
}

/// Two parameters with the same name: a field `m1` beside an array `m` whose entry 1 is
/// named `m1` too.
fn duplicates(
    entries: &[(String, TokenStream, String)],
    fields: &[&syn::Field],
) -> Option<syn::Error> {
    let mut seen = crate::engine::hash::HashSet::default();
    let (name, _, _) = entries.iter().find(|(n, _, _)| !seen.insert(n.clone()))?;
    let at = fields
        .iter()
        .filter_map(|f| f.ident.as_ref())
        .find(|i| name.starts_with(&i.to_string()) && **i != name.as_str())
        .or_else(|| {
            fields
                .iter()
                .filter_map(|f| f.ident.as_ref())
                .find(|i| **i == name.as_str())
        })?;
    Some(syn::Error::new_spanned(
        at,
        format!(
            "two parameters are named `{name}`: an array's entries are named by its name and their \
             index (`m: [f64; 3]` gives `m0`, `m1`, `m2`); rename one of them"
        ),
    ))
}

/// The text of `///` comments, joined into one line.
fn doc_comment(attrs: &[syn::Attribute]) -> String {
    let lines: Vec<String> = doc_attributes(attrs)
        .map(|line| line.trim().to_string())
        .collect();
    lines.join(" ").trim().to_string()
}

/// The text of `///` comments line by line, without the space after `///` (the struct's doc
/// comment, whose paragraphs and lists are kept).
fn doc_lines(attrs: &[syn::Attribute]) -> String {
    let lines: Vec<String> = doc_attributes(attrs)
        .map(|line| {
            let line = line.strip_prefix(' ').unwrap_or(&line);
            line.trim_end().to_string()
        })
        .collect();
    lines.join("\n").trim().to_string()
}

/// The strings of the `#[doc = "..."]` attributes (what `///` comments are).
fn doc_attributes(attrs: &[syn::Attribute]) -> impl Iterator<Item = String> + '_ {
    attrs
        .iter()
        .filter(|a| a.path().is_ident("doc"))
        .filter_map(|a| match &a.meta {
            syn::Meta::NameValue(nv) => match &nv.value {
                syn::Expr::Lit(syn::ExprLit {
                    lit: syn::Lit::Str(s),
                    ..
                }) => Some(s.value()),
                _ => None,
            },
            _ => None,
        })
}

#[cfg(test)]
mod tests {
    use super::expand;
    use proc_macro2::{Delimiter, Group};
    use quote::quote;

    #[test]
    fn array_lengths_substituted_by_macro_rules_are_read() {
        // `[f64; $len]` with `$len:literal` in a `macro_rules!`: the length reaches the
        // attribute wrapped in an invisible group.
        let len = Group::new(Delimiter::None, quote!(3));
        let item: syn::ItemStruct = syn::parse2(quote!(struct P { m: [f64; #len] })).unwrap();
        let out = expand(quote!(), &item).to_string();
        assert!(!out.contains("compile_error"), "{out}");
        assert!(out.contains("\"m0\"") && out.contains("\"m2\""), "{out}");
    }

    #[test]
    fn the_structs_doc_comment_is_the_models_doc_with_its_lines() {
        let item: syn::ItemStruct = syn::parse2(quote!(
            /// A sleigh.
            ///
            ///   Its blade: no sideways slip.
            struct P {
                /// mass (kg)
                m: f64,
            }
        ))
        .unwrap();
        let out = expand(quote!(), &item).to_string();
        assert!(
            out.contains(
                r#"const DOC : & 'static str = "A sleigh.\n\n  Its blade: no sideways slip." ;"#
            ),
            "{out}"
        );
        let bare: syn::ItemStruct = syn::parse2(quote!(
            struct P {
                m: f64,
            }
        ))
        .unwrap();
        let out = expand(quote!(), &bare).to_string();
        assert!(out.contains(r#"const DOC : & 'static str = "" ;"#), "{out}");
    }
}
