//! Rigid bodies and rolling contacts, as a model's `#[bodies]` and `#[contacts]` state them.

use super::{Rotation3, Vector3};

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
}

impl Body {
    pub const fn new(mass: f64, inertia: Inertia, centre: Vector3, orientation: Rotation3) -> Self {
        Body {
            mass,
            inertia,
            centre,
            orientation,
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

/// A body that rolls without slipping at a point: in a model's `#[contacts]` role, the macro
/// makes the velocity of the body's material point at the contact, v + ω × (P − r), equal to
/// that of the surface it rolls on, along the surface (two constraint rows). The surface is
/// the ground, the plane z = 0 at rest ([`Contact::ground`]), or a horizontal surface that
/// moves with another body, a turntable or a belt ([`Contact::on`]). The contact's height
/// above the surface is a holonomic condition, which `#[contacts(determines(..))]` states
/// where it is not already built into the coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    /// The body that rolls.
    pub body: Body,
    /// The body whose surface it rolls on; `None` for the ground at rest.
    pub surface: Option<Body>,
    /// Where they touch, in the ground frame.
    pub point: Vector3,
}

impl Contact {
    /// `body` rolls without slipping on the ground at rest (the plane z = 0), touching it at
    /// `point`.
    pub const fn ground(body: Body, point: Vector3) -> Self {
        Contact {
            body,
            surface: None,
            point,
        }
    }

    /// `body` rolls without slipping on a horizontal surface that moves with `surface` (a
    /// turntable, a belt: a body whose pose is a function of the time), touching it at
    /// `point`.
    pub const fn on(body: Body, surface: Body, point: Vector3) -> Self {
        Contact {
            body,
            surface: Some(surface),
            point,
        }
    }
}

/// The point of a thin disk (a knife-edge wheel) nearest a plane: the disk's centre `centre`,
/// its axle `axle` and the plane's normal `up`, pointing from the plane to the disk, both
/// unit vectors; the disk has radius `radius`. The point lies in the disk's plane, `radius`
/// from the centre along the steepest descent, P = c − r (u − (u·a) a) / √(1 − (u·a)²).
/// (Undefined when the disk lies flat, u·a = ±1.)
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
