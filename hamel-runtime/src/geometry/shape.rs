//! `Shape`: what a body looks like where it touches a surface, so that the contact point
//! follows from the shape and the surface (the shape's support point along the surface's
//! normal) instead of being written by hand.

use super::{Body, Vector3, check_shapes};
use crate::error::Error;

/// The shape of a body where it rolls, in the body's own axes: a thin disk (a knife-edge
/// wheel), a torus (a wheel with a round tyre), a sphere or an ellipsoid, centred `centre`
/// from the body's centre of mass (zero unless moved with [`Shape::at`]).
///
/// Given to a body with [`Body::with_shape`], it makes [`super::Contact::rolling`] find the
/// point where the body touches a surface — the point of the shape farthest along the
/// surface's inward normal ([`Shape::support`]) — so that the contact cannot be off the
/// body. Scenes draw a body by its shape when it has one.
///
/// ```
/// use hamel_runtime::geometry::{Body, Inertia, Rotation3, Shape, Vector3};
/// // A wheel of radius 0.3 on its y axis, leaning by 0.2 rad.
/// let wheel = Body::new(2.0, Inertia::principal(0.045, 0.09, 0.045), Vector3::new(0.0, 0.0, 0.3),
///     Rotation3::about_x(0.2)).with_shape(Shape::disk(0.3, Vector3::y()));
/// let lowest = wheel.shape.unwrap().support(&wheel, -Vector3::z());
/// assert!(((lowest - wheel.centre).norm() - 0.3).abs() < 1e-15);
/// assert!((lowest.z - (0.3 - 0.3 * 0.2f64.cos())).abs() < 1e-15);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shape {
    /// A thin disk of radius `radius` about the axle `axle` (a unit vector in body axes).
    Disk {
        centre: Vector3,
        axle: Vector3,
        radius: f64,
    },
    /// A torus: a wheel of radius `radius` to the centre line of a tyre of round cross-section
    /// of radius `tube`, about the axle `axle` (a unit vector in body axes). Its outer radius
    /// is `radius + tube`.
    Torus {
        centre: Vector3,
        axle: Vector3,
        radius: f64,
        tube: f64,
    },
    /// A sphere of radius `radius`.
    Sphere { centre: Vector3, radius: f64 },
    /// An ellipsoid whose semi-axes, `semi_axes.x` … `semi_axes.z`, lie along the body's
    /// axes.
    Ellipsoid { centre: Vector3, semi_axes: Vector3 },
}

impl Shape {
    /// A thin disk of radius `radius` about the axle `axle` (in body axes; normalized).
    pub fn disk(radius: f64, axle: Vector3) -> Shape {
        Shape::Disk {
            centre: Vector3::zeros(),
            axle: axle.normalize(),
            radius,
        }
    }

    /// A wheel of radius `radius` (to the tyre's centre line) with a tyre of round
    /// cross-section of radius `tube`, about the axle `axle` (in body axes; normalized).
    pub fn torus(radius: f64, tube: f64, axle: Vector3) -> Shape {
        Shape::Torus {
            centre: Vector3::zeros(),
            axle: axle.normalize(),
            radius,
            tube,
        }
    }

    /// A sphere of radius `radius`.
    pub const fn sphere(radius: f64) -> Shape {
        Shape::Sphere {
            centre: Vector3::zeros(),
            radius,
        }
    }

    /// An ellipsoid with the semi-axes `a`, `b`, `c` along the body's x, y and z axes.
    pub const fn ellipsoid(a: f64, b: f64, c: f64) -> Shape {
        Shape::Ellipsoid {
            centre: Vector3::zeros(),
            semi_axes: Vector3::new(a, b, c),
        }
    }

    /// The same shape centred `centre` from the body's centre of mass, in body axes (a
    /// ball whose centre of mass is not its centre, a rattleback's hull).
    pub const fn at(self, centre: Vector3) -> Shape {
        match self {
            Shape::Disk { axle, radius, .. } => Shape::Disk {
                centre,
                axle,
                radius,
            },
            Shape::Torus {
                axle, radius, tube, ..
            } => Shape::Torus {
                centre,
                axle,
                radius,
                tube,
            },
            Shape::Sphere { radius, .. } => Shape::Sphere { centre, radius },
            Shape::Ellipsoid { semi_axes, .. } => Shape::Ellipsoid { centre, semi_axes },
        }
    }

    /// The shape's centre from the body's centre of mass, in body axes.
    pub const fn centre(&self) -> Vector3 {
        match self {
            Shape::Disk { centre, .. }
            | Shape::Torus { centre, .. }
            | Shape::Sphere { centre, .. }
            | Shape::Ellipsoid { centre, .. } => *centre,
        }
    }

    /// The point of the shape, carried by `body`, farthest along the unit vector `direction`
    /// (in the ground frame): where it touches a plane whose normal is −`direction`.
    /// For a disk (and a torus) it is undefined when `direction` is along the axle, the disk
    /// lying flat on the plane: NaN; [`Shape::try_support`] says why instead.
    pub fn support(&self, body: &Body, direction: Vector3) -> Vector3 {
        let centre = body.point(self.centre());
        match *self {
            Shape::Disk { axle, radius, .. } => {
                rim(centre, body.orientation * axle, radius, direction)
            }
            Shape::Torus {
                axle, radius, tube, ..
            } => rim(centre, body.orientation * axle, radius, direction) + tube * direction,
            Shape::Sphere { radius, .. } => centre + radius * direction,
            Shape::Ellipsoid { semi_axes, .. } => {
                // In body axes the support of x²/a² + … = 1 along m is D² m / √(mᵀ D² m).
                let m = body.orientation.transpose() * direction;
                let stretched = Vector3::new(
                    semi_axes.x * semi_axes.x * m.x,
                    semi_axes.y * semi_axes.y * m.y,
                    semi_axes.z * semi_axes.z * m.z,
                );
                centre + body.orientation * (stretched / stretched.dot(&m).sqrt())
            }
        }
    }
}

impl Shape {
    /// [`Shape::support`], or an [`Error::ImpossibleGeometry`] saying why there is no such
    /// point: a shape of no size or without an axle, a body whose orientation is not a
    /// rotation, a direction that is not a unit vector, or a disk (or torus) whose axle is
    /// along the direction, every point of its rim as far along it.
    ///
    /// ```
    /// use hamel_runtime::geometry::{Body, Inertia, Rotation3, Shape, Vector3};
    /// let wheel = Body::new(2.0, Inertia::principal(0.045, 0.09, 0.045), Vector3::zeros(),
    ///     Rotation3::identity());
    /// let flat = Shape::disk(0.3, Vector3::z());
    /// let e = flat.try_support(&wheel, -Vector3::z()).unwrap_err();
    /// assert!(e.to_string().contains("along its axle"), "{e}");
    /// let e = Shape::sphere(-0.1).try_support(&wheel, -Vector3::z()).unwrap_err();
    /// assert!(e.to_string().contains("radius is -0.1"), "{e}");
    /// ```
    pub fn try_support(&self, body: &Body, direction: Vector3) -> Result<Vector3, Error> {
        let impossible = |reason: String| Error::ImpossibleGeometry {
            what: "the shape's support point".into(),
            reason,
        };
        let problem = check_shapes::impossible_shape(self)
            .or_else(|| {
                check_shapes::not_a_rotation(&body.orientation)
                    .map(|r| format!("the body's orientation: {r}"))
            })
            .or_else(|| check_shapes::not_a_unit_vector("the direction", direction));
        if let Some(reason) = problem {
            return Err(impossible(reason));
        }
        let point = self.support(body, direction);
        if point.to_array().iter().all(|v| v.is_finite()) {
            return Ok(point);
        }
        Err(impossible(
            "the direction is along its axle: every point of the rim is as far along it (a \
             disk lying flat)"
                .into(),
        ))
    }
}

/// The point of the rim of a disk (centre, unit axle, radius) farthest along `direction`.
fn rim(centre: Vector3, axle: Vector3, radius: f64, direction: Vector3) -> Vector3 {
    let along = direction.dot(&axle);
    let across = direction - along * axle;
    centre + (radius / (1.0 - along * along).sqrt()) * across
}
