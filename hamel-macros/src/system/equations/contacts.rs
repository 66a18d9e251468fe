//! The rows a model's rolling contacts give: two nonholonomic rows per contact (no slip along
//! the surface), and, for each contact whose height above its surface varies with the
//! coordinates, that height as a holonomic constraint, matched with the coordinate
//! `#[contacts(determines(..))]` names for it. A height that is zero whatever the
//! coordinates (the rear wheel of a bicycle whose coordinates are its contact point) is
//! built into the coordinates and adds no row.

use super::bodies::{self, Motion};
use super::rows::row_source;
use crate::engine::graph::NodeId;
use crate::engine::lower::Lowerer;
use crate::system::generic;
use crate::system::spec::{Contacts, Spec};

/// The contacts' rows: nonholonomic (two per contact), and the heights that are holonomic
/// constraints, in the order of the contacts.
#[derive(Default)]
pub struct ContactRows {
    pub rows: Vec<NodeId>,
    pub heights: Vec<NodeId>,
}

/// Relative size below which a height counts as zero at a generic point.
const FLAT: f64 = 1e-10;

/// The contacts' rows in the velocity symbols `v`; `None` after a mistake (reported).
pub fn build<'a>(
    lowerer: &mut Lowerer<'a, '_>,
    spec: &Spec<'a>,
    t: NodeId,
    q: &[NodeId],
    v: &[NodeId],
) -> Option<ContactRows> {
    let Some(declared) = &spec.geometry.contacts else {
        return Some(ContactRows::default());
    };
    let contacts = bodies::contacts(lowerer, spec, t, q)?;
    let g = &mut *lowerer.graph;
    let mut motion = Motion::new(g, t, q, v);
    let rows = bodies::rolling_rows(g, &contacts, &mut motion);
    let all = bodies::heights(g, &contacts);
    let varying = varying_heights(lowerer, declared, &all, t, q)?;
    let heights = varying.iter().map(|&i| all[i]).collect();
    Some(ContactRows { rows, heights })
}

/// The contacts whose heights vary with the coordinates (or the time): one for each
/// coordinate named in `determines(..)`. A height that is constant but not zero, or a
/// count that does not match, is an error.
fn varying_heights(
    lowerer: &mut Lowerer<'_, '_>,
    declared: &Contacts<'_>,
    heights: &[NodeId],
    t: NodeId,
    q: &[NodeId],
) -> Option<Vec<usize>> {
    let g = &*lowerer.graph;
    let moving: Vec<NodeId> = std::iter::once(t).chain(q.iter().copied()).collect();
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
                format!(
                    "contact {i} is not on its surface: its height above it is {} at every \
                     configuration; the contact point must touch the surface (the ground is \
                     the plane z = 0)",
                    super::significant(values.first().copied().unwrap_or(f64::NAN))
                ),
            ));
            continue;
        }
        varying.push(i);
    }
    if varying.len() != declared.dependent.len() && errors.is_empty() {
        errors.push(count_error(declared, &varying));
    }
    if errors.is_empty() {
        return Some(varying);
    }
    for e in errors {
        lowerer.push_error(e);
    }
    None
}

/// `determines(..)` names more or fewer coordinates than there are contacts whose height
/// varies.
fn count_error(declared: &Contacts<'_>, varying: &[usize]) -> syn::Error {
    let which: Vec<String> = varying.iter().map(|i| i.to_string()).collect();
    let named = declared.dependent.len();
    let message = match (varying.len(), named) {
        (0, _) => format!(
            "`determines(..)` names {named} coordinate(s), but no contact's height varies with \
             the coordinates: each contact stays on its surface by the choice of coordinates; \
             remove `determines(..)`"
        ),
        (v, 0) => format!(
            "the height above the surface of contact {} varies with the coordinates: it is a \
             holonomic constraint, which must determine a coordinate; name one per such \
             contact, `#[contacts(determines(theta))]` ({v} in all)",
            which.join(", ")
        ),
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
