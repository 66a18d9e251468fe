//! Hamel's equations, assembled on the graph from derivatives of the user's functions
//! (`hamel::docs::design` has the mathematics; indices there are 1-based, here 0-based).
//!
//! With the rows ω = r(t, q, q̇) = A(q, t) q̇ + a(q, t) (constraints first), their inverse
//! q̇ = B(q, t)(ω − a) and, for every column B_k of B,
//!
//! ```text
//! Σ_{l>p} M_kl ω̇_l − rhs_k = λ_k (k < p),  0 (k ≥ p)
//! ```
//!
//! evaluated at ω = (0, …, 0, w): the free rows are the equations of motion, the constrained
//! ones give the constraint forces. One step per module, in the order `build` takes them:
//!
//! * `rows` — the rows: constraints, the holonomic constraints' time derivatives,
//!   quasi-velocities; checked to be affine in q̇ with A regular; A and a read off.
//! * `transformation` — q̇ = B(ω − a): the user's closed-form inverse (checked by
//!   `inverse`), or an LU of A unrolled into the code.
//! * `lagrangian` — L(t, q, q̇), or L̃(t, q, ω) where Hamel's route can take it, and the
//!   energy.
//! * `hamel` — Hamel's equations from L̃: given directly (the paper's eq. 12), or composed as
//!   L(t, q, B(ω − a)) with a closed-form inverse.
//! * `projected` — when B is only known numerically, Lagrange's equations projected on the
//!   columns of B.
//! * `gamma` — the coefficients γʲ_{l,k}, for inspection.
//!
//! Directions in second derivatives (q̇, B_k, p) are fresh symbols while differentiating and
//! are substituted afterwards: they depend on q themselves and must not be differentiated.

mod bodies;
mod contacts;

pub use contacts::{ContactReading, read as read_contacts};
mod gamma;
mod hamel;
mod impossible;
mod inverse;
mod lagrangian;
mod projected;
mod rows;
mod transformation;

use super::ldlt;
use super::spec::Spec;
use crate::engine::graph::{Graph, Node, NodeId};
use crate::engine::hash::HashMap;
use crate::engine::lower::{Lowerer, Value};
pub use rows::constraint_row;
use transformation::Transformation;

/// Graph inputs of the generated methods.
pub struct Inputs {
    pub t: NodeId,
    pub q: Vec<NodeId>,
    /// The free quasi-velocities of the state.
    pub w: Vec<NodeId>,
    pub u: Vec<NodeId>,
    /// Velocity symbols q̇ of the rows, for the methods that take velocities.
    pub v: Vec<NodeId>,
}

impl Inputs {
    /// The inputs a right-hand side varies with: t, the state (q, w) and u. Everything
    /// else it reads is a parameter, fixed for a run.
    pub fn varying(&self) -> Vec<NodeId> {
        std::iter::once(self.t)
            .chain(self.q.iter().copied())
            .chain(self.w.iter().copied())
            .chain(self.u.iter().copied())
            .collect()
    }
}

/// What a generated method that uses B checks first (when B is not the user's): the pivots
/// of the run-time LU factorization of A(q), or the determinants of the diagonal blocks
/// inverted in closed form, each against its scale.
pub struct TransformationPivots {
    pub checks: Vec<PivotCheck>,
}

/// |value| must exceed n·ε·scale.
#[derive(Clone, Copy)]
pub struct PivotCheck {
    pub value: NodeId,
    pub scale: NodeId,
    /// The coordinate whose velocity the pivot determines.
    pub coordinate: usize,
}

/// The holonomic constraints f(t, q) and their Jacobian ∂f/∂q (row-major, k × n).
pub struct HolonomicNodes {
    pub residual: Vec<NodeId>,
    pub jacobian: Vec<NodeId>,
}

pub struct Equations {
    pub inputs: Inputs,
    /// Present when B is computed from A at run time.
    pub transformation: Option<TransformationPivots>,
    /// The constraint rows r_c(t, q, v) (holonomic ones last) and the quasi-velocity rows.
    pub constraint_rows: Vec<NodeId>,
    pub quasi_rows: Vec<NodeId>,
    /// q̇ = B(ω − a) at ω = (0, w).
    pub qd: Vec<NodeId>,
    /// ω̇_{p+1…n}.
    pub wdot: Vec<NodeId>,
    /// Pivots of the LDLᵀ factorization of the mass matrix.
    pub pivots: Vec<NodeId>,
    pub mass: Vec<Vec<NodeId>>,
    pub energy: NodeId,
    /// dE/dt = f·q̇ − λᵀa_c − ∂L/∂t.
    pub power: NodeId,
    /// λ, one per constraint row.
    pub multipliers: Vec<NodeId>,
    /// γʲ_{l,k}, indexed [j][l − p][k − p].
    pub gamma: Vec<Vec<Vec<NodeId>>>,
    /// A·B − I and A·Q₀ + a when the user gave the inverse (checks that it is one).
    pub inverse_defect: Option<Vec<NodeId>>,
    pub holonomic: Option<HolonomicNodes>,
    /// No forces, no affine part in the constraints, no explicit time in L: E is conserved.
    pub conservative: bool,
    /// Whether the power vanishes identically when every input is zero.
    pub power_vanishes_without_inputs: bool,
    /// Conservative, T quadratic in q̇, and every row (quasi-velocities too) homogeneous in q̇
    /// and independent of t: (q, ω) ↦ (q, −ω) reverses the reduced ODE.
    pub reversible: bool,
}

pub(super) fn fresh(g: &mut Graph, name: &str, count: usize) -> Vec<NodeId> {
    (0..count)
        .map(|i| g.new_input(format!("{name}[{i}]")))
        .collect()
}

pub(super) fn array(nodes: &[NodeId]) -> Value {
    Value::Array(nodes.iter().map(|&n| Value::Real(n)).collect())
}

pub(super) fn dot(g: &mut Graph, a: &[NodeId], b: &[NodeId]) -> NodeId {
    let terms: Vec<NodeId> = a.iter().zip(b).map(|(&x, &y)| g.mul(x, y)).collect();
    g.sum(&terms)
}

/// Substitute one map into many roots.
pub(super) fn subst(g: &mut Graph, roots: &[NodeId], map: &[(NodeId, NodeId)]) -> Vec<NodeId> {
    let map: HashMap<NodeId, NodeId> = map.iter().copied().collect();
    g.substitute(roots, &map)
}

pub(super) fn pairs(keys: &[NodeId], values: &[NodeId]) -> Vec<(NodeId, NodeId)> {
    keys.iter().copied().zip(values.iter().copied()).collect()
}

/// Lower a role function and flatten its result (None after an error, already reported).
/// `t` is passed first when the function takes the time.
pub(super) fn lower<'a>(
    lowerer: &mut Lowerer<'a, '_>,
    spec: &Spec<'a>,
    f: &'a syn::ImplItemFn,
    t: NodeId,
    args: Vec<Value>,
) -> Option<Vec<NodeId>> {
    lower_value(lowerer, spec, f, t, args)?.flatten()
}

/// Lower a role function and keep its value as it is (`None` after an error, already
/// reported): the vocabulary's values, bodies and contacts, are read part by part.
pub(super) fn lower_value<'a>(
    lowerer: &mut Lowerer<'a, '_>,
    spec: &Spec<'a>,
    f: &'a syn::ImplItemFn,
    t: NodeId,
    args: Vec<Value>,
) -> Option<Value> {
    let mut all = Vec::with_capacity(args.len() + 1);
    if spec.takes_time(f) {
        all.push(Value::Real(t));
    }
    all.extend(args);
    let value = lowerer.call_role(f, all);
    (!value.is_poison()).then_some(value)
}

/// The columns of a matrix given by rows.
pub(super) fn columns(m: &[Vec<NodeId>]) -> Vec<Vec<NodeId>> {
    let width = m.first().map_or(0, Vec::len);
    (0..width)
        .map(|k| m.iter().map(|row| row[k]).collect())
        .collect()
}

/// What both assemblies give: for the free columns B_k of B (k = p … n − 1), the mass
/// coupling to the free accelerations, Σ_l mass[k − p][l] ω̇_l, and the rest, rhs[k − p];
/// what gives the multipliers; the energy; and ∂L/∂t along the motion.
pub(super) struct Assembled {
    pub mass: Vec<Vec<NodeId>>,
    pub rhs: Vec<NodeId>,
    pub constrained: Constrained,
    pub energy: NodeId,
    pub lagrangian_rate: NodeId,
}

/// How the constrained columns give λ once ω̇ is known.
pub(super) enum Constrained {
    /// Hamel's rows k < p: λ_k = Σ_l mass[k][l] ω̇_l − rhs[k].
    Rows {
        mass: Vec<Vec<NodeId>>,
        rhs: Vec<NodeId>,
    },
    /// Lagrange's equations in q before projection: the residual R = Σ_l coupling[l] ω̇_l −
    /// terms (coupling[l] = H_vv B_l), and λ_k = B_kᵀ R, the first p entries of A⁻ᵀR. One
    /// transposed solve is as sparse as A, where the p dense columns of a B that fills in
    /// (the N-trailer's) would cost p·n.
    Residual {
        coupling: Vec<Vec<NodeId>>,
        terms: Vec<NodeId>,
    },
}

/// The vectors both assemblies read.
pub(super) struct Vectors<'v> {
    pub t: NodeId,
    pub q: &'v [NodeId],
    pub w: &'v [NodeId],
    /// The admissible velocity q̇ = B(ω − a).
    pub qd: &'v [NodeId],
    /// The free columns of B, B_p … B_{n−1}.
    pub b_free: &'v [Vec<NodeId>],
    /// The rows r(t, q, v), in the velocity symbols `v`, and their parts without velocity.
    pub rows: &'v [NodeId],
    pub offset: &'v [NodeId],
    pub v: &'v [NodeId],
    pub forces: &'v [NodeId],
}

/// Below this many operations that depend on the state, a model stated from bodies is built
/// twice, its bodies' speeds taken as they are and in the frames of their first turns, and
/// the cheaper right-hand side kept: the second build costs less than the time it saves a
/// run. (The Whipple bicycle's takes about 2800, and would double its build.)
const TRY_BOTH_BELOW: usize = 1500;

/// The equations, from the cheaper of the two ways of taking the bodies' speeds
/// (`bodies::squared_speed`) where trying both costs little.
pub fn build_cheaper<'a>(spec: &Spec<'a>, lowerer: &mut Lowerer<'a, '_>) -> Option<Equations> {
    let plain = build(spec, lowerer)?;
    if spec.geometry.bodies.is_none() || lowerer.has_errors() {
        return Some(plain);
    }
    let cost = |g: &Graph, eq: &Equations| {
        let roots: Vec<NodeId> = eq
            .qd
            .iter()
            .chain(&eq.wdot)
            .chain(&eq.pivots)
            .copied()
            .collect();
        state_operations(g, &roots, &eq.inputs.varying())
    };
    let before = cost(lowerer.graph, &plain);
    if before >= TRY_BOTH_BELOW {
        return Some(plain);
    }
    spec.heading_frames.set(true);
    let turned = build(spec, lowerer);
    match turned {
        Some(turned) if cost(lowerer.graph, &turned) < before => Some(turned),
        _ => {
            spec.heading_frames.set(false);
            Some(plain)
        }
    }
}

pub fn build<'a>(spec: &Spec<'a>, lowerer: &mut Lowerer<'a, '_>) -> Option<Equations> {
    let (n, p, m) = (spec.dims.n, spec.dims.p, spec.dims.m);
    let g = &mut *lowerer.graph;
    let inputs = Inputs {
        t: spec.symbols.t,
        q: spec.symbols.q.clone(),
        w: fresh(g, "w", spec.dims.free()),
        u: fresh(g, "u", m),
        v: spec.symbols.v.clone(),
    };
    let omega = fresh(g, "omega", n);
    let (t, q, v) = (inputs.t, inputs.q.as_slice(), inputs.v.as_slice());

    let rows = rows::build(lowerer, spec, t, q, v)?;
    let (transformation, inverse_defect) =
        transformation::build(lowerer, spec, &rows, t, q, &omega)?;
    let (b_free, checks) = transformation.columns(lowerer.graph, p);
    let mut qd = admissible_velocity(lowerer.graph, &transformation, &rows, &b_free, &inputs.w);
    let mut transformation_pivots = (!checks.is_empty()).then_some(TransformationPivots { checks });
    let forces = forces(lowerer, spec, &inputs, &qd)?;
    let vectors = Vectors {
        t,
        q,
        w: &inputs.w,
        qd: &qd,
        b_free: &b_free,
        rows: &rows.all,
        offset: &rows.offset,
        v,
        forces: &forces,
    };
    let assembled = match lagrangian::quasi(lowerer, spec, &transformation, t, q, &omega)? {
        Some(lt) => {
            let (b, _) = transformation.columns(lowerer.graph, 0);
            hamel::assemble(lowerer.graph, lt, &omega, &b, &vectors, p)
        }
        None => {
            let l = lagrangian::lagrangian(lowerer, spec, t, q, v)?;
            projected::assemble(lowerer.graph, l, &transformation, &vectors)
        }
    };
    let split_energy = lagrangian::split_energy(lowerer, spec, t, q, v, &qd)?;
    let quadratic_kinetic = match split_energy {
        Some(_) => true,
        None => lagrangian::quadratic_in_velocities(lowerer, spec, t, q, (v, &omega))?,
    };
    let energy = split_energy.unwrap_or(assembled.energy);
    let g = &mut *lowerer.graph;
    let mut motion = solve(g, &assembled, &transformation, &vectors, p);
    let offsets_vanish = rows.offset[..p].iter().all(|&a| g.is_zero(a));
    let conservative =
        spec.forces.is_none() && offsets_vanish && g.is_zero(assembled.lagrangian_rate);
    let on_time = g.depends_on(&[t]);
    let reversible = conservative
        && quadratic_kinetic
        && rows.offset.iter().all(|&a| g.is_zero(a))
        && rows.all.iter().all(|r| !on_time[r.index()]);
    let gamma = gamma::gamma(g, &rows.all, q, v, &b_free);
    let varying = inputs.varying();
    factor_right_hand_side(
        g,
        &varying,
        &mut qd,
        &mut motion,
        &mut transformation_pivots,
    );
    let power_vanishes_without_inputs =
        conservative || g.vanishes_with(&inputs.u)[motion.power.index()];
    Some(Equations {
        transformation: transformation_pivots,
        constraint_rows: rows.all[..p].to_vec(),
        quasi_rows: rows.all[p..].to_vec(),
        qd,
        wdot: motion.wdot,
        pivots: motion.pivots,
        mass: motion.mass,
        energy,
        power: motion.power,
        multipliers: motion.multipliers,
        gamma,
        inverse_defect,
        holonomic: rows.holonomic,
        conservative,
        power_vanishes_without_inputs,
        reversible,
        inputs,
    })
}

/// What the right-hand side computes (q̇, ω̇ and what its checks read) with the common
/// factors of its sums taken out ([`Graph::factored`]), once nothing more is built on it;
/// kept only if the right-hand side then takes fewer operations that depend on the state
/// (the parameter-only ones are prepared once): taking a factor out rebuilds the products
/// of the sum's terms, which loses what they shared with other sums (the N-trailer's and
/// the bicycle's take more operations factored, the robot's fewer).
fn factor_right_hand_side(
    g: &mut Graph,
    varying: &[NodeId],
    qd: &mut [NodeId],
    motion: &mut Motion,
    transformation: &mut Option<TransformationPivots>,
) {
    let free = motion.wdot.len();
    let mut roots: Vec<NodeId> = qd.to_vec();
    roots.extend(&motion.wdot);
    roots.extend(&motion.pivots);
    roots.extend((0..free).map(|k| motion.mass[k][k]));
    if let Some(t) = transformation.as_ref() {
        roots.extend(t.checks.iter().flat_map(|c| [c.value, c.scale]));
    }
    let mapped = g.factored(&roots, varying);
    if state_operations(g, &mapped, varying) >= state_operations(g, &roots, varying) {
        return;
    }
    let mut next = mapped.into_iter();
    for x in qd
        .iter_mut()
        .chain(&mut motion.wdot)
        .chain(&mut motion.pivots)
    {
        *x = next.next().unwrap_or(*x);
    }
    for k in 0..free {
        motion.mass[k][k] = next.next().unwrap_or(motion.mass[k][k]);
    }
    if let Some(t) = transformation.as_mut() {
        for c in &mut t.checks {
            c.value = next.next().unwrap_or(c.value);
            c.scale = next.next().unwrap_or(c.scale);
        }
    }
}

/// The cost of the operations computing `roots` that depend on the `varying` inputs: one
/// per operation, four per division (its throughput on current processors).
fn state_operations(g: &Graph, roots: &[NodeId], varying: &[NodeId]) -> usize {
    let active = g.depends_on(varying);
    g.live_set(roots)
        .into_iter()
        .filter(|&id| active[id.index()])
        .map(|id| match g.node(id) {
            Node::Div(..) => 4,
            node if node.operands().as_slice().is_empty() => 0,
            _ => 1,
        })
        .sum()
}

/// q̇ = Σ_{l≥p} B_l w_l + Q₀, with Q₀ = −B a the drift that affine rows impose.
fn admissible_velocity(
    g: &mut Graph,
    transformation: &Transformation,
    rows: &rows::Rows,
    b_free: &[Vec<NodeId>],
    w: &[NodeId],
) -> Vec<NodeId> {
    let drift = transformation.drift(g, &rows.offset);
    (0..drift.len())
        .map(|i| {
            let row: Vec<NodeId> = b_free.iter().map(|col| col[i]).collect();
            let s = dot(g, &row, w);
            g.add(s, drift[i])
        })
        .collect()
}

/// The generalized forces at the admissible velocity (zero without `#[forces]`).
fn forces<'a>(
    lowerer: &mut Lowerer<'a, '_>,
    spec: &Spec<'a>,
    inputs: &Inputs,
    qd: &[NodeId],
) -> Option<Vec<NodeId>> {
    let Some(f) = spec.forces else {
        return Some(vec![lowerer.graph.zero(); spec.dims.n]);
    };
    let args = vec![
        Value::Real(inputs.t),
        array(&inputs.q),
        array(qd),
        array(&inputs.u),
    ];
    let value = lowerer.call_role(f, args);
    if value.is_poison() {
        return None;
    }
    value.flatten()
}

/// The motion from the assembled equations: the free rows solved by LDLᵀ for ω̇, the
/// constrained ones giving the multipliers, and the power.
struct Motion {
    mass: Vec<Vec<NodeId>>,
    wdot: Vec<NodeId>,
    pivots: Vec<NodeId>,
    multipliers: Vec<NodeId>,
    power: NodeId,
}

fn solve(
    g: &mut Graph,
    assembled: &Assembled,
    transformation: &Transformation,
    x: &Vectors<'_>,
    p: usize,
) -> Motion {
    let solution = ldlt::solve(g, &assembled.mass, &assembled.rhs);
    let multipliers = multipliers(g, &assembled.constrained, transformation, &solution.x, p);
    let power = power(
        g,
        x.forces,
        x.qd,
        &multipliers,
        &x.offset[..p],
        assembled.lagrangian_rate,
    );
    Motion {
        mass: assembled.mass.clone(),
        wdot: solution.x,
        pivots: solution.pivots,
        multipliers,
        power,
    }
}

/// λ from the constrained columns, with the free accelerations `wdot` solved.
fn multipliers(
    g: &mut Graph,
    constrained: &Constrained,
    transformation: &Transformation,
    wdot: &[NodeId],
    p: usize,
) -> Vec<NodeId> {
    match constrained {
        Constrained::Rows { mass, rhs } => mass
            .iter()
            .zip(rhs)
            .map(|(row, &r)| {
                let coupled = dot(g, row, wdot);
                g.sub(coupled, r)
            })
            .collect(),
        Constrained::Residual { coupling, terms } => {
            let residual: Vec<NodeId> = terms
                .iter()
                .enumerate()
                .map(|(i, &term)| {
                    let along: Vec<NodeId> = coupling.iter().map(|c| c[i]).collect();
                    let coupled = dot(g, &along, wdot);
                    g.sub(coupled, term)
                })
                .collect();
            let mut mu = transformation.solve_transposed(g, &residual);
            mu.truncate(p);
            mu
        }
    }
}

/// dE/dt = f·q̇ − λᵀa_c − ∂L/∂t: the power of the forces, of the constraint forces where the
/// constraints carry an affine part (A_c q̇ = −a_c), and of an explicit time dependence.
fn power(
    g: &mut Graph,
    forces: &[NodeId],
    qd: &[NodeId],
    multipliers: &[NodeId],
    offsets: &[NodeId],
    lagrangian_rate: NodeId,
) -> NodeId {
    let force_power = dot(g, forces, qd);
    let constraint_power = dot(g, multipliers, offsets);
    let p = g.sub(force_power, constraint_power);
    g.sub(p, lagrangian_rate)
}

/// A number for a message, to four significant digits (`1.198`, `3.2e-9`).
pub(super) fn significant(x: f64) -> String {
    if x != 0.0 && (x.abs() < 1e-3 || x.abs() >= 1e5) {
        format!("{x:.3e}")
    } else {
        format!("{}", (x * 1e4).round() / 1e4)
    }
}
