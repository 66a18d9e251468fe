// Several independent mistakes in one model: one build reports them all.
use hamel::prelude::*;

#[hamel_system]
pub struct Sleigh {
    pub m: f64,
    pub inertia: f64,
    pub a: f64,
    // 1. a parameter that is not an `f64`
    pub links: usize,
}

#[hamel_system(coordinates(x, y, theta), speeds(v, omega))]
impl Sleigh {
    // 2. a `while` loop in the energy
    #[kinetic_energy]
    fn kinetic_energy(&self, _q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        let mut t = 0.5 * self.m * (qd[0] * qd[0] + qd[1] * qd[1]);
        while t < 0.0 {
            t = -t;
        }
        t + 0.5 * self.inertia * qd[2] * qd[2]
    }

    // 3. a constraint that is not linear in the velocities
    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [-qd[0] * q[2].sin() + qd[1] * qd[1] * q[2].cos() - self.a * qd[2]]
    }

    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[2]]
    }

    // 4. `u` of the wrong length (the model declares no inputs), and 5. a call of a function
    // the macro cannot see
    #[forces]
    fn forces(&self, _t: f64, _q: &[f64; 3], qd: &[f64; 3], _u: &[f64; 2]) -> [f64; 3] {
        [0.0, 0.0, -clamp(qd[2])]
    }
}

fn clamp(x: f64) -> f64 {
    x.max(-1.0).min(1.0)
}

fn main() {}
