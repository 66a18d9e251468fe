// A moment of inertia written as a negative number: no matter makes it.
use hamel::prelude::*;

#[hamel_system]
pub struct Ball {
    pub m: f64,
    pub r: f64,
}

#[hamel_system(coordinates(x, y, alpha, beta, gamma))]
impl Ball {
    #[bodies]
    fn bodies(&self, q: &[f64; 5]) -> [Body; 1] {
        let orientation = Rotation3::about_y(q[2]) * Rotation3::about_z(q[3]) * Rotation3::about_y(q[4]);
        let inertia = Inertia::principal(-0.4, 0.4, 0.4);
        let ball = Body::new(self.m, inertia, Vector3::new(q[0], q[1], self.r), orientation);
        [ball.with_shape(Shape::sphere(self.r))]
    }

    #[contacts]
    fn contacts(&self, q: &[f64; 5]) -> [Contact; 1] {
        let [ball] = self.bodies(q);
        [Contact::rolling(ball, Surface::ground())]
    }

    #[quasi_velocities]
    fn rates(&self, _q: &[f64; 5], qd: &[f64; 5]) -> [f64; 3] {
        [qd[2], qd[3], qd[4]]
    }
}

fn main() {
    let ball = Ball { m: 1.0, r: 0.1 };
    let _ = Simulation::new(&ball, [0.0; 8]);
}
