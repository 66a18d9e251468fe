//! The Chaplygin sleigh: a rigid body on a plane, supported by a knife edge whose contact
//! point lies a distance `a` behind the centre of mass, on the body's axis (Bloch,
//! *Nonholonomic Mechanics and Control*, §1.7). q = (x, y, θ) are the centre of mass and the
//! heading; the contact point's velocity across the blade vanishes:
//! −ẋ sin θ + ẏ cos θ − a θ̇ = 0.
//!
//! With v the forward speed of the centre of mass and ω = θ̇ the reduced equations are
//! v̇ = a ω², ω̇ = −m a v ω / (I + m a²): the sleigh straightens out and v tends to √(2E/m).
//! Unlike the knife edge, this motion depends on the sign of the γ terms.

use crate::hamel_system;

#[hamel_system]
#[derive(Clone, Debug, PartialEq)]
pub struct ChaplyginSleigh {
    /// mass (kg)
    pub m: f64,
    /// moment of inertia about the centre of mass (kg m²)
    pub inertia: f64,
    /// distance of the contact point behind the centre of mass (m)
    pub a: f64,
}

impl Default for ChaplyginSleigh {
    fn default() -> Self {
        ChaplyginSleigh {
            m: 2.0,
            inertia: 0.5,
            a: 0.4,
        }
    }
}

#[hamel_system(
    coordinates(x, y, theta),
    speeds(v, omega),
    constraints(blade),
    units(
        t = "s",
        x = "m",
        y = "m",
        theta = "rad",
        v = "m/s",
        omega = "rad/s",
        energy = "J"
    )
)]
impl ChaplyginSleigh {
    #[kinetic_energy]
    pub fn kinetic_energy(&self, _q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        0.5 * self.m * (qd[0] * qd[0] + qd[1] * qd[1]) + 0.5 * self.inertia * qd[2] * qd[2]
    }

    /// The contact point does not slide across the blade.
    #[constraints]
    pub fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [-qd[0] * q[2].sin() + qd[1] * q[2].cos() - self.a * qd[2]]
    }

    /// Forward speed of the centre of mass, and the turning rate.
    #[quasi_velocities]
    pub fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[2]]
    }
}
