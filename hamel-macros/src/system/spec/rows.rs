//! How many constraint rows a model has: the nonholonomic constraints' and the rolling
//! contacts', the holonomic ones' and the contacts' heights (the model's shape, from the
//! role functions' signatures), and the coordinates the holonomic constraints determine.

use super::signatures::{record_expected_signatures, takes_time};
use super::{Contacts, Holonomic, Symbols};
use super::{count, error_at_output, fail};
use crate::engine::lower::geometry::GeoKind;
use crate::engine::lower::{Lowerer, Shape};
use crate::system::equations::{self, ContactReading};
use crate::system::model::{Role, RoleFn, Roles, names_of};
use syn::ext::IdentExt;

/// k, from the holonomic function's result type: at least one constraint (0 without one).
/// `None` when the result type is not an array of them (reported): the rows cannot be counted,
/// and the checks that need their number (the quasi-velocities', the speed names') are left
/// out rather than made against a count that is wrong.
pub(super) fn holonomic_count(
    holonomic: Option<&RoleFn<'_>>,
    lowerer: &mut Lowerer<'_, '_>,
    ok: &mut bool,
) -> Option<usize> {
    let Some(h) = holonomic else {
        return Some(0);
    };
    let k = lowerer.signature(h.f).and_then(|sig| match sig.output {
        Some(Shape::Array(k, inner)) if *inner == Shape::Real => Some(k),
        _ => None,
    });
    match k {
        Some(k) if k > 0 => Some(k),
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
            None
        }
        None => {
            fail(
                lowerer,
                ok,
                error_at_output(
                    h.f,
                    "`#[holonomic]` must return an array `[f64; K]`, one entry per holonomic \
                     constraint f(q) = 0 (for one constraint, `-> [f64; 1]` and `[f]`)",
                ),
            );
            None
        }
    }
}

/// The coordinates named in `#[holonomic(determines(..))]` or
/// `#[contacts(determines(..))]`, as indices: each a coordinate, none named twice nor
/// already determined (`taken`, by the holonomic constraints). `k`: how many the role
/// needs (one per holonomic constraint), `None` for the contacts (one per contact whose
/// height varies, known once the bodies are lowered). `None` after a mistake (reported)
/// or when a holonomic role names none.
pub(super) fn dependent_coordinates(
    h: &RoleFn<'_>,
    k: Option<usize>,
    (coordinates, speeds): (&[syn::Ident], &[syn::Ident]),
    taken: &[usize],
    lowerer: &mut Lowerer<'_, '_>,
) -> Option<Vec<usize>> {
    let known: Vec<String> = coordinates.iter().map(|c| c.unraw().to_string()).collect();
    let what = if k.is_some() {
        "each holonomic constraint determines its own coordinate"
    } else {
        "each contact's height determines its own coordinate"
    };
    let mut indices = Vec::new();
    let mut good = true;
    for name in &h.determines {
        let plain = name.unraw().to_string();
        let message = match known.iter().position(|c| *c == plain) {
            Some(i) if indices.contains(&i) || taken.contains(&i) => {
                format!("`{name}` is named twice: {what}")
            }
            Some(i) => {
                indices.push(i);
                continue;
            }
            None if speeds.iter().any(|s| s.unraw() == plain) => format!(
                "`{name}` is a speed (a quasi-velocity), not a coordinate: a holonomic \
                 constraint f(q) = 0 determines one of the coordinates ({})",
                names_of(coordinates)
            ),
            None => {
                let hint = crate::engine::lower::closest(&plain, &known)
                    .map(|g| format!("; did you mean `{g}`?"))
                    .unwrap_or_default();
                format!(
                    "`{name}` is not a coordinate{hint} (the coordinates are {})",
                    names_of(coordinates)
                )
            }
        };
        lowerer.push_error(syn::Error::new(name.span(), message));
        good = false;
    }
    if let Some(k) = k.filter(|&k| good && !h.determines.is_empty() && indices.len() != k && k > 0)
    {
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
    let named = !h.determines.is_empty() || k.is_none();
    (good && named).then_some(indices)
}

/// The number of nonholonomic constraint rows: those of `#[constraints]` (from its result
/// type; at least one when the role is there) and the rolling contacts' (`contacts`: the
/// role, how many contacts and how many rows they keep). With the k holonomic ones they must
/// be fewer than the coordinates. `None` when they cannot be counted (the mistake is
/// reported).
pub(super) fn constraint_count(
    constraints: Option<&RoleFn<'_>>,
    contacts: Option<(&RoleFn<'_>, usize, usize)>,
    k: usize,
    coordinates: &[syn::Ident],
    lowerer: &mut Lowerer<'_, '_>,
    ok: &mut bool,
) -> Option<usize> {
    let n = coordinates.len();
    let written = match constraints {
        Some(c) => Some(constraint_rows(c, lowerer, ok)?),
        None => None,
    };
    let rolling = contacts.map_or(0, |(_, _, rows)| rows);
    let p = written.unwrap_or(0) + rolling;
    let blame = match (constraints, contacts) {
        (Some(c), _) => c.f,
        (None, Some((c, _, _))) => c.f,
        (None, None) => return None,
    };
    if p + k >= n {
        let holonomic = if k > 0 {
            format!(" and {}", count(k, "holonomic constraint"))
        } else {
            String::new()
        };
        let rows = match (written, contacts) {
            (Some(w), Some((_, c, _))) => format!(
                "{} and {} ({})",
                count(w, "constraint"),
                count(c, "rolling contact"),
                count(rolling, "independent row")
            ),
            (None, Some((_, c, _))) => format!(
                "{} ({})",
                count(c, "rolling contact"),
                count(rolling, "independent row")
            ),
            _ => count(p, "constraint"),
        };
        fail(
            lowerer,
            ok,
            error_at_output(
                blame,
                format!(
                    "{rows}{holonomic} on {} leave no motion: there must be fewer constraints \
                     than coordinates ({})",
                    count(n, "coordinate"),
                    names_of(coordinates)
                ),
            ),
        );
        return None;
    }
    Some(p)
}

/// The rows of `#[constraints]`, from its result type `[f64; P]`, P ≥ 1.
fn constraint_rows(c: &RoleFn<'_>, lowerer: &mut Lowerer<'_, '_>, ok: &mut bool) -> Option<usize> {
    let sig = lowerer.signature(c.f)?;
    match sig.output {
        Some(Shape::Array(0, inner)) if *inner == Shape::Real => {
            fail(
                lowerer,
                ok,
                error_at_output(
                    c.f,
                    "`#[constraints]` returns no constraint: a model needs at least one",
                ),
            );
            None
        }
        Some(Shape::Array(p, inner)) if *inner == Shape::Real => Some(p),
        Some(_) => {
            fail(
                lowerer,
                ok,
                error_at_output(
                    c.f,
                    "`#[constraints]` must return an array `[f64; P]`, one entry per constraint",
                ),
            );
            None
        }
        None => None,
    }
}

/// How many values of the vocabulary type `kind` a role returns, `[Body; B]`, at least
/// one; 0 without the role, `None` after a mistake (reported).
pub(super) fn geometry_count(
    rf: Option<&RoleFn<'_>>,
    kind: GeoKind,
    lowerer: &mut Lowerer<'_, '_>,
    ok: &mut bool,
) -> Option<usize> {
    let Some(rf) = rf else {
        return Some(0);
    };
    let attribute = rf_attribute(rf);
    let name = kind.name();
    let output = lowerer.signature(rf.f)?.output?;
    match output {
        Shape::Array(len, inner) if *inner == Shape::Geo(kind) && len > 0 => Some(len),
        Shape::Array(0, inner) if *inner == Shape::Geo(kind) => {
            fail(
                lowerer,
                ok,
                error_at_output(
                    rf.f,
                    format!(
                        "`#[{attribute}]` returns no `{name}`: return at least one, or remove the role"
                    ),
                ),
            );
            None
        }
        other => {
            fail(
                lowerer,
                ok,
                error_at_output(
                    rf.f,
                    format!(
                        "`#[{attribute}]` must return an array `[{name}; {}]`, found {}",
                        if kind == GeoKind::Body { "B" } else { "C" },
                        other.describe()
                    ),
                ),
            );
            None
        }
    }
}

fn rf_attribute(rf: &RoleFn<'_>) -> String {
    rf.attr
        .path()
        .segments
        .last()
        .map(|s| s.ident.to_string())
        .unwrap_or_default()
}

/// What the role functions' signatures say the model's shape is, once checked, with what
/// the contacts give (read as soon as the coordinates are known).
pub(super) struct ModelShape<'r, 'a> {
    pub(super) constraints: Option<&'r RoleFn<'a>>,
    pub(super) holonomic: Option<&'r RoleFn<'a>>,
    pub(super) contacts: Option<(&'r RoleFn<'a>, usize)>,
    pub(super) bodies: Option<(&'a syn::ImplItemFn, usize)>,
    /// What the contacts give, when they could be read.
    pub(super) reading: Option<ContactReading>,
    /// Holonomic constraints: `#[holonomic]`'s and the contacts' heights.
    pub(super) k: usize,
    /// All constraint rows, when they can be counted.
    pub(super) p: Option<usize>,
}

impl ModelShape<'_, '_> {
    /// The contacts' rows kept, and the heights that are holonomic constraints (as
    /// `determines(..)` names them when the contacts could not be read).
    pub(super) fn contact_rows(&self) -> (usize, usize) {
        match (&self.reading, self.contacts) {
            (Some(r), _) => (r.kept.len(), r.varying.len()),
            (None, Some((c, count))) => (2 * count, c.determines.len()),
            (None, None) => (0, 0),
        }
    }
}

/// The counts the signatures give — holonomic constraints, contacts, bodies — and, the
/// contacts read, every constraint row.
pub(super) fn model_shape<'r, 'a>(
    roles: &'r Roles<'a>,
    coordinates: &[syn::Ident],
    m: usize,
    symbols: &Symbols,
    lowerer: &mut Lowerer<'a, '_>,
    ok: &mut bool,
) -> ModelShape<'r, 'a> {
    let n = coordinates.len();
    let constraints = roles.get(Role::Constraints);
    let holonomic = roles.get(Role::Holonomic);
    let contacts_role = roles.get(Role::Contacts);
    record_expected_signatures(roles, n, m, None, lowerer);
    let counted = holonomic_count(holonomic, lowerer, ok);
    let contacts = geometry_count(contacts_role, GeoKind::Contact, lowerer, ok);
    let bodies = geometry_count(roles.get(Role::Bodies), GeoKind::Body, lowerer, ok);
    let contacts = contacts_role.zip(contacts);
    let bodies = roles
        .get(Role::Bodies)
        .zip(bodies)
        .map(|(b, count)| (b.f, count));
    let reading = contacts
        .filter(|(c, _)| readable(c.f, n, lowerer))
        .and_then(|(c, _)| {
            let timed = takes_time(Role::Contacts, c.f, n, m, None);
            let bodies = bodies
                .filter(|(f, _)| readable(f, n, lowerer))
                .map(|(f, _)| (f, takes_time(Role::Bodies, f, n, m, None)));
            equations::read_contacts(lowerer, c, timed, bodies, (symbols, coordinates))
        });
    let mut shape = ModelShape {
        constraints,
        holonomic,
        contacts,
        bodies,
        reading,
        k: 0,
        p: None,
    };
    let (rolling, heights) = shape.contact_rows();
    shape.k = counted.unwrap_or(0) + heights;
    shape.p = match contacts_role {
        // A failed `#[contacts]` or `#[holonomic]` leaves the rows uncounted.
        Some(_) if shape.reading.is_none() => None,
        _ if counted.is_none() => None,
        _ => {
            let contacts = contacts.map(|(c, count)| (c, count, rolling));
            constraint_count(constraints, contacts, shape.k, coordinates, lowerer, ok)
                .map(|p| p + shape.k)
        }
    };
    if shape.reading.is_some() {
        // The quasi-velocities' expected count, now that the contacts' rows are known.
        record_expected_signatures(roles, n, m, shape.p, lowerer);
    }
    shape
}

/// Whether a role of the coordinates alone (`#[bodies]`, `#[contacts]`) can be read: it
/// takes `q: &[f64; N]`, after the time or not (its other mistakes are reported by the
/// signature check, and the body's by reading it).
fn readable(f: &syn::ImplItemFn, n: usize, lowerer: &mut Lowerer<'_, '_>) -> bool {
    let Some(signature) = lowerer.signature(f) else {
        return false;
    };
    let coordinates = Shape::Array(n, Box::new(Shape::Real));
    match signature.args.as_slice() {
        [q] => q.shape == coordinates,
        [t, q] => t.shape == Shape::Real && q.shape == coordinates,
        _ => false,
    }
}

/// The coordinates the holonomic constraints and the contacts' heights determine: the
/// holonomic role and the contacts, or `None` after a mistake (reported).
#[allow(clippy::type_complexity)]
pub(super) fn dependent<'a>(
    shape: &mut ModelShape<'_, 'a>,
    names: (&[syn::Ident], &[syn::Ident]),
    lowerer: &mut Lowerer<'_, '_>,
    ok: &mut bool,
) -> Option<(Option<Holonomic<'a>>, Option<Contacts<'a>>)> {
    let (_, heights) = shape.contact_rows();
    let holonomic = match shape.holonomic {
        Some(h) => {
            let k = shape.k - heights;
            let Some(dependent) = dependent_coordinates(h, Some(k), names, &[], lowerer) else {
                *ok = false;
                return None;
            };
            Some(Holonomic { f: h.f, dependent })
        }
        None => None,
    };
    let taken = holonomic.as_ref().map_or(&[][..], |h| &h.dependent[..]);
    let contacts = match shape.contacts {
        Some((c, _)) => {
            let Some(dependent) = dependent_coordinates(c, None, names, taken, lowerer) else {
                *ok = false;
                return None;
            };
            let Some(reading) = shape.reading.take() else {
                *ok = false;
                return None;
            };
            Some(Contacts {
                f: c.f,
                attr: c.attr,
                reading,
                dependent,
            })
        }
        None => None,
    };
    Some((holonomic, contacts))
}
