//! `Surface`: what a body rolls on — a plane of any orientation and offset, at rest or
//! carried by a moving body, or a sphere rolled on from outside or inside.

use super::{Body, Rotation3, Vector3};

/// A surface a body rolls on without slipping, in the ground frame at one configuration.
///
/// * [`Surface::ground`]: the plane z = 0 at rest;
/// * [`Surface::plane`]: the plane z = 0 of a frame placed at `origin` with `orientation` —
///   an inclined plane is `Surface::plane(Vector3::zeros(), Rotation3::about_y(angle))`;
/// * [`Surface::of`]: the plane z = 0 of a body's own axes through its centre, moving with
///   it (a turntable, tilted or not; a belt; a cart's deck);
/// * [`Surface::sphere`]: a ball at rest, rolled on from outside;
/// * [`Surface::bowl`]: the inside of a sphere at rest.
///
/// In a model, a plane's or a sphere's pose may depend on the coordinates and the time: the
/// surface then moves, and the contact rows compare the rolling body's material velocity
/// with the surface's.
///
/// ```
/// use hamel_runtime::geometry::{Rotation3, Surface, Vector3};
/// let incline = Surface::plane(Vector3::zeros(), Rotation3::about_y(0.3));
/// let p = Vector3::new(1.0, 0.0, 0.0);
/// assert!((incline.normal(p) - Vector3::new(0.3f64.sin(), 0.0, 0.3f64.cos())).norm() < 1e-15);
/// assert!((incline.height(p) - 0.3f64.sin()).abs() < 1e-15);
/// let bowl = Surface::bowl(Vector3::new(0.0, 0.0, 1.0), 1.0);
/// assert_eq!(bowl.height(Vector3::new(0.0, 0.0, 0.5)), 0.5);
/// assert_eq!(bowl.normal(Vector3::zeros()), Vector3::z());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Surface {
    /// The plane z = 0 of the frame at `origin` turned by `orientation`: its normal is the
    /// frame's z axis, and it rolls along the frame's x and y axes.
    Plane {
        origin: Vector3,
        orientation: Rotation3,
    },
    /// A sphere, touched from outside.
    Sphere { centre: Vector3, radius: f64 },
    /// The inside of a sphere.
    Bowl { centre: Vector3, radius: f64 },
}

impl Surface {
    /// The ground at rest, the plane z = 0.
    pub const fn ground() -> Surface {
        Surface::Plane {
            origin: Vector3::zeros(),
            orientation: Rotation3::identity(),
        }
    }

    /// The plane z = 0 of the frame at `origin` turned by `orientation`.
    pub const fn plane(origin: Vector3, orientation: Rotation3) -> Surface {
        Surface::Plane {
            origin,
            orientation,
        }
    }

    /// The plane z = 0 of `body`'s own axes through its centre, moving with the body.
    pub const fn of(body: Body) -> Surface {
        Surface::Plane {
            origin: body.centre,
            orientation: body.orientation,
        }
    }

    /// A sphere of radius `radius` about `centre`, rolled on from outside.
    pub const fn sphere(centre: Vector3, radius: f64) -> Surface {
        Surface::Sphere { centre, radius }
    }

    /// The inside of a sphere of radius `radius` about `centre`.
    pub const fn bowl(centre: Vector3, radius: f64) -> Surface {
        Surface::Bowl { centre, radius }
    }

    /// The unit normal at (or over) `point`, pointing away from the surface towards the side
    /// a body rolls on: up from a plane, out of a sphere, in towards a bowl's centre.
    pub fn normal(&self, point: Vector3) -> Vector3 {
        match *self {
            Surface::Plane { orientation, .. } => orientation * Vector3::z(),
            Surface::Sphere { centre, .. } => (point - centre).normalize(),
            Surface::Bowl { centre, .. } => (centre - point).normalize(),
        }
    }

    /// How far `point` is from the surface, on the side bodies roll on (negative inside a
    /// plane's lower half-space, a sphere, or beyond a bowl's wall).
    pub fn height(&self, point: Vector3) -> f64 {
        match *self {
            Surface::Plane {
                origin,
                orientation,
            } => (orientation * Vector3::z()).dot(&(point - origin)),
            Surface::Sphere { centre, radius } => (point - centre).norm() - radius,
            Surface::Bowl { centre, radius } => radius - (point - centre).norm(),
        }
    }
}

impl Default for Surface {
    fn default() -> Self {
        Surface::ground()
    }
}
