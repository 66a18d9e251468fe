// Shared helpers named by their path, `helpers(wheels::Wheels)`, and called by it: a
// function the set does not have is named as such (the set is marked and named already).
use hamel::prelude::*;

mod wheels {
    use hamel::geometry::{Body, Inertia, Rotation3, Vector3};

    pub struct Wheels;

    #[hamel::helpers]
    impl Wheels {
        pub fn rolling(m: f64, r: f64, q: &[f64; 5]) -> Body {
            let heading = Rotation3::about_z(q[2]) * Rotation3::about_x(q[3]);
            let centre = Vector3::new(q[0], q[1], 0.0) + heading * Vector3::new(0.0, 0.0, r);
            let diameter = m * r * r / 4.0;
            Body::new(m, Inertia::principal(diameter, 2.0 * diameter, diameter), centre, heading * Rotation3::about_y(q[4]))
        }
    }
}

#[hamel_system]
pub struct Coin {
    pub m: f64,
    pub r: f64,
}

#[hamel_system(coordinates(x, y, psi, phi, theta), helpers(wheels::Wheels))]
impl Coin {
    #[bodies]
    fn bodies(&self, q: &[f64; 5]) -> [Body; 1] {
        [wheels::Wheels::rolling(self.m, self.r, q)]
    }

    #[contacts]
    fn contacts(&self, q: &[f64; 5]) -> [Contact; 1] {
        [Contact::ground(wheels::Wheels::disk(self.m, self.r, q), Vector3::new(q[0], q[1], 0.0))]
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
