//! The checked model: dimensions, names and role functions, after every check that can be
//! made from the signatures alone. All mistakes are reported together, each at its span.

use super::model::{Names, Role, RoleFn, Roles};
use crate::engine::lower::{Lowerer, Shape};
use proc_macro2::Span;
use quote::{ToTokens, format_ident};
use std::collections::HashMap;
use syn::ext::IdentExt;

#[derive(Clone, Copy)]
pub struct Dims {
    /// Coordinates.
    pub n: usize,
    /// Constraints.
    pub p: usize,
    /// Inputs.
    pub m: usize,
}

impl Dims {
    /// Free quasi-velocities ("speeds").
    pub fn free(&self) -> usize {
        self.n - self.p
    }
}

/// Where the model's energy comes from.
pub enum Energy<'a> {
    /// L(q, q̇)
    Lagrangian(&'a syn::ImplItemFn),
    /// T(q, q̇) and optionally V(q)
    Split {
        kinetic: &'a syn::ImplItemFn,
        potential: Option<&'a syn::ImplItemFn>,
    },
    /// L̃(q, ω)
    Quasi(&'a syn::ImplItemFn),
}

pub struct Spec<'a> {
    pub dims: Dims,
    pub coordinates: Vec<syn::Ident>,
    pub speeds: Vec<syn::Ident>,
    pub inputs: Vec<syn::Ident>,
    pub energy: Energy<'a>,
    pub constraints: &'a syn::ImplItemFn,
    pub quasi_velocities: &'a syn::ImplItemFn,
    pub velocities: Option<&'a syn::ImplItemFn>,
    pub forces: Option<&'a syn::ImplItemFn>,
}

/// Check names, roles and signatures. Errors go to the lowerer's error list; `None` when the
/// model cannot be built at all.
pub fn check<'a>(
    names: Names,
    roles: &Roles<'a>,
    lowerer: &mut Lowerer<'_, '_>,
    at: Span,
) -> Option<Spec<'a>> {
    let mut ok = true;

    let coordinates = match names.coordinates {
        Some((span, list)) if list.is_empty() => {
            fail(
                lowerer,
                &mut ok,
                syn::Error::new(span, "a model needs at least one coordinate"),
            );
            Vec::new()
        }
        Some((_, list)) => list,
        None => {
            fail(
                lowerer,
                &mut ok,
                syn::Error::new(
                    at,
                    "name the generalized coordinates: `#[hamel_system(coordinates(x, y, theta))]` \
                     (the names appear in accessors, `Debug` output and CSV headers)",
                ),
            );
            Vec::new()
        }
    };
    let n = coordinates.len();
    let m = names.inputs.len();

    let energy = energy_roles(roles, lowerer, at, &mut ok);
    let constraints = required(
        roles,
        Role::Constraints,
        lowerer,
        at,
        &mut ok,
        "constraint rows ω¹…ωᵖ(q, qd), linear in qd and zero on every motion (without nonholonomic \
         constraints a system is holonomic, and hamel is not the tool for it)",
    );
    let quasi_velocities = required(
        roles,
        Role::QuasiVelocities,
        lowerer,
        at,
        &mut ok,
        "the quasi-velocities ω^{p+1}…ωⁿ(q, qd) that complete the constraints to an invertible \
         transformation ω = A(q)·qd",
    );

    if n == 0 {
        return None;
    }
    let real_array = |len: usize| Shape::Array(len, Box::new(Shape::Real));

    // p comes from the constraints' result type.
    let p = constraints.and_then(|c| {
        let sig = lowerer.signature(c.f)?;
        match sig.output {
            Some(Shape::Array(p, inner)) if *inner == Shape::Real => Some(p),
            Some(_) => {
                fail(lowerer, &mut ok, error_at_output(c.f, "`#[constraints]` must return an array `[f64; P]`, one entry per constraint"));
                None
            }
            None => None,
        }
    });
    if let (Some(p), Some(c)) = (p, constraints) {
        if p == 0 {
            fail(
                lowerer,
                &mut ok,
                error_at_output(
                    c.f,
                    "`#[constraints]` returns no constraint: a model needs at least one",
                ),
            );
        } else if p >= n {
            fail(
                lowerer,
                &mut ok,
                error_at_output(
                    c.f,
                    format!(
                        "{p} constraints on {n} coordinates leave no motion: there must be fewer \
                         constraints than coordinates"
                    ),
                ),
            );
        }
    }
    let p = p.filter(|&p| p > 0 && p < n);

    // Signatures of every role present.
    let q = ("q", real_array(n));
    let qd = ("qd", real_array(n));
    let w = ("w", real_array(n));
    for (role, rf) in &roles.by_role {
        let (expected_args, expected_out): (Vec<(&str, Shape)>, Option<Shape>) = match role {
            Role::Lagrangian | Role::KineticEnergy => {
                (vec![q.clone(), qd.clone()], Some(Shape::Real))
            }
            Role::PotentialEnergy => (vec![q.clone()], Some(Shape::Real)),
            Role::QuasiLagrangian => (vec![q.clone(), w.clone()], Some(Shape::Real)),
            Role::Constraints => (vec![q.clone(), qd.clone()], None),
            Role::QuasiVelocities => (vec![q.clone(), qd.clone()], p.map(|p| real_array(n - p))),
            Role::Velocities => (vec![q.clone(), w.clone()], Some(real_array(n))),
            Role::Forces => (
                vec![
                    ("t", Shape::Real),
                    q.clone(),
                    qd.clone(),
                    ("u", real_array(m)),
                ],
                Some(real_array(n)),
            ),
        };
        if !check_signature(
            *role,
            rf,
            &expected_args,
            expected_out.as_ref(),
            lowerer,
            &coordinates,
            p,
        ) {
            ok = false;
        }
    }

    // Names of the speeds: given, or w{p+1}…w{n} as in the paper.
    let speeds = match (names.speeds, p) {
        (Some((span, list)), Some(p)) if list.len() != n - p => {
            fail(
                lowerer,
                &mut ok,
                syn::Error::new(
                    span,
                    format!(
                        "{} speed names for {} free quasi-velocities ({n} coordinates − {p} constraints)",
                        list.len(),
                        n - p
                    ),
                ),
            );
            list
        }
        (Some((_, list)), _) => list,
        (None, Some(p)) => (p + 1..=n).map(|k| format_ident!("w{}", k)).collect(),
        (None, None) => Vec::new(),
    };
    let mut seen: HashMap<String, &syn::Ident> = HashMap::new();
    for ident in coordinates.iter().chain(&speeds).chain(&names.inputs) {
        if seen
            .insert(ident.unraw().to_string().to_uppercase(), ident)
            .is_some()
        {
            fail(
                lowerer,
                &mut ok,
                syn::Error::new(
                    ident.span(),
                    format!(
                        "duplicate name `{ident}`: coordinates, speeds and inputs need distinct names \
                         (also in upper case, which names their index constants, `Self::{}`)",
                        ident.unraw().to_string().to_uppercase()
                    ),
                ),
            );
        }
    }

    if !ok {
        return None;
    }
    Some(Spec {
        dims: Dims { n, p: p?, m },
        coordinates,
        speeds,
        inputs: names.inputs,
        energy: energy?,
        constraints: constraints?.f,
        quasi_velocities: quasi_velocities?.f,
        velocities: roles.get(Role::Velocities).map(|r| r.f),
        forces: roles.get(Role::Forces).map(|r| r.f),
    })
}

fn fail(lowerer: &mut Lowerer<'_, '_>, ok: &mut bool, e: syn::Error) {
    lowerer.push_error(e);
    *ok = false;
}

fn required<'r, 'a>(
    roles: &'r Roles<'a>,
    role: Role,
    lowerer: &mut Lowerer<'_, '_>,
    at: Span,
    ok: &mut bool,
    what: &str,
) -> Option<&'r RoleFn<'a>> {
    let found = roles.get(role);
    if found.is_none() {
        lowerer.push_error(syn::Error::new(
            at,
            format!(
                "missing role `#[{}]`: mark the function that gives {what}; expected signature `{}`",
                role.attribute(),
                role.expected_signature()
            ),
        ));
        *ok = false;
    }
    found
}

/// Exactly one way of giving the energy.
fn energy_roles<'a>(
    roles: &Roles<'a>,
    lowerer: &mut Lowerer<'_, '_>,
    at: Span,
    ok: &mut bool,
) -> Option<Energy<'a>> {
    let l = roles.get(Role::Lagrangian);
    let t = roles.get(Role::KineticEnergy);
    let v = roles.get(Role::PotentialEnergy);
    let lq = roles.get(Role::QuasiLagrangian);
    let mut conflict = |second: &RoleFn<'_>, first: Role, message: &str| {
        lowerer.push_error(syn::Error::new_spanned(
            second.attr,
            format!(
                "ambiguous energy: this model already has a `#[{}]`; {message}",
                first.attribute()
            ),
        ));
        *ok = false;
    };
    let give = "give either a `#[lagrangian]` L = T − V, or a `#[kinetic_energy]` T (with an optional \
                `#[potential_energy]` V), or a `#[quasi_lagrangian]` L̃(q, w) — exactly one of these";
    match (l, t, v, lq) {
        (Some(_), Some(t), _, _) => conflict(t, Role::Lagrangian, give),
        (Some(_), None, Some(v), _) => conflict(
            v,
            Role::Lagrangian,
            "a Lagrangian already contains the potential energy (L = T − V)",
        ),
        (_, _, _, Some(lq)) if l.is_some() || t.is_some() => conflict(
            lq,
            if l.is_some() {
                Role::Lagrangian
            } else {
                Role::KineticEnergy
            },
            give,
        ),
        (None, None, Some(v), Some(_)) => conflict(
            v,
            Role::QuasiLagrangian,
            "L̃ already contains the potential energy",
        ),
        (None, None, Some(v), None) => {
            lowerer.push_error(syn::Error::new_spanned(
                v.attr,
                "a potential energy alone does not make a model: add the `#[kinetic_energy]` T(q, qd)",
            ));
            *ok = false;
        }
        (None, None, None, None) => {
            lowerer.push_error(syn::Error::new(
                at,
                format!("missing role: the model needs its energy; {give}"),
            ));
            *ok = false;
        }
        _ => {}
    }
    if !*ok {
        return None;
    }
    match (l, t, lq) {
        (Some(l), None, None) => Some(Energy::Lagrangian(l.f)),
        (None, Some(t), None) => Some(Energy::Split {
            kinetic: t.f,
            potential: v.map(|v| v.f),
        }),
        (None, None, Some(lq)) => Some(Energy::Quasi(lq.f)),
        _ => None,
    }
}

fn error_at_output(f: &syn::ImplItemFn, message: impl std::fmt::Display) -> syn::Error {
    match &f.sig.output {
        syn::ReturnType::Type(_, ty) => syn::Error::new_spanned(ty, message),
        syn::ReturnType::Default => syn::Error::new_spanned(&f.sig, message),
    }
}

/// Compare a role function's signature with what its role needs.
fn check_signature(
    role: Role,
    rf: &RoleFn<'_>,
    expected: &[(&str, Shape)],
    output: Option<&Shape>,
    lowerer: &mut Lowerer<'_, '_>,
    coordinates: &[syn::Ident],
    p: Option<usize>,
) -> bool {
    let f = rf.f;
    let Some(sig) = lowerer.signature(f) else {
        return false;
    };
    let rendered = render(expected, output);
    let mut ok = true;
    if sig.args.len() != expected.len() {
        lowerer.push_error(syn::Error::new_spanned(
            &f.sig,
            format!(
                "`#[{}]` takes {} argument(s) besides `&self`, this function takes {}: expected `{rendered}`",
                role.attribute(),
                expected.len(),
                sig.args.len()
            ),
        ));
        return false;
    }
    let names: Vec<String> = coordinates.iter().map(ToString::to_string).collect();
    for (arg, (name, shape)) in sig.args.iter().zip(expected) {
        if arg.shape != *shape {
            let why = match shape {
                Shape::Array(len, _) if *name == "u" => {
                    format!("one per input ({len} declared in `inputs(..)`)")
                }
                Shape::Array(..) => format!("one per coordinate: {}", names.join(", ")),
                _ => "the time".to_string(),
            };
            lowerer.push_error(syn::Error::new_spanned(
                &arg.ty,
                format!(
                    "argument `{}` of `#[{}]` must be {} ({why}), found {}; expected `{rendered}`",
                    arg.pat.to_token_stream(),
                    role.attribute(),
                    shape.describe(),
                    arg.shape.describe()
                ),
            ));
            ok = false;
        }
    }
    if let (Some(want), Some(got)) = (output, &sig.output)
        && want != got
    {
        let why = match (role, p) {
            (Role::QuasiVelocities, Some(p)) => format!(
                "there are {} coordinates and {p} constraints, so the quasi-velocities that complete \
                 them number {}",
                coordinates.len(),
                coordinates.len() - p
            ),
            (Role::Velocities | Role::Forces, _) => {
                format!("one per coordinate: {}", names.join(", "))
            }
            _ => "a scalar".to_string(),
        };
        lowerer.push_error(error_at_output(
            f,
            format!(
                "`#[{}]` must return {} ({why}), found {}",
                role.attribute(),
                want.describe(),
                got.describe()
            ),
        ));
        ok = false;
    }
    ok && sig.output.is_some()
}

fn render(args: &[(&str, Shape)], output: Option<&Shape>) -> String {
    let args: Vec<String> = args
        .iter()
        .map(|(n, s)| match s {
            Shape::Real => format!("{n}: f64"),
            other => format!("{n}: &{}", other.describe().trim_matches('`')),
        })
        .collect();
    let out = output.map_or_else(
        || "[f64; P]".to_string(),
        |s| s.describe().trim_matches('`').to_string(),
    );
    format!("fn(&self, {}) -> {out}", args.join(", "))
}
