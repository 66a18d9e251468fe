//! The vertical rolling disk: a coin of radius R that rolls upright without slipping on a
//! plane (Bloch, *Nonholonomic Mechanics and Control*, §1.4; Neimark & Fufaev, *Dynamics of
//! Nonholonomic Systems*, ch. I). q = (x, y, θ, φ): the contact point, the rolling angle and
//! the heading; the contact point moves along the heading at the rolling speed,
//! ẋ = R cos φ θ̇, ẏ = R sin φ θ̇.
//!
//! With no forces the speeds θ̇ = ω_θ and φ̇ = ω_φ are constant and the contact point runs
//! round a circle of radius R ω_θ/ω_φ (Bloch §1.4); the constraint forces, the multipliers of
//! the rows as written here, are λ₁ = m ẍ = −m R ω_θ ω_φ sin φ and λ₂ = m ÿ =
//! m R ω_θ ω_φ cos φ. The model is reversible ([`hamel::HamelSystem::REVERSIBLE`]): a closed
//! form for every integrator's long runs.

use crate::hamel_system;

/// Parameters of the vertical disk. Defaults: a 1 kg disk of 0.5 m radius, its moments of
/// inertia those of a thin uniform disk.
#[hamel_system]
#[derive(Clone, Debug, PartialEq)]
pub struct VerticalDisk {
    /// mass (kg)
    pub m: f64,
    /// moment of inertia about the axle, for the rolling (kg m²)
    pub i_roll: f64,
    /// moment of inertia about the vertical diameter, for the turning (kg m²)
    pub i_turn: f64,
    /// radius (m)
    pub r: f64,
}

impl Default for VerticalDisk {
    fn default() -> Self {
        VerticalDisk {
            m: 1.0,
            i_roll: 0.125,
            i_turn: 0.0625,
            r: 0.5,
        }
    }
}

#[hamel_system(
    coordinates(x, y, theta, phi),
    speeds(roll, turn),
    constraints(rolling_x, rolling_y),
    units(
        t = "s",
        x = "m",
        y = "m",
        theta = "rad",
        phi = "rad",
        roll = "rad/s",
        turn = "rad/s",
        energy = "J"
    )
)]
impl VerticalDisk {
    #[kinetic_energy]
    pub fn kinetic_energy(&self, _q: &[f64; 4], qd: &[f64; 4]) -> f64 {
        0.5 * self.m * (qd[0] * qd[0] + qd[1] * qd[1])
            + 0.5 * self.i_roll * qd[2] * qd[2]
            + 0.5 * self.i_turn * qd[3] * qd[3]
    }

    /// The contact point moves along the heading at the rolling speed R θ̇.
    #[constraints]
    pub fn rolling(&self, q: &[f64; 4], qd: &[f64; 4]) -> [f64; 2] {
        let (s, c) = q[3].sin_cos();
        [qd[0] - self.r * c * qd[2], qd[1] - self.r * s * qd[2]]
    }

    /// The rolling rate θ̇ and the turning rate φ̇.
    #[quasi_velocities]
    pub fn speeds(&self, _q: &[f64; 4], qd: &[f64; 4]) -> [f64; 2] {
        [qd[2], qd[3]]
    }
}
