// `units(..)` names a quantity the model does not have (a misspelt coordinate).
use hamel::prelude::*;
use hamel::geometry::Mechanism;

#[hamel_system]
pub struct Disk {
    pub m: f64,
    pub r: f64,
    pub g: f64,
}

#[hamel_system(coordinates(x, y, psi, phi, theta), units(x = "m", y = "m", thta = "rad"))]
impl Disk {
    #[bodies]
    fn bodies(&self, q: &[f64; 5]) -> [Body; 1] {
        let heading = Rotation3::about_z(q[2]) * Rotation3::about_x(q[3]);
        let centre = Vector3::new(q[0], q[1], 0.0) + heading * Vector3::new(0.0, 0.0, self.r);
        let (diameter, axle) = (0.25 * self.m * self.r * self.r, 0.5 * self.m * self.r * self.r);
        [Body::new(self.m, Inertia::principal(diameter, axle, diameter), centre, heading * Rotation3::about_y(q[4]))]
    }

    #[gravity]
    fn gravity(&self) -> Vector3 {
        Vector3::new(0.0, 0.0, -self.g)
    }

    #[contacts]
    fn contacts(&self, q: &[f64; 5]) -> [Contact; 1] {
        let [disk] = self.bodies(q);
        [Contact::ground(disk, Vector3::new(q[0], q[1], 0.0))]
    }

    #[quasi_velocities]
    fn rates(&self, _q: &[f64; 5], qd: &[f64; 5]) -> [f64; 3] {
        [qd[2], qd[3], qd[4]]
    }
}

// The program draws the model: the stand-in `Mechanism` keeps rustc from adding errors.
fn main() {
    let disk = Disk { m: 1.0, r: 0.5, g: 9.81 };
    let _ = disk.bodies_at(0.0, &[0.0; 5]);
    let _ = Disk::BODIES;
    let _ = Simulation::new(&disk, [0.0; 8]);
}
