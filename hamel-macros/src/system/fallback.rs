//! What `#[hamel_system]` emits when the model has mistakes: the errors, and enough of the
//! model for the user's other code to type-check, so that rustc adds no errors of its own
//! to ours (the idea of thiserror's `fallback.rs`).
//!
//! Code that uses a model calls `sleigh.state_from_speeds(..)`, passes it to
//! `Simulation::new`, reads `Sleigh::THETA`. Without an `impl HamelSystem` each of these
//! is an error of rustc's, with lists of the catalogue's models; a wrong array length in
//! the stand-in would be one too. So the stand-in has the dimensions the user wrote, as far
//! as they are known, and bodies that are `unreachable!()`: with our `compile_error!` the
//! crate never builds, so they never run.

use super::interface::{self, Bodies, Dims, Header};
use super::model::{Names, Role, Roles, array_length, written_length};
use crate::engine::hash::HashSet;
use proc_macro2::{Literal, TokenStream};
use quote::quote;
use syn::ext::IdentExt;

/// What the user wrote about the model's shape, read without checking it.
pub struct Sketch {
    /// `Model::THETA` and the like: each name upper-cased, with its index.
    pub index_consts: Vec<(String, usize)>,
    /// n, p, m when the written code tells them.
    dims: Option<(usize, usize, usize)>,
    coordinates: Vec<String>,
    speeds: Vec<String>,
    inputs: Vec<String>,
    /// The names in `constraints(..)`, if given.
    constraints: Option<Vec<String>>,
    constraint_fn: String,
    /// The holonomic function's name and written length.
    holonomic: Option<(String, usize)>,
    /// The block is a piece of a model ([`Roles::is_fragment`]): no stand-ins.
    fragment: bool,
    /// The bodies' names, for a model with `#[bodies]`: as given, or as many defaults as
    /// the function's result has bodies.
    bodies: Option<Vec<String>>,
    /// What control code the model asks for (`#[outputs]`, `control(..)`), as written.
    control: Option<super::control::emit::StandIn>,
}

impl Sketch {
    pub fn new(names: &Names, roles: &Roles<'_>) -> Sketch {
        let list = |l: &Option<(proc_macro2::Span, Vec<syn::Ident>)>| {
            l.as_ref().map(|(_, l)| l.clone()).unwrap_or_default()
        };
        let (coordinates, speeds) = (list(&names.coordinates), list(&names.speeds));
        let constraints = list(&names.constraints);
        let mut index_consts = Vec::new();
        for (list, groups) in [&coordinates, &speeds, &names.inputs, &constraints]
            .into_iter()
            .zip(&names.groups)
        {
            for (i, ident) in list.iter().enumerate() {
                index_consts.push((ident.unraw().to_string().to_uppercase(), i));
            }
            for group in groups {
                let base = group.base.unraw().to_string().to_uppercase();
                index_consts.push((base, group.start));
            }
        }
        let plain =
            |l: &[syn::Ident]| -> Vec<String> { l.iter().map(|i| i.unraw().to_string()).collect() };
        let dims = dimensions(&coordinates, speeds.len(), names.inputs.len(), roles);
        let speeds = match dims {
            Some((n, p, _)) if speeds.len() != n - p => {
                (p + 1..=n).map(|k| format!("w{k}")).collect()
            }
            _ => plain(&speeds),
        };
        let constraint_fn = roles.get(Role::Constraints).map_or_else(
            || "constraints".into(),
            |c| c.f.sig.ident.unraw().to_string(),
        );
        let holonomic = roles.get(Role::Holonomic).and_then(|h| {
            let k = written_length(&h.f.sig.output)?;
            Some((h.f.sig.ident.unraw().to_string(), k))
        });
        let bodies = roles.get(Role::Bodies).map(|b| {
            match (&names.bodies, written_length(&b.f.sig.output)) {
                (Some((_, given)), _) => plain(given),
                (None, Some(count)) => (0..count).map(|i| format!("body{i}")).collect(),
                (None, None) => Vec::new(),
            }
        });
        Sketch {
            control: control_sketch(names, roles),
            bodies,
            index_consts,
            dims,
            coordinates: plain(&coordinates),
            speeds,
            inputs: plain(&names.inputs),
            constraints: names.constraints.as_ref().map(|_| plain(&constraints)),
            constraint_fn,
            holonomic,
            fragment: roles.is_fragment(),
        }
    }
}

/// The control code asked for, as written: the outputs' names (or as many defaults as the
/// function's result has values), the order (2 by default with outputs) and the number of
/// brackets to the depth asked for.
fn control_sketch(names: &Names, roles: &Roles<'_>) -> Option<super::control::emit::StandIn> {
    let outputs_fn = roles.get(Role::Outputs);
    if outputs_fn.is_none() && names.control.is_none() && names.outputs.is_none() {
        return None;
    }
    let outputs: Vec<String> = match (&names.outputs, outputs_fn) {
        (Some((_, given)), _) => given.iter().map(|i| i.unraw().to_string()).collect(),
        (None, Some(f)) => (0..written_length(&f.f.sig.output).unwrap_or(0))
            .map(|i| format!("y{i}"))
            .collect(),
        (None, None) => Vec::new(),
    };
    let key = names.control.as_ref();
    let order = match key.and_then(|k| k.order) {
        Some((k, _)) if !outputs.is_empty() => k.min(super::spec::control::MOST_ORDER),
        None if !outputs.is_empty() => 2,
        _ => 0,
    };
    let depth = key
        .and_then(|k| k.brackets)
        .map_or(0, |(d, _)| d.min(super::spec::control::MOST_DEPTH));
    let generators = names.inputs.len() + 1;
    let brackets = super::spec::control::bracket_count(generators, depth)
        .min(super::spec::control::MOST_BRACKETS);
    Some(super::control::emit::StandIn {
        outputs,
        order,
        brackets,
    })
}

/// n from the coordinates' names or else from the length of `q` in a role's signature; p
/// from the written results of the roles that give constraint rows, or else from the
/// quasi-velocities' or the number of speed names; m from the inputs' names. `None` when n or p is not to be had: a stand-in
/// with made-up lengths would only trade rustc's errors for others.
fn dimensions(
    coordinates: &[syn::Ident],
    speed_names: usize,
    m: usize,
    roles: &Roles<'_>,
) -> Option<(usize, usize, usize)> {
    let n = if coordinates.is_empty() {
        // The first array argument is `q` in every role (after `t`, where there is one).
        roles.by_role.values().find_map(|rf| {
            typed_arguments(rf.f).find_map(|ty| array_length(ty).filter(|&n| n > 0))
        })?
    } else {
        coordinates.len()
    };
    let written = |role: Role| written_length(&roles.get(role)?.f.sig.output);
    let from_rows = super::spec::written_rows(roles).filter(|&p| p < n);
    let from_speeds = written(Role::QuasiVelocities).and_then(|k| n.checked_sub(k));
    // Rolling contacts may give fewer rows than two each (two wheels on one axle) and
    // fewer heights than `determines(..)` names: the speeds say better.
    let (first, second) = match roles.get(Role::Contacts) {
        Some(_) => (from_speeds, from_rows),
        None => (from_rows, from_speeds),
    };
    let p = first.or(second).or_else(|| {
        (speed_names > 0)
            .then(|| n.checked_sub(speed_names))
            .flatten()
    })?;
    Some((n, p, m))
}

fn typed_arguments(f: &syn::ImplItemFn) -> impl Iterator<Item = &syn::Type> {
    f.sig.inputs.iter().filter_map(|a| match a {
        syn::FnArg::Typed(pt) => Some(&*pt.ty),
        syn::FnArg::Receiver(_) => None,
    })
}

/// The errors, and the user's impl block as written (without our role attributes, which
/// rustc would not know) with the index constants, `rhs_generic` and `impl HamelSystem` as
/// stand-ins. The bodies of the functions the errors are about are left out too (an
/// `unreachable!()`), so that rustc does not report the same mistake again in its own words
/// (`self.m = ..` in a `&self` method, an `f32` argument in `f64` arithmetic), and so are
/// those of the functions that use `rate!` and its kin: only the macro knows what they mean,
/// and their run-time stand-ins are compile errors of their own.
pub fn fallback(
    imp: &syn::ItemImpl,
    faulty: &HashSet<String>,
    sketch: &Sketch,
    error: syn::Error,
) -> TokenStream {
    let left_out = |f: &syn::ImplItemFn| {
        faulty.contains(&f.sig.ident.to_string()) || crate::engine::lower::uses_rate(f)
    };
    let model = stand_in(imp, Some(imp), &left_out, sketch);
    let error = error.into_compile_error();
    quote!(#model #error)
}

/// The stand-in of a model: the items of `inherent` (its functions' bodies an `unreachable!()`
/// where `left_out` says so) with the index constants and `rhs_generic` missing from them,
/// under `inherent`'s header; and, for a whole model whose dimensions are written, the trait
/// impls with `traits`' header (`impl HamelSystem for ..`), when given.
pub fn stand_in(
    inherent: &syn::ItemImpl,
    traits: Option<&syn::ItemImpl>,
    left_out: &dyn Fn(&syn::ImplItemFn) -> bool,
    sketch: &Sketch,
) -> TokenStream {
    let mut stripped = super::model::strip_role_attributes(inherent);
    let mut taken: HashSet<String> = HashSet::default();
    for item in &mut stripped.items {
        match item {
            syn::ImplItem::Fn(f) => {
                taken.insert(f.sig.ident.to_string());
                if left_out(f) {
                    f.block = syn::parse_quote!({
                        ::core::unreachable!(
                            "hamel: this function has errors, reported at build time"
                        )
                    });
                    f.attrs.push(syn::parse_quote!(#[allow(unused_variables)]));
                }
            }
            syn::ImplItem::Const(c) => {
                taken.insert(c.ident.to_string());
            }
            _ => {}
        }
    }
    if sketch.fragment {
        return quote!(#stripped);
    }
    let inherent = inherent_items(inherent, sketch, &mut taken);
    let Some(imp) = traits else {
        return quote!(#stripped #inherent);
    };
    let system = sketch.dims.map(|dims| trait_impl(imp, sketch, dims));
    let mechanism = sketch
        .dims
        .zip(sketch.bodies.as_ref())
        .map(|((n, _, _), names)| super::mechanism::mechanism_impl(imp, n, names, None));
    let control = sketch
        .dims
        .zip(sketch.control.as_ref())
        .map(|((n, p, m), request)| super::control::emit::stand_in(imp, 2 * n - p, m, request));
    quote!(#stripped #inherent #system #control #mechanism)
}

fn lit(i: usize) -> Literal {
    Literal::usize_unsuffixed(i)
}

/// The index constants, and `rhs_generic` when the dimensions are known; each only when the
/// user's impl has no item of that name.
fn inherent_items(
    imp: &syn::ItemImpl,
    sketch: &Sketch,
    taken: &mut HashSet<String>,
) -> TokenStream {
    let consts: Vec<TokenStream> = sketch
        .index_consts
        .iter()
        .filter_map(|(name, i)| {
            let ident = syn::parse_str::<syn::Ident>(name).ok()?;
            if !taken.insert(name.clone()) {
                return None;
            }
            let i = lit(*i);
            Some(quote!(pub const #ident: usize = #i;))
        })
        .collect();
    let rhs_generic = match sketch.dims {
        Some((n, p, m)) if taken.insert("rhs_generic".into()) => {
            let k = sketch.holonomic.as_ref().map_or(0, |(_, k)| *k).min(p);
            let signature = interface::rhs_generic_signature(Dims { n, p, m, k });
            quote! {
                #[allow(unused_variables)]
                #signature {
                    ::core::unreachable!("hamel: the model has errors, reported at build time")
                }
            }
        }
        _ => TokenStream::new(),
    };
    if consts.is_empty() && rhs_generic.is_empty() {
        return TokenStream::new();
    }
    let ty = &imp.self_ty;
    let (impl_generics, _, where_clause) = imp.generics.split_for_impl();
    // Hidden: in the stand-in of a model with helpers (`helpers_stand_in`) the block is also
    // emitted when the model builds, and documents nothing.
    quote! {
        #[doc(hidden)]
        #[allow(dead_code, clippy::all)]
        impl #impl_generics #ty #where_clause {
            #(#consts)*
            #rhs_generic
        }
    }
}

/// `impl HamelSystem` with the written dimensions and names, and unreachable methods.
fn trait_impl(imp: &syn::ItemImpl, sketch: &Sketch, dims: (usize, usize, usize)) -> TokenStream {
    let (n, p, m) = dims;
    let k = sketch.holonomic.as_ref().map_or(0, |(_, k)| *k).min(p);
    // The names as the model would have them: those of `constraints(..)`, when there are as
    // many as rows, or else the functions' (`blade0`).
    let constraints = match &sketch.constraints {
        Some(names) if names.len() == p => names.clone(),
        _ => {
            let mut rows: Vec<String> = (0..p - k)
                .map(|i| format!("{}{i}", sketch.constraint_fn))
                .collect();
            if let Some((name, _)) = &sketch.holonomic {
                rows.extend((0..k).map(|i| format!("{name}{i}")));
            }
            rows
        }
    };
    let header = Header {
        imp,
        dims: Dims { n, p, m, k },
        coordinates: sketch.coordinates.clone(),
        speeds: sketch.speeds.clone(),
        inputs: sketch.inputs.clone(),
        constraints,
        dependent: Vec::new(),
        conservative: false,
        power_vanishes_without_inputs: false,
        reversible: false,
        constant_determinant: false,
        units: Vec::new(),
        check_bodies: None,
        singular: None,
    };
    interface::trait_impl(&header, &Bodies::unreachable())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sketch(attr: TokenStream, imp: syn::ItemImpl) -> Option<(usize, usize, usize)> {
        let mut errors = Vec::new();
        let names = super::super::model::parse_names(attr, &mut errors);
        let roles = Roles::find(&imp.items, &mut errors);
        Sketch::new(&names, &roles).dims
    }

    #[test]
    fn dimensions_come_from_what_is_written() {
        let imp: syn::ItemImpl = syn::parse_quote! {
            impl Sleigh {
                #[forces]
                fn f(&self, t: f64, q: &[f64; 4], qd: &[f64; 4], u: &[f64; 1]) -> [f64; 4] { todo() }
                #[constraints]
                fn c(&self, q: &[f64; 4], qd: &[f64; 4]) -> [f64; 2] { todo() }
            }
        };
        // Without coordinate names, n is the length of `q` (the second argument of forces).
        assert_eq!(sketch(quote!(inputs(push)), imp.clone()), Some((4, 2, 1)));
        assert_eq!(
            sketch(quote!(coordinates(x, y, theta)), imp),
            // p = 2 < 3 from the constraints' result.
            Some((3, 2, 0))
        );
        let imp: syn::ItemImpl = syn::parse_quote! {
            impl Sleigh {
                #[quasi_velocities]
                fn s(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] { todo() }
            }
        };
        // Without constraints, p from the quasi-velocities: 3 − 2.
        assert_eq!(
            sketch(quote!(coordinates(x, y, theta)), imp),
            Some((3, 1, 0))
        );
        let imp: syn::ItemImpl = syn::parse_quote!(impl Sleigh {});
        // Nothing tells p: no stand-in.
        assert_eq!(sketch(quote!(coordinates(x, y, theta)), imp.clone()), None);
        assert_eq!(
            sketch(quote!(coordinates(x, y, theta), speeds(v, omega)), imp),
            Some((3, 1, 0))
        );
    }
}
