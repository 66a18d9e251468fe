// A body's pose is a function of the configuration: the macro derives its velocity, so the
// function that states the bodies cannot take the velocities.
use hamel::prelude::*;

#[hamel_system]
pub struct Disk {
    pub m: f64,
    pub r: f64,
}

#[hamel_system(coordinates(x, y, psi, phi, theta))]
impl Disk {
    #[bodies]
    fn bodies(&self, q: &[f64; 5], qd: &[f64; 5]) -> [Body; 1] {
        let heading = Rotation3::about_z(q[2]) * Rotation3::about_x(q[3]);
        let centre = Vector3::new(q[0] + 0.1 * qd[0], q[1], 0.0) + heading * Vector3::new(0.0, 0.0, self.r);
        [Body::new(self.m, Inertia::principal(1.0, 2.0, 1.0), centre, heading * Rotation3::about_y(q[4]))]
    }

    #[contacts]
    fn contacts(&self, q: &[f64; 5]) -> [Contact; 1] {
        let [disk] = self.bodies(q, &[0.0; 5]);
        [Contact::ground(disk, Vector3::new(q[0], q[1], 0.0))]
    }

    #[quasi_velocities]
    fn rates(&self, _q: &[f64; 5], qd: &[f64; 5]) -> [f64; 3] {
        [qd[2], qd[3], qd[4]]
    }
}

fn main() {
    let disk = Disk { m: 1.0, r: 0.5 };
    let _ = Simulation::new(&disk, [0.0; 8]);
}
