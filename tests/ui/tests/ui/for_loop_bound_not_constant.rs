// A `for` loop is unrolled at compile time: its bound must be a constant, not a parameter.
use hamel::prelude::*;

#[hamel_system]
pub struct Sleigh {
    pub m: f64,
    pub inertia: f64,
    pub a: f64,
    pub n: f64,
}

#[hamel_system(coordinates(x, y, theta), speeds(v, omega))]
impl Sleigh {
    #[kinetic_energy]
    fn kinetic_energy(&self, _q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        let mut t = 0.0;
        for i in 0..self.n {
            t += 0.5 * self.m * qd[i] * qd[i];
        }
        t + 0.5 * self.inertia * qd[2] * qd[2]
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [-qd[0] * q[2].sin() + qd[1] * q[2].cos() - self.a * qd[2]]
    }

    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[2]]
    }
}

fn main() {}
