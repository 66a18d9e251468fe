//! Rigid bodies and rolling contacts, as a model's `#[bodies]` and `#[contacts]` state them.

use super::{Rotation3, Shape, Surface, Vector3, check_shapes};
use crate::error::Error;

/// The inertia tensor of a body about its centre of mass, in the body's own axes. The
/// products are the tensor's off-diagonal entries (SymPy's `inertia(frame, ixx, iyy, izz,
/// ixy, iyz, izx)`, and the Whipple bicycle benchmark's I_xz): the rotational kinetic energy
/// is ½ Ωᵀ I Ω for the angular velocity Ω in body axes.
///
/// ```
/// use hamel_runtime::geometry::Inertia;
/// let disk = Inertia::principal(0.25, 0.25, 0.5); // m r²/4 about diameters, m r²/2 about the axle
/// assert_eq!(disk.matrix()[2][2], 0.5);
/// let frame = Inertia::new(9.2, 11.0, 2.8, 0.0, 0.0, 2.4);
/// assert_eq!(frame.matrix()[0][2], 2.4);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Inertia {
    pub xx: f64,
    pub yy: f64,
    pub zz: f64,
    pub xy: f64,
    pub yz: f64,
    pub zx: f64,
}

impl Inertia {
    /// Principal moments: the body's axes are its principal axes.
    pub const fn principal(ixx: f64, iyy: f64, izz: f64) -> Self {
        Inertia::new(ixx, iyy, izz, 0.0, 0.0, 0.0)
    }

    /// Moments and products of inertia (the tensor's entries I_xy, I_yz, I_zx).
    pub const fn new(ixx: f64, iyy: f64, izz: f64, ixy: f64, iyz: f64, izx: f64) -> Self {
        Inertia {
            xx: ixx,
            yy: iyy,
            zz: izz,
            xy: ixy,
            yz: iyz,
            zx: izx,
        }
    }

    /// The tensor, row by row.
    pub const fn matrix(&self) -> [[f64; 3]; 3] {
        [
            [self.xx, self.xy, self.zx],
            [self.xy, self.yy, self.yz],
            [self.zx, self.yz, self.zz],
        ]
    }
}

/// A rigid body at one configuration: its mass, its inertia about its centre of mass in its
/// own axes, where its centre of mass is and how it is oriented (the rotation from its axes
/// to the ground frame).
///
/// In a model's `#[bodies]` role these are functions of the coordinates (and the time); the
/// macro derives the velocity of the centre, the angular velocity Ω (from Rᵀ Ṙ), the kinetic
/// energy Σ ½ m |ṙ|² + ½ Ωᵀ I Ω and, with `#[gravity]`, the potential energy of gravity.
/// A body may have a [`Shape`] ([`Body::with_shape`]): where it rolls, the contact point then
/// follows from the shape ([`Contact::rolling`]), and scenes draw it.
///
/// ```
/// use hamel_runtime::geometry::{Body, Inertia, Rotation3, Vector3};
/// let wheel = Body::new(
///     2.0,
///     Inertia::principal(0.06, 0.12, 0.06),
///     Vector3::new(0.0, 0.0, 0.3),
///     Rotation3::about_y(0.5),
/// );
/// // The point of the rim straight below the axle in the wheel's own axes:
/// let rim = wheel.point(Vector3::new(0.0, 0.0, -0.3));
/// assert!((rim - wheel.centre).norm() - 0.3 < 1e-15);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Body {
    pub mass: f64,
    pub inertia: Inertia,
    pub centre: Vector3,
    pub orientation: Rotation3,
    /// Its shape where it rolls, if it has been given one.
    pub shape: Option<Shape>,
}

impl Body {
    /// A body without a shape (give it one with [`Body::with_shape`]).
    pub const fn new(mass: f64, inertia: Inertia, centre: Vector3, orientation: Rotation3) -> Self {
        Body {
            mass,
            inertia,
            centre,
            orientation,
            shape: None,
        }
    }

    /// The same body with the shape `shape` (in its own axes).
    pub const fn with_shape(self, shape: Shape) -> Self {
        Body {
            shape: Some(shape),
            ..self
        }
    }

    /// A point mass: no inertia of its own, no orientation.
    pub const fn point_mass(mass: f64, centre: Vector3) -> Self {
        Body::new(
            mass,
            Inertia::principal(0.0, 0.0, 0.0),
            centre,
            Rotation3::identity(),
        )
    }

    /// The point fixed in the body at `local` from its centre of mass, in the body's axes.
    pub fn point(&self, local: Vector3) -> Vector3 {
        self.centre + self.orientation * local
    }
}

/// A body that rolls without slipping on a surface: in a model's `#[contacts]` role, the
/// macro makes the velocity of the body's material point at the contact, v + ω × (P − r),
/// equal to that of the surface there, along the surface (two constraint rows). The contact's
/// height above the surface is a holonomic condition, which `#[contacts(determines(..))]`
/// states where it is not already built into the coordinates.
///
/// [`Contact::rolling`] finds the point from the body's [`Shape`] and the [`Surface`]; the
/// other constructors take it as written.
///
/// ```
/// use hamel_runtime::geometry::{Body, Contact, Inertia, Rotation3, Shape, Surface, Vector3};
/// // A ball of radius 0.1 resting on a plane inclined by 0.2 rad about y.
/// let incline = Rotation3::about_y(0.2);
/// let ball = Body::new(1.0, Inertia::principal(0.004, 0.004, 0.004),
///     incline * Vector3::new(0.0, 0.0, 0.1), Rotation3::identity()).with_shape(Shape::sphere(0.1));
/// let contact = Contact::rolling(ball, Surface::plane(Vector3::zeros(), incline));
/// assert!(contact.point.norm() < 1e-16);
/// assert!(contact.surface.height(contact.point).abs() < 1e-16);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    /// The body that rolls.
    pub body: Body,
    /// What it rolls on.
    pub surface: Surface,
    /// Where they touch, in the ground frame.
    pub point: Vector3,
}

impl Contact {
    /// `body` rolls without slipping on the ground at rest (the plane z = 0), touching it at
    /// `point`.
    pub const fn ground(body: Body, point: Vector3) -> Self {
        Contact {
            body,
            surface: Surface::ground(),
            point,
        }
    }

    /// `body` rolls without slipping on the plane z = 0 of `surface`'s own axes (through its
    /// centre), which moves with `surface` (a turntable, tilted or not, or a belt: a body whose
    /// pose is a function of the time), touching it at `point`.
    pub const fn on(body: Body, surface: Body, point: Vector3) -> Self {
        Contact {
            body,
            surface: Surface::of(surface),
            point,
        }
    }

    /// `body` rolls without slipping on `surface`, touching it at `point`.
    pub const fn new(body: Body, surface: Surface, point: Vector3) -> Self {
        Contact {
            body,
            surface,
            point,
        }
    }

    /// `body` rolls without slipping on `surface`, touching it where its shape does: the
    /// point of the shape farthest along the surface's inward normal (on a sphere or in a
    /// bowl, towards or away from its centre: exact for a ball). A body without a shape is
    /// a point at its centre of mass. In a model, the macro requires the shape, and a ball
    /// for a sphere or a bowl. Where the point does not exist (a ball at a sphere's centre, a
    /// disk lying flat) it is NaN: [`Contact::try_rolling`] says why instead, and a model's
    /// state builder and runs refuse such a contact ([`super::check_contacts`]).
    pub fn rolling(body: Body, surface: Surface) -> Self {
        let point = match body.shape {
            None => body.centre,
            Some(shape) => {
                let centre = body.point(shape.centre());
                let inward = match surface {
                    Surface::Plane { orientation, .. } => -(orientation * Vector3::z()),
                    Surface::Sphere { centre: c, .. } => (c - centre).normalize(),
                    Surface::Bowl { centre: c, .. } => (centre - c).normalize(),
                };
                shape.support(&body, inward)
            }
        };
        Contact {
            body,
            surface,
            point,
        }
    }
}

impl Contact {
    /// [`Contact::rolling`], or an [`Error::ImpossibleGeometry`] saying why the body cannot
    /// touch the surface: a shape of no size, a plane whose frame is not a rotation, a
    /// sphere or bowl of no size, a ball no smaller than its bowl or at its sphere's centre, a
    /// disk lying flat.
    ///
    /// ```
    /// use hamel_runtime::geometry::{Body, Contact, Inertia, Rotation3, Shape, Surface, Vector3};
    /// let ball = Body::new(1.0, Inertia::principal(0.004, 0.004, 0.004), Vector3::zeros(),
    ///     Rotation3::identity()).with_shape(Shape::sphere(0.1));
    /// let sphere = Surface::sphere(Vector3::zeros(), 1.0);
    /// let e = Contact::try_rolling(ball, sphere).unwrap_err();
    /// assert!(e.to_string().contains("at the sphere's centre"), "{e}");
    /// ```
    pub fn try_rolling(body: Body, surface: Surface) -> Result<Contact, Error> {
        if let Some(reason) = body.shape.as_ref().and_then(check_shapes::impossible_shape) {
            return Err(Error::ImpossibleGeometry {
                what: "the body's shape".into(),
                reason,
            });
        }
        let contact = Contact::rolling(body, surface);
        check_shapes::check_contact(&contact)?;
        Ok(contact)
    }
}

/// The point of a thin disk (a knife-edge wheel) nearest a plane: the disk's centre `centre`,
/// its axle `axle` and the plane's normal `up`, pointing from the plane to the disk, both
/// unit vectors; the disk has radius `radius`. The point lies in the disk's plane, `radius`
/// from the centre along the steepest descent, P = c − r (u − (u·a) a) / √(1 − (u·a)²).
/// (Undefined when the disk lies flat, u·a = ±1: NaN; [`try_disk_contact`] says why.)
///
/// ```
/// use hamel_runtime::geometry::{Rotation3, Vector3, disk_contact};
/// // A wheel of radius 0.5 that leans by 0.3 rad about its heading x, its centre placed
/// // for it to touch the ground at the origin.
/// let lean = Rotation3::about_x(0.3);
/// let centre = Vector3::new(0.0, -0.5 * 0.3f64.sin(), 0.5 * 0.3f64.cos());
/// let p = disk_contact(centre, lean * Vector3::y(), 0.5, Vector3::z());
/// assert!(p.norm() < 1e-15);
/// ```
pub fn disk_contact(centre: Vector3, axle: Vector3, radius: f64, up: Vector3) -> Vector3 {
    let along = up.dot(&axle);
    let descent = up - along * axle;
    centre - (radius / (1.0 - along * along).sqrt()) * descent
}

/// [`disk_contact`], or an [`Error::ImpossibleGeometry`] saying why there is no such point:
/// a radius that is not positive, an axle or a normal that is not a unit vector, or a disk
/// lying flat on the plane (its axle along the normal).
///
/// ```
/// use hamel_runtime::geometry::{Vector3, try_disk_contact};
/// let e = try_disk_contact(Vector3::zeros(), Vector3::z(), 0.5, Vector3::z()).unwrap_err();
/// assert!(e.to_string().contains("lies flat"), "{e}");
/// ```
pub fn try_disk_contact(
    centre: Vector3,
    axle: Vector3,
    radius: f64,
    up: Vector3,
) -> Result<Vector3, Error> {
    let impossible = |reason: String| Error::ImpossibleGeometry {
        what: "the disk's contact point".into(),
        reason,
    };
    let shape = Shape::Disk {
        centre: Vector3::zeros(),
        axle,
        radius,
    };
    if let Some(reason) = check_shapes::impossible_shape(&shape) {
        return Err(impossible(reason));
    }
    if let Some(reason) = check_shapes::not_a_unit_vector("the plane's normal", up) {
        return Err(impossible(reason));
    }
    let point = disk_contact(centre, axle, radius, up);
    if point.to_array().iter().all(|v| v.is_finite()) && up.dot(&axle).abs() < 1.0 {
        return Ok(point);
    }
    Err(impossible(
        "the disk lies flat on the plane (its axle along the normal), where its rim has no \
         lowest point"
            .into(),
    ))
}
