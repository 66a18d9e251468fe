// A ball's contact written half a radius above the ground: its height is 0.5 r whatever the
// coordinates. The message names the parameter it is made of, where it quoted a height
// computed from a placeholder value of `r`, not the user's.
use hamel::prelude::*;

#[hamel_system]
pub struct Ball {
    pub m: f64,
    pub r: f64,
    pub g: f64,
}

#[hamel_system(coordinates(x, y, alpha, beta, gamma))]
impl Ball {
    #[bodies]
    fn bodies(&self, q: &[f64; 5]) -> [Body; 1] {
        let orientation = Rotation3::about_y(q[2]) * Rotation3::about_z(q[3]) * Rotation3::about_y(q[4]);
        let inertia = Inertia::principal(0.4, 0.4, 0.4);
        [Body::new(self.m, inertia, Vector3::new(q[0], q[1], self.r), orientation)]
    }

    #[contacts]
    fn contacts(&self, q: &[f64; 5]) -> [Contact; 1] {
        let [ball] = self.bodies(q);
        [Contact::ground(ball, Vector3::new(q[0], q[1], 0.5 * self.r))]
    }

    #[quasi_velocities]
    fn rates(&self, _q: &[f64; 5], qd: &[f64; 5]) -> [f64; 3] {
        [qd[2], qd[3], qd[4]]
    }
}

fn main() {
    let ball = Ball { m: 1.0, r: 0.1, g: 9.81 };
    let _ = Simulation::new(&ball, [0.0; 8]);
}
