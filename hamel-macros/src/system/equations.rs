//! Hamel's equations, assembled on the graph from derivatives of the user's functions
//! (`hamel::docs::design` has the mathematics; indices there are 1-based, here 0-based).
//!
//! With ω = A(q) q̇, q̇ = B(q) ω and k > p:
//!
//! ```text
//! M ω̇ = f̃ + Bᵀ ∇_q L̃ − (∂²L̃/∂ω∂q) q̇ − Σ_j p_j γʲ ω,   M_kl = ∂²L̃/∂ω_k∂ω_l
//! ```
//!
//! evaluated at ω = (0, …, 0, w). Two routes lead there:
//!
//! * **Hamel** — when L̃ is at hand: given directly (the paper's eq. 12), or composed as
//!   L(q, B(q) ω) from a Lagrangian and a closed-form inverse. The γ term never builds the n³
//!   tensor: with Φ(q, v) = pᵀ A(q) v it is Φ''[q̇, B_k] − Φ''[B_k, q̇].
//! * **Projected Lagrange** — when B is only known numerically (LU of A(q) at run time), L̃
//!   cannot be differentiated in q. Lagrange's equations are projected on the admissible
//!   directions instead: Mᵣ = Bᵣᵀ H_vv Bᵣ and
//!   Bᵣᵀ (f + ∇_q L − H_vq q̇ − H_vv Ḃω) with Ḃω = −B (D_q̇A) q̇.
//!
//! Directions in second derivatives (q̇, B_k, p) are fresh symbols while differentiating and
//! are substituted afterwards: they depend on q themselves and must not be differentiated.

use super::generic;
use super::ldlt;
use super::linearity::{self, Verdict, Why};
use super::rank;
use super::sparse_lu::SparseLu;
use super::spec::{Energy, Spec};
use crate::engine::diff;
use crate::engine::graph::{Graph, NodeId};
use crate::engine::lower::{Lowerer, Value};
use quote::ToTokens;
use std::collections::HashMap;

/// Graph inputs of the generated methods.
pub struct Inputs {
    pub t: NodeId,
    pub q: Vec<NodeId>,
    /// The free quasi-velocities of the state.
    pub w: Vec<NodeId>,
    pub u: Vec<NodeId>,
}

/// Pivots of the run-time LU factorization of A(q) (when no inverse is given), with the
/// entries of A that set their scale: a generated method that uses B checks them first.
pub struct TransformationPivots {
    /// Each pivot with the coordinate whose velocity it determines.
    pub pivots: Vec<(NodeId, usize)>,
    pub entries: Vec<NodeId>,
}

pub struct Equations {
    pub inputs: Inputs,
    /// Present when B is computed from A at run time.
    pub transformation: Option<TransformationPivots>,
    /// q̇ = Σ_{k>p} B_k w_k.
    pub qd: Vec<NodeId>,
    /// ω̇_{p+1…n}.
    pub wdot: Vec<NodeId>,
    /// Pivots of the LDLᵀ factorization of the mass matrix.
    pub pivots: Vec<NodeId>,
    pub mass: Vec<Vec<NodeId>>,
    pub energy: NodeId,
    /// γʲ_{l,k}, indexed [j][l − p][k − p].
    pub gamma: Vec<Vec<Vec<NodeId>>>,
    /// A(q)·B(q) − I when the user gave B (checks that it is the inverse).
    pub inverse_defect: Option<Vec<NodeId>>,
}

fn fresh(g: &mut Graph, name: &str, count: usize) -> Vec<NodeId> {
    (0..count)
        .map(|i| g.new_input(format!("{name}[{i}]")))
        .collect()
}

fn array(nodes: &[NodeId]) -> Value {
    Value::Array(nodes.iter().map(|&n| Value::Real(n)).collect())
}

fn dot(g: &mut Graph, a: &[NodeId], b: &[NodeId]) -> NodeId {
    let terms: Vec<NodeId> = a.iter().zip(b).map(|(&x, &y)| g.mul(x, y)).collect();
    g.sum(&terms)
}

/// Substitute one map into many roots.
fn subst(g: &mut Graph, roots: &[NodeId], map: &[(NodeId, NodeId)]) -> Vec<NodeId> {
    let map: HashMap<NodeId, NodeId> = map.iter().copied().collect();
    g.substitute(roots, &map)
}

fn pairs(keys: &[NodeId], values: &[NodeId]) -> Vec<(NodeId, NodeId)> {
    keys.iter().copied().zip(values.iter().copied()).collect()
}

/// Lower a role function and flatten its result (None after an error, already reported).
fn lower<'a>(
    lowerer: &mut Lowerer<'a, '_>,
    f: &'a syn::ImplItemFn,
    args: Vec<Value>,
) -> Option<Vec<NodeId>> {
    let value = lowerer.call_role(f, args);
    if value.is_poison() {
        return None;
    }
    value.flatten()
}

/// The coefficient matrix of rows that are linear in `vars`.
fn coefficients(g: &mut Graph, rows: &[NodeId], vars: &[NodeId]) -> Vec<Vec<NodeId>> {
    let zero = g.zero();
    let one = g.one();
    let columns: Vec<Vec<NodeId>> = (0..vars.len())
        .map(|j| {
            let unit: Vec<NodeId> = (0..vars.len())
                .map(|i| if i == j { one } else { zero })
                .collect();
            subst(g, rows, &pairs(vars, &unit))
        })
        .collect();
    (0..rows.len())
        .map(|i| columns.iter().map(|c| c[i]).collect())
        .collect()
}

/// A number for a message, to four significant digits (`1.198`, `3.2e-9`).
fn significant(x: f64) -> String {
    if x != 0.0 && (x.abs() < 1e-3 || x.abs() >= 1e5) {
        format!("{x:.3e}")
    } else {
        format!("{}", (x * 1e4).round() / 1e4)
    }
}

/// The source of element `index` of a function's result, if its tail is an array literal.
fn row_source(f: &syn::ImplItemFn, index: usize) -> proc_macro2::TokenStream {
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

/// Check that rows are linear and homogeneous in `vars`, reporting each offender.
fn check_linear(
    lowerer: &mut Lowerer<'_, '_>,
    f: &syn::ImplItemFn,
    rows: &[NodeId],
    vars: &[NodeId],
    what: &str,
    var_name: &str,
) -> bool {
    let mut ok = true;
    for (i, &row) in rows.iter().enumerate() {
        // Rows are named as at run time: `blade[1]` is row 1 of the function `blade`.
        let row_name = format!("`{}[{i}]`", f.sig.ident);
        let verdict = linearity::classify(lowerer.graph, row, vars);
        let problem = match verdict {
            Verdict::Linear => continue,
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
                "{what} {row_name} does not depend on the velocities `{var_name}`: rows are linear in \
                 `{var_name}`, of the form Σ a_j(q)·{var_name}[j]"
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
                    Why::Affine => format!(
                        "{what} {row_name} mixes terms with and without velocities: rows must be linear and \
                         homogeneous in `{var_name}` (affine constraints a(q, t) are not supported yet)"
                    ),
                    Why::Condition => format!(
                        "{what} {row_name} branches on a velocity, which is not linear in `{var_name}`"
                    ),
                };
                let message =
                    format!("{message}; {what} rows must have the form Σ a_j(q)·{var_name}[j]");
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

fn requires_velocities(
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

pub fn build<'a>(spec: &Spec<'a>, lowerer: &mut Lowerer<'a, '_>) -> Option<Equations> {
    let (n, p, m) = (spec.dims.n, spec.dims.p, spec.dims.m);
    let free = spec.dims.free();
    let g = &mut *lowerer.graph;
    let t = g.new_input("t");
    let q = fresh(g, "q", n);
    let w = fresh(g, "w", free);
    let u = fresh(g, "u", m);
    let v = fresh(g, "v", n);
    let zero = g.zero();
    let one = g.one();

    let (rows, a, structure) = transformation(lowerer, spec, &q, &v)?;
    // B(q): closed form from the user's inverse, or by LU of A(q) at run time.
    let omega = fresh(lowerer.graph, "omega", n);
    let mut transformation = None;
    let (b_free, solver) = match spec.velocities {
        Some(f) => {
            let out = lower(lowerer, f, vec![array(&q), array(&omega)])?;
            if !check_linear(lowerer, f, &out, &omega, "velocity", "w") {
                return None;
            }
            let b = coefficients(lowerer.graph, &out, &omega);
            if !check_inverse(lowerer, spec, f, &a, &b) {
                return None;
            }
            let columns: Vec<Vec<NodeId>> =
                (0..n).map(|k| (0..n).map(|i| b[i][k]).collect()).collect();
            (columns[p..].to_vec(), Solver::Closed(b))
        }
        None => {
            let lu = structure;
            let g = &mut *lowerer.graph;
            let mut pivots = Vec::new();
            let columns: Vec<Vec<NodeId>> = (p..n)
                .map(|k| {
                    let unit: Vec<NodeId> =
                        (0..n).map(|i| if i == k { one } else { zero }).collect();
                    let (x, used) = lu.solve(g, &unit);
                    pivots = used;
                    x
                })
                .collect();
            let entries = a
                .iter()
                .flatten()
                .copied()
                .filter(|&e| !g.is_zero(e))
                .collect();
            transformation = Some(TransformationPivots { pivots, entries });
            (columns, Solver::Numeric(lu))
        }
    };
    let qd: Vec<NodeId> = (0..n)
        .map(|i| {
            let row: Vec<NodeId> = b_free.iter().map(|col| col[i]).collect();
            dot(lowerer.graph, &row, &w)
        })
        .collect();

    // Generalized forces at the admissible velocity.
    let forces = match spec.forces {
        Some(f) => lower(
            lowerer,
            f,
            vec![Value::Real(t), array(&q), array(&qd), array(&u)],
        )?,
        None => vec![zero; n],
    };

    // Hamel's route needs L̃(q, ω): given directly, or composed with a closed-form B. Without
    // one, Lagrange's equations are projected instead.
    let quasi_lagrangian = match (&spec.energy, &solver) {
        (Energy::Quasi(f), _) => {
            let lt = *lower(lowerer, f, vec![array(&q), array(&omega)])?.first()?;
            Some((lt, *f))
        }
        (energy, Solver::Closed(b)) => {
            let b_omega: Vec<NodeId> = (0..n).map(|i| dot(lowerer.graph, &b[i], &omega)).collect();
            Some(lagrangian(lowerer, energy, &q, &b_omega)?)
        }
        (_, Solver::Numeric(_)) => None,
    };
    let vectors = Vectors {
        q: &q,
        w: &w,
        qd: &qd,
        b_free: &b_free,
        rows: &rows,
        v: &v,
        forces: &forces,
    };
    let assembled = match (quasi_lagrangian, &solver) {
        (Some((lt, f)), _) => {
            if !requires_velocities(lowerer, f, lt, &omega, "the Lagrangian") {
                return None;
            }
            hamel(lowerer.graph, lt, &omega, &vectors, p)
        }
        (None, Solver::Numeric(lu)) => {
            let (l, f) = lagrangian(lowerer, &spec.energy, &q, &v)?;
            if !requires_velocities(lowerer, f, l, &v, "the Lagrangian") {
                return None;
            }
            projected(lowerer.graph, l, lu, &vectors)
        }
        (None, Solver::Closed(_)) => return None,
    };
    let energy = match &spec.energy {
        // T + V exactly, rather than through the Legendre transform.
        Energy::Split { kinetic, potential } => {
            let t_value = *lower(lowerer, kinetic, vec![array(&q), array(&qd)])?.first()?;
            match potential {
                Some(vf) => {
                    let v_value = *lower(lowerer, vf, vec![array(&q)])?.first()?;
                    lowerer.graph.add(t_value, v_value)
                }
                None => t_value,
            }
        }
        _ => assembled.energy,
    };

    let g = &mut *lowerer.graph;
    let inverse_defect = match &solver {
        Solver::Closed(b) => {
            let mut defect = Vec::with_capacity(n * n);
            for (i, row) in a.iter().enumerate() {
                for k in 0..n {
                    let col: Vec<NodeId> = b.iter().map(|b_row| b_row[k]).collect();
                    let product = dot(g, row, &col);
                    let identity = if i == k { one } else { zero };
                    defect.push(g.sub(product, identity));
                }
            }
            Some(defect)
        }
        Solver::Numeric(_) => None,
    };
    let solution = ldlt::solve(g, &assembled.mass, &assembled.rhs);
    let gamma = gamma(g, &rows, &q, &v, &b_free);
    Some(Equations {
        inputs: Inputs { t, q, w, u },
        transformation,
        qd,
        wdot: solution.x,
        pivots: solution.pivots,
        mass: assembled.mass,
        energy,
        gamma,
        inverse_defect,
    })
}

/// The rows of ω = A(q)·v (constraints, then quasi-velocities) and the matrix A(q), after
/// the checks that A can be inverted: rows linear in `v`, and A regular, structurally and at
/// generic points. Also the structure of A, for its LU factorization.
fn transformation<'a>(
    lowerer: &mut Lowerer<'a, '_>,
    spec: &Spec<'a>,
    q: &[NodeId],
    v: &[NodeId],
) -> Option<(Vec<NodeId>, Vec<Vec<NodeId>>, SparseLu)> {
    let constraint_rows = lower(lowerer, spec.constraints, vec![array(q), array(v)]);
    let quasi_rows = lower(lowerer, spec.quasi_velocities, vec![array(q), array(v)]);
    // Check whichever rows lowered, so that a mistake in one function does not hide one in
    // the other; B and the equations are only built from rows that are all linear.
    let mut linear = true;
    if let Some(rows) = &constraint_rows {
        linear &= check_linear(lowerer, spec.constraints, rows, v, "constraint", "qd");
    }
    if let Some(rows) = &quasi_rows {
        linear &= check_linear(
            lowerer,
            spec.quasi_velocities,
            rows,
            v,
            "quasi-velocity",
            "qd",
        );
    }
    let (constraint_rows, quasi_rows) = (constraint_rows?, quasi_rows?);
    if !linear {
        return None;
    }
    let rows: Vec<NodeId> = constraint_rows.iter().chain(&quasi_rows).copied().collect();
    let a = coefficients(lowerer.graph, &rows, v);
    let structure = match SparseLu::new(lowerer.graph, &a) {
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
    let named_rows: Vec<rank::Row<'_>> = named(spec.constraints, constraint_rows.len(), true)
        .chain(named(spec.quasi_velocities, quasi_rows.len(), false))
        .collect();
    if !rank::check(lowerer, &a, &named_rows, row_source) {
        return None;
    }
    Some((rows, a, structure))
}

/// A closed-form inverse must invert A(q). A typo in it would not show in the motion's
/// kinematics, only (through the momenta of the constrained directions and the γ terms) as
/// a wrong acceleration, so it is checked here: B(q)·A(q) − I is evaluated at a few
/// configurations and parameter values (generic ones, the same every build). Row r of that
/// defect is the velocity of coordinate r as the inverse gives it, which names the mistake.
fn check_inverse(
    lowerer: &mut Lowerer<'_, '_>,
    spec: &Spec<'_>,
    f: &syn::ImplItemFn,
    a: &[Vec<NodeId>],
    b: &[Vec<NodeId>],
) -> bool {
    let n = a.len();
    let g = &mut *lowerer.graph;
    let mut defect = Vec::with_capacity(n * n);
    for b_row in b {
        for j in 0..n {
            let column: Vec<NodeId> = a.iter().map(|a_row| a_row[j]).collect();
            let product = dot(g, b_row, &column);
            let identity = if defect.len() % (n + 1) == 0 {
                g.one()
            } else {
                g.zero()
            };
            defect.push(g.sub(product, identity));
        }
    }
    let mut bad_rows: Option<Vec<(usize, f64)>> = None;
    let mut failures = 0;
    for values in generic::points(3, g.input_count()) {
        let d = g.evaluate(&defect, &values);
        if d.iter().any(|x| !x.is_finite()) {
            continue; // outside the inverse's domain here: no verdict from this point
        }
        let rows: Vec<(usize, f64)> = (0..n)
            .map(|r| {
                (
                    r,
                    d[r * n..(r + 1) * n]
                        .iter()
                        .fold(0.0f64, |m, x| m.max(x.abs())),
                )
            })
            .filter(|&(_, worst)| worst > 1e-6)
            .collect();
        if !rows.is_empty() {
            failures += 1;
            bad_rows.get_or_insert(rows);
        }
    }
    match bad_rows {
        Some(rows) if failures >= 2 => {
            for (r, worst) in rows {
                let name = &spec.coordinates[r];
                lowerer.push_error(syn::Error::new_spanned(
                    row_source(f, r),
                    format!(
                        "`#[velocities]` is not the inverse of the constraints and quasi-velocities: \
                         the velocity of `{name}` it gives is wrong (at a generic configuration \
                         B(q)·A(q) differs from the identity by {} in this row); q̇ = B(q)·w must \
                         solve w = A(q)·q̇ for every w, including the constrained entries",
                        significant(worst)
                    ),
                ));
            }
            false
        }
        _ => true,
    }
}

/// The Lagrangian L(q, velocities) from the role functions, and the function to blame when
/// it does not depend on the velocities.
fn lagrangian<'a>(
    lowerer: &mut Lowerer<'a, '_>,
    energy: &Energy<'a>,
    q: &[NodeId],
    velocities: &[NodeId],
) -> Option<(NodeId, &'a syn::ImplItemFn)> {
    match energy {
        Energy::Lagrangian(f) => Some((
            *lower(lowerer, f, vec![array(q), array(velocities)])?.first()?,
            f,
        )),
        Energy::Split { kinetic, potential } => {
            let t = *lower(lowerer, kinetic, vec![array(q), array(velocities)])?.first()?;
            let l = match potential {
                Some(vf) => {
                    let v = *lower(lowerer, vf, vec![array(q)])?.first()?;
                    lowerer.graph.sub(t, v)
                }
                None => t,
            };
            Some((l, kinetic))
        }
        Energy::Quasi(_) => None,
    }
}

/// How B is known: in closed form (n×n entries), or through the run-time LU of A.
enum Solver {
    Closed(Vec<Vec<NodeId>>),
    Numeric(SparseLu),
}

struct Assembled {
    mass: Vec<Vec<NodeId>>,
    rhs: Vec<NodeId>,
    energy: NodeId,
}

/// The vectors both routes read: coordinates, speeds, the admissible velocity, the free
/// columns of B, the rows of A (in the velocity symbols `v`), and the forces.
struct Vectors<'v> {
    q: &'v [NodeId],
    w: &'v [NodeId],
    qd: &'v [NodeId],
    b_free: &'v [Vec<NodeId>],
    rows: &'v [NodeId],
    v: &'v [NodeId],
    forces: &'v [NodeId],
}

/// Hamel's equations from L̃(q, ω) (`omega` are its velocity symbols).
fn hamel(g: &mut Graph, lt: NodeId, omega: &[NodeId], x: &Vectors<'_>, p: usize) -> Assembled {
    let Vectors {
        q,
        w,
        qd,
        b_free,
        rows,
        v,
        forces,
    } = *x;
    let n = q.len();
    let free = n - p;
    let one = g.one();
    let zero = g.zero();
    let wrt: Vec<NodeId> = q.iter().chain(omega).copied().collect();
    let gradient = diff::adjoint(g, &[lt], &[one], &wrt);
    let (grad_q, momenta) = gradient.split_at(n);
    let momenta_free = &momenta[p..];

    // M_kl = ∂p_k/∂ω_l, one tangent sweep per column.
    let columns: Vec<Vec<NodeId>> = (p..n)
        .map(|l| diff::tangent(g, momenta_free, &[(omega[l], one)]))
        .collect();
    let mass: Vec<Vec<NodeId>> = (0..free)
        .map(|k| columns.iter().map(|c| c[k]).collect())
        .collect();

    // (∂p_k/∂q)·q̇ with q̇ held as a symbol.
    let a_sym = fresh(g, "qd_direction", n);
    let hq = diff::tangent(g, momenta_free, &pairs(q, &a_sym));

    // γ term: Φ''[q̇, B_k] − Φ''[B_k, q̇] with Φ = Σ_j P_j·row_j(q, v).
    let p_sym = fresh(g, "momentum", n);
    let products: Vec<NodeId> = p_sym
        .iter()
        .zip(rows)
        .map(|(&pj, &r)| g.mul(pj, r))
        .collect();
    let phi = g.sum(&products);
    let dq = fresh(g, "q_direction", n);
    let dv = fresh(g, "v_direction", n);
    let second = diff::bidirectional(g, &[phi], &pairs(q, &dq), &pairs(v, &dv))[0];

    let mut rhs = Vec::with_capacity(free);
    for (k, bk) in b_free.iter().enumerate() {
        let forward: Vec<NodeId> = dq.iter().chain(&dv).copied().collect();
        let qd_bk: Vec<NodeId> = qd.iter().chain(bk).copied().collect();
        let bk_qd: Vec<NodeId> = bk.iter().chain(qd).copied().collect();
        let d1 = subst(g, &[second], &pairs(&forward, &qd_bk))[0];
        let d2 = subst(g, &[second], &pairs(&forward, &bk_qd))[0];
        let gamma_term = g.sub(d1, d2);
        let f_tilde = dot(g, bk, forces);
        let b_grad = dot(g, bk, grad_q);
        let s = g.add(f_tilde, b_grad);
        let s = g.sub(s, hq[k]);
        rhs.push(g.sub(s, gamma_term));
    }
    // Energy: Σ ω_k ∂L̃/∂ω_k − L̃.
    let pw: Vec<NodeId> = momenta_free.to_vec();
    let legendre = dot(g, &pw, &omega[p..]);
    let energy = g.sub(legendre, lt);

    // Evaluate at ω = (0, w); the symbols q̇ and p take their values.
    let mut at_state: Vec<(NodeId, NodeId)> = (0..p).map(|j| (omega[j], zero)).collect();
    at_state.extend(pairs(&omega[p..], w));
    let momenta_now = subst(g, momenta, &at_state);
    let mut all = at_state.clone();
    all.extend(pairs(&a_sym, qd));
    all.extend(pairs(&p_sym, &momenta_now));
    let mut roots: Vec<NodeId> = mass.iter().flatten().copied().collect();
    roots.extend(&rhs);
    roots.push(energy);
    let done = subst(g, &roots, &all);
    let (mass_flat, rest) = done.split_at(free * free);
    Assembled {
        mass: mass_flat.chunks(free).map(<[NodeId]>::to_vec).collect(),
        rhs: rest[..free].to_vec(),
        energy: rest[free],
    }
}

/// Lagrange's equations projected on the admissible directions, for a numeric B.
fn projected(g: &mut Graph, l: NodeId, lu: &SparseLu, x: &Vectors<'_>) -> Assembled {
    let Vectors {
        q,
        qd,
        b_free,
        rows,
        v,
        forces,
        ..
    } = *x;
    let n = q.len();
    let one = g.one();
    let wrt: Vec<NodeId> = q.iter().chain(v).copied().collect();
    let gradient = diff::adjoint(g, &[l], &[one], &wrt);
    let (grad_q, grad_v) = gradient.split_at(n);

    // Mᵣ = Bᵣᵀ H_vv Bᵣ: one tangent of ∇_v L per free direction (B entries are inputs).
    let h_b: Vec<Vec<NodeId>> = b_free
        .iter()
        .map(|bl| diff::tangent(g, grad_v, &pairs(v, bl)))
        .collect();
    let mass: Vec<Vec<NodeId>> = b_free
        .iter()
        .map(|bk| h_b.iter().map(|hl| dot(g, bk, hl)).collect())
        .collect();

    // Ḃω = −B (D_q̇ A) q̇: the rows' derivative along a q-direction, at v = direction = q̇.
    let a_sym = fresh(g, "qd_direction", n);
    let along = diff::tangent(g, rows, &pairs(q, &a_sym));
    let mut at_qd = pairs(v, qd);
    at_qd.extend(pairs(&a_sym, qd));
    let along = subst(g, &along, &at_qd);
    let (solved, _) = lu.solve(g, &along);
    let b_dot_omega: Vec<NodeId> = solved.into_iter().map(|d| g.neg(d)).collect();

    // d/dt ∂L/∂q̇ − H_vv·(B_free ω̇) = H_vq q̇ + H_vv Ḃω: one tangent with both directions.
    let c_sym = fresh(g, "bdot_omega", n);
    let mut seeds = pairs(q, &a_sym);
    seeds.extend(pairs(v, &c_sym));
    let drift = diff::tangent(g, grad_v, &seeds);
    let rhs: Vec<NodeId> = b_free
        .iter()
        .map(|bk| {
            let terms: Vec<NodeId> = (0..n)
                .map(|i| {
                    let s = g.add(forces[i], grad_q[i]);
                    g.sub(s, drift[i])
                })
                .collect();
            dot(g, bk, &terms)
        })
        .collect();
    let legendre = dot(g, grad_v, v);
    let energy = g.sub(legendre, l);

    let mut all = pairs(v, qd);
    all.extend(pairs(&a_sym, qd));
    all.extend(pairs(&c_sym, &b_dot_omega));
    let free = b_free.len();
    let mut roots: Vec<NodeId> = mass.iter().flatten().copied().collect();
    roots.extend(&rhs);
    roots.push(energy);
    let done = subst(g, &roots, &all);
    let (mass_flat, rest) = done.split_at(free * free);
    Assembled {
        mass: mass_flat.chunks(free).map(<[NodeId]>::to_vec).collect(),
        rhs: rest[..free].to_vec(),
        energy: rest[free],
    }
}

/// γʲ_{l,k} = Aⱼ''[B_l, B_k] − Aⱼ''[B_k, B_l] with Aⱼ''[a, c] = Σ ∂A^j_ν/∂q^σ a^σ c^ν.
fn gamma(
    g: &mut Graph,
    rows: &[NodeId],
    q: &[NodeId],
    v: &[NodeId],
    b_free: &[Vec<NodeId>],
) -> Vec<Vec<Vec<NodeId>>> {
    let n = q.len();
    let dq = fresh(g, "gamma_q_direction", n);
    let dv = fresh(g, "gamma_v_direction", n);
    let second = diff::bidirectional(g, rows, &pairs(q, &dq), &pairs(v, &dv));
    let directions: Vec<NodeId> = dq.iter().chain(&dv).copied().collect();
    second
        .iter()
        .map(|&d| {
            b_free
                .iter()
                .map(|bl| {
                    b_free
                        .iter()
                        .map(|bk| {
                            let lk: Vec<NodeId> = bl.iter().chain(bk).copied().collect();
                            let kl: Vec<NodeId> = bk.iter().chain(bl).copied().collect();
                            let x = subst(g, &[d], &pairs(&directions, &lk))[0];
                            let y = subst(g, &[d], &pairs(&directions, &kl))[0];
                            g.sub(x, y)
                        })
                        .collect()
                })
                .collect()
        })
        .collect()
}
