//! The geometry vocabulary of `hamel::geometry` (`Vector3`, `Rotation3`, `Inertia`, `Body`,
//! `Shape`, `Surface`, `Contact`, `disk_contact`), known to the lowering by name as `f64::sin`
//! is: constructors, operators, methods and fields become graph nodes, so that a model's
//! geometry is differentiated like the rest of its bodies and costs nothing at run time.
//!
//! A rotation keeps, besides its matrix, the elementary turns it was composed of while they
//! are known (`about_x(a) * from_axis_angle(k, b)`, a quaternion's rotation): the body
//! angular velocity of such a product follows from the turns' rates alone (`system::bodies`
//! uses it), as a hand derivation would write it, instead of from Rᵀ Ṙ. A vector likewise
//! keeps how it was made from others (`c + r * l`): its velocity is then ċ + ω × (r l) + r l̇,
//! again as a hand derivation writes it, where differentiating the entries of r l would
//! expand every product of sines and cosines in r.
//!
//! One file per job: this one the values, `algebra` the operations on the graph, `shapes`
//! where a shape touches a surface, `lowering` the vocabulary's calls, methods and operators.
//! The run-time vocabulary (`hamel_runtime::geometry`) is the other copy of the same
//! definitions: the validation suite evaluates every function both ways.

mod algebra;
mod lowering;
mod shapes;
mod spin;

pub use algebra::*;
pub use shapes::contact_frame;
pub use spin::angular_velocity;

use crate::engine::graph::{Graph, NodeId};
use std::rc::Rc;

/// The vocabulary's types, by their names in `hamel::geometry`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GeoKind {
    Vector,
    Rotation,
    Inertia,
    Body,
    Contact,
    Shape,
    Surface,
}

impl GeoKind {
    const ALL: [GeoKind; 7] = [
        GeoKind::Vector,
        GeoKind::Rotation,
        GeoKind::Inertia,
        GeoKind::Body,
        GeoKind::Contact,
        GeoKind::Shape,
        GeoKind::Surface,
    ];

    pub fn name(self) -> &'static str {
        match self {
            GeoKind::Vector => "Vector3",
            GeoKind::Rotation => "Rotation3",
            GeoKind::Inertia => "Inertia",
            GeoKind::Body => "Body",
            GeoKind::Contact => "Contact",
            GeoKind::Shape => "Shape",
            GeoKind::Surface => "Surface",
        }
    }

    /// The type a path names, when it is one of the vocabulary's: `Vector3`,
    /// `geometry::Vector3`, `hamel::geometry::Vector3`.
    pub fn from_path(segments: &[&str]) -> Option<Self> {
        let (last, prefix) = segments.split_last()?;
        if !prefix.iter().all(|s| PREFIXES.contains(s)) {
            return None;
        }
        GeoKind::ALL.into_iter().find(|k| k.name() == *last)
    }

    /// How many reals a value of the kind holds in its plainest form (a body without a
    /// shape, a contact on a plane, a sphere): the form a fresh argument of the type takes.
    pub fn len(self) -> usize {
        match self {
            GeoKind::Vector => 3,
            GeoKind::Rotation => 9,
            GeoKind::Inertia => 6,
            GeoKind::Body => BODY_LEN,
            GeoKind::Contact => BODY_LEN + SURFACE_LEN + 3,
            GeoKind::Shape => SHAPE_LEN,
            GeoKind::Surface => SURFACE_LEN,
        }
    }
}

/// The paths the vocabulary is reached by.
const PREFIXES: [&str; 4] = ["hamel", "hamel_runtime", "geometry", "prelude"];

/// Mass, inertia, centre, orientation.
const BODY_LEN: usize = 1 + 6 + 3 + 9;
/// Centre, axle, sizes.
const SHAPE_LEN: usize = 9;
/// The frame's body and the radius.
const SURFACE_LEN: usize = BODY_LEN + 1;

/// The vocabulary, for messages.
pub const VOCABULARY: &str = "`Vector3` (`new`, `zeros`, `x`, `y`, `z`, `+`, `-`, `* f64`, \
     `/ f64`, `dot`, `cross`, `norm`, `norm_squared`, `normalize`, `to_array`, `.x`, `[i]`), \
     `Rotation3` (`identity`, `about_x`, `about_y`, `about_z`, `from_axis_angle`, \
     `from_euler_angles`, `from_quaternion`, `from_matrix_unchecked`, `*`, `transpose`, \
     `inverse`, `matrix`, `[(i, j)]`), `Inertia` (`principal`, `new`), `Body` (`new`, \
     `point_mass`, `with_shape`, `point`, `.centre`, `.orientation`), `Shape` (`disk`, \
     `torus`, `sphere`, `ellipsoid`, `at`), `Surface` (`ground`, `plane`, `of`, `sphere`, \
     `bowl`, `normal`, `height`), `Contact` (`ground`, `on`, `new`, `rolling`) and \
     `disk_contact`";

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

/// How one factor of a composed rotation turns: by `angle` about the unit vector `axis`, or
/// as the quaternion (w, x, y, z) of any length (the rotation of q/|q|).
#[derive(Clone, Debug, PartialEq)]
pub enum Spin {
    Axis { axis: Vec3, angle: NodeId },
    Quaternion([NodeId; 4]),
}

/// One factor of a composed rotation, with its matrix.
#[derive(Clone, Debug, PartialEq)]
pub struct Turn {
    pub spin: Spin,
    pub matrix: Mat3,
}

/// A rotation: its matrix, and the turns it is the product of (in order, the first applied
/// last), while they are known.
#[derive(Clone, Debug, PartialEq)]
pub struct Rotation {
    pub matrix: Mat3,
    pub turns: Option<Vec<Turn>>,
}

/// Which shape a [`ShapeNodes`] is (`hamel::geometry::Shape`'s variants).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShapeKind {
    Disk,
    Torus,
    Sphere,
    Ellipsoid,
}

impl ShapeKind {
    pub fn name(self) -> &'static str {
        match self {
            ShapeKind::Disk => "disk",
            ShapeKind::Torus => "torus",
            ShapeKind::Sphere => "sphere",
            ShapeKind::Ellipsoid => "ellipsoid",
        }
    }

    /// A wheel: it rolls along its heading and across its axle.
    pub fn is_wheel(self) -> bool {
        matches!(self, ShapeKind::Disk | ShapeKind::Torus)
    }
}

/// A body's shape, in its own axes: its centre from the centre of mass, its axle (a unit
/// vector, for a disk or a torus; zero otherwise) and its sizes — a disk's or a sphere's
/// radius, a torus's radius and tube, an ellipsoid's semi-axes (the rest zero).
#[derive(Clone, Debug, PartialEq)]
pub struct ShapeNodes {
    pub kind: ShapeKind,
    pub centre: Vec3,
    pub axle: Vec3,
    pub sizes: [NodeId; 3],
}

#[derive(Clone, Debug, PartialEq)]
pub struct Body {
    pub mass: NodeId,
    /// I_xx, I_yy, I_zz, I_xy, I_yz, I_zx.
    pub inertia: [NodeId; 6],
    pub centre: Point,
    pub orientation: Rotation,
    pub shape: Option<Box<ShapeNodes>>,
}

/// Which surface a [`Surface`] is (`hamel::geometry::Surface`'s variants).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SurfaceKind {
    /// The plane z = 0 of the frame's axes.
    Plane,
    /// A sphere about the frame's centre, touched from outside.
    Sphere,
    /// The inside of a sphere about the frame's centre.
    Bowl,
}

/// A surface: its kind, the frame it is fixed in — a body, whose material velocity is the
/// surface's (the ground at rest, a fixed plane's pose, a turntable) — and a sphere's radius
/// (zero for a plane).
#[derive(Clone, Debug, PartialEq)]
pub struct Surface {
    pub kind: SurfaceKind,
    pub frame: Body,
    pub radius: NodeId,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Contact {
    pub body: Body,
    pub surface: Surface,
    pub point: Vec3,
    /// Whether the point was found from the body's shape (`Contact::rolling`), rather than
    /// written.
    pub from_shape: bool,
}

/// A value of the vocabulary.
#[derive(Clone, Debug, PartialEq)]
pub enum Geo {
    Vector(Point),
    Rotation(Box<Rotation>),
    Inertia([NodeId; 6]),
    Body(Box<Body>),
    Contact(Box<Contact>),
    Shape(Box<ShapeNodes>),
    Surface(Box<Surface>),
}

impl Geo {
    pub fn kind(&self) -> GeoKind {
        match self {
            Geo::Vector(_) => GeoKind::Vector,
            Geo::Rotation(_) => GeoKind::Rotation,
            Geo::Inertia(_) => GeoKind::Inertia,
            Geo::Body(_) => GeoKind::Body,
            Geo::Contact(_) => GeoKind::Contact,
            Geo::Shape(_) => GeoKind::Shape,
            Geo::Surface(_) => GeoKind::Surface,
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
                surface_nodes(&c.surface, out);
                out.extend(c.point);
            }
            Geo::Shape(s) => shape_nodes(s, out),
            Geo::Surface(s) => surface_nodes(s, out),
        }
    }

    /// Whether two values are made alike — the same kinds of shapes and surfaces in the same
    /// places — so that one can be rebuilt from the other's reals.
    fn alike(&self, other: &Geo) -> bool {
        let body = |a: &Body, b: &Body| {
            a.shape.as_ref().map(|s| s.kind) == b.shape.as_ref().map(|s| s.kind)
        };
        match (self, other) {
            (Geo::Body(a), Geo::Body(b)) => body(a, b),
            (Geo::Contact(a), Geo::Contact(b)) => {
                body(&a.body, &b.body)
                    && a.surface.kind == b.surface.kind
                    && body(&a.surface.frame, &b.surface.frame)
                    && a.from_shape == b.from_shape
            }
            (Geo::Shape(a), Geo::Shape(b)) => a.kind == b.kind,
            (Geo::Surface(a), Geo::Surface(b)) => a.kind == b.kind && body(&a.frame, &b.frame),
            (a, b) => a.kind() == b.kind(),
        }
    }

    /// A value made like `self` from reals in the order of [`Geo::flatten_into`] (a
    /// rotation's turns are then unknown).
    fn rebuilt(&self, nodes: &mut impl Iterator<Item = NodeId>) -> Option<Geo> {
        Some(match self {
            Geo::Vector(_) => Geo::Vector(Point::leaf(vec3(nodes)?)),
            Geo::Rotation(_) => Geo::Rotation(Box::new(plain_rotation(nodes)?)),
            Geo::Inertia(_) => Geo::Inertia(take::<6>(nodes)?),
            Geo::Body(b) => Geo::Body(Box::new(rebuilt_body(b, nodes)?)),
            Geo::Contact(c) => Geo::Contact(Box::new(Contact {
                body: rebuilt_body(&c.body, nodes)?,
                surface: rebuilt_surface(&c.surface, nodes)?,
                point: vec3(nodes)?,
                from_shape: c.from_shape,
            })),
            Geo::Shape(s) => Geo::Shape(Box::new(rebuilt_shape(s.kind, nodes)?)),
            Geo::Surface(s) => Geo::Surface(Box::new(rebuilt_surface(s, nodes)?)),
        })
    }

    /// A value of `kind` in its plainest form ([`GeoKind::len`]) from reals in the order of
    /// [`Geo::flatten_into`].
    pub fn from_nodes(kind: GeoKind, nodes: &[NodeId]) -> Geo {
        let plain_body = || Body {
            mass: nodes[0],
            inertia: [nodes[0]; 6],
            centre: Point::leaf([nodes[0]; 3]),
            orientation: Rotation {
                matrix: [[nodes[0]; 3]; 3],
                turns: None,
            },
            shape: None,
        };
        let like = match kind {
            GeoKind::Vector => Geo::Vector(Point::leaf([nodes[0]; 3])),
            GeoKind::Rotation => Geo::Rotation(Box::new(Rotation {
                matrix: [[nodes[0]; 3]; 3],
                turns: None,
            })),
            GeoKind::Inertia => Geo::Inertia([nodes[0]; 6]),
            GeoKind::Body => Geo::Body(Box::new(plain_body())),
            GeoKind::Shape => Geo::Shape(Box::new(ShapeNodes {
                kind: ShapeKind::Sphere,
                centre: [nodes[0]; 3],
                axle: [nodes[0]; 3],
                sizes: [nodes[0]; 3],
            })),
            GeoKind::Surface | GeoKind::Contact => {
                let surface = Surface {
                    kind: SurfaceKind::Plane,
                    frame: plain_body(),
                    radius: nodes[0],
                };
                if kind == GeoKind::Surface {
                    Geo::Surface(Box::new(surface))
                } else {
                    Geo::Contact(Box::new(Contact {
                        body: plain_body(),
                        surface,
                        point: [nodes[0]; 3],
                        from_shape: false,
                    }))
                }
            }
        };
        like.rebuilt(&mut nodes.iter().copied()).unwrap_or(like)
    }

    /// `if c { self } else { other }`, part by part (a rotation chosen so is no longer a
    /// product of known turns); `None` when they are not made alike (different kinds, or
    /// shapes or surfaces of different kinds).
    pub fn select(self, g: &mut Graph, c: NodeId, other: Geo) -> Option<Geo> {
        if !self.alike(&other) {
            return None;
        }
        if self == other {
            return Some(self);
        }
        let (mut a, mut b) = (Vec::new(), Vec::new());
        self.flatten_into(&mut a);
        other.flatten_into(&mut b);
        let picked: Vec<NodeId> = a.iter().zip(&b).map(|(&x, &y)| g.select(c, x, y)).collect();
        self.rebuilt(&mut picked.into_iter())
    }
}

fn body_nodes(b: &Body, out: &mut Vec<NodeId>) {
    out.push(b.mass);
    out.extend(b.inertia);
    out.extend(b.centre.at);
    out.extend(b.orientation.matrix.iter().flatten());
    if let Some(s) = &b.shape {
        shape_nodes(s, out);
    }
}

fn shape_nodes(s: &ShapeNodes, out: &mut Vec<NodeId>) {
    out.extend(s.centre);
    out.extend(s.axle);
    out.extend(s.sizes);
}

fn surface_nodes(s: &Surface, out: &mut Vec<NodeId>) {
    body_nodes(&s.frame, out);
    out.push(s.radius);
}

fn take<const N: usize>(nodes: &mut impl Iterator<Item = NodeId>) -> Option<[NodeId; N]> {
    let v: Vec<NodeId> = nodes.take(N).collect();
    v.try_into().ok()
}

fn vec3(nodes: &mut impl Iterator<Item = NodeId>) -> Option<Vec3> {
    take::<3>(nodes)
}

fn plain_rotation(nodes: &mut impl Iterator<Item = NodeId>) -> Option<Rotation> {
    Some(Rotation {
        matrix: [vec3(nodes)?, vec3(nodes)?, vec3(nodes)?],
        turns: None,
    })
}

fn rebuilt_body(like: &Body, nodes: &mut impl Iterator<Item = NodeId>) -> Option<Body> {
    Some(Body {
        mass: nodes.next()?,
        inertia: take::<6>(nodes)?,
        centre: Point::leaf(vec3(nodes)?),
        orientation: plain_rotation(nodes)?,
        shape: match &like.shape {
            Some(s) => Some(Box::new(rebuilt_shape(s.kind, nodes)?)),
            None => None,
        },
    })
}

fn rebuilt_shape(kind: ShapeKind, nodes: &mut impl Iterator<Item = NodeId>) -> Option<ShapeNodes> {
    Some(ShapeNodes {
        kind,
        centre: vec3(nodes)?,
        axle: vec3(nodes)?,
        sizes: vec3(nodes)?,
    })
}

fn rebuilt_surface(like: &Surface, nodes: &mut impl Iterator<Item = NodeId>) -> Option<Surface> {
    Some(Surface {
        kind: like.kind,
        frame: rebuilt_body(&like.frame, nodes)?,
        radius: nodes.next()?,
    })
}
