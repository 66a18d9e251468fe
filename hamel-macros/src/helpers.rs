//! Shared helpers: functions written once, outside any model, that the roles of several
//! models call (`Wheels::contact(..)`).
//!
//! A proc macro sees only the item it is on, so a model's macro cannot read the source of a
//! function defined elsewhere. `#[hamel::helpers]` on `impl Wheels { .. }` therefore emits,
//! besides the impl itself, a `macro_rules!` that carries the impl's tokens, under the name
//! `Wheels` in the macro namespace (the type keeps the type namespace, so `use` brings both).
//! `#[hamel_system(helpers(Wheels))]` then expands to a call of that macro, which calls back
//! `hamel::__hamel_with_helpers!` with the model and the helpers' tokens appended; with
//! several helper sets, each calls the next. The last call expands the model with every
//! helper known by name, and differentiates through them like the model's own functions.
//! Beside the first call, the model stands in for itself should a set's macro be missing
//! (`system::helpers_stand_in`), so that rustc's "cannot find macro" is the only error.
//! (The technique of `macro_rules_attribute` and `ambassador`.)

use proc_macro2::{Delimiter, Group, TokenStream, TokenTree};
use quote::{format_ident, quote};
use syn::spanned::Spanned;

/// `#[hamel::helpers]` on an inherent impl of associated functions.
pub fn expand(attr: TokenStream, item: TokenStream) -> TokenStream {
    let imp = match syn::parse2::<syn::ItemImpl>(item.clone()) {
        Ok(imp) => imp,
        Err(_) => {
            let error = syn::Error::new_spanned(
                &item,
                "`#[hamel::helpers]` goes on an impl block of functions, `impl Helpers { .. }`, \
                 whose functions the roles of models call as `Helpers::name(..)`",
            )
            .into_compile_error();
            return quote!(#item #error);
        }
    };
    let errors = check(&attr, &imp);
    let Some(name) = set_name(&imp) else {
        let error = syn::Error::new_spanned(
            &imp.self_ty,
            "`#[hamel::helpers]` goes on the impl of a named type, `impl Helpers { .. }`",
        )
        .into_compile_error();
        return quote!(#imp #error);
    };
    if let Some(e) = errors {
        let error = e.into_compile_error();
        return quote!(#imp #error);
    }
    let carrier = format_ident!("__hamel_helpers_{}", name);
    quote! {
        #imp

        #[doc(hidden)]
        #[allow(non_snake_case, unused_macros)]
        macro_rules! #carrier {
            ($($model:tt)*) => {
                ::hamel::__hamel_with_helpers! { $($model)* { #imp } }
            };
        }

        #[doc(hidden)]
        #[allow(unused_imports)]
        pub(crate) use #carrier as #name;
    }
}

/// The type's name: the last segment of `impl path::Helpers`.
fn set_name(imp: &syn::ItemImpl) -> Option<syn::Ident> {
    match &*imp.self_ty {
        syn::Type::Path(p) if p.qself.is_none() => p.path.segments.last().map(|s| s.ident.clone()),
        _ => None,
    }
}

/// Every mistake in the helpers' shape, combined.
fn check(attr: &TokenStream, imp: &syn::ItemImpl) -> Option<syn::Error> {
    let mut errors: Vec<syn::Error> = Vec::new();
    if !attr.is_empty() {
        errors.push(syn::Error::new_spanned(
            attr,
            "`#[hamel::helpers]` takes no arguments",
        ));
    }
    if let Some((path, _)) = &imp.trait_ {
        errors.push(syn::Error::new_spanned(
            path,
            "`#[hamel::helpers]` goes on an inherent impl (`impl Helpers { .. }`), not a trait impl",
        ));
    }
    if !imp.generics.params.is_empty() {
        errors.push(syn::Error::new_spanned(
            &imp.generics,
            "helpers cannot be generic: the macro differentiates them over `f64`",
        ));
    }
    for item in &imp.items {
        if let syn::ImplItem::Fn(f) = item
            && let Some(receiver) = f.sig.receiver()
        {
            errors.push(syn::Error::new_spanned(
                receiver,
                format!(
                    "a shared helper takes no `self`: `{}` is called as `{}::{}(..)` from the \
                     roles of several models, so pass it what it needs (a model's parameters \
                     are `self.field` in the model's own roles)",
                    f.sig.ident,
                    set_name(imp).map(|n| n.to_string()).unwrap_or_default(),
                    f.sig.ident
                ),
            ));
        }
    }
    errors.into_iter().reduce(|mut a, b| {
        a.combine(b);
        a
    })
}

/// A model whose helpers are being gathered: the names still to fetch, the model's
/// attribute arguments and impl, and the helper impls fetched so far.
pub struct Gathering {
    pub remaining: Vec<syn::Path>,
    pub attr: TokenStream,
    pub item: TokenStream,
    pub helpers: Vec<TokenStream>,
}

/// The marker that starts the tokens passed along the chain.
const MARKER: &str = "__hamel_model";

/// The call that starts gathering the helpers `paths` for a model: the first helper set's
/// macro, with the model's tokens and the rest of the list.
pub fn start(paths: &[syn::Path], attr: &TokenStream, item: &TokenStream) -> TokenStream {
    let Some((first, rest)) = paths.split_first() else {
        return TokenStream::new();
    };
    pass_on(first, rest, attr, item, &[])
}

/// `first! { __hamel_model [rest] { attr } { item } { helper } … }`, spanned at the name the
/// user wrote, so that a name that holds no helpers is rustc's error there.
fn pass_on(
    first: &syn::Path,
    rest: &[syn::Path],
    attr: &TokenStream,
    item: &TokenStream,
    helpers: &[TokenStream],
) -> TokenStream {
    let marker = format_ident!("{}", MARKER);
    let helpers = helpers.iter().map(|h| quote!({ #h }));
    invoke(
        first,
        quote!(#marker [#(#rest),*] { #attr } { #item } #(#helpers)*),
    )
}

/// `set! { tokens }`, spanned at the name the user wrote. Every call of a set's macro is
/// spelled so, so that when the name holds no helpers, rustc's "cannot find macro" is the
/// same diagnostic at each call, which rustc reports once.
pub fn invoke(set: &syn::Path, tokens: TokenStream) -> TokenStream {
    let bang = quote::quote_spanned!(set.span()=> !);
    quote!(#set #bang { #tokens })
}

/// The marker of the call that a model's stand-in makes of each helper set's macro
/// (`helpers_stand_in`): the call gives `0` once the set's macro exists.
pub const STAND_IN_MARKER: &str = "__hamel_stand_in";

/// Whether `input`, passed back by a helper set's macro, is the stand-in's call.
pub fn is_stand_in_call(input: &TokenStream) -> bool {
    matches!(input.clone().into_iter().next(), Some(TokenTree::Ident(i)) if i == STAND_IN_MARKER)
}

/// Read the tokens a helper macro passed back.
pub fn parse(input: TokenStream) -> syn::Result<Gathering> {
    let mut tokens = input.into_iter().peekable();
    let marker_ok = matches!(tokens.next(), Some(TokenTree::Ident(i)) if i == MARKER);
    let group = |t: Option<TokenTree>, delimiter: Delimiter| match t {
        Some(TokenTree::Group(g)) if g.delimiter() == delimiter => Some(g),
        _ => None,
    };
    let remaining = group(tokens.next(), Delimiter::Bracket);
    let attr = group(tokens.next(), Delimiter::Brace);
    let item = group(tokens.next(), Delimiter::Brace);
    let (Some(remaining), Some(attr), Some(item), true) = (remaining, attr, item, marker_ok) else {
        return Err(syn::Error::new(
            proc_macro2::Span::call_site(),
            "hamel internal error: `__hamel_with_helpers!` is called by the macros that \
             `#[hamel::helpers]` defines, not by hand",
        ));
    };
    let helpers = tokens
        .filter_map(|t| group(Some(t), Delimiter::Brace).map(|g: Group| g.stream()))
        .collect();
    let remaining = syn::parse::Parser::parse2(
        syn::punctuated::Punctuated::<syn::Path, syn::Token![,]>::parse_terminated,
        remaining.stream(),
    )?
    .into_iter()
    .collect();
    Ok(Gathering {
        remaining,
        attr: attr.stream(),
        item: item.stream(),
        helpers,
    })
}

/// The next step of the chain: the next helper set's macro, or `None` when every set has
/// been fetched.
pub fn next(g: &Gathering) -> Option<TokenStream> {
    let (first, rest) = g.remaining.split_first()?;
    Some(pass_on(first, rest, &g.attr, &g.item, &g.helpers))
}

/// The tokens with every `self` resolving as at `at`. The expansion of a model with helpers
/// is called from a helper set's `macro_rules!`, where `self` is hygienic: the `&self` of the
/// methods the expansion makes up would not be the `self` the model's own tokens read. Only
/// `self` moves: the rest keeps the expansion's context, whose lints rustc and clippy leave
/// to the macro.
pub fn self_resolved_at(tokens: TokenStream, at: proc_macro2::Span) -> TokenStream {
    tokens
        .into_iter()
        .map(|token| match token {
            TokenTree::Group(g) => {
                let mut group = Group::new(g.delimiter(), self_resolved_at(g.stream(), at));
                group.set_span(g.span());
                TokenTree::Group(group)
            }
            TokenTree::Ident(mut i) if i == "self" => {
                i.set_span(i.span().resolved_at(at));
                TokenTree::Ident(i)
            }
            other => other,
        })
        .collect()
}
