// A closed-form `#[velocities]` with a sign typo: ẏ = +w₀ cos φ + w₁ sin φ where the inverse of
// the constraint and quasi-velocities has ẏ = −w₀ cos φ + w₁ sin φ. Checked at compile time.
use hamel::prelude::*;

#[hamel_system]
pub struct KnifeEdge {
    pub m: f64,
    pub j: f64,
    pub g: f64,
    pub incline: f64,
}

#[hamel_system(coordinates(x, y, phi), speeds(v, omega))]
impl KnifeEdge {
    #[lagrangian]
    fn lagrangian(&self, q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        0.5 * self.m * (qd[0] * qd[0] + qd[1] * qd[1])
            + 0.5 * self.j * qd[2] * qd[2]
            + self.m * self.g * self.incline.sin() * q[0]
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [qd[0] * q[2].sin() - qd[1] * q[2].cos()]
    }

    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[2]]
    }

    #[velocities]
    fn velocities(&self, q: &[f64; 3], w: &[f64; 3]) -> [f64; 3] {
        let (s, c) = q[2].sin_cos();
        [w[0] * s + w[1] * c, w[0] * c + w[1] * s, w[2]]
    }
}

fn main() {}
