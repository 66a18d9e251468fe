//! The checked model: dimensions, names and role functions, after every check that can be
//! made from the signatures alone. All mistakes are reported together, each at its span.
//!
//! One file per concern: `signatures` (each role's signature against what it must be),
//! `names` (the names of coordinates, speeds, inputs and constraints, and the reserved
//! ones), `energy` (the roles that give the energy, and the required ones), `rows` (how
//! many constraint rows the constraints, the rolling contacts and the holonomic constraints
//! give, and the coordinates those determine), `labels` (the bodies' names and the units,
//! for display).

pub mod control;
mod energy;
mod labels;
mod names;
mod rows;
mod signatures;

pub use signatures::{argument_name, written_rows};

use super::equations::ContactReading;
use super::model::{Group, Names, Role, Roles};
use crate::engine::graph::NodeId;
use crate::engine::hash::HashSet;
use crate::engine::lower::Lowerer;
use energy::{energy_roles, rows_roles};
use names::{check_all_names, coordinate_names, speed_names};
use proc_macro2::TokenStream;
use rows::{dependent, model_shape};
use signatures::check_signatures;

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
    /// T(q, q̇) and optionally V(q); without T, the bodies' kinetic energy is the model's
    Split {
        kinetic: Option<&'a syn::ImplItemFn>,
        potential: Option<&'a syn::ImplItemFn>,
    },
    /// L̃(q, ω)
    Quasi(&'a syn::ImplItemFn),
}

/// The roles of a model stated from geometry.
pub struct Geometry<'a> {
    /// `#[bodies]`, returning this many bodies.
    pub bodies: Option<(&'a syn::ImplItemFn, usize)>,
    pub gravity: Option<&'a syn::ImplItemFn>,
    pub contacts: Option<Contacts<'a>>,
}

/// `#[contacts]`: what they give (the rows kept, the heights that are holonomic
/// constraints), and the coordinates their heights determine (one per contact whose height
/// varies with the coordinates, in order).
pub struct Contacts<'a> {
    pub f: &'a syn::ImplItemFn,
    pub attr: &'a syn::Attribute,
    pub reading: ContactReading,
    pub dependent: Vec<usize>,
}

/// The graph's symbols for the time, the coordinates and the velocities, in which the role
/// functions are read (the contacts as soon as the coordinates are known: how many rows the
/// model has depends on them).
pub struct Symbols {
    pub t: NodeId,
    pub q: Vec<NodeId>,
    pub v: Vec<NodeId>,
}

impl Symbols {
    fn new(lowerer: &mut Lowerer<'_, '_>, n: usize) -> Self {
        let g = &mut *lowerer.graph;
        let t = g.new_input("t");
        let mut fresh = |name: &str| {
            (0..n)
                .map(|i| g.new_input(format!("{name}[{i}]")))
                .collect()
        };
        let q = fresh("q");
        let v = fresh("v");
        Symbols { t, q, v }
    }
}

pub struct Spec<'a> {
    pub dims: Dims,
    pub coordinates: Vec<syn::Ident>,
    pub speeds: Vec<syn::Ident>,
    pub inputs: Vec<syn::Ident>,
    /// The constraint rows' names, when `constraints(..)` gives them (otherwise each row is
    /// named after its function and its index, `blade0`).
    pub constraint_names: Option<Vec<syn::Ident>>,
    /// The indexed groups of names (coordinates, speeds, inputs, constraints).
    pub groups: [Vec<Group>; 4],
    pub energy: Energy<'a>,
    /// `#[constraints]`, which a model whose constraints are all rolling contacts can do
    /// without.
    pub constraints: Option<&'a syn::ImplItemFn>,
    pub quasi_velocities: &'a syn::ImplItemFn,
    pub velocities: Option<&'a syn::ImplItemFn>,
    pub forces: Option<&'a syn::ImplItemFn>,
    pub holonomic: Option<Holonomic<'a>>,
    pub geometry: Geometry<'a>,
    /// The bodies' names, one per body of `#[bodies]` (none without it).
    pub body_names: Vec<String>,
    /// The units `units(..)` gives: a quantity's name and its unit.
    pub units: Vec<(String, String)>,
    /// The role functions that take the time as a leading argument (by name).
    timed: HashSet<String>,
    pub symbols: Symbols,
    /// Whether the bodies' speeds are taken in the frame of their first turns
    /// (`equations::bodies::squared_speed`): `equations::build_cheaper` tries both.
    pub heading_frames: std::cell::Cell<bool>,
    /// The control code the model asks for (`#[outputs]`, `control(..)`), if any.
    pub control: Option<control::ControlRequest<'a>>,
}

impl Spec<'_> {
    /// Whether `f` takes a leading `t: f64` (the forces always do).
    pub fn takes_time(&self, f: &syn::ImplItemFn) -> bool {
        self.timed.contains(&f.sig.ident.to_string())
    }

    /// The rows of `#[constraints]`.
    pub fn written_constraints(&self) -> usize {
        self.dims.nonholonomic() - self.contact_rows()
    }

    /// The rolling contacts' rows kept.
    pub fn contact_rows(&self) -> usize {
        self.geometry
            .contacts
            .as_ref()
            .map_or(0, |c| c.reading.kept.len())
    }

    /// The coordinates the holonomic constraints determine, in the order of their rows: those
    /// of `#[holonomic]`, then those of the contacts' heights.
    pub fn dependent(&self) -> Vec<usize> {
        let holonomic = self.holonomic.iter().flat_map(|h| h.dependent.iter());
        let contacts = self
            .geometry
            .contacts
            .iter()
            .flat_map(|c| c.dependent.iter());
        holonomic.chain(contacts).copied().collect()
    }

    /// The holonomic constraints of `#[holonomic]` (the contacts' heights follow them).
    pub fn written_holonomic(&self) -> usize {
        self.holonomic.as_ref().map_or(0, |h| h.dependent.len())
    }
}

/// A block with `#[hamel_system]` that holds neither the energy nor the constraints
/// ([`Roles::is_fragment`]): one error, rather than one per role it lacks.
fn fragment(roles: &Roles<'_>, at: &TokenStream) -> syn::Error {
    let held: Vec<String> = roles
        .by_role
        .iter()
        .map(|(role, rf)| format!("`#[{}] {}`", role.attribute(), rf.f.sig.ident))
        .collect();
    syn::Error::new_spanned(
        at,
        format!(
            "this impl block has `#[hamel_system]` and {}, but neither the model's energy nor its \
             constraints: all the roles of a model go in one impl block, which alone carries \
             `#[hamel_system(coordinates(..))]`; if the others are in another impl block, move \
             these functions there and remove `#[hamel_system]` from this one",
            held.join(", ")
        ),
    )
}

/// Check names, roles and signatures. Errors go to the lowerer's error list; `None` when the
/// model cannot be built at all. A mistake that does not stop the equations from being built
/// (a name, an optional role's signature) is reported without stopping them, so that the
/// mistakes in the bodies are found in the same build. `at` is what errors about the model
/// as a whole point at (`impl Model`).
pub fn check<'a>(
    names: Names,
    roles: &Roles<'a>,
    lowerer: &mut Lowerer<'a, '_>,
    at: &TokenStream,
) -> Option<Spec<'a>> {
    if roles.is_fragment() {
        lowerer.push_error(fragment(roles, at));
        return None;
    }
    let mut ok = true;
    let coordinates = coordinate_names(
        names.coordinates.clone(),
        names.garbled,
        lowerer,
        at,
        &mut ok,
    );
    let (n, m) = (coordinates.len(), names.inputs.len());
    let energy = energy_roles(roles, lowerer, at, &mut ok);
    let (constraints, quasi_velocities) = rows_roles(roles, lowerer, at, &mut ok);
    if n == 0 {
        return None;
    }
    let written_speeds = names.speeds.as_ref().map_or(&[][..], |(_, l)| &l[..]);
    let symbols = Symbols::new(lowerer, n);
    let mut shape = model_shape(roles, &coordinates, m, &symbols, lowerer, &mut ok);
    let (timed, dropped) = check_signatures(
        roles,
        (n, m, shape.p),
        &coordinates,
        &names.inputs,
        lowerer,
        &mut ok,
    );
    let holonomic = dependent(&mut shape, (&coordinates, written_speeds), lowerer, &mut ok);
    let speeds = speed_names(names.speeds.clone(), names.garbled, n, shape.p, lowerer);
    let constraint_names = check_all_names(
        &names,
        &shape,
        (&coordinates, &speeds),
        roles,
        lowerer,
        &mut ok,
    );
    let control = control::request(&names, roles, &dropped, (n, m, shape.p), lowerer);
    let body_names = labels::body_names(&names, shape.bodies, lowerer);
    let units = labels::units(&names, [&coordinates, &speeds, &names.inputs], lowerer);
    if !ok {
        return None;
    }
    let (holonomic, contacts) = holonomic?;
    let optional = |role: Role| {
        roles
            .get(role)
            .filter(|_| !dropped.contains(&role))
            .map(|r| r.f)
    };
    Some(Spec {
        dims: Dims {
            n,
            p: shape.p?,
            m,
            k: shape.k,
        },
        coordinates,
        speeds,
        inputs: names.inputs,
        constraint_names,
        groups: names.groups,
        energy: energy?,
        constraints: constraints.map(|c| c.f),
        quasi_velocities: quasi_velocities?.f,
        velocities: optional(Role::Velocities),
        forces: optional(Role::Forces),
        holonomic,
        geometry: Geometry {
            bodies: shape.bodies,
            gravity: roles.get(Role::Gravity).map(|g| g.f),
            contacts,
        },
        body_names,
        units,
        timed,
        symbols,
        heading_frames: std::cell::Cell::new(false),
        control,
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
