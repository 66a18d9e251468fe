//! How many constraint rows a model has: the nonholonomic constraints' and the holonomic
//! ones', and the coordinates the holonomic constraints determine.

use super::{count, error_at_output, fail};
use crate::engine::lower::{Lowerer, Shape};
use crate::system::model::{RoleFn, names_of};
use syn::ext::IdentExt;

/// k, from the holonomic function's result type: at least one constraint (0 without one).
pub(super) fn holonomic_count(
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
pub(super) fn dependent_coordinates(
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
pub(super) fn constraint_count(
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
