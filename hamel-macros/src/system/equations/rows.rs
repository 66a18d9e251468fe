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
    let Written {
        constraints,
        contacts,
        quasi,
        holonomic,
    } = written(lowerer, spec, t, q, v)?;
    let mut residual = holonomic;
    residual.extend(&contacts.1);
    let g = &mut *lowerer.graph;
    let (velocity_rows, jacobian) = if residual.is_empty() {
        (Vec::new(), None)
    } else {
        let (rows, jacobian) = time_derivative(g, &residual, t, q, v);
        (rows, Some(jacobian))
    };
    let all: Vec<NodeId> = constraints
        .iter()
        .chain(&contacts.0)
        .chain(&velocity_rows)
        .chain(&quasi)
        .copied()
        .collect();
    let (a, offset) = coefficients(g, &all, v);
    // Before A's regularity: a constant holonomic constraint gives a row of zeros, which the
    // structural check would blame on the quasi-velocities.
    if let Some(jacobian) = &jacobian
        && !varies(lowerer, spec, jacobian)
    {
        return None;
    }
    let structure = regular(lowerer, spec, &a)?;
    let holonomic = match jacobian {
        Some(jacobian) => {
            if !determines(lowerer, spec, &jacobian) {
                return None;
            }
            Some(HolonomicNodes {
                residual,
                jacobian: jacobian.into_iter().flatten().collect(),
            })
        }
        None => None,
    };
    Some(Rows {
        all,
        a,
        offset,
        structure,
        holonomic,
    })
}

/// The rows as the role functions give them, before the holonomic ones are differentiated.
struct Written {
    constraints: Vec<NodeId>,
    /// The contacts' rows kept and their heights that are holonomic constraints, as read with
    /// the model's shape.
    contacts: (Vec<NodeId>, Vec<NodeId>),
    quasi: Vec<NodeId>,
    /// f(t, q) of `#[holonomic]`.
    holonomic: Vec<NodeId>,
}

/// Lower the functions that give rows, and check the affine ones: whichever lowered, so
/// that a mistake in one function does not hide one in another. `None` after a mistake.
fn written<'a>(
    lowerer: &mut Lowerer<'a, '_>,
    spec: &Spec<'a>,
    t: NodeId,
    q: &[NodeId],
    v: &[NodeId],
) -> Option<Written> {
    let constraints = spec
        .constraints
        .map(|f| lower(lowerer, spec, f, t, vec![array(q), array(v)]));
    let quasi = lower(
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
    let contacts = spec
        .geometry
        .contacts
        .as_ref()
        .map(|c| (c.reading.rows.clone(), c.reading.heights.clone()))
        .unwrap_or_default();
    // B and the equations are only built from rows that are all affine.
    let mut affine = true;
    if let (Some(f), Some(Some(rows))) = (spec.constraints, &constraints) {
        affine &= check_affine(lowerer, f, rows, v, "constraint", "qd");
    }
    if let Some(rows) = &quasi {
        affine &= check_affine(
            lowerer,
            spec.quasi_velocities,
            rows,
            v,
            "quasi-velocity",
            "qd",
        );
    }
    let written = Written {
        constraints: constraints.unwrap_or(Some(Vec::new()))?,
        contacts,
        quasi: quasi?,
        holonomic: holonomic.unwrap_or(Some(Vec::new()))?,
    };
    affine.then_some(written)
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
fn regular(lowerer: &mut Lowerer<'_, '_>, spec: &Spec<'_>, a: &[Vec<NodeId>]) -> Option<SparseLu> {
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
    if !rank::check(lowerer, a, &named_rows(spec), row_source) {
        return None;
    }
    Some(structure)
}

/// Every row of A named as at run time, in order: the constraints', the contacts' (two
/// each), the holonomic constraints' and the contacts' heights, the quasi-velocities'.
fn named_rows<'a>(spec: &Spec<'a>) -> Vec<rank::Row<'a>> {
    let named = |f, count: usize, constraint| {
        (0..count).map(move |index| rank::Row {
            f,
            index,
            constraint,
            slip: None,
        })
    };
    let mut rows: Vec<rank::Row<'a>> = Vec::new();
    if let Some(f) = spec.constraints {
        rows.extend(named(f, spec.written_constraints(), true));
    }
    let contacts = spec.geometry.contacts.as_ref();
    if let Some(c) = contacts {
        rows.extend(c.reading.kept.iter().map(|&row| rank::Row {
            f: c.f,
            index: row / 2,
            constraint: true,
            slip: Some(["x", "y"][row % 2]),
        }));
    }
    if let Some(h) = &spec.holonomic {
        rows.extend(named(h.f, h.dependent.len(), true));
    }
    if let Some(c) = contacts {
        rows.extend(named(c.f, c.dependent.len(), true));
    }
    rows.extend(named(spec.quasi_velocities, spec.dims.free(), false));
    rows
}

/// Each holonomic constraint (and contact's height) must depend on the coordinates: one that
/// does not (a constant, a function of the time alone) holds nowhere or everywhere, and fixes
/// none of them. Its row of ∂f/∂q is zero by construction, so this is a structural check.
fn varies(lowerer: &mut Lowerer<'_, '_>, spec: &Spec<'_>, jacobian: &[Vec<NodeId>]) -> bool {
    let Some(i) = jacobian
        .iter()
        .position(|row| row.iter().all(|&e| lowerer.graph.is_zero(e)))
    else {
        return true;
    };
    // One row per coordinate determined, in the same order (`spec::dependent`).
    let Some(name) = spec.dependent().get(i).map(|&j| &spec.coordinates[j]) else {
        return true;
    };
    let written = spec.written_holonomic();
    let error = match (&spec.holonomic, &spec.geometry.contacts) {
        (Some(h), _) if i < written => syn::Error::new_spanned(
            row_source(h.f, i),
            format!(
                "the holonomic constraint `{}` depends on no coordinate: f = 0 is to fix `{name}` \
                 in terms of the others, but this f is the same at every q, so it holds \
                 everywhere or nowhere; write f(q) so that it varies with `{name}`, or remove the \
                 constraint",
                constraint_row(h.f, i),
            ),
        ),
        (_, Some(c)) => syn::Error::new_spanned(
            c.attr,
            format!(
                "the height of contact {} depends on no coordinate, so it cannot determine \
                 `{name}`: leave `{name}` out of `#[contacts(determines(..))]`",
                i - written,
            ),
        ),
        _ => return true,
    };
    lowerer.push_error(error);
    false
}

/// The name of row `index` of a constraint function as the model has it at run time, when
/// `constraints(..)` does not name it: `blade0`, `blade1`.
pub fn constraint_row(f: &syn::ImplItemFn, index: usize) -> String {
    use syn::ext::IdentExt;
    format!("{}{index}", f.sig.ident.unraw())
}

/// The holonomic constraints (and the contacts' heights) must determine the coordinates they
/// are said to: ∂f/∂q on those columns regular at generic points.
fn determines(lowerer: &mut Lowerer<'_, '_>, spec: &Spec<'_>, jacobian: &[Vec<NodeId>]) -> bool {
    let dependent = spec.dependent();
    let block: Vec<Vec<NodeId>> = jacobian
        .iter()
        .map(|row| dependent.iter().map(|&j| row[j]).collect())
        .collect();
    let Some((i, _)) = rank::dependent_row(lowerer.graph, &block) else {
        return true;
    };
    let name = &spec.coordinates[dependent[i]];
    let all: Vec<String> = dependent
        .iter()
        .map(|&j| format!("`{}`", spec.coordinates[j]))
        .collect();
    let written = spec.written_holonomic();
    let error = match (&spec.holonomic, &spec.geometry.contacts) {
        (Some(h), _) if i < written => syn::Error::new_spanned(
            row_source(h.f, i),
            format!(
                "the holonomic constraint `{}` does not determine `{name}`: together with the \
                 constraints before it, its derivative with respect to {} is singular at generic \
                 configurations; name, in `#[holonomic(determines(..))]`, the coordinates the \
                 constraints can be solved for",
                constraint_row(h.f, i),
                all.join(", ")
            ),
        ),
        (_, Some(c)) => syn::Error::new_spanned(
            c.attr,
            format!(
                "the height of contact {} does not determine `{name}`: together with the \
                 holonomic constraints before it, its derivative with respect to {} is singular \
                 at generic configurations; name, in `#[contacts(determines(..))]`, the \
                 coordinate that the contact's height fixes",
                i - written,
                all.join(", ")
            ),
        ),
        _ => return true,
    };
    lowerer.push_error(error);
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
        // A constraint row is named as at run time: `blade1` is row 1 of the function
        // `blade`; a quasi-velocity by its entry in the function's result, `speeds[1]`.
        let row_name = if what == "constraint" {
            format!("`{}`", constraint_row(f, i))
        } else {
            format!("`{}[{i}]`", f.sig.ident)
        };
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
