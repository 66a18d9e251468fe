// A scene of a model written from its energy: it states no bodies to draw, so
// `hamel::scene::Scene` does not accept it (one error, at the model given).
use hamel::prelude::*;
use hamel::scene::Scene;

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
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[2]]
    }
}

fn main() -> Result<(), hamel::Error> {
    let sleigh = Sleigh { m: 1.0, inertia: 0.1, a: 0.2 };
    let x0 = sleigh.state_from_speeds(0.0, &[0.0; 3], &[1.0, 0.5])?;
    let run = Simulation::new(&sleigh, x0)
        .end_time(1.0)
        .run_constant(&DormandPrince::new(1e-8, 1e-10), [])?;
    Scene::new(&sleigh, &run)?
        .show(["x", "y"])
        .write_html("sleigh.html")?;
    Ok(())
}
