// `determines(..)` names two coordinates, but only one contact height varies with the
// coordinates. The speeds and constraint names are right for the model with one: the one
// error says what is wrong with `determines(..)`.
use hamel::prelude::*;

#[hamel_system]
pub struct Ball {
    pub m: f64,
    pub r: f64,
    pub g: f64,
}

#[hamel_system(
    coordinates(x, y, z, alpha, beta, gamma),
    speeds(alpha_rate, beta_rate, gamma_rate),
    constraints(slip_x, slip_y, height)
)]
impl Ball {
    #[bodies]
    fn bodies(&self, q: &[f64; 6]) -> [Body; 1] {
        let orientation = Rotation3::about_y(q[3]) * Rotation3::about_z(q[4]) * Rotation3::about_y(q[5]);
        let inertia = Inertia::principal(0.4, 0.4, 0.4);
        let ball = Body::new(self.m, inertia, Vector3::new(q[0], q[1], q[2]), orientation);
        [ball.with_shape(Shape::sphere(self.r))]
    }

    #[gravity]
    fn gravity(&self) -> Vector3 {
        Vector3::new(0.0, 0.0, -self.g)
    }

    #[contacts(determines(z, alpha))]
    fn contacts(&self, q: &[f64; 6]) -> [Contact; 1] {
        let [ball] = self.bodies(q);
        [Contact::rolling(ball, Surface::ground())]
    }

    #[quasi_velocities]
    fn rates(&self, _q: &[f64; 6], qd: &[f64; 6]) -> [f64; 3] {
        [qd[3], qd[4], qd[5]]
    }
}

fn main() {
    let ball = Ball { m: 1.0, r: 0.1, g: 9.81 };
    let _ = Simulation::new(&ball, [0.0; 9]);
}
