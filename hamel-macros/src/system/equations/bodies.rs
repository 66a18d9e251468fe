//! What a model states from geometry: the rigid bodies' kinetic and potential energy, and
//! the rolling contacts' constraint rows and heights, derived by forward differentiation
//! along the motion.
//!
//! A body is given as a pose (centre r, orientation R) at (t, q). Along a motion with
//! velocities q̇ the centre moves at ṙ = ∂r/∂q q̇ + ∂r/∂t, a tangent of the graph; the body
//! angular velocity Ω is read off Rᵀ Ṙ = [Ω]ₓ, or, when R is a product of turns about fixed
//! axes, R = F₁ ⋯ Fₖ with Fᵢ = Rot(aᵢ, θᵢ), from the turns' rates alone,
//! Ω = Σᵢ (Fᵢ₊₁ ⋯ Fₖ)ᵀ aᵢ θ̇ᵢ (as a hand derivation writes it, and as cheap).
//!
//! A body B touching a surface S at P rolls without slipping when the material points of
//! both at P move alike: v_B + ω_B × (P − r_B) = v_S + ω_S × (P − r_S), along the surface.
//! That is the velocity of the material point, not Ṗ: the contact point itself moves over
//! the body as it rolls. The rows are the slip's components along two tangents of the
//! surface at P; the contact's height above the surface is a holonomic condition.

use super::{array, pairs};
use crate::engine::diff;
use crate::engine::graph::{Graph, NodeId};
use crate::engine::hash::HashMap;
use crate::engine::lower::geometry::{
    self, Body, Contact, Geo, GeoKind, Made, Mat3, Point, Rotation, Vec3, add, apply,
    apply_transposed, contact_frame, cross, dot, scale, sub,
};
use crate::engine::lower::{Lowerer, Value};
use crate::system::spec::Spec;

/// The direction a motion moves the graph's inputs in: q along the velocities, t at unit
/// rate. Tangents along it are time derivatives; the velocities of vectors and the angular
/// velocities of rotations found along it are kept, as the same vector (a wheel's centre)
/// is met again and again.
pub struct Motion {
    seeds: Vec<(NodeId, NodeId)>,
    /// The inputs whose motion is known (t and q), for telling fixed axes from moving ones.
    moving: Vec<NodeId>,
    velocities: HashMap<Vec3, Vec3>,
    spins: HashMap<Mat3, Vec3>,
}

impl Motion {
    pub fn new(g: &mut Graph, t: NodeId, q: &[NodeId], velocities: &[NodeId]) -> Self {
        let one = g.one();
        let mut seeds = pairs(q, velocities);
        seeds.push((t, one));
        let moving = std::iter::once(t).chain(q.iter().copied()).collect();
        Motion {
            seeds,
            moving,
            velocities: HashMap::default(),
            spins: HashMap::default(),
        }
    }

    /// The time derivatives of `nodes` along the motion.
    pub fn rate(&self, g: &mut Graph, nodes: &[NodeId]) -> Vec<NodeId> {
        diff::tangent(g, nodes, &self.seeds)
    }

    fn rate3(&self, g: &mut Graph, v: Vec3) -> Vec3 {
        let r = self.rate(g, &v);
        [r[0], r[1], r[2]]
    }

    /// The velocity of a vector: by the rule of the operation it was made by, down to the
    /// vectors whose entries are differentiated as they are.
    pub fn velocity(&mut self, g: &mut Graph, p: &Point) -> Vec3 {
        if let Some(v) = self.velocities.get(&p.at) {
            return *v;
        }
        let v = match p.how.as_deref() {
            None => self.rate3(g, p.at),
            Some(Made::Sum(a, b)) => {
                let (va, vb) = (self.velocity(g, a), self.velocity(g, b));
                add(g, va, vb)
            }
            Some(Made::Difference(a, b)) => {
                let (va, vb) = (self.velocity(g, a), self.velocity(g, b));
                sub(g, va, vb)
            }
            Some(Made::Negated(a)) => {
                let va = self.velocity(g, a);
                [g.neg(va[0]), g.neg(va[1]), g.neg(va[2])]
            }
            Some(Made::Scaled(s, a)) => {
                let rate = self.rate(g, &[*s])[0];
                let va = self.velocity(g, a);
                let stretched = scale(g, rate, a.at);
                let carried = scale(g, *s, va);
                add(g, stretched, carried)
            }
            Some(Made::Cross(a, b)) => {
                let (va, vb) = (self.velocity(g, a), self.velocity(g, b));
                let left = cross(g, va, b.at);
                let right = cross(g, a.at, vb);
                add(g, left, right)
            }
            // (r v)˙ = ω × r v + r v̇.
            Some(Made::Rotated(r, v)) => {
                let omega = self.spin(g, r);
                let turning = cross(g, omega, p.at);
                let vv = self.velocity(g, v);
                let carried = apply(g, &r.matrix, vv);
                add(g, turning, carried)
            }
        };
        self.velocities.insert(p.at, v);
        v
    }

    /// The angular velocity ω of a rotation, in the frame it maps to
    /// (`geometry::angular_velocity`), kept for the next time the rotation is met.
    pub fn spin(&mut self, g: &mut Graph, r: &Rotation) -> Vec3 {
        if let Some(w) = self.spins.get(&r.matrix) {
            return *w;
        }
        let moving = g.depends_on(&self.moving);
        let seeds = &self.seeds;
        let w = geometry::angular_velocity(g, r, &moving, &mut |g, nodes| {
            diff::tangent(g, nodes, seeds)
        });
        self.spins.insert(r.matrix, w);
        w
    }

    /// Whether a turn is about a fixed axis, or a quaternion's: a rotation its velocities can
    /// be seen in.
    fn is_fixed_turn(&self, g: &Graph, turn: &geometry::Turn) -> bool {
        match &turn.spin {
            geometry::Spin::Axis { axis, .. } => {
                let moving = g.depends_on(&self.moving);
                axis.iter().all(|a| !moving[a.index()])
            }
            geometry::Spin::Quaternion(_) => false,
        }
    }

    /// The body angular velocity Ω = Rᵀ ω, in the body's own axes.
    pub fn body_spin(&mut self, g: &mut Graph, r: &Rotation) -> Vec3 {
        let w = self.spin(g, r);
        apply_transposed(g, &r.matrix, w)
    }

    /// The velocity of the material point of `body` that is at `point`, in the ground frame:
    /// v + ω × (P − r).
    pub fn material_velocity(&mut self, g: &mut Graph, body: &Body, point: Vec3) -> Vec3 {
        let velocity = self.velocity(g, &body.centre);
        let omega = self.spin(g, &body.orientation);
        let arm = sub(g, point, body.centre.at);
        let turning = cross(g, omega, arm);
        add(g, velocity, turning)
    }
}

/// The bodies' kinetic energy along the motion at the given velocities and their potential
/// energy in gravity (zero without `#[gravity]`); `Some(None)` without `#[bodies]`, `None`
/// after a mistake (reported).
pub fn energies<'a>(
    lowerer: &mut Lowerer<'a, '_>,
    spec: &Spec<'a>,
    t: NodeId,
    q: &[NodeId],
    velocities: &[NodeId],
) -> Option<Option<(NodeId, NodeId)>> {
    if spec.geometry.bodies.is_none() {
        return Some(None);
    }
    let bodies = bodies(lowerer, spec, t, q)?;
    if !super::impossible::check_written(lowerer, spec, &bodies) {
        return None;
    }
    let gravity = gravity(lowerer, spec, t)?;
    let g = &mut *lowerer.graph;
    let mut motion = Motion::new(g, t, q, velocities);
    let kinetic = kinetic_energy(g, &bodies, &mut motion, spec.heading_frames.get());
    let potential = match gravity {
        Some(field) => potential_energy(g, &bodies, field),
        None => g.zero(),
    };
    Some(Some((kinetic, potential)))
}

/// The bodies of `#[bodies]` at (t, q), or `None` after a mistake (reported).
pub fn bodies<'a>(
    lowerer: &mut Lowerer<'a, '_>,
    spec: &Spec<'a>,
    t: NodeId,
    q: &[NodeId],
) -> Option<Vec<Body>> {
    let (f, _) = spec.geometry.bodies?;
    let value = super::lower_value(lowerer, spec, f, t, vec![array(q)])?;
    items(value, GeoKind::Body)?
        .into_iter()
        .map(|geo| match geo {
            Geo::Body(b) => Some(*b),
            _ => None,
        })
        .collect()
}

/// The gravitational acceleration of `#[gravity]`, if the model has it.
pub fn gravity<'a>(
    lowerer: &mut Lowerer<'a, '_>,
    spec: &Spec<'a>,
    t: NodeId,
) -> Option<Option<Vec3>> {
    let Some(f) = spec.geometry.gravity else {
        return Some(None);
    };
    match super::lower_value(lowerer, spec, f, t, Vec::new())? {
        Value::Geo(Geo::Vector(g)) => Some(Some(g.at)),
        _ => None,
    }
}

/// The vocabulary values of an array of `kind`.
pub(super) fn items(value: Value, kind: GeoKind) -> Option<Vec<Geo>> {
    match value {
        Value::Array(items) => items
            .into_iter()
            .map(|item| match item {
                Value::Geo(geo) if geo.kind() == kind => Some(geo),
                _ => None,
            })
            .collect(),
        _ => None,
    }
}

/// T = Σ ½ m |ṙ|² + ½ Ωᵀ I Ω along the motion.
pub fn kinetic_energy(g: &mut Graph, bodies: &[Body], motion: &mut Motion, turned: bool) -> NodeId {
    let half = g.constant(0.5);
    let terms: Vec<NodeId> = bodies
        .iter()
        .map(|body| {
            let velocity = motion.velocity(g, &body.centre);
            let speed = squared_speed(g, body, motion, velocity, turned);
            let translation = g.mul(body.mass, speed);
            let rotation = rotation_form(g, body, motion);
            let both = g.add(translation, rotation);
            g.mul(half, both)
        })
        .collect();
    g.sum(&terms)
}

/// |ṙ|², with `turned` from the components of ṙ in the frame of the first turn of the
/// body's orientation, when that is a turn about a fixed axis (a vehicle's yaw):
/// |F₁ᵀ ṙ|² = |ṙ|², but the components of F₁ᵀ ṙ are sums in which sin² + cos² of the turn
/// can meet factor by factor (c(cA − sB) + s(sA + cB) = A), where in |ṙ|² they meet only once
/// the squares of sums are expanded, which the graph's normal form does not do. The yaw of
/// the paper's robot and of a rolling disk then drops out of the energy, as it does of the
/// physics, instead of staying in every term of its derivatives (half the right-hand side's
/// operations); the bicycle's centres, built from its rear contact, are simpler as they are
/// (`equations::build` takes the cheaper).
fn squared_speed(
    g: &mut Graph,
    body: &Body,
    motion: &Motion,
    velocity: Vec3,
    turned: bool,
) -> NodeId {
    let first = body.orientation.turns.as_ref().and_then(|t| t.first());
    match first.filter(|t| turned && motion.is_fixed_turn(g, t)) {
        Some(turn) => {
            let seen = apply_transposed(g, &turn.matrix, velocity);
            dot(g, seen, seen)
        }
        None => dot(g, velocity, velocity),
    }
}

/// Ωᵀ I Ω. For a body symmetric about one of its axes k (a wheel: the other two moments
/// alike, no products of inertia), I_⊥ (|ω|² − (ω·a)²) + I_k (ω·a)² with a = R e_k the axis
/// in the ground frame: the body's turning about its own axis (a wheel's spin angle) then
/// drops out of the expression, as it does of the energy, instead of cancelling between
/// sines and cosines of it.
fn rotation_form(g: &mut Graph, body: &Body, motion: &mut Motion) -> NodeId {
    let [xx, yy, zz, xy, yz, zx] = body.inertia;
    let no_products = [xy, yz, zx].iter().all(|&p| g.is_zero(p));
    let axis = match (xx == yy, yy == zz, zz == xx) {
        _ if !no_products => None,
        (true, true, _) => {
            // A sphere's inertia: I |ω|².
            let w = motion.spin(g, &body.orientation);
            let square = dot(g, w, w);
            return g.mul(xx, square);
        }
        (_, true, _) => Some((0, xx, yy)),
        (_, _, true) => Some((1, yy, xx)),
        (true, _, _) => Some((2, zz, xx)),
        _ => None,
    };
    let Some((k, along, across)) = axis else {
        let omega = motion.body_spin(g, &body.orientation);
        return inertia_form(g, &body.inertia, omega);
    };
    let w = motion.spin(g, &body.orientation);
    let m = &body.orientation.matrix;
    let a = [m[0][k], m[1][k], m[2][k]];
    let spin = dot(g, w, a);
    let spin2 = g.mul(spin, spin);
    let all = dot(g, w, w);
    let rest = g.sub(all, spin2);
    let about = g.mul(along, spin2);
    let around = g.mul(across, rest);
    g.add(about, around)
}

/// Ωᵀ I Ω for the tensor's entries (xx, yy, zz, xy, yz, zx).
fn inertia_form(g: &mut Graph, i: &[NodeId; 6], w: Vec3) -> NodeId {
    let [xx, yy, zz, xy, yz, zx] = *i;
    let square = |g: &mut Graph, a: NodeId, x: NodeId| {
        let xx = g.mul(x, x);
        g.mul(a, xx)
    };
    let product = |g: &mut Graph, a: NodeId, x: NodeId, y: NodeId| {
        let two = g.constant(2.0);
        let xy = g.mul(x, y);
        let a2 = g.mul(two, a);
        g.mul(a2, xy)
    };
    let terms = [
        square(g, xx, w[0]),
        square(g, yy, w[1]),
        square(g, zz, w[2]),
        product(g, xy, w[0], w[1]),
        product(g, yz, w[1], w[2]),
        product(g, zx, w[2], w[0]),
    ];
    g.sum(&terms)
}

/// V = −Σ m g·r: the potential of the uniform gravitational acceleration `gravity`.
pub fn potential_energy(g: &mut Graph, bodies: &[Body], gravity: Vec3) -> NodeId {
    let terms: Vec<NodeId> = bodies
        .iter()
        .map(|body| {
            let height = dot(g, gravity, body.centre.at);
            let weight = g.mul(body.mass, height);
            g.neg(weight)
        })
        .collect();
    g.sum(&terms)
}

/// Two rows per contact: the slip, the velocity of the rolling body's material point at the
/// contact relative to the surface's, along the contact frame's two tangents (`contact_frame`:
/// a wheel's heading and axle, or the surface's x and y axes).
pub fn rolling_rows(g: &mut Graph, contacts: &[Contact], motion: &mut Motion) -> Vec<NodeId> {
    let mut rows = Vec::with_capacity(2 * contacts.len());
    for c in contacts {
        let body = motion.material_velocity(g, &c.body, c.point);
        let surface = motion.material_velocity(g, &c.surface.frame, c.point);
        let slip = sub(g, body, surface);
        let frame = contact_frame(g, c);
        rows.extend(frame.tangents.map(|t| dot(g, slip, t)));
    }
    rows
}

/// Each contact's height above its surface (z for the ground).
pub fn heights(g: &mut Graph, contacts: &[Contact]) -> Vec<NodeId> {
    contacts
        .iter()
        .map(|c| contact_frame(g, c).height)
        .collect()
}
