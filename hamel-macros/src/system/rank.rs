//! Is A(q) singular at every q? Rows that repeat a constraint, or that are any linear
//! combination of the rows before them, leave ω = A(q)·q̇ without an inverse anywhere, and a
//! simulation would only fail at its first step. A matching of rows to columns
//! (`sparse_lu`) finds the structural cases; this finds the numeric ones, by the rank of A
//! at a few generic points.

use super::generic;
use crate::engine::graph::NodeId;
use crate::engine::lower::Lowerer;
use syn::ext::IdentExt;

/// A row of A, with the function it comes from: a constraint row named as at run time
/// (`blade1`, `wheel0_x`), a quasi-velocity as the entry of its function's result
/// (`speeds[1]`).
pub struct Row<'a> {
    pub f: &'a syn::ImplItemFn,
    pub index: usize,
    /// Whether the row is a constraint (else a quasi-velocity).
    pub constraint: bool,
    /// For a rolling contact's row, the direction of the slip it forbids (`index` is then
    /// the contact's).
    pub slip: Option<&'static str>,
}

impl Row<'_> {
    fn name(&self) -> String {
        let function = self.f.sig.ident.unraw();
        match self.slip {
            Some(axis) => format!("`{function}{}_{axis}` (its slip along {axis})", self.index),
            None if self.constraint => format!("`{function}{}`", self.index),
            None => format!("`{function}[{}]`", self.index),
        }
    }
}

/// Relative size below which what a row adds to the rows before it counts as nothing.
const TOLERANCE: f64 = 1e-9;

/// The first row of `a` that is a linear combination of the rows before it, with the one
/// row before it that it repeats up to a factor, if it does; decided at three generic
/// points, of which at least two must agree that A is singular (a point where A is not
/// finite, outside the functions' domain, gives no verdict). `None` when A is regular.
pub fn dependent_row(
    g: &crate::engine::graph::Graph,
    a: &[Vec<NodeId>],
) -> Option<(usize, Option<usize>)> {
    let n = a.len();
    let entries: Vec<NodeId> = a.iter().flatten().copied().collect();
    let mut first = None;
    let mut singular = 0;
    for point in generic::points(3, g.input_count()) {
        let values = g.evaluate(&entries, &point);
        if values.iter().any(|x| !x.is_finite()) {
            continue;
        }
        let rows: Vec<&[f64]> = values.chunks(n).collect();
        if let Some(i) = first_dependent(&rows) {
            singular += 1;
            let repeated = (0..i).find(|&j| parallel(rows[i], rows[j]));
            first.get_or_insert((i, repeated));
        }
    }
    first.filter(|_| singular >= 2)
}

/// Whether two rows are multiples of each other (Cauchy–Schwarz with equality).
fn parallel(a: &[f64], b: &[f64]) -> bool {
    let (na, nb) = (norm(a), norm(b));
    na > 0.0 && nb > 0.0 && (dot(a, b).abs() - na * nb).abs() <= TOLERANCE * na * nb
}

/// Gram–Schmidt over the rows in order (twice per row, for orthogonality in floating point):
/// the first row that adds no direction of its own.
fn first_dependent(rows: &[&[f64]]) -> Option<usize> {
    let mut basis: Vec<Vec<f64>> = Vec::new();
    for (i, row) in rows.iter().enumerate() {
        let size = norm(row);
        let mut r = row.to_vec();
        for _ in 0..2 {
            for b in &basis {
                let along = dot(&r, b);
                r.iter_mut().zip(b).for_each(|(x, y)| *x -= along * y);
            }
        }
        let left = norm(&r);
        if size == 0.0 || left <= TOLERANCE * size {
            return Some(i);
        }
        basis.push(r.iter().map(|x| x / left).collect());
    }
    None
}

/// The matrix `rows` evaluated at the generic points where every entry is finite.
pub fn samples(g: &crate::engine::graph::Graph, rows: &[Vec<NodeId>]) -> Vec<Vec<Vec<f64>>> {
    let width = rows.first().map_or(0, Vec::len);
    let entries: Vec<NodeId> = rows.iter().flatten().copied().collect();
    generic::points(3, g.input_count())
        .into_iter()
        .map(|point| g.evaluate(&entries, &point))
        .filter(|values| values.iter().all(|x| x.is_finite()))
        .map(|values| values.chunks(width.max(1)).map(<[f64]>::to_vec).collect())
        .collect()
}

/// Whether `row` is a linear combination of `basis` (to [`TOLERANCE`] of its size; a zero row
/// is one of any).
pub fn in_span(basis: &[&[f64]], row: &[f64]) -> bool {
    let mut rows: Vec<&[f64]> = basis.to_vec();
    rows.push(row);
    let independent_before = first_dependent(basis).is_none();
    // The basis itself is independent (its rows were kept for being so); should rounding
    // make it look otherwise, the row adds nothing a dependent basis would not.
    !independent_before || first_dependent(&rows) == Some(basis.len())
}

/// c with a = c b, when the rows are parallel and b is not zero.
pub fn factor(a: &[f64], b: &[f64]) -> Option<f64> {
    parallel(a, b).then(|| dot(a, b) / dot(b, b))
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn norm(a: &[f64]) -> f64 {
    dot(a, a).sqrt()
}

/// Report A(q) singular at every q at the dependent row (`rows` names the rows of A).
pub fn check(
    lowerer: &mut Lowerer<'_, '_>,
    a: &[Vec<NodeId>],
    rows: &[Row<'_>],
    source: impl Fn(&syn::ImplItemFn, usize) -> proc_macro2::TokenStream,
) -> bool {
    let Some((i, repeated)) = dependent_row(lowerer.graph, a) else {
        return true;
    };
    let Some(row) = rows.get(i) else {
        return true;
    };
    let before: Vec<String> = rows[..i].iter().map(Row::name).collect();
    let before = match repeated.and_then(|j| rows.get(j)) {
        Some(twin) => format!("it repeats {} up to a factor", twin.name()),
        None => before.join(", "),
    };
    let message = if row.constraint {
        let p = rows.iter().filter(|r| r.constraint).count();
        format!(
            "constraint {} is a linear combination of the constraints before it ({before}): it \
             constrains nothing new, and A(q) is singular at every q; remove it (and return \
             `[f64; {}]`)",
            row.name(),
            p - 1
        )
    } else {
        format!(
            "quasi-velocity {} is a linear combination of the rows before it ({before}), so \
             ω = A(q)·qd cannot be inverted at any q (A(q) is singular at generic \
             configurations); each quasi-velocity must add a velocity direction that the \
             constraints and the quasi-velocities before it leave free",
            row.name()
        )
    };
    lowerer.push_error(syn::Error::new_spanned(source(row.f, row.index), message));
    false
}

#[cfg(test)]
mod tests {
    use super::first_dependent;

    #[test]
    fn the_first_row_in_the_span_of_those_before_it() {
        let rows: [&[f64]; 3] = [&[1.0, 2.0, 0.0], &[0.0, 1.0, 1.0], &[2.0, 5.0, 1.0]];
        assert_eq!(first_dependent(&rows), Some(2));
        let rows: [&[f64]; 3] = [&[1.0, 2.0, 0.0], &[0.0, 1.0, 1.0], &[0.0, 0.0, 1.0]];
        assert_eq!(first_dependent(&rows), None);
        let rows: [&[f64]; 2] = [&[0.3, 0.4], &[0.6, 0.8]];
        assert_eq!(first_dependent(&rows), Some(1));
        assert!(super::parallel(rows[0], rows[1]));
        assert!(super::parallel(&[1.0, -2.0], &[-0.5, 1.0]));
        assert!(!super::parallel(&[1.0, 2.0], &[1.0, 2.1]));
    }
}
