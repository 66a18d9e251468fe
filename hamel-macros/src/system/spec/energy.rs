//! The roles every model needs, and the energy: exactly one way of giving it.

use super::Energy;
use crate::engine::lower::Lowerer;
use crate::system::model::{Role, RoleFn, Roles};
use proc_macro2::TokenStream;
use quote::ToTokens;

/// Where the roles go, for messages about a missing one (it may be in another impl block).
pub(super) const ONE_BLOCK: &str = "All the roles of a model must be in the impl block that carries \
                         `#[hamel_system]`";

pub(super) fn required<'r, 'a>(
    roles: &'r Roles<'a>,
    role: Role,
    lowerer: &mut Lowerer<'_, '_>,
    at: &TokenStream,
    ok: &mut bool,
    what: &str,
    aside: &str,
) -> Option<&'r RoleFn<'a>> {
    let found = roles.get(role);
    if found.is_none() {
        let attribute = role.attribute();
        let signature = role.expected_signature();
        lowerer.push_error(match forgotten(roles, role) {
            Some(f) => syn::Error::new_spanned(
                &f.sig.ident,
                format!(
                    "missing role `#[{attribute}]`: no function is marked with it; if `{}` gives \
                     {what}, put `#[{attribute}]` above it (expected signature `{signature}`)",
                    f.sig.ident,
                ),
            ),
            None => syn::Error::new_spanned(
                at,
                format!(
                    "missing role `#[{attribute}]`: mark the function that gives {what}{aside}; \
                     expected signature `{signature}`. {ONE_BLOCK}"
                ),
            ),
        });
        *ok = false;
    }
    found
}

/// The one unmarked function that looks as if it should have played `role` (its name is the
/// role's, or its signature has the role's form), if there is exactly one.
pub(super) fn forgotten<'a>(roles: &Roles<'a>, role: Role) -> Option<&'a syn::ImplItemFn> {
    let typed = |f: &syn::ImplItemFn| {
        f.sig
            .inputs
            .iter()
            .filter(|a| matches!(a, syn::FnArg::Typed(_)))
            .count()
    };
    let returns_array = |f: &syn::ImplItemFn| matches!(&f.sig.output, syn::ReturnType::Type(_, ty) if matches!(**ty, syn::Type::Array(_)));
    let returns_f64 = |f: &syn::ImplItemFn| matches!(&f.sig.output, syn::ReturnType::Type(_, ty) if ty.to_token_stream().to_string() == "f64");
    if let Some(f) = roles
        .unmarked
        .iter()
        .find(|f| f.sig.ident == role.attribute())
    {
        return Some(f);
    }
    let fits = |f: &&&syn::ImplItemFn| match role {
        Role::Constraints | Role::QuasiVelocities => typed(f) == 2 && returns_array(f),
        Role::Lagrangian | Role::KineticEnergy => typed(f) == 2 && returns_f64(f),
        _ => false,
    };
    let mut candidates = roles.unmarked.iter().filter(fits);
    match (candidates.next(), candidates.next()) {
        (Some(f), None) => Some(f),
        _ => None,
    }
}

/// Exactly one way of giving the energy: a Lagrangian, or a kinetic energy with an optional
/// potential one, or L̃. The rigid bodies of `#[bodies]` (and `#[gravity]`) add their
/// energies to the first two, and are an energy of their own when the model has no other.
pub(super) fn energy_roles<'a>(
    roles: &Roles<'a>,
    lowerer: &mut Lowerer<'_, '_>,
    at: &TokenStream,
    ok: &mut bool,
) -> Option<Energy<'a>> {
    let (l, t, v, lq) = (
        roles.get(Role::Lagrangian),
        roles.get(Role::KineticEnergy),
        roles.get(Role::PotentialEnergy),
        roles.get(Role::QuasiLagrangian),
    );
    let bodies = roles.get(Role::Bodies);
    if let Some(e) = energy_conflict(roles) {
        lowerer.push_error(e);
        *ok = false;
    } else if l.is_none() && t.is_none() && lq.is_none() && bodies.is_none() {
        lowerer.push_error(missing_energy(roles, v, at));
        *ok = false;
    }
    if let (Some(g), None) = (roles.get(Role::Gravity), bodies) {
        lowerer.push_error(syn::Error::new_spanned(
            g.attr,
            "`#[gravity]` acts on the rigid bodies of a `#[bodies]` role, and this model has \
             none: state the bodies with `#[bodies]`, or write gravity's potential in a \
             `#[potential_energy]`",
        ));
        *ok = false;
    }
    if !*ok {
        return None;
    }
    match (l, lq) {
        (Some(l), None) => Some(Energy::Lagrangian(l.f)),
        (None, Some(lq)) => Some(Energy::Quasi(lq.f)),
        _ => Some(Energy::Split {
            kinetic: t.map(|t| t.f),
            potential: v.map(|v| v.f),
        }),
    }
}

/// Two ways of giving the energy at once: the error, at the second.
fn energy_conflict(roles: &Roles<'_>) -> Option<syn::Error> {
    let (l, t, v, lq) = (
        roles.get(Role::Lagrangian),
        roles.get(Role::KineticEnergy),
        roles.get(Role::PotentialEnergy),
        roles.get(Role::QuasiLagrangian),
    );
    let conflict = |second: &RoleFn<'_>, first: Role, message: &str| {
        let holder = roles
            .get(first)
            .map(|rf| format!(" (`{}`)", rf.f.sig.ident))
            .unwrap_or_default();
        Some(syn::Error::new_spanned(
            second.attr,
            format!(
                "ambiguous energy: this model already has a `#[{}]`{holder}; {message}",
                first.attribute()
            ),
        ))
    };
    match (l, t, v, lq, roles.get(Role::Bodies)) {
        (Some(_), Some(t), _, _, _) => conflict(t, Role::Lagrangian, GIVE),
        (Some(_), None, Some(v), _, _) => conflict(
            v,
            Role::Lagrangian,
            "a Lagrangian already contains the potential energy (L = T − V)",
        ),
        (_, _, _, Some(lq), _) if l.is_some() || t.is_some() => conflict(
            lq,
            if l.is_some() {
                Role::Lagrangian
            } else {
                Role::KineticEnergy
            },
            GIVE,
        ),
        (None, None, Some(v), Some(_), _) => conflict(
            v,
            Role::QuasiLagrangian,
            "L̃ already contains the potential energy",
        ),
        (_, _, _, Some(_), Some(b)) => conflict(
            b,
            Role::QuasiLagrangian,
            "L̃(q, w) is the whole Lagrangian, which the bodies' energies cannot be added to: \
             state the bodies with `#[bodies]` and the rest of the energy in \
             `#[kinetic_energy]` and `#[potential_energy]`, or give L̃ alone",
        ),
        _ => None,
    }
}

const GIVE: &str = "give either a `#[lagrangian]` L = T − V, or a `#[kinetic_energy]` T (with an \
                    optional `#[potential_energy]` V), or a `#[quasi_lagrangian]` L̃(q, w) — \
                    exactly one of these";

/// No energy at all (`v`: a potential energy without the kinetic one).
fn missing_energy(roles: &Roles<'_>, v: Option<&RoleFn<'_>>, at: &TokenStream) -> syn::Error {
    if let Some(v) = v {
        return syn::Error::new_spanned(
            v.attr,
            "a potential energy alone does not make a model: add the `#[kinetic_energy]` T(q, qd)",
        );
    }
    match forgotten(roles, Role::KineticEnergy).or_else(|| forgotten(roles, Role::Lagrangian)) {
        Some(f) => syn::Error::new_spanned(
            &f.sig.ident,
            format!(
                "missing role: no function is marked as the model's energy; if `{}` is the \
                 kinetic energy T, put `#[kinetic_energy]` above it (`#[lagrangian]` if it is L \
                 = T − V)",
                f.sig.ident
            ),
        ),
        None => syn::Error::new_spanned(
            at,
            format!("missing role: the model needs its energy; {GIVE}. {ONE_BLOCK}"),
        ),
    }
}

/// The roles that give the rows of A: the constraints (required, unless rolling contacts
/// give them) and the quasi-velocities (required).
#[allow(clippy::type_complexity)]
pub(super) fn rows_roles<'r, 'a>(
    roles: &'r Roles<'a>,
    lowerer: &mut Lowerer<'_, '_>,
    at: &TokenStream,
    ok: &mut bool,
) -> (Option<&'r RoleFn<'a>>, Option<&'r RoleFn<'a>>) {
    let constraints = match roles.get(Role::Contacts) {
        Some(_) => roles.get(Role::Constraints),
        None => required(
            roles,
            Role::Constraints,
            lowerer,
            at,
            ok,
            "the constraint rows ω¹…ωᵖ(q, qd), linear in qd and zero on every motion",
            " (without nonholonomic constraints a system is holonomic, and hamel is not the tool for it)",
        ),
    };
    let quasi_velocities = required(
        roles,
        Role::QuasiVelocities,
        lowerer,
        at,
        ok,
        "the quasi-velocities ω^{p+1}…ωⁿ(q, qd) that complete the constraints to an invertible \
         transformation ω = A(q)·qd",
        "",
    );
    (constraints, quasi_velocities)
}
