// The contact is on a disk built anew in `#[contacts]`, with another mass than the body of
// `#[bodies]`: its motion would not be the one the equations describe.
use hamel::prelude::*;

#[hamel_system]
pub struct Coin {
    pub m: f64,
    pub r: f64,
}

#[hamel_system(coordinates(x, y, psi, phi, theta))]
impl Coin {
    fn disk(&self, q: &[f64; 5], m: f64) -> Body {
        let heading = Rotation3::about_z(q[2]) * Rotation3::about_x(q[3]);
        let centre = Vector3::new(q[0], q[1], 0.0) + heading * Vector3::new(0.0, 0.0, self.r);
        let diameter = m * self.r * self.r / 4.0;
        let inertia = Inertia::principal(diameter, 2.0 * diameter, diameter);
        Body::new(m, inertia, centre, heading * Rotation3::about_y(q[4]))
    }

    #[bodies]
    fn bodies(&self, q: &[f64; 5]) -> [Body; 1] {
        [self.disk(q, self.m)]
    }

    #[contacts]
    fn contacts(&self, q: &[f64; 5]) -> [Contact; 1] {
        [Contact::ground(self.disk(q, 1.0), Vector3::new(q[0], q[1], 0.0))]
    }

    #[quasi_velocities]
    fn rates(&self, _q: &[f64; 5], qd: &[f64; 5]) -> [f64; 3] {
        [qd[2], qd[3], qd[4]]
    }
}

fn main() {
    let coin = Coin { m: 0.1, r: 0.05 };
    let _ = Simulation::new(&coin, [0.0; 8]);
}
