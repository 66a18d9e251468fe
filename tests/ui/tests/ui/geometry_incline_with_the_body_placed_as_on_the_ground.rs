// A disk rolling on an incline, its centre placed r above the ground as on flat ground: the
// contact's height varies with x. The message says to place the body on the surface, and names
// the user's coordinates, where it suggested `determines(theta)`, a word from the guide.
use hamel::prelude::*;

#[hamel_system]
pub struct Slope {
    pub m: f64,
    pub r: f64,
    pub alpha: f64,
}

#[hamel_system(coordinates(x, y, heading, spin))]
impl Slope {
    #[bodies]
    fn bodies(&self, q: &[f64; 4]) -> [Body; 1] {
        let orientation = Rotation3::about_z(q[2]) * Rotation3::about_y(q[3]);
        let diameter = self.m * self.r * self.r / 4.0;
        let inertia = Inertia::principal(diameter, 2.0 * diameter, diameter);
        let disk = Body::new(self.m, inertia, Vector3::new(q[0], q[1], self.r), orientation);
        [disk.with_shape(Shape::disk(self.r, Vector3::y()))]
    }

    #[contacts]
    fn contacts(&self, q: &[f64; 4]) -> [Contact; 1] {
        let [disk] = self.bodies(q);
        let incline = Surface::plane(Vector3::zeros(), Rotation3::about_y(self.alpha));
        [Contact::rolling(disk, incline)]
    }

    #[quasi_velocities]
    fn rates(&self, _q: &[f64; 4], qd: &[f64; 4]) -> [f64; 2] {
        [qd[2], qd[3]]
    }
}

fn main() {
    let slope = Slope { m: 1.0, r: 0.1, alpha: 0.2 };
    let _ = Simulation::new(&slope, [0.0; 6]);
}
