// A model with one mistake (an unknown function in its energy) and a correct `rate!` in its
// constraints: the one error is the mistake's, the `rate!` draws none.
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
        0.5 * self.m * squared(qd[0]) + 0.5 * self.m * qd[1] * qd[1] + 0.5 * self.inertia * qd[2] * qd[2]
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], _qd: &[f64; 3]) -> [f64; 1] {
        let (s, c) = q[2].sin_cos();
        let contact = Vector3::new(q[0] - self.a * c, q[1] - self.a * s, 0.0);
        [rate!(contact).dot(&Vector3::new(-s, c, 0.0))]
    }

    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[2]]
    }
}

fn squared(x: f64) -> f64 {
    x * x
}

fn main() {
    let sleigh = Sleigh { m: 2.0, inertia: 0.5, a: 0.4 };
    let _ = sleigh.blade(&[0.0; 3], &[0.0; 3]);
    let _ = Simulation::new(&sleigh, [0.0; 5]);
}
