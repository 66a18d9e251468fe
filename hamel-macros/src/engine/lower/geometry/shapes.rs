//! Where a shape touches a surface, and the frame of a contact: the surface's normal there,
//! the two directions the rolling rows forbid slip along, and the contact's height above the
//! surface. The same definitions as `hamel_runtime::geometry::{Shape, Surface, Contact}`.

use super::{
    Body, Contact, ShapeKind, ShapeNodes, Surface, SurfaceKind, Vec3, add, apply, apply_transposed,
    column, cross, disk_contact, dot, neg, norm, normalize, scale, sub,
};
use crate::engine::graph::{Func, Graph, NodeId};

/// The shape's centre in the ground frame.
fn shape_centre(g: &mut Graph, body: &Body, shape: &ShapeNodes) -> Vec3 {
    let arm = apply(g, &body.orientation.matrix, shape.centre);
    add(g, body.centre.at, arm)
}

/// The point of a disk's rim (centre, unit axle, radius) farthest along the unit `direction`:
/// its lowest point on a plane whose normal is −`direction`.
fn rim(g: &mut Graph, centre: Vec3, axle: Vec3, radius: NodeId, direction: Vec3) -> Vec3 {
    let up = neg(g, direction);
    disk_contact(g, centre, axle, radius, up)
}

/// The point of `shape`, carried by `body`, farthest along the unit vector `direction`
/// (`Shape::support`).
pub fn support(g: &mut Graph, body: &Body, shape: &ShapeNodes, direction: Vec3) -> Vec3 {
    let centre = shape_centre(g, body, shape);
    let r = &body.orientation.matrix;
    let [first, second, _] = shape.sizes;
    match shape.kind {
        ShapeKind::Disk | ShapeKind::Torus => {
            let axle = apply(g, r, shape.axle);
            let edge = rim(g, centre, axle, first, direction);
            if shape.kind == ShapeKind::Disk {
                return edge;
            }
            let tube = scale(g, second, direction);
            add(g, edge, tube)
        }
        ShapeKind::Sphere => {
            let offset = scale(g, first, direction);
            add(g, centre, offset)
        }
        ShapeKind::Ellipsoid => {
            // In body axes the support of x²/a² + … = 1 along m is D² m / √(mᵀ D² m).
            let m = apply_transposed(g, r, direction);
            let stretched: Vec<NodeId> = (0..3)
                .map(|i| {
                    let a = shape.sizes[i];
                    let aa = g.mul(a, a);
                    g.mul(aa, m[i])
                })
                .collect();
            let stretched = [stretched[0], stretched[1], stretched[2]];
            let reach = dot(g, stretched, m);
            let length = g.unary(Func::Sqrt, reach);
            let local = [
                g.div(stretched[0], length),
                g.div(stretched[1], length),
                g.div(stretched[2], length),
            ];
            let offset = apply(g, r, local);
            add(g, centre, offset)
        }
    }
}

/// Where `body` touches `surface` by its shape (`Contact::rolling`): the support point along
/// the surface's inward normal. `Err` with what is missing: a shape, or a ball for a sphere
/// or a bowl (whose contact point is closed-form only for a ball).
pub fn rolling_point(g: &mut Graph, body: &Body, surface: &Surface) -> Result<Vec3, String> {
    let Some(shape) = body.shape.as_deref() else {
        return Err("the body has no shape: give it one, \
                    `Body::new(..).with_shape(Shape::disk(radius, Vector3::y()))` (or `torus`, \
                    `sphere`, `ellipsoid`), or write the point with `Contact::new(body, \
                    surface, point)`"
            .into());
    };
    let inward = match surface.kind {
        SurfaceKind::Plane => {
            let up = column(&surface.frame.orientation.matrix, 2);
            neg(g, up)
        }
        SurfaceKind::Sphere | SurfaceKind::Bowl if shape.kind != ShapeKind::Sphere => {
            return Err(format!(
                "a {} rolls on a sphere or in a bowl only in special cases, whose contact point \
                 has no closed form; a `Shape::sphere` does (a ball on a ball, a ball in a \
                 bowl), or write the point with `Contact::new(body, surface, point)`",
                shape.kind.name()
            ));
        }
        kind => {
            let centre = shape_centre(g, body, shape);
            let towards = sub(g, surface.frame.centre.at, centre);
            let towards = normalize(g, towards);
            if kind == SurfaceKind::Sphere {
                towards
            } else {
                neg(g, towards)
            }
        }
    };
    Ok(support(g, body, shape, inward))
}

/// The unit normal of `surface` at (or over) `point`, towards the side bodies roll on
/// (`Surface::normal`).
pub fn surface_normal(g: &mut Graph, surface: &Surface, point: Vec3) -> Vec3 {
    let centre = surface.frame.centre.at;
    match surface.kind {
        SurfaceKind::Plane => column(&surface.frame.orientation.matrix, 2),
        SurfaceKind::Sphere => {
            let out = sub(g, point, centre);
            normalize(g, out)
        }
        SurfaceKind::Bowl => {
            let inward = sub(g, centre, point);
            normalize(g, inward)
        }
    }
}

/// How far `point` is from `surface`, on the side bodies roll on (`Surface::height`).
pub fn surface_height(g: &mut Graph, surface: &Surface, point: Vec3) -> NodeId {
    let centre = surface.frame.centre.at;
    let arm = sub(g, point, centre);
    match surface.kind {
        SurfaceKind::Plane => {
            let up = column(&surface.frame.orientation.matrix, 2);
            dot(g, up, arm)
        }
        SurfaceKind::Sphere => {
            let distance = norm(g, arm);
            g.sub(distance, surface.radius)
        }
        SurfaceKind::Bowl => {
            let distance = norm(g, arm);
            g.sub(surface.radius, distance)
        }
    }
}

/// A contact's frame: the surface's normal at the contact, the two directions of slip its
/// rows forbid, and its height above the surface.
pub struct ContactFrame {
    pub normal: Vec3,
    pub tangents: [Vec3; 2],
    pub height: NodeId,
}

/// The frame of `c`. A wheel (a disk or a torus) rolls along its heading a × n and across it
/// along n × (a × n), the ISO wheel axes x and y: the rows' multipliers are its longitudinal
/// and lateral forces. Other bodies slip along the ground's x and y axes on a horizontal plane
/// (and on a sphere or in a bowl, whose contacts must then keep off the sphere's horizontal
/// great circle), and along the plane's own x and y axes on any other.
pub fn contact_frame(g: &mut Graph, c: &Contact) -> ContactFrame {
    let normal = surface_normal(g, &c.surface, c.point);
    let height = surface_height(g, &c.surface, c.point);
    let wheel = c.body.shape.as_deref().filter(|s| s.kind.is_wheel());
    let tangents = match (wheel, c.surface.kind) {
        (Some(shape), _) => {
            let axle = apply(g, &c.body.orientation.matrix, shape.axle);
            let heading = cross(g, axle, normal);
            let heading = normalize(g, heading);
            let across = cross(g, normal, heading);
            [heading, across]
        }
        (None, SurfaceKind::Plane) if !is_vertical(g, normal) => {
            let m = &c.surface.frame.orientation.matrix;
            [column(m, 0), column(m, 1)]
        }
        _ => {
            let (zero, one) = (g.zero(), g.one());
            [[one, zero, zero], [zero, one, zero]]
        }
    };
    ContactFrame {
        normal,
        tangents,
        height,
    }
}

/// Whether `v` is the constant (0, 0, 1).
fn is_vertical(g: &Graph, v: Vec3) -> bool {
    g.is_zero(v[0]) && g.is_zero(v[1]) && g.is_const(v[2], 1.0)
}
