//! A knife edge (a skate) sliding on an inclined plane, the classic example of Neimark and
//! Fufaev and of Bloch, *Nonholonomic Mechanics and Control*, §1.6. Its centre of mass is at
//! the contact point; the blade cannot slide sideways. With x down the slope:
//!
//! L = ½ m (ẋ² + ẏ²) + ½ J φ̇² + m g sin(incline) x,  constraint ẋ sin φ − ẏ cos φ = 0.
//!
//! The heading turns uniformly (φ = φ₀ + ωt) and the path speed oscillates,
//! v = v₀ + (g sin(incline)/ω) sin ωt (for φ₀ = 0): a closed-form solution to test against.

use crate::hamel_system;

#[hamel_system]
#[derive(Clone, Debug, PartialEq)]
pub struct KnifeEdge {
    /// mass (kg)
    pub m: f64,
    /// moment of inertia about the vertical through the contact point (kg m²)
    pub j: f64,
    /// gravitational acceleration (m/s²)
    pub g: f64,
    /// inclination of the plane (rad)
    pub incline: f64,
}

impl Default for KnifeEdge {
    fn default() -> Self {
        KnifeEdge {
            m: 1.0,
            j: 0.1,
            g: 9.81,
            incline: 0.3,
        }
    }
}

#[hamel_system(
    coordinates(x, y, phi),
    speeds(v, omega),
    constraints(blade),
    units(
        t = "s",
        x = "m",
        y = "m",
        phi = "rad",
        v = "m/s",
        omega = "rad/s",
        energy = "J"
    )
)]
impl KnifeEdge {
    #[lagrangian]
    pub fn lagrangian(&self, q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        0.5 * self.m * (qd[0] * qd[0] + qd[1] * qd[1])
            + 0.5 * self.j * qd[2] * qd[2]
            + self.m * self.g * self.incline.sin() * q[0]
    }

    /// No sideways sliding of the blade.
    #[constraints]
    pub fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [qd[0] * q[2].sin() - qd[1] * q[2].cos()]
    }

    /// Path speed along the blade, and the turning rate.
    #[quasi_velocities]
    pub fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[2]]
    }

    #[velocities]
    pub fn velocities(&self, q: &[f64; 3], w: &[f64; 3]) -> [f64; 3] {
        let (s, c) = q[2].sin_cos();
        [w[0] * s + w[1] * c, -w[0] * c + w[1] * s, w[2]]
    }
}
