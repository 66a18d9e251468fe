// `outputs(..)` names one output and the `#[outputs]` function returns two: one error, at
// the names.
use hamel::prelude::*;

#[hamel_system]
pub struct Skate {
    pub m: f64,
    pub j: f64,
}

#[hamel_system(
    coordinates(x, y, phi),
    speeds(v, omega),
    inputs(force, torque),
    outputs(px)
)]
impl Skate {
    #[kinetic_energy]
    fn kinetic_energy(&self, _q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        0.5 * self.m * (qd[0] * qd[0] + qd[1] * qd[1]) + 0.5 * self.j * qd[2] * qd[2]
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [qd[0] * q[2].sin() - qd[1] * q[2].cos()]
    }

    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[2]]
    }

    #[outputs]
    fn contact(&self, q: &[f64; 3]) -> [f64; 2] {
        [q[0], q[1]]
    }

    #[forces]
    fn drive(&self, _t: f64, q: &[f64; 3], _qd: &[f64; 3], u: &[f64; 2]) -> [f64; 3] {
        [u[0] * q[2].cos(), u[0] * q[2].sin(), u[1]]
    }
}

fn main() {
    let skate = Skate { m: 1.0, j: 0.1 };
    let _ = hamel::ControlAffine::outputs(&skate, 0.0, &[0.0; 5]);
}
