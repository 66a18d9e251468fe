//! The checked model: dimensions, names and role functions, after every check that can be
//! made from the signatures alone. All mistakes are reported together, each at its span.
//!
//! One file per concern: `signatures` (each role's signature against what it must be),
//! `names` (the names of coordinates, speeds, inputs and constraints, and the reserved
//! ones), `energy` (the roles that give the energy, and the required ones), `rows` (how
//! many constraint rows the constraints and the holonomic constraints give, and the
//! coordinates those determine).

mod energy;
mod names;
mod rows;
mod signatures;

pub use signatures::argument_name;

use super::model::{Group, Names, Role, Roles};
use crate::engine::lower::Lowerer;
use energy::{energy_roles, required};
use names::{
    Rows, check_group_names, check_inputs_are_read, check_names, constraint_names,
    coordinate_names, speed_names,
};
use proc_macro2::TokenStream;
use rows::{constraint_count, dependent_coordinates, holonomic_count};
use signatures::{check_signatures, record_expected_signatures};
use std::collections::HashSet;

#[derive(Clone, Copy)]
pub struct Dims {
    /// Coordinates.
    pub n: usize,
    /// Constraint rows, the holonomic constraints' included.
    pub p: usize,
    /// Inputs.
    pub m: usize,
    /// Holonomic constraints (their velocity rows are the last k of the p).
    pub k: usize,
}

impl Dims {
    /// Free quasi-velocities ("speeds").
    pub fn free(&self) -> usize {
        self.n - self.p
    }

    /// The rows of the `#[constraints]` function.
    pub fn nonholonomic(&self) -> usize {
        self.p - self.k
    }
}

/// The holonomic constraints f(t, q) = 0 and the coordinates they determine.
pub struct Holonomic<'a> {
    pub f: &'a syn::ImplItemFn,
    /// For each constraint, the index of the coordinate it determines.
    pub dependent: Vec<usize>,
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
    /// The constraint rows' names, when `constraints(..)` gives them (otherwise each row is
    /// named after its function, `blade[0]`).
    pub constraint_names: Option<Vec<syn::Ident>>,
    /// The indexed groups of names (coordinates, speeds, inputs, constraints).
    pub groups: [Vec<Group>; 4],
    pub energy: Energy<'a>,
    pub constraints: &'a syn::ImplItemFn,
    pub quasi_velocities: &'a syn::ImplItemFn,
    pub velocities: Option<&'a syn::ImplItemFn>,
    pub forces: Option<&'a syn::ImplItemFn>,
    pub holonomic: Option<Holonomic<'a>>,
    /// The role functions that take the time as a leading argument (by name).
    timed: HashSet<String>,
}

impl Spec<'_> {
    /// Whether `f` takes a leading `t: f64` (the forces always do).
    pub fn takes_time(&self, f: &syn::ImplItemFn) -> bool {
        self.timed.contains(&f.sig.ident.to_string())
    }
}

/// Check names, roles and signatures. Errors go to the lowerer's error list; `None` when the
/// model cannot be built at all. A mistake that does not stop the equations from being built
/// (a name, an optional role's signature) is reported without stopping them, so that the
/// mistakes in the bodies are found in the same build. `at` is what errors about the model
/// as a whole point at (`impl Model`).
pub fn check<'a>(
    names: Names,
    roles: &Roles<'a>,
    lowerer: &mut Lowerer<'_, '_>,
    at: &TokenStream,
) -> Option<Spec<'a>> {
    let mut ok = true;

    let coordinates = coordinate_names(
        names.coordinates.clone(),
        names.garbled,
        lowerer,
        at,
        &mut ok,
    );
    let n = coordinates.len();
    let m = names.inputs.len();

    let energy = energy_roles(roles, lowerer, at, &mut ok);
    let constraints = required(
        roles,
        Role::Constraints,
        lowerer,
        at,
        &mut ok,
        "the constraint rows ω¹…ωᵖ(q, qd), linear in qd and zero on every motion",
        " (without nonholonomic constraints a system is holonomic, and hamel is not the tool for it)",
    );
    let quasi_velocities = required(
        roles,
        Role::QuasiVelocities,
        lowerer,
        at,
        &mut ok,
        "the quasi-velocities ω^{p+1}…ωⁿ(q, qd) that complete the constraints to an invertible \
         transformation ω = A(q)·qd",
        "",
    );

    if n == 0 {
        return None;
    }
    let holonomic = roles.get(Role::Holonomic);
    record_expected_signatures(roles, constraints, holonomic, n, m, lowerer);
    let k = holonomic_count(holonomic, lowerer, &mut ok);
    let p = constraint_count(constraints, k, &coordinates, lowerer, &mut ok).map(|p| p + k);
    let (timed, dropped) = check_signatures(
        roles,
        (n, m, p),
        &coordinates,
        &names.inputs,
        lowerer,
        &mut ok,
    );
    let dependent = holonomic.and_then(|h| dependent_coordinates(h, k, &coordinates, lowerer));
    if holonomic.is_some() && dependent.is_none() {
        ok = false;
    }

    let speeds = speed_names(names.speeds.clone(), names.garbled, n, p, lowerer);
    // (A failed `#[holonomic]` leaves k unknown: the rows cannot be counted.)
    let rows = p.filter(|_| holonomic.is_none() || k > 0).map(|p| Rows {
        constraints: constraints.map(|c| c.f),
        nonholonomic: p - k,
        holonomic: holonomic.map(|h| h.f),
        k,
    });
    let constraint_names = constraint_names(&names, rows, lowerer);
    let lists = [
        &coordinates[..],
        &speeds,
        &names.inputs,
        constraint_names.as_deref().unwrap_or_default(),
    ];
    check_names(lists, lowerer, &mut ok);
    check_group_names(&names.groups, lists, lowerer);
    check_inputs_are_read(&names, roles, n, lowerer);

    if !ok {
        return None;
    }
    Some(Spec {
        dims: Dims { n, p: p?, m, k },
        coordinates,
        speeds,
        inputs: names.inputs,
        constraint_names,
        groups: names.groups,
        energy: energy?,
        constraints: constraints?.f,
        quasi_velocities: quasi_velocities?.f,
        velocities: roles
            .get(Role::Velocities)
            .filter(|_| !dropped.contains(&Role::Velocities))
            .map(|r| r.f),
        forces: roles
            .get(Role::Forces)
            .filter(|_| !dropped.contains(&Role::Forces))
            .map(|r| r.f),
        holonomic: holonomic
            .zip(dependent)
            .map(|(h, dependent)| Holonomic { f: h.f, dependent }),
        timed,
    })
}

/// "1 constraint", "2 constraints".
pub(super) fn count(k: usize, what: &str) -> String {
    if k == 1 {
        format!("1 {what}")
    } else if let Some(stem) = what.strip_suffix('y') {
        format!("{k} {stem}ies")
    } else {
        format!("{k} {what}s")
    }
}

pub(super) fn fail(lowerer: &mut Lowerer<'_, '_>, ok: &mut bool, e: syn::Error) {
    lowerer.push_error(e);
    *ok = false;
}

pub(super) fn error_at_output(f: &syn::ImplItemFn, message: impl std::fmt::Display) -> syn::Error {
    match &f.sig.output {
        syn::ReturnType::Type(_, ty) => syn::Error::new_spanned(ty, message),
        syn::ReturnType::Default => syn::Error::new_spanned(&f.sig, message),
    }
}
