// The role signatures' arrays have the length `N`, a constant of the module, which the macro
// cannot read: one error, where there was one at each of the six uses, each calling `N` an
// `f64`.
use hamel::prelude::*;

const N: usize = 3;

#[hamel_system]
pub struct Sleigh {
    pub m: [f64; 3],
    pub inertia: f64,
    pub a: f64,
}

#[hamel_system(coordinates(x, y, theta), speeds(v, omega))]
impl Sleigh {
    #[kinetic_energy]
    fn kinetic_energy(&self, _q: &[f64; N], qd: &[f64; N]) -> f64 {
        0.5 * self.m[0] * (qd[0] * qd[0] + qd[1] * qd[1]) + 0.5 * self.inertia * qd[2] * qd[2]
    }

    #[constraints]
    fn blade(&self, q: &[f64; N], qd: &[f64; N]) -> [f64; 1] {
        [-qd[0] * q[2].sin() + qd[1] * q[2].cos() - self.a * qd[2]]
    }

    #[quasi_velocities]
    fn speeds(&self, q: &[f64; N], qd: &[f64; N]) -> [f64; 2] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[2]]
    }
}

fn main() -> Result<(), hamel::Error> {
    let sleigh = Sleigh { m: [2.0; 3], inertia: 0.5, a: 0.4 };
    let x0 = sleigh.state_from_speeds(0.0, &[0.0, 0.0, 0.0], &[1.0, 2.0])?;
    let run = Simulation::new(&sleigh, x0)
        .end_time(1.0)
        .run_constant(&DormandPrince::new(1e-10, 1e-12), [])?;
    println!("{} {}", run.column("v").unwrap()[0] / sleigh.m[0], run.summary());
    Ok(())
}
