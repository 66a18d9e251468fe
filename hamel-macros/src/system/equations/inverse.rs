//! A closed-form inverse must invert the rows. A typo in it would not show in the motion's
//! kinematics, only (through the momenta of the constrained directions and the γ terms) as
//! a wrong acceleration, so it is checked here: B(q)·A(q) − I and Q₀ + B·a (Q₀ = −B a when
//! Q inverts ω = A q̇ + a) are evaluated at a few configurations and parameter values
//! (generic ones, the same every build). Row r of the defect is the velocity of coordinate
//! r as the inverse gives it, which names the mistake.

use super::dot;
use super::rows::{Rows, row_source};
use crate::engine::graph::NodeId;
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
    let n = b.len();
    let g = &mut *lowerer.graph;
    let mut defect = Vec::with_capacity(n * (n + 1));
    for (r, b_row) in b.iter().enumerate() {
        for j in 0..n {
            let column: Vec<NodeId> = rows.a.iter().map(|a_row| a_row[j]).collect();
            let product = dot(g, b_row, &column);
            let identity = if r == j { g.one() } else { g.zero() };
            defect.push(g.sub(product, identity));
        }
    }
    for (b_row, &q0_r) in b.iter().zip(q0) {
        let drift = dot(g, b_row, &rows.offset);
        defect.push(g.add(q0_r, drift));
    }
    // What the generated `inverse_defect` reports: A·B − I (equivalent to B·A − I for a square
    // matrix, and what its documentation states), then the offset part.
    let mut reported = Vec::with_capacity(n * (n + 1));
    for (i, a_row) in rows.a.iter().enumerate() {
        for k in 0..n {
            let column: Vec<NodeId> = b.iter().map(|b_row| b_row[k]).collect();
            let product = dot(g, a_row, &column);
            let identity = if i == k { g.one() } else { g.zero() };
            reported.push(g.sub(product, identity));
        }
    }
    reported.extend_from_slice(&defect[n * n..]);
    let mut bad_rows: Option<Vec<(usize, f64, bool)>> = None;
    let mut failures = 0;
    for values in generic::points(3, g.input_count()) {
        let d = g.evaluate(&defect, &values);
        if d.iter().any(|x| !x.is_finite()) {
            continue; // outside the inverse's domain here: no verdict from this point
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
            bad_rows.get_or_insert(wrong);
        }
    }
    match bad_rows {
        Some(wrong) if failures >= 2 => {
            for (r, worst, linear) in wrong {
                let name = &spec.coordinates[r];
                let how = if linear {
                    format!(
                        "B(q)·A(q) differs from the identity by {} in this row",
                        super::significant(worst)
                    )
                } else {
                    format!(
                        "at w = 0 it gives {} where the rows' parts without velocities require \
                         −B·a",
                        super::significant(worst)
                    )
                };
                lowerer.push_error(syn::Error::new_spanned(
                    row_source(f, r),
                    format!(
                        "`#[velocities]` is not the inverse of the constraints and quasi-velocities: \
                         the velocity of `{name}` it gives is wrong (at a generic configuration \
                         {how}); q̇ = B·(w − a) must solve w = A·q̇ + a for every w, including the \
                         constrained entries"
                    ),
                ));
            }
            None
        }
        _ => Some(reported),
    }
}
