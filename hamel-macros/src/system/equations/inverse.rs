//! A closed-form inverse must invert the rows. A typo in it would not show in the motion's
//! kinematics, only (through the momenta of the constrained directions and the γ terms) as
//! a wrong acceleration, so it is checked here: B(q)·A(q) − I and Q₀ + B·a (Q₀ = −B a when
//! Q inverts ω = A q̇ + a) are evaluated at a few configurations and parameter values
//! (generic ones, the same every build). Row r of the defect is the velocity of coordinate
//! r as the inverse gives it, which names the mistake.

use super::dot;
use super::rows::{Rows, row_source};
use crate::engine::graph::{Graph, NodeId};
use crate::engine::lower::Lowerer;
use crate::system::generic;
use crate::system::spec::Spec;

/// Largest defect entry at a generic point that is rounding, not a mistake.
const TOLERANCE: f64 = 1e-6;

/// The defect nodes the generated code reports (A·B − I row by row, then Q₀ + B·a), or `None`
/// with an error at each wrong row of the user's inverse (found from B·A − I, whose row r
/// belongs to coordinate r).
pub fn check(
    lowerer: &mut Lowerer<'_, '_>,
    spec: &Spec<'_>,
    f: &syn::ImplItemFn,
    rows: &Rows,
    b: &[Vec<NodeId>],
    q0: &[NodeId],
) -> Option<Vec<NodeId>> {
    let (defect, reported) = defects(lowerer.graph, rows, b, q0);
    let Some(wrong) = wrong_rows(lowerer.graph, &defect, b.len()) else {
        return Some(reported);
    };
    for (r, worst, linear) in wrong {
        let name = &spec.coordinates[r];
        let how = if linear {
            format!(
                "B(q)·A(q) differs from the identity by {} in this row",
                super::significant(worst)
            )
        } else {
            format!(
                "at w = 0 it gives {} where the rows' parts without velocities require −B·a",
                super::significant(worst)
            )
        };
        lowerer.push_error(syn::Error::new_spanned(
            row_source(f, r),
            format!(
                "`#[velocities]` is not the inverse of the constraints and quasi-velocities: \
                 the velocity of `{name}` it gives is wrong (at a generic configuration {how}); \
                 q̇ = B·(w − a) must solve w = A·q̇ + a for every w, including the constrained \
                 entries"
            ),
        ));
    }
    None
}

/// B·A − I row by row then Q₀ + B·a (row r belongs to coordinate r: what a diagnosis needs),
/// and what the generated `inverse_defect` reports: A·B − I (equivalent for a square matrix,
/// and what its documentation states), then the same offset part.
fn defects(
    g: &mut Graph,
    rows: &Rows,
    b: &[Vec<NodeId>],
    q0: &[NodeId],
) -> (Vec<NodeId>, Vec<NodeId>) {
    let n = b.len();
    let product = |g: &mut Graph, left: &[Vec<NodeId>], right: &[Vec<NodeId>]| {
        let mut out = Vec::with_capacity(n * n);
        for (i, row) in left.iter().enumerate() {
            for k in 0..n {
                let column: Vec<NodeId> = right.iter().map(|r| r[k]).collect();
                let entry = dot(g, row, &column);
                let identity = if i == k { g.one() } else { g.zero() };
                out.push(g.sub(entry, identity));
            }
        }
        out
    };
    let mut defect = product(g, b, &rows.a);
    let mut reported = product(g, &rows.a, b);
    for (b_row, &q0_r) in b.iter().zip(q0) {
        let drift = dot(g, b_row, &rows.offset);
        let offset = g.add(q0_r, drift);
        defect.push(offset);
        reported.push(offset);
    }
    (defect, reported)
}

/// The rows of the defect that are wrong at a generic point — (row, worst entry, whether in
/// the linear part) — when at least two of three points agree; `None` when the inverse is
/// right (a point outside the inverse's domain gives no verdict).
fn wrong_rows(g: &Graph, defect: &[NodeId], n: usize) -> Option<Vec<(usize, f64, bool)>> {
    let mut first: Option<Vec<(usize, f64, bool)>> = None;
    let mut failures = 0;
    for values in generic::points(3, g.input_count()) {
        let d = g.evaluate(defect, &values);
        if d.iter().any(|x| !x.is_finite()) {
            continue;
        }
        let worst = |r: usize| {
            d[r * n..(r + 1) * n]
                .iter()
                .fold(0.0f64, |m, x| m.max(x.abs()))
        };
        let wrong: Vec<(usize, f64, bool)> = (0..n)
            .filter_map(|r| {
                let (linear, offset) = (worst(r), d[n * n + r].abs());
                if linear > TOLERANCE {
                    Some((r, linear, true))
                } else if offset > TOLERANCE {
                    Some((r, offset, false))
                } else {
                    None
                }
            })
            .collect();
        if !wrong.is_empty() {
            failures += 1;
            first.get_or_insert(wrong);
        }
    }
    first.filter(|_| failures >= 2)
}
