// Two helper sets, the second named by a path whose impl lacks `#[hamel::helpers]`, in a
// model that `main` uses as a program would: one error, at the name.
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

    pub mod ground {
        use hamel::geometry::{Body, Contact, Vector3};

        pub struct Ground;

        impl Ground {
            pub fn under(body: Body, q: &[f64; 5]) -> Contact {
                Contact::ground(body, Vector3::new(q[0], q[1], 0.0))
            }
        }
    }
}

#[hamel_system]
pub struct Coin {
    pub m: f64,
    pub r: f64,
    pub g: f64,
}

#[hamel_system(
    coordinates(x, y, psi, phi, theta),
    speeds(yaw_rate, lean_rate, spin_rate),
    helpers(wheels::Wheels, wheels::ground::Ground)
)]
impl Coin {
    #[bodies]
    fn bodies(&self, q: &[f64; 5]) -> [Body; 1] {
        [wheels::Wheels::rolling(self.m, self.r, q)]
    }

    #[gravity]
    fn gravity(&self) -> Vector3 {
        Vector3::new(0.0, 0.0, -self.g)
    }

    #[contacts]
    fn contacts(&self, q: &[f64; 5]) -> [Contact; 1] {
        let [coin] = self.bodies(q);
        [wheels::ground::Ground::under(coin, q)]
    }

    #[quasi_velocities]
    fn rates(&self, _q: &[f64; 5], qd: &[f64; 5]) -> [f64; 3] {
        [qd[2], qd[3], qd[4]]
    }

    /// The coin's height above the ground, an ordinary method of the model.
    pub fn height(&self, q: &[f64; 5]) -> f64 {
        let [coin] = self.bodies(q);
        coin.centre.z
    }
}

fn main() -> Result<(), hamel::Error> {
    let coin = Coin { m: 0.1, r: 0.05, g: 9.81 };
    let mut q = [0.0; 5];
    q[Coin::PHI] = 0.2;
    let x0 = coin.state_from_speeds(0.0, &q, &[0.0, 0.0, 10.0])?;
    let run = Simulation::new(&coin, x0)
        .end_time(1.0)
        .run_constant(&DormandPrince::new(1e-10, 1e-12), [])?;
    println!("{} {} {}", coin.height(&q), x0[Coin::SPIN_RATE], run.summary());
    Ok(())
}
