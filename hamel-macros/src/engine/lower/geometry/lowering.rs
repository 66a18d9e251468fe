//! The vocabulary as the lowering meets it: calls of its constructors and free functions,
//! methods, fields, indices and operators, each checked against what it takes and turned
//! into graph nodes.

use super::PREFIXES;
use super::shapes::{rolling_point, surface_height, surface_normal};
use super::{
    Body, Contact, Geo, GeoKind, Made, Point, Rotation, ShapeKind, ShapeNodes, Surface,
    SurfaceKind, VOCABULARY, Vec3, compose, cross, disk_contact, dot, frame, ground, identity,
    inverse, normalize, quaternion_turn, rotated, scale, single, sub, sum, turn, unit,
};
use crate::engine::graph::{Func, Graph, NodeId};
use crate::engine::lower::value::Value;
use crate::engine::lower::{Env, Lowerer};
use quote::ToTokens;
use syn::BinOp;

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
    /// `[[f64; 3]; 3]`, row by row.
    Matrix,
    Geo(GeoKind),
}

impl Want {
    fn describe(self) -> String {
        match self {
            Want::Real => "`f64`".into(),
            Want::Matrix => "`[[f64; 3]; 3]`".into(),
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
    const B: Want = Want::Geo(Body);
    const S: Want = Want::Geo(Surface);
    Some(match (owner, name) {
        (Some(Vector), "new") => &[R, R, R],
        (Some(Vector), "zeros" | "x" | "y" | "z") => &[],
        (Some(Rotation), "identity") => &[],
        (Some(Rotation), "about_x" | "about_y" | "about_z") => &[R],
        (Some(Rotation), "from_axis_angle") => &[V, R],
        (Some(Rotation), "from_euler_angles") => &[R, R, R],
        (Some(Rotation), "from_quaternion") => &[R, R, R, R],
        (Some(Rotation), "from_matrix_unchecked") => &[Want::Matrix],
        (Some(Inertia), "principal") => &[R, R, R],
        (Some(Inertia), "new") => &[R, R, R, R, R, R],
        (Some(Body), "new") => &[
            R,
            Want::Geo(GeoKind::Inertia),
            V,
            Want::Geo(GeoKind::Rotation),
        ],
        (Some(Body), "point_mass") => &[R, V],
        (Some(Shape), "disk") => &[R, V],
        (Some(Shape), "torus") => &[R, R, V],
        (Some(Shape), "sphere") => &[R],
        (Some(Shape), "ellipsoid") => &[R, R, R],
        (Some(Surface), "ground") => &[],
        (Some(Surface), "plane") => &[V, Want::Geo(GeoKind::Rotation)],
        (Some(Surface), "of") => &[B],
        (Some(Surface), "sphere" | "bowl") => &[V, R],
        (Some(Contact), "ground") => &[B, V],
        (Some(Contact), "on") => &[B, B, V],
        (Some(Contact), "new") => &[B, S, V],
        (Some(Contact), "rolling") => &[B, S],
        (None, "disk_contact") => &[V, V, R, V],
        _ => return None,
    })
}

/// The parts of a checked argument.
enum Part {
    Real(NodeId),
    Matrix([[NodeId; 3]; 3]),
    Geo(Geo),
}

impl Part {
    fn real(&self) -> Option<NodeId> {
        match self {
            Part::Real(n) => Some(*n),
            _ => None,
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

    fn surface(self) -> Option<Surface> {
        match self {
            Part::Geo(Geo::Surface(s)) => Some(*s),
            _ => None,
        }
    }

    fn rotation(self) -> Option<Rotation> {
        match self {
            Part::Geo(Geo::Rotation(r)) => Some(*r),
            _ => None,
        }
    }
}

/// A `[[f64; 3]; 3]` of reals.
fn matrix(value: &Value) -> Option<[[NodeId; 3]; 3]> {
    let Value::Array(rows) = value else {
        return None;
    };
    let row = |v: &Value| match v {
        Value::Array(items) if items.len() == 3 => {
            let real = |i: usize| match items[i] {
                Value::Real(n) => Some(n),
                _ => None,
            };
            Some([real(0)?, real(1)?, real(2)?])
        }
        _ => None,
    };
    match rows.as_slice() {
        [a, b, c] => Some([row(a)?, row(b)?, row(c)?]),
        _ => None,
    }
}

/// Whether a free function's path names the vocabulary's `disk_contact`.
fn is_free_function(segments: &[&str]) -> bool {
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
                (Want::Matrix, value) if matrix(&value).is_some() => {
                    parts.extend(matrix(&value).map(Part::Matrix));
                }
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
            Some(Ok(value)) => value,
            Some(Err(message)) => self.error(c, message),
            None => self.error(
                c,
                "hamel internal error: a geometry call was checked but not built",
            ),
        })
    }

    /// The value of the vocabulary's function `name` (of `owner`) on arguments checked
    /// against its signature (`None` only if they do not fit it; `Err` with a message when
    /// they fit but make no value: a rolling contact of a body without a shape).
    fn construct(
        &mut self,
        owner: Option<GeoKind>,
        name: &str,
        parts: Vec<Part>,
    ) -> Option<Result<Value, String>> {
        let g = &mut *self.graph;
        let real = |i: usize| parts.get(i).and_then(Part::real);
        let vec3 = |i: usize| parts.get(i).and_then(Part::vector);
        Some(Ok(match (owner, name) {
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
            (Some(GeoKind::Shape), _) => {
                Value::Geo(Geo::Shape(Box::new(make_shape(g, name, &parts)?)))
            }
            (Some(GeoKind::Surface), _) => {
                Value::Geo(Geo::Surface(Box::new(make_surface(g, name, parts)?)))
            }
            (Some(GeoKind::Contact), _) => match make_contact(g, name, parts)? {
                Ok(c) => Value::Geo(Geo::Contact(Box::new(c))),
                Err(message) => return Some(Err(message)),
            },
            (None, _) => vector(disk_contact(g, vec3(0)?, vec3(1)?, real(2)?, vec3(3)?)),
        }))
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
        let Some((arity, argument)) = method_signature(kind, &name) else {
            return self.error(
                &m.method,
                format!(
                    "`{}` has no method `{name}` in hamel's geometry vocabulary: {VOCABULARY}",
                    kind.name()
                ),
            );
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
        match apply_method(self.graph, receiver, &name, other) {
            Ok(value) => value,
            Err(Some(other)) => {
                let at = m.args.first().map(ToTokens::to_token_stream);
                self.error(
                    at.unwrap_or_else(|| m.to_token_stream()),
                    format!(
                        "`{name}` takes a `{}`, this is {}",
                        argument.name(),
                        other.describe()
                    ),
                )
            }
            Err(None) => self.error(m, format!("`{name}` is not supported here")),
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
            (Geo::Contact(c), "surface") => Value::Geo(Geo::Surface(Box::new(c.surface.clone()))),
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
            GeoKind::Body => {
                "`mass`, `inertia`, `centre` and `orientation` (its shape is not read inside a \
                 model)"
            }
            GeoKind::Contact => "`body`, `surface` and `point`",
            GeoKind::Shape | GeoKind::Surface => "no fields read inside a model",
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

/// The arity of a vocabulary value's method, and the kind its argument must be (if any).
fn method_signature(kind: GeoKind, name: &str) -> Option<(usize, GeoKind)> {
    use GeoKind::*;
    Some(match (kind, name) {
        (Vector, "cross" | "dot") | (Body, "point") | (Shape, "at") => (1, Vector),
        (Surface, "normal" | "height") => (1, Vector),
        (Body, "with_shape") => (1, Shape),
        (Vector, "norm" | "norm_squared" | "normalize" | "to_array")
        | (Rotation, "transpose" | "inverse" | "matrix")
        | (Inertia, "matrix")
        | (_, "clone") => (0, Vector),
        _ => return None,
    })
}

/// The value of a method on checked arguments: `Err(Some(argument))` when the argument is
/// not of the kind the method takes, `Err(None)` when nothing fits.
fn apply_method(
    g: &mut Graph,
    receiver: Geo,
    name: &str,
    other: Option<Value>,
) -> Result<Value, Option<Value>> {
    Ok(match (receiver, name, other) {
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
        (Geo::Body(b), "with_shape", Some(Value::Geo(Geo::Shape(shape)))) => {
            Value::Geo(Geo::Body(Box::new(super::Body {
                shape: Some(shape),
                ..*b
            })))
        }
        (Geo::Shape(s), "at", Some(Value::Geo(Geo::Vector(centre)))) => {
            Value::Geo(Geo::Shape(Box::new(ShapeNodes {
                centre: centre.at,
                ..*s
            })))
        }
        (Geo::Surface(s), "normal", Some(Value::Geo(Geo::Vector(p)))) => {
            vector(surface_normal(g, &s, p.at))
        }
        (Geo::Surface(s), "height", Some(Value::Geo(Geo::Vector(p)))) => {
            Value::Real(surface_height(g, &s, p.at))
        }
        (_, _, other) => return Err(other),
    })
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
        "from_quaternion" => single(quaternion_turn(g, [real(0)?, real(1)?, real(2)?, real(3)?])),
        "from_matrix_unchecked" => match parts.first()? {
            Part::Matrix(m) => Rotation {
                matrix: *m,
                turns: None,
            },
            _ => return None,
        },
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
            shape: None,
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
        shape: None,
    })
}

/// `Shape::name(..)` on checked arguments: centred at the body's centre of mass, its axle
/// normalized.
fn make_shape(g: &mut Graph, name: &str, parts: &[Part]) -> Option<ShapeNodes> {
    let real = |i: usize| parts.get(i).and_then(Part::real);
    let zero = g.zero();
    let (kind, sizes, axle) = match name {
        "disk" => (
            ShapeKind::Disk,
            [real(0)?, zero, zero],
            parts.get(1)?.vector()?,
        ),
        "torus" => (
            ShapeKind::Torus,
            [real(0)?, real(1)?, zero],
            parts.get(2)?.vector()?,
        ),
        "sphere" => (ShapeKind::Sphere, [real(0)?, zero, zero], [zero; 3]),
        _ => (
            ShapeKind::Ellipsoid,
            [real(0)?, real(1)?, real(2)?],
            [zero; 3],
        ),
    };
    let axle = if kind.is_wheel() {
        normalize(g, axle)
    } else {
        axle
    };
    Some(ShapeNodes {
        kind,
        centre: [zero; 3],
        axle,
        sizes,
    })
}

/// `Surface::name(..)` on checked arguments.
fn make_surface(g: &mut Graph, name: &str, parts: Vec<Part>) -> Option<Surface> {
    let zero = g.zero();
    let mut parts = parts.into_iter();
    let (kind, frame, radius) = match name {
        "ground" => (SurfaceKind::Plane, ground(g), zero),
        "of" => (SurfaceKind::Plane, parts.next()?.body()?, zero),
        "plane" => {
            let origin = parts.next()?.point()?;
            let orientation = parts.next()?.rotation()?;
            (SurfaceKind::Plane, frame(g, origin, orientation), zero)
        }
        sphere => {
            let centre = parts.next()?.point()?;
            let radius = parts.next()?.real()?;
            let kind = if sphere == "bowl" {
                SurfaceKind::Bowl
            } else {
                SurfaceKind::Sphere
            };
            let unrotated = identity(g);
            (kind, frame(g, centre, unrotated), radius)
        }
    };
    Some(Surface {
        kind,
        frame,
        radius,
    })
}

/// `Contact::name(..)` on checked arguments; `Err` for a rolling contact whose point cannot
/// be found from the body's shape.
fn make_contact(g: &mut Graph, name: &str, parts: Vec<Part>) -> Option<Result<Contact, String>> {
    let mut parts = parts.into_iter();
    let body = parts.next()?.body()?;
    let zero = g.zero();
    let plane = |frame: Body| Surface {
        kind: SurfaceKind::Plane,
        frame,
        radius: zero,
    };
    let surface = match name {
        "ground" => plane(ground(g)),
        "on" => plane(parts.next()?.body()?),
        _ => parts.next()?.surface()?,
    };
    let (point, from_shape) = match name {
        "rolling" => match rolling_point(g, &body, &surface) {
            Ok(point) => (point, true),
            Err(message) => return Some(Err(format!("`Contact::rolling`: {message}"))),
        },
        _ => (parts.next()?.vector()?, false),
    };
    Some(Ok(Contact {
        body,
        surface,
        point,
        from_shape,
    }))
}

fn axis_index(name: &str) -> usize {
    match name {
        "x" => 0,
        "y" => 1,
        _ => 2,
    }
}
