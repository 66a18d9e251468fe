//! The rows a model's rolling contacts give, read before the model's shape is settled (how
//! many rows and holonomic constraints it has depends on them): two nonholonomic rows per
//! contact (no slip along the surface), less those that repeat the others at every
//! configuration (two wheels on one axle), and, for each contact whose height above its
//! surface varies with the coordinates, that height as a holonomic constraint, matched with
//! the coordinate `#[contacts(determines(..))]` names for it. A height that is zero whatever
//! the coordinates (the rear wheel of a bicycle whose coordinates are its contact point) is
//! built into the coordinates and adds no row.
//!
//! Reading them also checks what a geometry can get silently wrong: a contact on a body that
//! is not among the model's bodies, a written contact point that is not the body's point
//! touching the surface, a contact that is not on its surface, rows that contradict each
//! other.

use super::bodies::{self, Motion};
use super::rows::{coefficients, row_source};
use crate::engine::graph::{Graph, NodeId};
use crate::engine::lower::geometry::{self, Body, Contact, Geo, GeoKind, contact_frame};
use crate::engine::lower::{Lowerer, Value};
use crate::system::generic;
use crate::system::model::RoleFn;
use crate::system::rank;
use crate::system::spec::Symbols;

/// What the contacts give the model.
#[derive(Default)]
pub struct ContactReading {
    /// The rolling rows kept, in the velocity symbols.
    pub rows: Vec<NodeId>,
    /// Their places among the 2C rows (contact i's are 2i, along its first tangent, and
    /// 2i + 1).
    pub kept: Vec<usize>,
    /// The rows left out, each with the kept rows it is a combination of.
    pub repeats: Vec<Repeat>,
    /// The heights that are holonomic constraints, and their contacts.
    pub heights: Vec<NodeId>,
    pub varying: Vec<usize>,
    /// The body of `#[bodies]` each contact is on (by its index), where the model has them.
    pub bodies: Vec<Option<usize>>,
    /// Which contacts roll by a wheel's shape (their rows are along its heading and axle).
    pub wheels: Vec<bool>,
}

/// A rolling row that is a combination of the kept rows before it at every configuration.
pub struct Repeat {
    pub row: usize,
    /// The row it repeats up to a constant factor, with the factor, if it does.
    pub of: Option<(usize, f64)>,
}

/// Relative size below which a height counts as zero at a generic point.
const FLAT: f64 = 1e-10;

/// Relative size below which a written contact point's normal velocity over its body counts
/// as rounding.
const ON_BODY: f64 = 1e-9;

/// The contacts of `#[contacts]` (`timed`: it takes the time first), with the bodies of
/// `#[bodies]` if any, read at the symbols; `None` after a mistake (reported).
pub fn read<'a>(
    lowerer: &mut Lowerer<'a, '_>,
    declared: &RoleFn<'a>,
    timed: bool,
    bodies: Option<(&'a syn::ImplItemFn, bool)>,
    (symbols, coordinates): (&Symbols, &[syn::Ident]),
) -> Option<ContactReading> {
    let contacts = lower_all(lowerer, declared.f, timed, symbols, GeoKind::Contact)?;
    let contacts: Vec<Contact> = contacts
        .into_iter()
        .filter_map(|geo| match geo {
            Geo::Contact(c) => Some(*c),
            _ => None,
        })
        .collect();
    let on = match bodies {
        Some((f, timed)) => {
            let bodies = lower_all(lowerer, f, timed, symbols, GeoKind::Body)?;
            let bodies: Vec<Body> = bodies
                .into_iter()
                .filter_map(|geo| match geo {
                    Geo::Body(b) => Some(*b),
                    _ => None,
                })
                .collect();
            among_bodies(lowerer, declared.f, &contacts, &bodies)?
        }
        None => vec![None; contacts.len()],
    };
    let g = &mut *lowerer.graph;
    let mut motion = Motion::new(g, symbols.t, &symbols.q, &symbols.v);
    let all = bodies::rolling_rows(g, &contacts, &mut motion);
    points_on_bodies(lowerer, declared.f, &contacts, &mut motion)?;
    let (kept, repeats) = independent_rows(lowerer, declared.f, &all, &symbols.v)?;
    let g = &mut *lowerer.graph;
    let heights = bodies::heights(g, &contacts);
    let varying = varying_heights(lowerer, declared, &heights, (symbols, coordinates))?;
    Some(ContactReading {
        rows: kept.iter().map(|&i| all[i]).collect(),
        kept,
        repeats,
        heights: varying.iter().map(|&i| heights[i]).collect(),
        varying,
        bodies: on,
        wheels: contacts
            .iter()
            .map(|c| c.body.shape.as_ref().is_some_and(|s| s.kind.is_wheel()))
            .collect(),
    })
}

/// The array of vocabulary values a role returns at the symbols' t and q.
fn lower_all<'a>(
    lowerer: &mut Lowerer<'a, '_>,
    f: &'a syn::ImplItemFn,
    timed: bool,
    symbols: &Symbols,
    kind: GeoKind,
) -> Option<Vec<Geo>> {
    let mut args = Vec::with_capacity(2);
    if timed {
        args.push(Value::Real(symbols.t));
    }
    args.push(super::array(&symbols.q));
    bodies::items(lowerer.call_role(f, args), kind)
}

/// The body of `#[bodies]` each contact is on; an error for a contact on a body that is not
/// one of them (its mass and inertia would be in no energy, and a scene would not draw it).
fn among_bodies(
    lowerer: &mut Lowerer<'_, '_>,
    f: &syn::ImplItemFn,
    contacts: &[Contact],
    bodies: &[Body],
) -> Option<Vec<Option<usize>>> {
    let same = |a: &Body, b: &Body| {
        a.mass == b.mass
            && a.inertia == b.inertia
            && a.centre.at == b.centre.at
            && a.orientation.matrix == b.orientation.matrix
    };
    let mut on = Vec::with_capacity(contacts.len());
    let mut ok = true;
    for (i, c) in contacts.iter().enumerate() {
        match bodies.iter().position(|b| same(b, &c.body)) {
            Some(j) => on.push(Some(j)),
            None => {
                ok = false;
                lowerer.push_error(syn::Error::new_spanned(
                    row_source(f, i),
                    format!(
                        "contact {i} is on a body that is not among the model's bodies: its \
                         mass, inertia, centre or orientation differs from each of the {} \
                         `#[bodies]` returns, so its motion is not the one the equations \
                         describe; take the body from them, `let [wheel, ..] = \
                         self.bodies(q);`, and give it to the contact",
                        bodies.len()
                    ),
                ));
            }
        }
    }
    ok.then_some(on)
}

/// A contact point that is written (not found from a shape) must be the body's point that
/// touches the surface: then it slides over the body only within the common tangent plane,
/// n·(Ṗ − v_B(P)) = 0 along every motion (the envelope property of the point of a convex
/// body farthest along −n). A point beside the body, or below its centre when the body leans,
/// moves off it along the normal, and its rows would constrain the wrong motion.
fn points_on_bodies(
    lowerer: &mut Lowerer<'_, '_>,
    f: &syn::ImplItemFn,
    contacts: &[Contact],
    motion: &mut Motion,
) -> Option<()> {
    let mut ok = true;
    for (i, c) in contacts.iter().enumerate().filter(|(_, c)| !c.from_shape) {
        let g = &mut *lowerer.graph;
        let travel = motion.rate(g, &c.point);
        let carried = motion.material_velocity(g, &c.body, c.point);
        let normal = contact_frame(g, c).normal;
        let over = geometry::sub(g, [travel[0], travel[1], travel[2]], carried);
        let off = geometry::dot(g, normal, over);
        let speeds = [geometry::norm(g, carried), geometry::norm(g, over)];
        let Some((value, scale)) = off_everywhere(g, off, speeds) else {
            continue;
        };
        ok = false;
        lowerer.push_error(syn::Error::new_spanned(
            row_source(f, i),
            format!(
                "the point of contact {i} is not where its body touches the surface: as the \
                 body moves, the point leaves it along the surface's normal (at {} against \
                 speeds of {} at a generic configuration); the contact point must be the \
                 body's point nearest the surface — the rim's lowest point for a wheel, \
                 `disk_contact(centre, axle, radius, up)` — or give the body a shape and write \
                 `Contact::rolling(body, surface)`",
                super::significant(value),
                super::significant(scale),
            ),
        ));
    }
    ok.then_some(())
}

/// The value of `off` and the scale at the first generic point, if it is beyond rounding of
/// the scale at every (finite) point of at least two.
fn off_everywhere(g: &Graph, off: NodeId, scales: [NodeId; 2]) -> Option<(f64, f64)> {
    let mut first = None;
    let mut finite = 0;
    for point in generic::points(3, g.input_count()) {
        let [value, a, b] = g.evaluate(&[off, scales[0], scales[1]], &point)[..] else {
            continue;
        };
        if !(value.is_finite() && a.is_finite() && b.is_finite()) {
            continue;
        }
        finite += 1;
        let scale = a.max(b);
        if value.abs() <= ON_BODY * scale {
            return None;
        }
        first.get_or_insert((value, scale));
    }
    first.filter(|_| finite >= 2)
}

/// The rows to keep: each row unless it is a combination of the kept rows before it at every
/// generic point (its coefficients and its part without velocities alike: a moving surface's
/// rows are affine). A row whose coefficients are such a combination but whose part without
/// velocities is not contradicts the others: no motion satisfies them all, an error.
fn independent_rows(
    lowerer: &mut Lowerer<'_, '_>,
    f: &syn::ImplItemFn,
    rows: &[NodeId],
    v: &[NodeId],
) -> Option<(Vec<usize>, Vec<Repeat>)> {
    let g = &mut *lowerer.graph;
    let (a, offset) = coefficients(g, rows, v);
    // Each row with its part without velocities appended.
    let augmented: Vec<Vec<NodeId>> = a
        .iter()
        .zip(&offset)
        .map(|(row, &o)| row.iter().copied().chain([o]).collect())
        .collect();
    let samples = rank::samples(g, &augmented);
    let mut kept = Vec::new();
    let mut repeats = Vec::new();
    for i in 0..rows.len() {
        let verdict = |with_offset: bool| {
            samples.iter().all(|rows| {
                let width = if with_offset {
                    rows[0].len()
                } else {
                    rows[0].len() - 1
                };
                let before: Vec<&[f64]> = kept.iter().map(|&k: &usize| &rows[k][..width]).collect();
                rank::in_span(&before, &rows[i][..width])
            })
        };
        if samples.len() < 2 || !verdict(false) {
            kept.push(i);
            continue;
        }
        if !verdict(true) {
            let contact = i / 2;
            lowerer.push_error(syn::Error::new_spanned(
                row_source(f, contact),
                format!(
                    "the rows of contact {contact} contradict those of the contacts before it: \
                     they constrain the same directions of motion to different velocities, so \
                     no motion satisfies them all (two wheels on one axle rolling on surfaces \
                     that move differently)"
                ),
            ));
            return None;
        }
        let of = kept.iter().find_map(|&k| {
            let ratios: Vec<f64> = samples
                .iter()
                .filter_map(|rows| rank::factor(&rows[i], &rows[k]))
                .collect();
            let first = *ratios.first()?;
            (ratios.len() == samples.len()
                && ratios
                    .iter()
                    .all(|r| (r - first).abs() <= 1e-9 * first.abs()))
            .then_some((k, first))
        });
        repeats.push(Repeat { row: i, of });
    }
    Some((kept, repeats))
}

/// The contacts whose heights vary with the coordinates (or the time): one for each
/// coordinate named in `determines(..)`. A height that is constant but not zero, or a
/// count that does not match, is an error.
fn varying_heights(
    lowerer: &mut Lowerer<'_, '_>,
    declared: &RoleFn<'_>,
    heights: &[NodeId],
    (symbols, coordinates): (&Symbols, &[syn::Ident]),
) -> Option<Vec<usize>> {
    let g = &*lowerer.graph;
    let moving: Vec<NodeId> = std::iter::once(symbols.t)
        .chain(symbols.q.iter().copied())
        .collect();
    let depends = g.depends_on(&moving);
    let points = generic::points(3, g.input_count());
    let mut varying = Vec::new();
    let mut errors = Vec::new();
    for (i, &h) in heights.iter().enumerate() {
        let values: Vec<f64> = points
            .iter()
            .map(|p| g.evaluate(&[h], p)[0])
            .filter(|x| x.is_finite())
            .collect();
        let zero = values.iter().all(|x| x.abs() <= FLAT);
        if zero {
            continue;
        }
        if !depends[h.index()] {
            errors.push(syn::Error::new_spanned(
                row_source(declared.f, i),
                off_surface(lowerer, i, h, &values),
            ));
            continue;
        }
        varying.push(i);
    }
    if varying.len() != declared.determines.len() && errors.is_empty() {
        let g = &*lowerer.graph;
        // The coordinates each varying height varies with, by the user's names.
        let with: Vec<Vec<String>> = varying
            .iter()
            .map(|&i| {
                symbols
                    .q
                    .iter()
                    .zip(coordinates)
                    .filter(|(q, _)| g.depends_on(&[**q])[heights[i].index()])
                    .map(|(_, name)| name.to_string())
                    .collect()
            })
            .collect();
        errors.push(count_error(declared, &varying, &with));
    }
    if errors.is_empty() {
        return Some(varying);
    }
    for e in errors {
        lowerer.push_error(e);
    }
    None
}

/// Contact `i` is not on its surface, at the height `h` whatever the coordinates (`values`
/// at generic points): the height is quoted only when no parameter enters it, since the
/// parameters' values at generic points are placeholders, not the user's.
fn off_surface(lowerer: &Lowerer<'_, '_>, i: usize, h: NodeId, values: &[f64]) -> String {
    let g = &*lowerer.graph;
    let parameters: Vec<String> = lowerer
        .externals
        .items
        .iter()
        .filter(|e| g.depends_on(&[e.node])[h.index()])
        .map(|e| format!("`{}`", e.tokens.to_string().replace(' ', "")))
        .collect();
    let height = if parameters.is_empty() {
        format!(
            "is {} at every configuration",
            super::significant(values.first().copied().unwrap_or(f64::NAN))
        )
    } else {
        format!(
            "is the same at every configuration and not zero: it depends only on {}",
            parameters.join(", ")
        )
    };
    format!(
        "contact {i} is not on its surface: its height above it {height}; the contact point \
         must touch the surface (the ground is the plane z = 0)"
    )
}

/// `determines(..)` names more or fewer coordinates than there are contacts whose height
/// varies (`with`: the coordinates each varies with).
fn count_error(declared: &RoleFn<'_>, varying: &[usize], with: &[Vec<String>]) -> syn::Error {
    let which: Vec<String> = varying.iter().map(|i| i.to_string()).collect();
    let named = declared.determines.len();
    let message = match (varying.len(), named) {
        (0, _) => format!(
            "`determines(..)` names {named} coordinate(s), but no contact's height varies with \
             the coordinates: each contact stays on its surface by the choice of coordinates; \
             remove `determines(..)`"
        ),
        (v, 0) => {
            let first = with.first().map(Vec::as_slice).unwrap_or_default();
            let names: Vec<String> = first.iter().map(|n| format!("`{n}`")).collect();
            let example: Vec<String> = with
                .iter()
                .map(|w| w.first().cloned().unwrap_or_default())
                .collect();
            format!(
                "the height above the surface of contact {} varies with the coordinates ({}): \
                 if the body should stay on the surface whatever they are (a wheel on an \
                 incline), place it on the surface, its centre from the surface's frame; if the \
                 height is a holonomic constraint, name the coordinate it determines, one per \
                 such contact ({v} in all), among those it varies with: \
                 `#[contacts(determines({}))]`",
                which.join(", "),
                names.join(", "),
                example.join(", ")
            )
        }
        (v, _) => format!(
            "the heights of {v} contact(s) ({}) vary with the coordinates, but \
             `determines(..)` names {named} coordinate(s): name one per such contact, in order",
            which.join(", ")
        ),
    };
    let at: &dyn quote::ToTokens = if named == 0 {
        &declared.f.sig.ident
    } else {
        declared.attr
    };
    syn::Error::new_spanned(at, message)
}
