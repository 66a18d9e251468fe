//! A skate that climbs a curved ridge to its end: the ridge's cross-section is a circle of
//! radius R, z = √(R² − x²), so its slope z′ = −x/√(R² − x²) grows without bound as the skate
//! nears x = R. With T = ½ m (ẋ² + ẏ² + ż²) + ½ I φ̇² and ż = z′ ẋ, the reduced mass matrix in
//! the speeds (v, ω) — v along the blade, ω = φ̇ — is diag(m (1 + z′² cos²φ), I): the
//! inertia of v diverges at the ridge's end, ω's stays I. The run stops there with a
//! singular mass matrix; the speed to name is v, whose inertia diverges, not ω, whose pivot
//! I merely looks like zero beside v's entry.

use hamel::{DormandPrince, Error, HamelSystem, Simulation, hamel_system};

#[hamel_system]
pub struct RidgeSkate {
    pub m: f64,
    pub inertia: f64,
    pub radius: f64,
}

#[hamel_system(coordinates(x, y, phi), speeds(v, omega))]
impl RidgeSkate {
    #[kinetic_energy]
    fn kinetic_energy(&self, q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        let slope = -q[0] / (self.radius * self.radius - q[0] * q[0]).sqrt();
        let zd = slope * qd[0];
        0.5 * self.m * (qd[0] * qd[0] + qd[1] * qd[1] + zd * zd)
            + 0.5 * self.inertia * qd[2] * qd[2]
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [-qd[0] * q[2].sin() + qd[1] * q[2].cos()]
    }

    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[2]]
    }
}

#[test]
fn the_skate_at_the_end_of_the_ridge_names_the_speed_whose_inertia_diverges() {
    let skate = RidgeSkate {
        m: 1.0,
        inertia: 0.1,
        radius: 1.0,
    };
    let x0 = skate
        .state_from_speeds(0.0, &[0.0, 0.0, 0.3], &[1.0, 0.2])
        .unwrap();
    let e = Simulation::new(&skate, x0)
        .end_time(10.0)
        .run_constant(&DormandPrince::new(1e-10, 1e-12), [])
        .unwrap_err();
    println!("{e}");
    match &e {
        Error::UnboundedInertia { speed, state, .. } => {
            assert_eq!(speed, "v", "{e}");
            assert!(state.get("x").unwrap() > 0.99, "{e}");
        }
        other => panic!("expected the inertia of v to be named, got {other}"),
    }
}
