//! The rattleback (celt): a body on a paraboloidal base whose principal axes of curvature are
//! turned by an angle δ against its principal axes of inertia. Spun one way it rocks, stops
//! and spins back the other way (Walker, *On a dynamical top*, Q. J. Pure Appl. Math. 28,
//! 1896; Garcia & Hubbard, *Spin reversal of the rattleback: theory and experiment*, Proc.
//! R. Soc. A 418, 1988). Stated from geometry: the centre of mass at (x, y, z), the
//! orientation a yaw ψ, a roll φ and a pitch θ, R = R_z(ψ) R_x(φ) R_y(θ) (z up); the base,
//! in axes (ξ, η) turned by δ about the body's z axis, is ζ = −h + ξ²/(2 R₁) + η²/(2 R₂) in
//! the body's axes, and the body touches the ground where the base's normal points straight
//! down.
//!
//! n = 6 coordinates; two rolling constraints and the contact's height, a holonomic
//! constraint that determines z; three speeds: 9 states. The orientation is singular at a
//! roll of ±π/2, far from the rattleback's rocking.
//!
//! Upright with no spin the body rocks about its two base axes at ω² = m g (R − h) / (I +
//! m h²) (δ = 0: the pendulum of a body rolling on a curved base). Spinning upright, its
//! linearization has eigenvalues whose real parts change sign with the direction of spin:
//! the spin is unstable one way and decays the other, which is the reversal.

use crate::hamel_system;
use hamel::geometry::{Body, Contact, Inertia, Rotation3, Vector3};

#[hamel_system]
#[derive(Clone, Debug, PartialEq)]
pub struct Rattleback {
    /// mass (kg)
    pub m: f64,
    /// principal moments of inertia about the body's x (long), y and z axes (kg m²)
    pub a: f64,
    pub b: f64,
    pub c: f64,
    /// radii of curvature of the base along its ξ and η axes (m)
    pub r1: f64,
    pub r2: f64,
    /// height of the centre of mass above the base's lowest point (m)
    pub h: f64,
    /// angle from the inertia axes to the base's axes, about the body's z axis (rad)
    pub delta: f64,
    /// gravitational acceleration (m/s²)
    pub g: f64,
}

impl Default for Rattleback {
    /// A hand-sized celt: 10 cm long, a base curved gently along its length and steeply
    /// across it, the axes turned by 0.05 rad.
    fn default() -> Self {
        Rattleback {
            m: 0.1,
            a: 2e-5,
            b: 1.6e-4,
            c: 1.7e-4,
            r1: 0.2,
            r2: 0.025,
            h: 0.01,
            delta: 0.05,
            g: 9.81,
        }
    }
}

#[hamel_system(
    coordinates(x, y, z, psi, phi, theta),
    speeds(yaw_rate, roll_rate, pitch_rate),
    constraints(slip_x, slip_y, height),
    bodies(rattleback),
    units(
        t = "s",
        x = "m",
        y = "m",
        z = "m",
        psi = "rad",
        phi = "rad",
        theta = "rad",
        yaw_rate = "rad/s",
        roll_rate = "rad/s",
        pitch_rate = "rad/s",
        energy = "J"
    )
)]
impl Rattleback {
    #[bodies]
    fn bodies(&self, q: &[f64; 6]) -> [Body; 1] {
        let orientation =
            Rotation3::about_z(q[3]) * Rotation3::about_x(q[4]) * Rotation3::about_y(q[5]);
        [Body::new(
            self.m,
            Inertia::principal(self.a, self.b, self.c),
            Vector3::new(q[0], q[1], q[2]),
            orientation,
        )]
    }

    #[gravity]
    fn gravity(&self) -> Vector3 {
        Vector3::new(0.0, 0.0, -self.g)
    }

    /// The point of the base whose normal points down, γ being the upward vertical in the
    /// base's axes: (ξ, η) = (−R₁ γ₁/γ₃, −R₂ γ₂/γ₃).
    #[contacts(determines(z))]
    fn contacts(&self, q: &[f64; 6]) -> [Contact; 1] {
        let [body] = self.bodies(q);
        let base = body.orientation * Rotation3::about_z(self.delta);
        let up = base.transpose() * Vector3::z();
        let (xi, eta) = (-self.r1 * up.x / up.z, -self.r2 * up.y / up.z);
        let lowest = Vector3::new(
            xi,
            eta,
            -self.h + xi * xi / (2.0 * self.r1) + eta * eta / (2.0 * self.r2),
        );
        [Contact::ground(body, body.centre + base * lowest)]
    }

    #[quasi_velocities]
    fn rates(&self, _q: &[f64; 6], qd: &[f64; 6]) -> [f64; 3] {
        [qd[3], qd[4], qd[5]]
    }
}
