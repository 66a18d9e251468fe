//! The checked model: dimensions, names and role functions, after every check that can be
//! made from the signatures alone. All mistakes are reported together, each at its span.

use super::model::{Group, Names, Role, RoleFn, Roles, names_of, written_length};
use super::reserved;
use crate::engine::lower::{Arg, Lowerer, Shape};
use proc_macro2::TokenStream;
use quote::{ToTokens, format_ident};
use std::collections::{HashMap, HashSet};
use syn::ext::IdentExt;

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

/// What each role's signature must be, for the messages about unsupported types in it (from
/// the lengths as written, before they are checked).
fn record_expected_signatures(
    roles: &Roles<'_>,
    constraints: Option<&RoleFn<'_>>,
    holonomic: Option<&RoleFn<'_>>,
    n: usize,
    m: usize,
    lowerer: &mut Lowerer<'_, '_>,
) {
    let p_written = constraints.and_then(|c| written_length(&c.f.sig.output));
    let k_written = holonomic.map_or(Some(0), |h| written_length(&h.f.sig.output));
    let p_total = p_written
        .zip(k_written)
        .map(|(p, k)| p + k)
        .filter(|&p| p < n);
    for (role, rf) in &roles.by_role {
        let timed = takes_time(*role, rf.f, n, m, p_total);
        let (args, out) = expected(*role, n, m, p_total, timed);
        let name = rf.f.sig.ident.to_string();
        lowerer
            .signature_hints
            .insert(name.clone(), render(*role, &args, out.as_ref()));
        lowerer.expected_arguments.insert(name, args);
    }
}

/// The signature of every role present: the functions that take the time, and the optional
/// roles left out of the model because their signature is wrong (their error stands, and
/// the rest of the model is still checked). A required role with a wrong signature clears
/// `ok`.
fn check_signatures(
    roles: &Roles<'_>,
    (n, m, p): (usize, usize, Option<usize>),
    coordinates: &[syn::Ident],
    inputs: &[syn::Ident],
    lowerer: &mut Lowerer<'_, '_>,
    ok: &mut bool,
) -> (HashSet<String>, Vec<Role>) {
    let mut dropped = Vec::new();
    let mut timed = HashSet::new();
    for (role, rf) in &roles.by_role {
        let takes = takes_time(*role, rf.f, n, m, p);
        let fits = check_signature(
            *role,
            rf,
            &expected(*role, n, m, p, takes),
            lowerer,
            (coordinates, inputs),
            p,
        );
        if takes && *role != Role::Forces {
            timed.insert(rf.f.sig.ident.to_string());
        }
        if !fits {
            lowerer.mark_faulty(rf.f.sig.ident.to_string());
            match role {
                Role::Velocities | Role::Forces => dropped.push(*role),
                _ => *ok = false,
            }
        }
    }
    (timed, dropped)
}

/// Whether a role function takes the time first: one argument more than the role needs,
/// and the role may take it (`fn(&self, t: f64, q: &[f64; N], qd: &[f64; N])`). A `t` of
/// the wrong type or in the wrong place is then reported by the signature check.
fn takes_time(role: Role, f: &syn::ImplItemFn, n: usize, m: usize, p: Option<usize>) -> bool {
    if role == Role::Forces {
        return true;
    }
    let typed: Vec<&syn::PatType> = f
        .sig
        .inputs
        .iter()
        .filter_map(|a| match a {
            syn::FnArg::Typed(pt) => Some(pt),
            syn::FnArg::Receiver(_) => None,
        })
        .collect();
    // One argument too many, and one of them is the time: named `t`, or a scalar `f64`.
    let is_time = |pt: &&syn::PatType| {
        argument_name(&pt.pat).is_some_and(|name| name == "t")
            || matches!(&*pt.ty, syn::Type::Path(ty) if ty.path.is_ident("f64"))
    };
    role.may_take_time()
        && typed.len() == expected(role, n, m, p, false).0.len() + 1
        && typed.iter().any(is_time)
}

/// k, from the holonomic function's result type: at least one constraint (0 without one).
fn holonomic_count(
    holonomic: Option<&RoleFn<'_>>,
    lowerer: &mut Lowerer<'_, '_>,
    ok: &mut bool,
) -> usize {
    let Some(h) = holonomic else {
        return 0;
    };
    let k = lowerer.signature(h.f).and_then(|sig| match sig.output {
        Some(Shape::Array(k, inner)) if *inner == Shape::Real => Some(k),
        _ => None,
    });
    match k {
        Some(k) if k > 0 => k,
        Some(_) => {
            fail(
                lowerer,
                ok,
                error_at_output(
                    h.f,
                    "`#[holonomic]` returns no constraint: return `[f64; K]`, one entry per \
                     holonomic constraint f(q) = 0, or remove the role",
                ),
            );
            0
        }
        None => {
            fail(
                lowerer,
                ok,
                error_at_output(
                    h.f,
                    "`#[holonomic]` must return an array `[f64; K]`, one entry per holonomic \
                     constraint f(q) = 0",
                ),
            );
            0
        }
    }
}

/// The coordinates named in `#[holonomic(determines(..))]`, as indices: one per constraint,
/// each a coordinate, no two the same.
fn dependent_coordinates(
    h: &RoleFn<'_>,
    k: usize,
    coordinates: &[syn::Ident],
    lowerer: &mut Lowerer<'_, '_>,
) -> Option<Vec<usize>> {
    let known: Vec<String> = coordinates.iter().map(|c| c.unraw().to_string()).collect();
    let mut indices = Vec::new();
    let mut good = true;
    for name in &h.determines {
        let plain = name.unraw().to_string();
        match known.iter().position(|c| *c == plain) {
            Some(i) if indices.contains(&i) => {
                lowerer.push_error(syn::Error::new(
                    name.span(),
                    format!("`{name}` is named twice: each holonomic constraint determines its own coordinate"),
                ));
                good = false;
            }
            Some(i) => indices.push(i),
            None => {
                let hint = crate::engine::lower::closest(&plain, &known)
                    .map(|g| format!("; did you mean `{g}`?"))
                    .unwrap_or_default();
                lowerer.push_error(syn::Error::new(
                    name.span(),
                    format!(
                        "`{name}` is not a coordinate{hint} (the coordinates are {})",
                        names_of(coordinates)
                    ),
                ));
                good = false;
            }
        }
    }
    if good && !h.determines.is_empty() && indices.len() != k && k > 0 {
        lowerer.push_error(syn::Error::new_spanned(
            h.attr,
            format!(
                "`{}` returns {} but `determines(..)` names {}: name one coordinate per \
                 holonomic constraint, the one it is solved for",
                h.f.sig.ident,
                count(k, "constraint"),
                count(indices.len(), "coordinate"),
            ),
        ));
        good = false;
    }
    (good && !h.determines.is_empty()).then_some(indices)
}

/// The number of nonholonomic constraints, from the constraints' result type: at least one,
/// and with the k holonomic ones fewer than the coordinates.
fn constraint_count(
    constraints: Option<&RoleFn<'_>>,
    k: usize,
    coordinates: &[syn::Ident],
    lowerer: &mut Lowerer<'_, '_>,
    ok: &mut bool,
) -> Option<usize> {
    let n = coordinates.len();
    let p = constraints.and_then(|c| {
        let sig = lowerer.signature(c.f)?;
        match sig.output {
            Some(Shape::Array(p, inner)) if *inner == Shape::Real => Some(p),
            Some(_) => {
                fail(lowerer, ok, error_at_output(c.f, "`#[constraints]` must return an array `[f64; P]`, one entry per constraint"));
                None
            }
            None => None,
        }
    });
    if let (Some(p), Some(c)) = (p, constraints) {
        if p == 0 {
            fail(
                lowerer,
                ok,
                error_at_output(
                    c.f,
                    "`#[constraints]` returns no constraint: a model needs at least one",
                ),
            );
        } else if p + k >= n {
            let holonomic = if k > 0 {
                format!(" and {}", count(k, "holonomic constraint"))
            } else {
                String::new()
            };
            fail(
                lowerer,
                ok,
                error_at_output(
                    c.f,
                    format!(
                        "{}{holonomic} on {} leave no motion: there must be fewer constraints \
                         than coordinates ({})",
                        count(p, "constraint"),
                        count(n, "coordinate"),
                        names_of(coordinates)
                    ),
                ),
            );
        }
    }
    p.filter(|&p| p > 0 && p + k < n)
}

/// Inputs are read by the forces only: without `#[forces]` they would be silently ignored.
fn check_inputs_are_read(
    names: &Names,
    roles: &Roles<'_>,
    n: usize,
    lowerer: &mut Lowerer<'_, '_>,
) {
    if let Some(written) = &names.inputs_written
        && !names.inputs.is_empty()
        && roles.get(Role::Forces).is_none()
    {
        let (args, out) = expected(Role::Forces, n, names.inputs.len(), None, true);
        let (declared, them) = match names.inputs.as_slice() {
            [one] => (format!("the input `{one}` is declared"), "it"),
            all => (format!("the inputs {} are declared", names_of(all)), "them"),
        };
        lowerer.push_error(syn::Error::new_spanned(
            written,
            format!(
                "{declared}, but the model has no `#[forces]` to read {them}, so {them} would \
                 be ignored: add a `#[forces]` function `{}` that uses `u`, or remove \
                 `inputs(..)`",
                render(Role::Forces, &args, out.as_ref())
            ),
        ));
    }
}

/// Names of the speeds: given, or w{p+1}…w{n} as in the paper. A mistake in the names is
/// reported, but does not stop the model from being checked.
fn speed_names(
    written: Option<(proc_macro2::Span, Vec<syn::Ident>)>,
    garbled: bool,
    n: usize,
    p: Option<usize>,
    lowerer: &mut Lowerer<'_, '_>,
) -> Vec<syn::Ident> {
    match (written, p) {
        // A list that could not be read is reported already, and its length means nothing.
        (Some((span, list)), Some(p)) if list.len() != n - p && !garbled => {
            lowerer.push_error(syn::Error::new(
                span,
                format!(
                    "{} for {} ({} − {}): name one speed per quasi-velocity",
                    count(list.len(), "speed name"),
                    count(n - p, "quasi-velocity"),
                    count(n, "coordinate"),
                    count(p, "constraint"),
                ),
            ));
            list
        }
        (Some((_, list)), _) => list,
        (None, Some(p)) => (p + 1..=n).map(|k| format_ident!("w{}", k)).collect(),
        (None, None) => Vec::new(),
    }
}

/// The constraint rows of a model, for the message about naming them.
struct Rows<'a> {
    constraints: Option<&'a syn::ImplItemFn>,
    nonholonomic: usize,
    holonomic: Option<&'a syn::ImplItemFn>,
    k: usize,
}

/// Names of the constraint rows, when `constraints(..)` gives them: one per row (`rows`, when
/// the rows could be counted), the nonholonomic ones first. A wrong count is reported, but
/// does not stop the model from being checked.
fn constraint_names(
    names: &Names,
    rows: Option<Rows<'_>>,
    lowerer: &mut Lowerer<'_, '_>,
) -> Option<Vec<syn::Ident>> {
    let (span, list) = names.constraints.clone()?;
    let Some(rows) = rows else {
        return Some(list);
    };
    let p = rows.nonholonomic + rows.k;
    // A list that could not be read is reported already, and its length means nothing.
    if list.len() != p && !names.garbled {
        let rows_of = |f: Option<&syn::ImplItemFn>, role: Role, rows: usize| {
            let what = count(rows, "row");
            match f {
                Some(f) => format!(
                    "`{}` (`#[{}]`) returns {what}",
                    f.sig.ident,
                    role.attribute()
                ),
                None => format!("`#[{}]` returns {what}", role.attribute()),
            }
        };
        let constraints = rows_of(rows.constraints, Role::Constraints, rows.nonholonomic);
        let first = rows.constraints.map_or_else(
            || "`#[constraints]`".to_string(),
            |f| format!("`{}`", f.sig.ident),
        );
        let given = match rows.holonomic {
            Some(h) => format!(
                "{constraints} and {}; name one per row, in order, those of {first} first",
                rows_of(Some(h), Role::Holonomic, rows.k)
            ),
            None => format!("{constraints}; name one per row, in order"),
        };
        lowerer.push_error(syn::Error::new(
            span,
            format!(
                "{} for {}: {given}",
                count(list.len(), "constraint name"),
                count(p, "constraint row"),
            ),
        ));
    }
    Some(list)
}

/// The coordinates' names; an error when there are none (unless the list could not be read,
/// which is reported already).
fn coordinate_names(
    written: Option<(proc_macro2::Span, Vec<syn::Ident>)>,
    garbled: bool,
    lowerer: &mut Lowerer<'_, '_>,
    at: &TokenStream,
    ok: &mut bool,
) -> Vec<syn::Ident> {
    let error = match written {
        Some((_, list)) if !list.is_empty() => return list,
        _ if garbled => {
            *ok = false;
            return Vec::new();
        }
        Some((span, _)) => syn::Error::new(span, "a model needs at least one coordinate"),
        None => syn::Error::new_spanned(
            at,
            "name the generalized coordinates: `#[hamel_system(coordinates(x, y, theta))]` \
             (the names appear in accessors, `Debug` output and CSV headers)",
        ),
    };
    fail(lowerer, ok, error);
    Vec::new()
}

/// What each list of names holds, in the order of the lists given to `check_names`.
const KINDS: [&str; 4] = ["coordinate", "speed", "input", "constraint"];

/// Each name must have an upper-case form that is an identifier (its index constant), be
/// distinct from the others, and not be reserved. `lists`: the coordinates, speeds, inputs
/// and constraints. A constraint's column is `lambda_<name>`, which no other column can be
/// (the `lambda_` prefix is reserved): its name need only be distinct, and not hide a
/// constant.
fn check_names(lists: [&[syn::Ident]; 4], lowerer: &mut Lowerer<'_, '_>, ok: &mut bool) {
    let mut seen: HashMap<String, (&syn::Ident, &str)> = HashMap::new();
    let named = lists
        .into_iter()
        .zip(KINDS)
        .flat_map(|(list, kind)| list.iter().map(move |ident| (ident, kind)));
    for (ident, kind) in named {
        let upper = ident.unraw().to_string().to_uppercase();
        if syn::parse_str::<syn::Ident>(&upper).is_err() {
            fail(
                lowerer,
                ok,
                syn::Error::new(
                    ident.span(),
                    format!(
                        "the name `{ident}` has no upper-case form that is an identifier (`{upper}`), \
                         which its index constant needs: choose another name"
                    ),
                ),
            );
        }
        let plain = ident.unraw().to_string();
        let reserved = if kind == "constraint" {
            reserved::constant_clash(&plain)
        } else {
            reserved::clash(&plain)
        };
        if let Some(why) = reserved {
            lowerer.push_error(syn::Error::new(
                ident.span(),
                format!("the name `{ident}` is reserved: {why}; choose another name"),
            ));
        }
        if let Some((first, first_kind)) = seen.insert(upper.clone(), (ident, kind)) {
            let already = if first.unraw() == ident.unraw() {
                format!("already the name of {}", a(first_kind))
            } else {
                format!("`{first}`, {}, has the same upper case", a(first_kind))
            };
            lowerer.push_error(syn::Error::new(
                ident.span(),
                format!(
                    "duplicate name `{ident}` ({already}): coordinates, speeds, inputs and \
                     constraints need distinct names (also in upper case, which names their \
                     index constants, `Self::{upper}`)"
                ),
            ));
        }
    }
}

/// "a coordinate", "an input".
fn a(kind: &str) -> String {
    if kind.starts_with(['a', 'e', 'i', 'o', 'u']) {
        format!("an {kind}")
    } else {
        format!("a {kind}")
    }
}

/// The base name of an indexed group names a constant too (`Self::THETA`, its first index):
/// it must clash with no other name's constant and not be reserved. (`lists` as for
/// `check_names`.)
fn check_group_names(
    groups: &[Vec<Group>; 4],
    lists: [&[syn::Ident]; 4],
    lowerer: &mut Lowerer<'_, '_>,
) {
    let upper = |i: &syn::Ident| i.unraw().to_string().to_uppercase();
    let mut taken: HashSet<String> = lists.iter().copied().flatten().map(upper).collect();
    for (group, kind) in groups
        .iter()
        .zip(KINDS)
        .flat_map(|(groups, kind)| groups.iter().map(move |g| (g, kind)))
    {
        let name = upper(&group.base);
        let base = group.base.unraw().to_string();
        let reserved = if kind == "constraint" {
            reserved::constant_clash(&base)
        } else {
            reserved::clash(&base)
        };
        if let Some(why) = reserved {
            lowerer.push_error(syn::Error::new(
                group.base.span(),
                format!(
                    "the group name `{}` is reserved: {why}; choose another name",
                    group.base
                ),
            ));
        } else if !taken.insert(name.clone()) {
            lowerer.push_error(syn::Error::new(
                group.base.span(),
                format!(
                    "the group `{base}[{len}]` names the constant `Self::{name}` (the index of \
                     `{base}0`), which another name already has: choose distinct names",
                    base = group.base,
                    len = group.len
                ),
            ));
        }
    }
}

/// What a role's function must take and return (`p`: the number of constraint rows, the
/// holonomic ones' included, when known; `timed`: the function takes the time first).
fn expected(
    role: Role,
    n: usize,
    m: usize,
    p: Option<usize>,
    timed: bool,
) -> (Vec<(&'static str, Shape)>, Option<Shape>) {
    let real_array = |len: usize| Shape::Array(len, Box::new(Shape::Real));
    let q = ("q", real_array(n));
    let qd = ("qd", real_array(n));
    let w = ("w", real_array(n));
    let (mut args, out) = match role {
        Role::Lagrangian | Role::KineticEnergy => (vec![q, qd], Some(Shape::Real)),
        Role::PotentialEnergy => (vec![q], Some(Shape::Real)),
        Role::QuasiLagrangian => (vec![q, w], Some(Shape::Real)),
        Role::Constraints => (vec![q, qd], None),
        Role::QuasiVelocities => (vec![q, qd], p.map(|p| real_array(n - p))),
        Role::Velocities => (vec![q, w], Some(real_array(n))),
        Role::Holonomic => (vec![q], None),
        Role::Forces => {
            return (
                vec![("t", Shape::Real), q, qd, ("u", real_array(m))],
                Some(real_array(n)),
            );
        }
    };
    if timed {
        args.insert(0, ("t", Shape::Real));
    }
    (args, out)
}

/// "1 constraint", "2 constraints".
fn count(k: usize, what: &str) -> String {
    if k == 1 {
        format!("1 {what}")
    } else if let Some(stem) = what.strip_suffix('y') {
        format!("{k} {stem}ies")
    } else {
        format!("{k} {what}s")
    }
}

fn fail(lowerer: &mut Lowerer<'_, '_>, ok: &mut bool, e: syn::Error) {
    lowerer.push_error(e);
    *ok = false;
}

/// Where the roles go, for messages about a missing one (it may be in another impl block).
const ONE_BLOCK: &str = "All the roles of a model must be in the impl block that carries \
                         `#[hamel_system]`";

fn required<'r, 'a>(
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
fn forgotten<'a>(roles: &Roles<'a>, role: Role) -> Option<&'a syn::ImplItemFn> {
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

/// Exactly one way of giving the energy.
fn energy_roles<'a>(
    roles: &Roles<'a>,
    lowerer: &mut Lowerer<'_, '_>,
    at: &TokenStream,
    ok: &mut bool,
) -> Option<Energy<'a>> {
    let l = roles.get(Role::Lagrangian);
    let t = roles.get(Role::KineticEnergy);
    let v = roles.get(Role::PotentialEnergy);
    let lq = roles.get(Role::QuasiLagrangian);
    let mut conflict = |second: &RoleFn<'_>, first: Role, message: &str| {
        let holder = roles
            .get(first)
            .map(|rf| format!(" (`{}`)", rf.f.sig.ident))
            .unwrap_or_default();
        lowerer.push_error(syn::Error::new_spanned(
            second.attr,
            format!(
                "ambiguous energy: this model already has a `#[{}]`{holder}; {message}",
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
            let message = format!("missing role: the model needs its energy; {give}. {ONE_BLOCK}");
            lowerer.push_error(match forgotten(roles, Role::KineticEnergy)
                .or_else(|| forgotten(roles, Role::Lagrangian))
            {
                Some(f) => syn::Error::new_spanned(
                    &f.sig.ident,
                    format!(
                        "missing role: no function is marked as the model's energy; if `{}` is the \
                         kinetic energy T, put `#[kinetic_energy]` above it (`#[lagrangian]` if it \
                         is L = T − V)",
                        f.sig.ident
                    ),
                ),
                None => syn::Error::new_spanned(at, message),
            });
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

/// Compare a role function's signature with what its role needs (`expected`: its arguments
/// and result; `names`: the coordinates and inputs).
fn check_signature(
    role: Role,
    rf: &RoleFn<'_>,
    expected: &(Vec<(&str, Shape)>, Option<Shape>),
    lowerer: &mut Lowerer<'_, '_>,
    names: (&[syn::Ident], &[syn::Ident]),
    p: Option<usize>,
) -> bool {
    let (expected, output) = (&expected.0, expected.1.as_ref());
    let (coordinates, inputs) = names;
    let f = rf.f;
    let Some(sig) = lowerer.signature(f) else {
        return false;
    };
    let rendered = render(role, expected, output);
    let mut ok = true;
    if sig.args.len() != expected.len() {
        let why = match role {
            Role::Holonomic => {
                "; a holonomic constraint f(q) = 0 depends on the configuration (and, with a \
                 leading `t: f64`, the time) only: the macro derives its velocity row"
            }
            Role::Forces => "",
            _ => " (or with a leading `t: f64`)",
        };
        lowerer.push_error(syn::Error::new_spanned(
            &f.sig.inputs,
            format!(
                "`#[{}]` takes {} besides `&self`, this function takes {}: expected \
                 `{rendered}`{why}",
                role.attribute(),
                count(expected.len(), "argument"),
                sig.args.len()
            ),
        ));
        return false;
    }
    if let Some(e) = misplaced(role, &sig.args, expected, &rendered) {
        lowerer.push_error(e);
        return false;
    }
    for (arg, (name, shape)) in sig.args.iter().zip(expected) {
        if arg.shape != *shape {
            let why = match shape {
                Shape::Array(_, _) if *name == "u" && inputs.is_empty() => {
                    "one per input, and the model declares none (name them in \
                     `#[hamel_system(inputs(..))]`)"
                        .to_string()
                }
                Shape::Array(..) if *name == "u" => {
                    format!("one per input ({})", names_of(inputs))
                }
                Shape::Array(..) => format!("one per coordinate ({})", names_of(coordinates)),
                _ => "the time".to_string(),
            };
            lowerer.push_error(syn::Error::new_spanned(
                &arg.ty,
                format!(
                    "argument `{}` of `#[{}]` must be {}, {why}; found {}. Expected `{rendered}`",
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
        let (attribute, want, got) = (role.attribute(), want.describe(), got.describe());
        let message = match (role, p) {
            (Role::QuasiVelocities, Some(p)) => format!(
                "`#[{attribute}]` must return {want}, found {got}: with {} and {}, {} complete the \
                 constraints to ω = A(q)·qd",
                count(coordinates.len(), "coordinate"),
                count(p, "constraint"),
                count(coordinates.len() - p, "quasi-velocity"),
            ),
            (Role::Velocities | Role::Forces, _) => format!(
                "`#[{attribute}]` must return {want}, one per coordinate ({}); found {got}",
                names_of(coordinates)
            ),
            _ => format!("`#[{attribute}]` must return {want}, found {got}"),
        };
        lowerer.push_error(error_at_output(f, message));
        ok = false;
    }
    ok && sig.output.is_some()
}

/// The name an argument is written with, without the leading underscores that only silence
/// "unused" warnings: `_q` is `q`. `None` for a pattern that is not a plain name.
pub fn argument_name(pat: &syn::Pat) -> Option<String> {
    match pat {
        syn::Pat::Ident(p) => Some(
            p.ident
                .unraw()
                .to_string()
                .trim_start_matches('_')
                .to_string(),
        ),
        _ => None,
    }
}

/// Arguments named as other arguments of the role (`fn(&self, qd, q)`): the names would say
/// one thing and the positions another, so the order is an error (other names, `config`,
/// `vel`, are the user's choice). One error for the whole list, at the first misplaced one.
fn misplaced(
    role: Role,
    args: &[Arg],
    expected: &[(&str, Shape)],
    rendered: &str,
) -> Option<syn::Error> {
    let swaps: Vec<(&Arg, &str)> = args
        .iter()
        .zip(expected)
        .filter_map(|(arg, (place, _))| {
            let name = argument_name(&arg.pat)?;
            let other = expected.iter().any(|(e, _)| *e == name);
            (other && name != *place).then_some((arg, *place))
        })
        .collect();
    let (first, place) = swaps.first()?;
    let rest: Vec<String> = swaps[1..]
        .iter()
        .map(|(arg, place)| {
            format!(
                " and `{}` in the place of `{place}`",
                arg.pat.to_token_stream()
            )
        })
        .collect();
    Some(syn::Error::new_spanned(
        &first.pat,
        format!(
            "argument `{}` is in the place of `{place}`{}: `#[{}]` takes `{rendered}`; put the \
             arguments in this order",
            first.pat.to_token_stream(),
            rest.concat(),
            role.attribute()
        ),
    ))
}

fn render(role: Role, args: &[(&str, Shape)], output: Option<&Shape>) -> String {
    let args: Vec<String> = args
        .iter()
        .map(|(n, s)| match s {
            Shape::Real => format!("{n}: f64"),
            other => format!("{n}: &{}", other.describe().trim_matches('`')),
        })
        .collect();
    let unknown = if role == Role::Holonomic {
        "[f64; K]"
    } else {
        "[f64; P]"
    };
    let out = output.map_or_else(
        || unknown.to_string(),
        |s| s.describe().trim_matches('`').to_string(),
    );
    format!("fn(&self, {}) -> {out}", args.join(", "))
}
