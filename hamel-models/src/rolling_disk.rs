//! A thin disk rolling without slipping on a horizontal plane: a coin, a wheel without a
//! frame (Neimark & Fufaev, *Dynamics of Nonholonomic Systems*, 1972, ch. II; O'Reilly, *The
//! dynamics of rolling disks and sliding disks*, Nonlinear Dynamics 10, 1996). Stated from
//! geometry: the disk's orientation is a yaw ψ, a lean φ about the heading and a spin θ about
//! the axle, R = R_z(ψ) R_x(φ) R_y(θ) (z up); its centre lies r above the contact point in
//! the disk's plane; it rolls on the ground at the contact point (x, y).
//!
//! n = 5 coordinates, two rolling constraints, three speeds: 8 states. The orientation is
//! singular when the disk lies flat (φ = ±π/2), where the yaw and the spin turn about the
//! same axis.
//!
//! Steady motions: upright, the disk rolls straight at r θ̇; leaning by φ it can turn
//! steadily at a yaw rate Ω when the spin about the axle, ω₃ = θ̇ + Ω sin φ, satisfies
//! (C + m r²) Ω ω₃ cos φ − A Ω² sin φ cos φ + m g r sin φ = 0 (A = m r²/4 about a
//! diameter, C = m r²/2 about the axle); with ω₃ = 0 the centre stands still and the disk
//! spins on its rim at Ω² = 4 g / (r cos φ), Euler's disk (Moffatt, Nature 404, 2000). The
//! validation suite checks each.

use crate::hamel_system;
use hamel::geometry::{Body, Contact, Inertia, Rotation3, Vector3};

#[hamel_system]
#[derive(Clone, Debug, PartialEq)]
pub struct RollingDisk {
    /// mass (kg)
    pub m: f64,
    /// radius (m)
    pub r: f64,
    /// gravitational acceleration (m/s²)
    pub g: f64,
}

impl Default for RollingDisk {
    /// A 10 cm coin of 100 g.
    fn default() -> Self {
        RollingDisk {
            m: 0.1,
            r: 0.05,
            g: 9.81,
        }
    }
}

#[hamel_system(
    coordinates(x, y, psi, phi, theta),
    speeds(yaw_rate, lean_rate, spin_rate),
    constraints(slip_x, slip_y),
    bodies(disk),
    units(
        t = "s",
        x = "m",
        y = "m",
        psi = "rad",
        phi = "rad",
        theta = "rad",
        yaw_rate = "rad/s",
        lean_rate = "rad/s",
        spin_rate = "rad/s",
        energy = "J"
    )
)]
impl RollingDisk {
    /// The disk: its axle is its y axis.
    #[bodies]
    fn bodies(&self, q: &[f64; 5]) -> [Body; 1] {
        let heading = Rotation3::about_z(q[2]) * Rotation3::about_x(q[3]);
        let centre = Vector3::new(q[0], q[1], 0.0) + heading * Vector3::new(0.0, 0.0, self.r);
        let (diameter, axle) = (
            self.m * self.r * self.r / 4.0,
            self.m * self.r * self.r / 2.0,
        );
        [Body::new(
            self.m,
            Inertia::principal(diameter, axle, diameter),
            centre,
            heading * Rotation3::about_y(q[4]),
        )]
    }

    #[gravity]
    fn gravity(&self) -> Vector3 {
        Vector3::new(0.0, 0.0, -self.g)
    }

    /// The disk touches the ground at (x, y).
    #[contacts]
    fn contacts(&self, q: &[f64; 5]) -> [Contact; 1] {
        let [disk] = self.bodies(q);
        [Contact::ground(disk, Vector3::new(q[0], q[1], 0.0))]
    }

    #[quasi_velocities]
    fn rates(&self, _q: &[f64; 5], qd: &[f64; 5]) -> [f64; 3] {
        [qd[2], qd[3], qd[4]]
    }
}
