// The second quasi-velocity is a combination of the constraint and the first: A(q) is
// singular at every q (reported before the closed-form inverse is checked against it).
use hamel::prelude::*;

#[hamel_system]
pub struct Sleigh {
    pub m: f64,
    pub inertia: f64,
    pub a: f64,
}

#[hamel_system(coordinates(x, y, theta), speeds(v, omega))]
impl Sleigh {
    #[kinetic_energy]
    fn kinetic_energy(&self, _q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        0.5 * self.m * (qd[0] * qd[0] + qd[1] * qd[1]) + 0.5 * self.inertia * qd[2] * qd[2]
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [-qd[0] * q[2].sin() + qd[1] * q[2].cos() - self.a * qd[2]]
    }

    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        let v = qd[0] * q[2].cos() + qd[1] * q[2].sin();
        [v, -qd[0] * q[2].sin() + qd[1] * q[2].cos() - self.a * qd[2] + 2.0 * v]
    }

    #[velocities]
    fn velocities(&self, q: &[f64; 3], w: &[f64; 3]) -> [f64; 3] {
        let (s, c) = q[2].sin_cos();
        [
            -s * (w[0] + self.a * w[2]) + c * w[1],
            c * (w[0] + self.a * w[2]) + s * w[1],
            w[2],
        ]
    }
}

fn main() {}
