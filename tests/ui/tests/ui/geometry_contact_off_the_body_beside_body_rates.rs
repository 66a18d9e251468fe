// The leaning coin's contact written off its rim (as in `geometry_contact_off_the_body`),
// with its body rates as quasi-velocities: one error, the contact's; the correct `body_rates!`
// was flagged twice beside it (checked without the velocities it is read with).
use hamel::prelude::*;

#[hamel_system]
pub struct Coin {
    pub m: f64,
    pub r: f64,
    pub g: f64,
}

#[hamel_system(coordinates(x, y, psi, phi, theta))]
impl Coin {
    #[bodies]
    fn bodies(&self, q: &[f64; 5]) -> [Body; 1] {
        let heading = Rotation3::about_z(q[2]) * Rotation3::about_x(q[3]);
        let centre = Vector3::new(q[0], q[1], 0.0) + heading * Vector3::new(0.0, 0.0, self.r);
        let diameter = self.m * self.r * self.r / 4.0;
        let inertia = Inertia::principal(diameter, 2.0 * diameter, diameter);
        [Body::new(self.m, inertia, centre, heading * Rotation3::about_y(q[4]))]
    }

    #[gravity]
    fn gravity(&self) -> Vector3 {
        Vector3::new(0.0, 0.0, -self.g)
    }

    #[contacts]
    fn contacts(&self, q: &[f64; 5]) -> [Contact; 1] {
        let [coin] = self.bodies(q);
        [Contact::ground(coin, Vector3::new(coin.centre.x, coin.centre.y, 0.0))]
    }

    #[quasi_velocities]
    fn rates(&self, q: &[f64; 5], _qd: &[f64; 5]) -> [f64; 3] {
        let [coin] = self.bodies(q);
        body_rates!(coin.orientation).to_array()
    }
}

fn main() {
    let coin = Coin { m: 0.1, r: 0.05, g: 9.81 };
    let _ = Simulation::new(&coin, [0.0; 8]);
}
