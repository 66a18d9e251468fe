// `rate!` is the time derivative along the motion, which needs the velocities: a potential
// energy, a function of the configuration alone, has none to take it with.
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

    #[potential_energy]
    fn potential_energy(&self, q: &[f64; 3]) -> f64 {
        let drag = rate!(q[0]);
        self.m * drag
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

fn main() {
    let sleigh = Sleigh { m: 2.0, inertia: 0.5, a: 0.4 };
    let _ = Simulation::new(&sleigh, [0.0; 5]);
}
