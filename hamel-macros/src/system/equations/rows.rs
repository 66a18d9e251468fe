//! The rows ω = r(t, q, v) = A(q, t)·v + a(q, t): the constraints, the time derivatives of the
//! holonomic constraints (ḟ = ∂f/∂q·v + ∂f/∂t, which the user never writes), then the
//! quasi-velocities. Each row must be affine in the velocities and depend on them; A must be
//! regular, structurally (a matching of rows to columns) and at generic points (no row a
//! combination of those before it); the holonomic constraints must determine the coordinates
//! they are said to.

use super::{HolonomicNodes, array, lower, pairs, subst};
use crate::engine::diff;
use crate::engine::graph::{Graph, NodeId};
use crate::engine::lower::Lowerer;
use crate::system::linearity::{self, Verdict, Why};
use crate::system::rank;
use crate::system::sparse_lu::SparseLu;
use crate::system::spec::Spec;
use quote::ToTokens;

pub struct Rows {
    /// r(t, q, v) of every row.
    pub all: Vec<NodeId>,
    /// A(q, t), row by row.
    pub a: Vec<Vec<NodeId>>,
    /// a(q, t) = r(t, q, 0).
    pub offset: Vec<NodeId>,
    /// The structure of A, for its LU factorization.
    pub structure: SparseLu,
    pub holonomic: Option<HolonomicNodes>,
}

pub fn build<'a>(
    lowerer: &mut Lowerer<'a, '_>,
    spec: &Spec<'a>,
    t: NodeId,
    q: &[NodeId],
    v: &[NodeId],
) -> Option<Rows> {
    let constraint_rows = lower(lowerer, spec, spec.constraints, t, vec![array(q), array(v)]);
    let quasi_rows = lower(
        lowerer,
        spec,
        spec.quasi_velocities,
        t,
        vec![array(q), array(v)],
    );
    let holonomic = spec
        .holonomic
        .as_ref()
        .map(|h| lower(lowerer, spec, h.f, t, vec![array(q)]));
    // Check whichever rows lowered, so that a mistake in one function does not hide one in
    // the other; B and the equations are only built from rows that are all affine.
    let mut affine = true;
    if let Some(rows) = &constraint_rows {
        affine &= check_affine(lowerer, spec.constraints, rows, v, "constraint", "qd");
    }
    if let Some(rows) = &quasi_rows {
        affine &= check_affine(
            lowerer,
            spec.quasi_velocities,
            rows,
            v,
            "quasi-velocity",
            "qd",
        );
    }
    let (constraint_rows, quasi_rows) = (constraint_rows?, quasi_rows?);
    let holonomic = match holonomic {
        Some(f) => Some(f?),
        None => None,
    };
    if !affine {
        return None;
    }
    let g = &mut *lowerer.graph;
    let (velocity_rows, jacobian) = match &holonomic {
        Some(f) => {
            let (rows, jacobian) = time_derivative(g, f, t, q, v);
            (rows, Some(jacobian))
        }
        None => (Vec::new(), None),
    };
    let all: Vec<NodeId> = constraint_rows
        .iter()
        .chain(&velocity_rows)
        .chain(&quasi_rows)
        .copied()
        .collect();
    let (a, offset) = coefficients(g, &all, v);
    let structure = regular(lowerer, spec, &a, constraint_rows.len())?;
    let holonomic = match (holonomic, jacobian, &spec.holonomic) {
        (Some(residual), Some(jacobian), Some(h)) => {
            if !determines(lowerer, spec, &jacobian, &h.dependent) {
                return None;
            }
            Some(HolonomicNodes {
                residual,
                jacobian: jacobian.into_iter().flatten().collect(),
            })
        }
        _ => None,
    };
    Some(Rows {
        all,
        a,
        offset,
        structure,
        holonomic,
    })
}

/// ḟ = ∂f/∂q·v + ∂f/∂t, and ∂f/∂q row by row.
fn time_derivative(
    g: &mut Graph,
    f: &[NodeId],
    t: NodeId,
    q: &[NodeId],
    v: &[NodeId],
) -> (Vec<NodeId>, Vec<Vec<NodeId>>) {
    let one = g.one();
    let along = diff::tangent(g, f, &pairs(q, v));
    let explicit = diff::tangent(g, f, &[(t, one)]);
    let rows: Vec<NodeId> = along
        .iter()
        .zip(&explicit)
        .map(|(&a, &e)| g.add(a, e))
        .collect();
    let (jacobian, _) = coefficients(g, &along, v);
    (rows, jacobian)
}

/// A and a of rows affine in `vars`: a = rows at vars = 0, column j of A = rows at vars = e_j,
/// minus a.
pub fn coefficients(
    g: &mut Graph,
    rows: &[NodeId],
    vars: &[NodeId],
) -> (Vec<Vec<NodeId>>, Vec<NodeId>) {
    let zero = g.zero();
    let one = g.one();
    let zeros = vec![zero; vars.len()];
    let offset = subst(g, rows, &pairs(vars, &zeros));
    let columns: Vec<Vec<NodeId>> = (0..vars.len())
        .map(|j| {
            let unit: Vec<NodeId> = (0..vars.len())
                .map(|i| if i == j { one } else { zero })
                .collect();
            let at_unit = subst(g, rows, &pairs(vars, &unit));
            at_unit
                .iter()
                .zip(&offset)
                .map(|(&x, &a)| g.sub(x, a))
                .collect()
        })
        .collect();
    let a = (0..rows.len())
        .map(|i| columns.iter().map(|c| c[i]).collect())
        .collect();
    (a, offset)
}

/// A regular: structurally (else the coordinate no row determines is named) and at generic
/// points (else the first row that repeats those before it). The structure, for the LU.
fn regular(
    lowerer: &mut Lowerer<'_, '_>,
    spec: &Spec<'_>,
    a: &[Vec<NodeId>],
    nonholonomic: usize,
) -> Option<SparseLu> {
    let structure = match SparseLu::new(lowerer.graph, a) {
        Ok(lu) => lu,
        Err(singular) => {
            let name = &spec.coordinates[singular.column];
            lowerer.push_error(syn::Error::new_spanned(
                &spec.quasi_velocities.sig.ident,
                format!(
                    "the constraints and quasi-velocities cannot be inverted for any q: \
                     together they do not determine the velocity of `{name}` (A(q) is \
                     structurally singular); choose quasi-velocities that complete the \
                     constraints"
                ),
            ));
            return None;
        }
    };
    let named = |f, count: usize, constraint| {
        (0..count).map(move |index| rank::Row {
            f,
            index,
            constraint,
        })
    };
    let (k, free) = (spec.dims.k, spec.dims.free());
    let mut named_rows: Vec<rank::Row<'_>> = named(spec.constraints, nonholonomic, true).collect();
    if let Some(h) = &spec.holonomic {
        named_rows.extend(named(h.f, k, true));
    }
    named_rows.extend(named(spec.quasi_velocities, free, false));
    if !rank::check(lowerer, a, &named_rows, row_source) {
        return None;
    }
    Some(structure)
}

/// The holonomic constraints must determine the coordinates they are said to: ∂f/∂q on
/// those columns regular at generic points.
fn determines(
    lowerer: &mut Lowerer<'_, '_>,
    spec: &Spec<'_>,
    jacobian: &[Vec<NodeId>],
    dependent: &[usize],
) -> bool {
    let block: Vec<Vec<NodeId>> = jacobian
        .iter()
        .map(|row| dependent.iter().map(|&j| row[j]).collect())
        .collect();
    let Some((i, _)) = rank::dependent_row(lowerer.graph, &block) else {
        return true;
    };
    let Some(h) = &spec.holonomic else {
        return true;
    };
    let name = &spec.coordinates[dependent[i]];
    let all: Vec<String> = dependent
        .iter()
        .map(|&j| format!("`{}`", spec.coordinates[j]))
        .collect();
    lowerer.push_error(syn::Error::new_spanned(
        row_source(h.f, i),
        format!(
            "the holonomic constraint `{}[{i}]` does not determine `{name}`: together with the \
             constraints before it, its derivative with respect to {} is singular at generic \
             configurations; name, in `#[holonomic(determines(..))]`, the coordinates the \
             constraints can be solved for",
            h.f.sig.ident,
            all.join(", ")
        ),
    ));
    false
}

/// The source of element `index` of a function's result, if its tail is an array literal.
pub fn row_source(f: &syn::ImplItemFn, index: usize) -> proc_macro2::TokenStream {
    if let Some(syn::Stmt::Expr(syn::Expr::Array(a), None)) = f.block.stmts.last()
        && let Some(e) = a.elems.iter().nth(index)
    {
        return e.to_token_stream();
    }
    match &f.sig.output {
        syn::ReturnType::Type(_, ty) => ty.to_token_stream(),
        syn::ReturnType::Default => f.sig.ident.to_token_stream(),
    }
}

/// Check that rows are affine in `vars` (linear plus a part without them), reporting each
/// offender.
pub fn check_affine(
    lowerer: &mut Lowerer<'_, '_>,
    f: &syn::ImplItemFn,
    rows: &[NodeId],
    vars: &[NodeId],
    what: &str,
    var_name: &str,
) -> bool {
    let mut ok = true;
    let form = format!("Σ a_j(q, t)·{var_name}[j] + a(q, t)");
    for (i, &row) in rows.iter().enumerate() {
        // Rows are named as at run time: `blade[1]` is row 1 of the function `blade`.
        let row_name = format!("`{}[{i}]`", f.sig.ident);
        let problem = match linearity::classify(lowerer.graph, row, vars) {
            Verdict::Linear | Verdict::Affine => continue,
            Verdict::Zero if what == "constraint" => format!(
                "constraint {row_name} is identically zero: it constrains nothing; remove it (and \
                 return `[f64; {}]`)",
                rows.len().saturating_sub(1)
            ),
            Verdict::Zero => format!(
                "{what} {row_name} is identically zero, so A(q) is singular everywhere: each row must \
                 depend on the velocities `{var_name}`"
            ),
            Verdict::Independent => format!(
                "{what} {row_name} does not depend on the velocities `{var_name}`: rows have the \
                 form {form}"
            ),
            Verdict::Broken(at, why) => {
                let message = match why {
                    Why::Product => format!(
                        "this product of velocities makes {what} {row_name} nonlinear in `{var_name}`"
                    ),
                    Why::Quotient => format!(
                        "dividing by a velocity makes {what} {row_name} nonlinear in `{var_name}`"
                    ),
                    Why::Function => format!(
                        "a nonlinear function of a velocity makes {what} {row_name} nonlinear in `{var_name}`"
                    ),
                    Why::Condition => format!(
                        "{what} {row_name} branches on a velocity, which is not affine in `{var_name}`"
                    ),
                };
                let message = format!("{message}; {what} rows must have the form {form}");
                match lowerer.graph.span(at) {
                    Some(span) => lowerer.push_error(span.error(message)),
                    None => lowerer.push_error(syn::Error::new_spanned(row_source(f, i), message)),
                }
                ok = false;
                continue;
            }
        };
        lowerer.push_error(syn::Error::new_spanned(row_source(f, i), problem));
        ok = false;
    }
    ok
}

/// Whether `value` depends on the velocities `vars`; an error at `f` when it does not.
pub fn requires_velocities(
    lowerer: &mut Lowerer<'_, '_>,
    f: &syn::ImplItemFn,
    value: NodeId,
    vars: &[NodeId],
    what: &str,
) -> bool {
    let active = lowerer.graph.depends_on(vars);
    if active[value.index()] {
        return true;
    }
    lowerer.push_error(syn::Error::new_spanned(
        &f.sig.ident,
        format!(
            "{what} `{}` does not depend on the velocities: without kinetic energy there is no \
             mass matrix and no motion to simulate",
            f.sig.ident
        ),
    ));
    false
}
