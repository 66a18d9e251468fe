//! The geometry vocabulary of `hamel::geometry` (`Vector3`, `Rotation3`, `Inertia`, `Body`,
//! `Contact`, `disk_contact`), known to the lowering by name as `f64::sin` is: constructors,
//! operators, methods and fields become graph nodes, so that a model's geometry is
//! differentiated like the rest of its bodies and costs nothing at run time.
//!
//! A rotation keeps, besides its matrix, the elementary turns it was composed of while they
//! are known (`about_x(a) * from_axis_angle(k, b)`): the body angular velocity of such a
//! product follows from the turns' rates alone (`system::bodies` uses it), as a hand
//! derivation would write it, instead of from Rᵀ Ṙ. A vector likewise keeps how it was made
//! from others (`c + r * l`): its velocity is then ċ + ω × (r l) + r l̇, again as a hand
//! derivation writes it, where differentiating the entries of r l would expand every product
//! of sines and cosines in r.

use super::value::Value;
use super::{Env, Lowerer};
use crate::engine::graph::{Func, Graph, NodeId};
use quote::ToTokens;
use std::rc::Rc;
use syn::BinOp;

/// The vocabulary's types, by their names in `hamel::geometry`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GeoKind {
    Vector,
    Rotation,
    Inertia,
    Body,
    Contact,
}

impl GeoKind {
    pub fn name(self) -> &'static str {
        match self {
            GeoKind::Vector => "Vector3",
            GeoKind::Rotation => "Rotation3",
            GeoKind::Inertia => "Inertia",
            GeoKind::Body => "Body",
            GeoKind::Contact => "Contact",
        }
    }

    /// The type a path names, when it is one of the vocabulary's: `Vector3`,
    /// `geometry::Vector3`, `hamel::geometry::Vector3`.
    pub fn from_path(segments: &[&str]) -> Option<Self> {
        let (last, prefix) = segments.split_last()?;
        if !prefix.iter().all(|s| PREFIXES.contains(s)) {
            return None;
        }
        [
            GeoKind::Vector,
            GeoKind::Rotation,
            GeoKind::Inertia,
            GeoKind::Body,
            GeoKind::Contact,
        ]
        .into_iter()
        .find(|k| k.name() == *last)
    }

    /// How many reals a value of the kind holds (its flattened form).
    pub fn len(self) -> usize {
        match self {
            GeoKind::Vector => 3,
            GeoKind::Rotation => 9,
            GeoKind::Inertia => 6,
            GeoKind::Body => BODY_LEN,
            GeoKind::Contact => 2 * BODY_LEN + 3,
        }
    }
}

/// The paths the vocabulary is reached by.
const PREFIXES: [&str; 4] = ["hamel", "hamel_runtime", "geometry", "prelude"];

/// Mass, inertia, centre, orientation.
const BODY_LEN: usize = 1 + 6 + 3 + 9;

/// The vocabulary, for messages.
pub const VOCABULARY: &str = "`Vector3` (`new`, `zeros`, `x`, `y`, `z`, `+`, `-`, `* f64`, \
     `/ f64`, `dot`, `cross`, `norm`, `norm_squared`, `normalize`, `to_array`, `.x`, `[i]`), \
     `Rotation3` (`identity`, `about_x`, `about_y`, `about_z`, `from_axis_angle`, \
     `from_euler_angles`, `*`, `transpose`, `inverse`, `matrix`, `[(i, j)]`), `Inertia` \
     (`principal`, `new`), `Body` (`new`, `point_mass`, `point`, `.centre`, `.orientation`), \
     `Contact` (`ground`, `on`) and `disk_contact`";

pub type Vec3 = [NodeId; 3];

/// A vector: its components, and how it was made from other vectors, where that is known.
#[derive(Clone, Debug, PartialEq)]
pub struct Point {
    pub at: Vec3,
    pub how: Option<Rc<Made>>,
}

impl Point {
    pub fn leaf(at: Vec3) -> Point {
        Point { at, how: None }
    }

    fn made(at: Vec3, how: Made) -> Point {
        Point {
            at,
            how: Some(Rc::new(how)),
        }
    }
}

/// The operation a vector is the result of.
#[derive(Debug, PartialEq)]
pub enum Made {
    Sum(Point, Point),
    Difference(Point, Point),
    Negated(Point),
    Scaled(NodeId, Point),
    Cross(Point, Point),
    Rotated(Rotation, Point),
}
pub type Mat3 = [[NodeId; 3]; 3];

/// One elementary turn of a composed rotation: by `angle` about `axis` (a unit vector), with
/// its matrix.
#[derive(Clone, Debug, PartialEq)]
pub struct Turn {
    pub axis: Vec3,
    pub angle: NodeId,
    pub matrix: Mat3,
}

/// A rotation: its matrix, and the turns it is the product of (in order, the first applied
/// last), while they are known.
#[derive(Clone, Debug, PartialEq)]
pub struct Rotation {
    pub matrix: Mat3,
    pub turns: Option<Vec<Turn>>,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Body {
    pub mass: NodeId,
    /// I_xx, I_yy, I_zz, I_xy, I_yz, I_zx.
    pub inertia: [NodeId; 6],
    pub centre: Point,
    pub orientation: Rotation,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Contact {
    pub body: Body,
    /// The body whose surface it rolls on: the ground at rest is a body whose pose is
    /// constant (no mass, at the origin, unrotated), so that its material velocity is zero.
    pub surface: Body,
    pub point: Vec3,
}

/// A value of the vocabulary.
#[derive(Clone, Debug, PartialEq)]
pub enum Geo {
    Vector(Point),
    Rotation(Box<Rotation>),
    Inertia([NodeId; 6]),
    Body(Box<Body>),
    Contact(Box<Contact>),
}

impl Geo {
    pub fn kind(&self) -> GeoKind {
        match self {
            Geo::Vector(_) => GeoKind::Vector,
            Geo::Rotation(_) => GeoKind::Rotation,
            Geo::Inertia(_) => GeoKind::Inertia,
            Geo::Body(_) => GeoKind::Body,
            Geo::Contact(_) => GeoKind::Contact,
        }
    }

    /// Every real of the value, in the order of its fields.
    pub fn flatten_into(&self, out: &mut Vec<NodeId>) {
        match self {
            Geo::Vector(v) => out.extend(v.at),
            Geo::Rotation(r) => out.extend(r.matrix.iter().flatten()),
            Geo::Inertia(i) => out.extend(i),
            Geo::Body(b) => body_nodes(b, out),
            Geo::Contact(c) => {
                body_nodes(&c.body, out);
                body_nodes(&c.surface, out);
                out.extend(c.point);
            }
        }
    }

    /// A value of `kind` from reals in the order of [`Geo::flatten_into`] (a rotation's turns
    /// are then unknown).
    pub fn from_nodes(kind: GeoKind, nodes: &[NodeId]) -> Geo {
        let vec3 = |s: &[NodeId]| [s[0], s[1], s[2]];
        let mat3 = |s: &[NodeId]| [vec3(&s[0..3]), vec3(&s[3..6]), vec3(&s[6..9])];
        let body = |s: &[NodeId]| Body {
            mass: s[0],
            inertia: [s[1], s[2], s[3], s[4], s[5], s[6]],
            centre: Point::leaf(vec3(&s[7..10])),
            orientation: Rotation {
                matrix: mat3(&s[10..19]),
                turns: None,
            },
        };
        match kind {
            GeoKind::Vector => Geo::Vector(Point::leaf(vec3(nodes))),
            GeoKind::Rotation => Geo::Rotation(Box::new(Rotation {
                matrix: mat3(nodes),
                turns: None,
            })),
            GeoKind::Inertia => {
                Geo::Inertia([nodes[0], nodes[1], nodes[2], nodes[3], nodes[4], nodes[5]])
            }
            GeoKind::Body => Geo::Body(Box::new(body(nodes))),
            GeoKind::Contact => Geo::Contact(Box::new(Contact {
                body: body(&nodes[..BODY_LEN]),
                surface: body(&nodes[BODY_LEN..2 * BODY_LEN]),
                point: vec3(&nodes[2 * BODY_LEN..]),
            })),
        }
    }

    /// `if c { self } else { other }`, part by part (a rotation chosen so is no longer a
    /// product of known turns); `None` when the kinds differ.
    pub fn select(self, g: &mut Graph, c: NodeId, other: Geo) -> Option<Geo> {
        if self.kind() != other.kind() {
            return None;
        }
        if self == other {
            return Some(self);
        }
        let (mut a, mut b) = (Vec::new(), Vec::new());
        self.flatten_into(&mut a);
        other.flatten_into(&mut b);
        let picked: Vec<NodeId> = a.iter().zip(&b).map(|(&x, &y)| g.select(c, x, y)).collect();
        Some(Geo::from_nodes(self.kind(), &picked))
    }
}

fn body_nodes(b: &Body, out: &mut Vec<NodeId>) {
    out.push(b.mass);
    out.extend(b.inertia);
    out.extend(b.centre.at);
    out.extend(b.orientation.matrix.iter().flatten());
}

/// The ground at rest, as a body: no mass, at the origin, unrotated.
pub fn ground(g: &mut Graph) -> Body {
    let zero = g.zero();
    Body {
        mass: zero,
        inertia: [zero; 6],
        centre: Point::leaf([zero; 3]),
        orientation: identity(g),
    }
}

pub fn identity(g: &mut Graph) -> Rotation {
    let (zero, one) = (g.zero(), g.one());
    Rotation {
        matrix: [[one, zero, zero], [zero, one, zero], [zero, zero, one]],
        turns: Some(Vec::new()),
    }
}

pub fn add(g: &mut Graph, a: Vec3, b: Vec3) -> Vec3 {
    [g.add(a[0], b[0]), g.add(a[1], b[1]), g.add(a[2], b[2])]
}

pub fn sub(g: &mut Graph, a: Vec3, b: Vec3) -> Vec3 {
    [g.sub(a[0], b[0]), g.sub(a[1], b[1]), g.sub(a[2], b[2])]
}

pub fn scale(g: &mut Graph, s: NodeId, a: Vec3) -> Vec3 {
    [g.mul(s, a[0]), g.mul(s, a[1]), g.mul(s, a[2])]
}

pub fn dot(g: &mut Graph, a: Vec3, b: Vec3) -> NodeId {
    let terms = [g.mul(a[0], b[0]), g.mul(a[1], b[1]), g.mul(a[2], b[2])];
    g.sum(&terms)
}

pub fn cross(g: &mut Graph, a: Vec3, b: Vec3) -> Vec3 {
    let component = |g: &mut Graph, i: usize, j: usize| {
        let p = g.mul(a[i], b[j]);
        let q = g.mul(a[j], b[i]);
        g.sub(p, q)
    };
    [component(g, 1, 2), component(g, 2, 0), component(g, 0, 1)]
}

/// M v.
pub fn apply(g: &mut Graph, m: &Mat3, v: Vec3) -> Vec3 {
    [dot(g, m[0], v), dot(g, m[1], v), dot(g, m[2], v)]
}

/// Mᵀ v.
pub fn apply_transposed(g: &mut Graph, m: &Mat3, v: Vec3) -> Vec3 {
    let t = transpose(m);
    apply(g, &t, v)
}

pub fn transpose(m: &Mat3) -> Mat3 {
    [
        [m[0][0], m[1][0], m[2][0]],
        [m[0][1], m[1][1], m[2][1]],
        [m[0][2], m[1][2], m[2][2]],
    ]
}

pub fn product(g: &mut Graph, a: &Mat3, b: &Mat3) -> Mat3 {
    let t = transpose(b);
    let row =
        |g: &mut Graph, i: usize| [dot(g, a[i], t[0]), dot(g, a[i], t[1]), dot(g, a[i], t[2])];
    [row(g, 0), row(g, 1), row(g, 2)]
}

/// The rotation by `angle` about the unit vector `k` (Rodrigues' formula; for a coordinate
/// axis, whose entries are the constants 0 and 1, the graph folds it to the elementary
/// rotation).
pub fn turn(g: &mut Graph, k: Vec3, angle: NodeId) -> Turn {
    let s = g.unary(Func::Sin, angle);
    let c = g.unary(Func::Cos, angle);
    let one = g.one();
    let v = g.sub(one, c);
    let entry = |g: &mut Graph, i: usize, j: usize| {
        let kk = g.mul(k[i], k[j]);
        let outer = g.mul(v, kk);
        if i == j {
            return g.add(c, outer);
        }
        // [k]ₓ: the entry (i, j) is −ε_ijl k_l.
        let l = 3 - i - j;
        let sk = g.mul(s, k[l]);
        if (i + 1) % 3 == j {
            g.sub(outer, sk)
        } else {
            g.add(outer, sk)
        }
    };
    let matrix = [
        [entry(g, 0, 0), entry(g, 0, 1), entry(g, 0, 2)],
        [entry(g, 1, 0), entry(g, 1, 1), entry(g, 1, 2)],
        [entry(g, 2, 0), entry(g, 2, 1), entry(g, 2, 2)],
    ];
    Turn {
        axis: k,
        angle,
        matrix,
    }
}

fn unit(g: &mut Graph, i: usize) -> Vec3 {
    let (zero, one) = (g.zero(), g.one());
    let mut v = [zero; 3];
    v[i] = one;
    v
}

fn single(t: Turn) -> Rotation {
    Rotation {
        matrix: t.matrix,
        turns: Some(vec![t]),
    }
}

fn compose(g: &mut Graph, a: &Rotation, b: &Rotation) -> Rotation {
    let turns = match (&a.turns, &b.turns) {
        (Some(x), Some(y)) => Some(x.iter().chain(y).cloned().collect()),
        _ => None,
    };
    Rotation {
        matrix: product(g, &a.matrix, &b.matrix),
        turns,
    }
}

fn inverse(g: &mut Graph, r: &Rotation) -> Rotation {
    let turns = r.turns.as_ref().map(|turns| {
        turns
            .iter()
            .rev()
            .map(|t| Turn {
                axis: t.axis,
                angle: g.neg(t.angle),
                matrix: transpose(&t.matrix),
            })
            .collect()
    });
    Rotation {
        matrix: transpose(&r.matrix),
        turns,
    }
}

/// The lowest point of a thin disk (`hamel::geometry::disk_contact`).
pub fn disk_contact(g: &mut Graph, centre: Vec3, axle: Vec3, radius: NodeId, up: Vec3) -> Vec3 {
    let along = dot(g, up, axle);
    let tilted = scale(g, along, axle);
    let descent = sub(g, up, tilted);
    let one = g.one();
    let square = g.mul(along, along);
    let left = g.sub(one, square);
    let length = g.unary(Func::Sqrt, left);
    let factor = g.div(radius, length);
    let offset = scale(g, factor, descent);
    sub(g, centre, offset)
}

fn vector(v: Vec3) -> Value {
    Value::Geo(Geo::Vector(Point::leaf(v)))
}

fn point(p: Point) -> Value {
    Value::Geo(Geo::Vector(p))
}

fn rotation(r: Rotation) -> Value {
    Value::Geo(Geo::Rotation(Box::new(r)))
}

fn reals(v: &[NodeId]) -> Value {
    Value::Array(v.iter().map(|&n| Value::Real(n)).collect())
}

/// What an argument must be, for messages and for taking it apart.
#[derive(Clone, Copy)]
enum Want {
    Real,
    Geo(GeoKind),
}

impl Want {
    fn describe(self) -> String {
        match self {
            Want::Real => "`f64`".into(),
            Want::Geo(k) => format!("`{}`", k.name()),
        }
    }
}

/// A free function or an associated function of the vocabulary, by its path's last two
/// segments: the arguments it takes and what it makes of them.
fn signature(owner: Option<GeoKind>, name: &str) -> Option<&'static [Want]> {
    use GeoKind::*;
    const V: Want = Want::Geo(Vector);
    const R: Want = Want::Real;
    Some(match (owner, name) {
        (Some(Vector), "new") => &[R, R, R],
        (Some(Vector), "zeros" | "x" | "y" | "z") => &[],
        (Some(Rotation), "identity") => &[],
        (Some(Rotation), "about_x" | "about_y" | "about_z") => &[R],
        (Some(Rotation), "from_axis_angle") => &[V, R],
        (Some(Rotation), "from_euler_angles") => &[R, R, R],
        (Some(Inertia), "principal") => &[R, R, R],
        (Some(Inertia), "new") => &[R, R, R, R, R, R],
        (Some(Body), "new") => &[
            R,
            Want::Geo(GeoKind::Inertia),
            V,
            Want::Geo(GeoKind::Rotation),
        ],
        (Some(Body), "point_mass") => &[R, V],
        (Some(Contact), "ground") => &[Want::Geo(GeoKind::Body), V],
        (Some(Contact), "on") => &[Want::Geo(GeoKind::Body), Want::Geo(GeoKind::Body), V],
        (None, "disk_contact") => &[V, V, R, V],
        _ => return None,
    })
}

/// The parts of a checked argument.
enum Part {
    Real(NodeId),
    Geo(Geo),
}

impl Part {
    fn real(&self) -> Option<NodeId> {
        match self {
            Part::Real(n) => Some(*n),
            Part::Geo(_) => None,
        }
    }

    fn vector(&self) -> Option<Vec3> {
        self.point().map(|p| p.at)
    }

    fn point(&self) -> Option<Point> {
        match self {
            Part::Geo(Geo::Vector(v)) => Some(v.clone()),
            _ => None,
        }
    }

    fn body(self) -> Option<Body> {
        match self {
            Part::Geo(Geo::Body(b)) => Some(*b),
            _ => None,
        }
    }
}

/// Whether a free function's path names the vocabulary's `disk_contact`.
pub fn is_free_function(segments: &[&str]) -> bool {
    matches!(segments.split_last(), Some((&"disk_contact", prefix)) if prefix.iter().all(|s| PREFIXES.contains(s)))
}

impl Lowerer<'_, '_> {
    /// A call of the vocabulary's associated or free function at `segments`
    /// (`Vector3::new`, `hamel::geometry::disk_contact`); `None` when the path is not the
    /// vocabulary's.
    pub fn geometry_call(
        &mut self,
        env: &mut Env,
        segments: &[&str],
        c: &syn::ExprCall,
    ) -> Option<Value> {
        let (name, owner_path) = segments.split_last()?;
        let owner = match owner_path {
            [] => None,
            path => Some(GeoKind::from_path(path)?),
        };
        if owner.is_none() && !is_free_function(segments) {
            return None;
        }
        let Some(wants) = signature(owner, name) else {
            let owner = owner.map_or("hamel::geometry", GeoKind::name);
            return Some(self.error(
                &c.func,
                format!(
                    "`{owner}::{name}` is not part of hamel's geometry vocabulary: {VOCABULARY}"
                ),
            ));
        };
        let args: Vec<Value> = c.args.iter().map(|a| self.expr(env, a)).collect();
        if args.iter().any(Value::is_poison) {
            return Some(Value::Poison);
        }
        let written = segments.join("::");
        if args.len() != wants.len() {
            return Some(self.error(
                c,
                format!(
                    "`{written}` takes {} argument(s), {} given",
                    wants.len(),
                    args.len()
                ),
            ));
        }
        let mut parts = Vec::with_capacity(args.len());
        for ((arg, value), want) in c.args.iter().zip(args).zip(wants) {
            match (want, value) {
                (Want::Real, Value::Real(n)) => parts.push(Part::Real(n)),
                (Want::Geo(k), Value::Geo(g)) if g.kind() == *k => parts.push(Part::Geo(g)),
                (want, other) => {
                    let hint = match (want, &other) {
                        (Want::Real, Value::Int(_)) => " (write a float literal such as `2.0`)",
                        (Want::Geo(GeoKind::Inertia), _) => {
                            ": write `Inertia::principal(ixx, iyy, izz)`, or \
                             `Inertia::new(ixx, iyy, izz, ixy, iyz, izx)` with the products of \
                             inertia"
                        }
                        (Want::Geo(GeoKind::Vector), Value::Array(_)) => {
                            ": write `Vector3::new(x, y, z)`"
                        }
                        (Want::Geo(GeoKind::Rotation), _) => {
                            ": build it from `Rotation3::about_x(angle)` and its kin, composed \
                             with `*`"
                        }
                        _ => "",
                    };
                    return Some(self.error(
                        arg,
                        format!(
                            "`{written}` takes {} here, this is {}{hint}",
                            want.describe(),
                            other.describe()
                        ),
                    ));
                }
            }
        }
        Some(match self.construct(owner, name, parts) {
            Some(value) => value,
            None => self.error(
                c,
                "hamel internal error: a geometry call was checked but not built",
            ),
        })
    }

    /// The value of the vocabulary's function `name` (of `owner`) on arguments checked
    /// against its signature (`None` only if they do not fit it).
    fn construct(&mut self, owner: Option<GeoKind>, name: &str, parts: Vec<Part>) -> Option<Value> {
        let g = &mut *self.graph;
        let real = |i: usize| parts.get(i).and_then(Part::real);
        let vec3 = |i: usize| parts.get(i).and_then(Part::vector);
        Some(match (owner, name) {
            (Some(GeoKind::Vector), "new") => vector([real(0)?, real(1)?, real(2)?]),
            (Some(GeoKind::Vector), "zeros") => {
                let zero = g.zero();
                vector([zero; 3])
            }
            (Some(GeoKind::Vector), axis) => vector(unit(g, axis_index(axis))),
            (Some(GeoKind::Rotation), _) => rotation(make_rotation(g, name, &parts)?),
            (Some(GeoKind::Inertia), "principal") => {
                let zero = g.zero();
                let [xx, yy, zz] = [real(0)?, real(1)?, real(2)?];
                Value::Geo(Geo::Inertia([xx, yy, zz, zero, zero, zero]))
            }
            (Some(GeoKind::Inertia), _) => {
                let moments = [real(0)?, real(1)?, real(2)?];
                let products = [real(3)?, real(4)?, real(5)?];
                let [xx, yy, zz] = moments;
                let [xy, yz, zx] = products;
                Value::Geo(Geo::Inertia([xx, yy, zz, xy, yz, zx]))
            }
            (Some(GeoKind::Body), _) => {
                Value::Geo(Geo::Body(Box::new(make_body(g, name, &parts)?)))
            }
            (Some(GeoKind::Contact), on) => {
                let point = vec3(parts.len().checked_sub(1)?)?;
                let mut parts = parts.into_iter();
                let body = parts.next()?.body()?;
                let surface = match on {
                    "on" => parts.next()?.body()?,
                    _ => ground(g),
                };
                Value::Geo(Geo::Contact(Box::new(Contact {
                    body,
                    surface,
                    point,
                })))
            }
            (None, _) => vector(disk_contact(g, vec3(0)?, vec3(1)?, real(2)?, vec3(3)?)),
        })
    }

    /// A method of a vocabulary value: `a.cross(&b)`, `r.transpose()`.
    pub fn geometry_method(
        &mut self,
        receiver: Geo,
        m: &syn::ExprMethodCall,
        args: Vec<Value>,
    ) -> Value {
        let name = m.method.to_string();
        let kind = receiver.kind();
        let arity = match (kind, name.as_str()) {
            (GeoKind::Vector, "cross" | "dot") | (GeoKind::Body, "point") => 1,
            (GeoKind::Vector, "norm" | "norm_squared" | "normalize" | "to_array")
            | (GeoKind::Rotation, "transpose" | "inverse" | "matrix")
            | (GeoKind::Inertia, "matrix")
            | (_, "clone") => 0,
            _ => {
                return self.error(
                    &m.method,
                    format!(
                        "`{}` has no method `{name}` in hamel's geometry vocabulary: {VOCABULARY}",
                        kind.name()
                    ),
                );
            }
        };
        if args.len() != arity {
            return self.error(
                m,
                format!("`{name}` takes {arity} argument(s), {} given", args.len()),
            );
        }
        if args.iter().any(Value::is_poison) {
            return Value::Poison;
        }
        let other = args.into_iter().next();
        let g = &mut *self.graph;
        match (receiver, name.as_str(), other) {
            (value, "clone", None) => Value::Geo(value),
            (Geo::Vector(a), "cross", Some(Value::Geo(Geo::Vector(b)))) => {
                let at = cross(g, a.at, b.at);
                point(Point::made(at, Made::Cross(a, b)))
            }
            (Geo::Vector(a), "dot", Some(Value::Geo(Geo::Vector(b)))) => {
                Value::Real(dot(g, a.at, b.at))
            }
            (Geo::Vector(a), "norm_squared", None) => Value::Real(dot(g, a.at, a.at)),
            (Geo::Vector(a), "norm", None) => {
                let square = dot(g, a.at, a.at);
                Value::Real(g.unary(Func::Sqrt, square))
            }
            (Geo::Vector(a), "normalize", None) => vector(normalize(g, a.at)),
            (Geo::Vector(a), "to_array", None) => reals(&a.at),
            (Geo::Rotation(r), "transpose" | "inverse", None) => rotation(inverse(g, &r)),
            (Geo::Rotation(r), "matrix", None) => {
                Value::Array(r.matrix.iter().map(|row| reals(row)).collect())
            }
            (Geo::Inertia(i), "matrix", None) => {
                let [xx, yy, zz, xy, yz, zx] = i;
                Value::Array(vec![
                    reals(&[xx, xy, zx]),
                    reals(&[xy, yy, yz]),
                    reals(&[zx, yz, zz]),
                ])
            }
            (Geo::Body(b), "point", Some(Value::Geo(Geo::Vector(local)))) => {
                let arm = rotated(g, &b.orientation, &local);
                point(sum(g, b.centre.clone(), arm))
            }
            (_, _, Some(other)) => {
                let at = m.args.first().map(ToTokens::to_token_stream);
                self.error(
                    at.unwrap_or_else(|| m.to_token_stream()),
                    format!("`{name}` takes a `Vector3`, this is {}", other.describe()),
                )
            }
            _ => self.error(m, format!("`{name}` is not supported here")),
        }
    }

    /// A field of a vocabulary value: `v.x`, `body.centre`; `None` when the value is not the
    /// vocabulary's.
    pub fn geometry_field(&mut self, value: &Value, f: &syn::ExprField) -> Option<Value> {
        let Value::Geo(geo) = value else {
            return None;
        };
        let name = match &f.member {
            syn::Member::Named(id) => id.to_string(),
            syn::Member::Unnamed(i) => i.index.to_string(),
        };
        let got = match (geo, name.as_str()) {
            (Geo::Vector(v), "x") => Value::Real(v.at[0]),
            (Geo::Vector(v), "y") => Value::Real(v.at[1]),
            (Geo::Vector(v), "z") => Value::Real(v.at[2]),
            (Geo::Inertia(i), field) => match ["xx", "yy", "zz", "xy", "yz", "zx"]
                .iter()
                .position(|n| *n == field)
            {
                Some(k) => Value::Real(i[k]),
                None => return Some(self.no_field(geo, f)),
            },
            (Geo::Body(b), "mass") => Value::Real(b.mass),
            (Geo::Body(b), "inertia") => Value::Geo(Geo::Inertia(b.inertia)),
            (Geo::Body(b), "centre") => point(b.centre.clone()),
            (Geo::Body(b), "orientation") => rotation(b.orientation.clone()),
            (Geo::Contact(c), "body") => Value::Geo(Geo::Body(Box::new(c.body.clone()))),
            (Geo::Contact(c), "point") => vector(c.point),
            _ => return Some(self.no_field(geo, f)),
        };
        Some(got)
    }

    fn no_field(&mut self, geo: &Geo, f: &syn::ExprField) -> Value {
        let fields = match geo.kind() {
            GeoKind::Vector => "`x`, `y` and `z`",
            GeoKind::Rotation => "no fields (index it, `r[(i, j)]`, or call `matrix()`)",
            GeoKind::Inertia => "`xx`, `yy`, `zz`, `xy`, `yz` and `zx`",
            GeoKind::Body => "`mass`, `inertia`, `centre` and `orientation`",
            GeoKind::Contact => "`body` and `point`",
        };
        self.error(&f.member, format!("`{}` has {fields}", geo.kind().name()))
    }

    /// `v[i]` or `r[(i, j)]`, with indices known at compile time.
    pub fn geometry_index(&mut self, geo: Geo, index: Value, i: &syn::ExprIndex) -> Value {
        let small = |v: &Value| match v {
            Value::Int(k) => usize::try_from(*k).ok().filter(|&k| k < 3),
            _ => None,
        };
        match (&geo, &index) {
            (_, Value::Poison) => Value::Poison,
            (Geo::Vector(v), k) => match small(k) {
                Some(k) => Value::Real(v.at[k]),
                None => self.error(
                    &i.index,
                    format!(
                        "a `Vector3` has the components 0, 1 and 2, indexed by an integer known at \
                         compile time; this is {}",
                        k.describe()
                    ),
                ),
            },
            (Geo::Rotation(r), Value::Tuple(ij)) if ij.len() == 2 => {
                match (small(&ij[0]), small(&ij[1])) {
                    (Some(a), Some(b)) => Value::Real(r.matrix[a][b]),
                    _ => self.error(
                        &i.index,
                        "a `Rotation3` is indexed by (row, column), each 0, 1 or 2 and known at \
                         compile time",
                    ),
                }
            }
            (Geo::Rotation(_), _) => self.error(
                &i.index,
                "a `Rotation3` is indexed by (row, column): `r[(0, 2)]`",
            ),
            _ => self.error(
                &i.expr,
                format!("a `{}` cannot be indexed", geo.kind().name()),
            ),
        }
    }

    /// An arithmetic operator with a vocabulary value on either side; `None` when neither
    /// side is one.
    pub fn geometry_arith(
        &mut self,
        op: &BinOp,
        left: &Value,
        right: &Value,
        at: &syn::ExprBinary,
    ) -> Option<Value> {
        if !matches!(left, Value::Geo(_)) && !matches!(right, Value::Geo(_)) {
            return None;
        }
        let g = &mut *self.graph;
        use Geo::{Rotation as Rot, Vector as V};
        let value = match (op, left, right) {
            (BinOp::Add(_), Value::Geo(V(a)), Value::Geo(V(b))) => {
                point(sum(g, a.clone(), b.clone()))
            }
            (BinOp::Sub(_), Value::Geo(V(a)), Value::Geo(V(b))) => {
                let at = sub(g, a.at, b.at);
                point(Point::made(at, Made::Difference(a.clone(), b.clone())))
            }
            (BinOp::Mul(_), Value::Geo(V(a)), Value::Real(s))
            | (BinOp::Mul(_), Value::Real(s), Value::Geo(V(a))) => {
                let at = scale(g, *s, a.at);
                point(Point::made(at, Made::Scaled(*s, a.clone())))
            }
            (BinOp::Div(_), Value::Geo(V(a)), Value::Real(s)) => {
                vector([g.div(a.at[0], *s), g.div(a.at[1], *s), g.div(a.at[2], *s)])
            }
            (BinOp::Mul(_), Value::Geo(Rot(r)), Value::Geo(V(v))) => point(rotated(g, r, v)),
            (BinOp::Mul(_), Value::Geo(Rot(a)), Value::Geo(Rot(b))) => rotation(compose(g, a, b)),
            (_, l, r) => {
                let hint = if matches!(l, Value::Int(_)) || matches!(r, Value::Int(_)) {
                    " (write a float literal such as `2.0`)"
                } else {
                    ""
                };
                return Some(self.error(
                    at,
                    format!(
                        "`{}` cannot combine {} and {}{hint}: the vector operations are `a + b`, \
                         `a - b`, `a * s`, `s * a`, `a / s` and `r * a` (a rotation), and \
                         rotations compose by `r * s`",
                        op.to_token_stream(),
                        l.describe(),
                        r.describe()
                    ),
                ));
            }
        };
        Some(value)
    }

    /// `-v` for a vector.
    pub fn geometry_neg(&mut self, geo: Geo, u: &syn::ExprUnary) -> Value {
        match geo {
            Geo::Vector(v) => {
                let g = &mut *self.graph;
                let at = [g.neg(v.at[0]), g.neg(v.at[1]), g.neg(v.at[2])];
                point(Point::made(at, Made::Negated(v)))
            }
            other => self.error(u, format!("a `{}` cannot be negated", other.kind().name())),
        }
    }
}

/// `Rotation3::name(..)` on checked arguments.
fn make_rotation(g: &mut Graph, name: &str, parts: &[Part]) -> Option<Rotation> {
    let real = |i: usize| parts.get(i).and_then(Part::real);
    Some(match name {
        "identity" => identity(g),
        "from_axis_angle" => {
            let k = normalize(g, parts.first()?.vector()?);
            single(turn(g, k, real(1)?))
        }
        "from_euler_angles" => {
            let (ex, ey, ez) = (unit(g, 0), unit(g, 1), unit(g, 2));
            let z = single(turn(g, ez, real(2)?));
            let y = single(turn(g, ey, real(1)?));
            let x = single(turn(g, ex, real(0)?));
            let zy = compose(g, &z, &y);
            compose(g, &zy, &x)
        }
        about => {
            let k = unit(g, axis_index(about.trim_start_matches("about_")));
            single(turn(g, k, real(0)?))
        }
    })
}

/// `Body::name(..)` on checked arguments.
fn make_body(g: &mut Graph, name: &str, parts: &[Part]) -> Option<Body> {
    let mass = parts.first()?.real()?;
    if name == "point_mass" {
        let zero = g.zero();
        return Some(Body {
            mass,
            inertia: [zero; 6],
            centre: parts.get(1)?.point()?,
            orientation: identity(g),
        });
    }
    let (Some(Part::Geo(Geo::Inertia(inertia))), Some(Part::Geo(Geo::Rotation(r)))) =
        (parts.get(1), parts.get(3))
    else {
        return None;
    };
    Some(Body {
        mass,
        inertia: *inertia,
        centre: parts.get(2)?.point()?,
        orientation: (**r).clone(),
    })
}

/// a + b, remembered as a sum.
fn sum(g: &mut Graph, a: Point, b: Point) -> Point {
    let at = add(g, a.at, b.at);
    Point::made(at, Made::Sum(a, b))
}

/// r v, remembered as a rotated vector.
fn rotated(g: &mut Graph, r: &Rotation, v: &Point) -> Point {
    let at = apply(g, &r.matrix, v.at);
    Point::made(at, Made::Rotated(r.clone(), v.clone()))
}

fn axis_index(name: &str) -> usize {
    match name {
        "x" => 0,
        "y" => 1,
        _ => 2,
    }
}

fn normalize(g: &mut Graph, v: Vec3) -> Vec3 {
    let square = dot(g, v, v);
    let length = g.unary(Func::Sqrt, square);
    [
        g.div(v[0], length),
        g.div(v[1], length),
        g.div(v[2], length),
    ]
}
