//! What a model stated from geometry says of itself at run time (`hamel::geometry::Mechanism`,
//! which `#[hamel_system]` implements), against the model's equations: at seeded random
//! states, the energy of the bodies it returns — T = Σ ½ m |ṙ|² + ½ Ωᵀ I Ω with ṙ and Ω from
//! central differences of the returned poses along q̇, and V = −Σ m g·r — equals the model's
//! `energy`. So scenes and pictures, which draw these bodies, draw the mechanism the equations
//! describe. Also the names and units the catalogue gives.

use crate::common::xorshift::XorShift;
use hamel::geometry::{Mechanism, Rotation3, Vector3};
use hamel::models::{ChaplyginBall, Rattleback, RollingDisk, WhippleBicycle};
use hamel::{HamelSystem, Parameters, Vector};

/// Ω in body axes from R at q − h q̇ and q + h q̇: the axial vector of Rᵀ Ṙ.
fn body_rate(r: &Rotation3, minus: &Rotation3, plus: &Rotation3, h: f64) -> Vector3 {
    let m = |rot: &Rotation3, i: usize, j: usize| rot.matrix()[i][j];
    let rdot = |i: usize, j: usize| (m(plus, i, j) - m(minus, i, j)) / (2.0 * h);
    // (Rᵀ Ṙ)_ij = Σ_k R_ki Ṙ_kj
    let w = |i: usize, j: usize| (0..3).map(|k| m(r, k, i) * rdot(k, j)).sum::<f64>();
    Vector3::new(w(2, 1), w(0, 2), w(1, 0))
}

/// The bodies' energy at (t, x), from their poses.
fn energy_of_bodies<S: Mechanism>(model: &S, t: f64, x: &S::State) -> f64 {
    let q = S::Coordinates::from_slice(&x.as_ref()[..S::N]).unwrap();
    let qd = model.generalized_velocities(t, x).unwrap();
    let h = 1e-6;
    let shifted = |sign: f64| {
        let mut p = q;
        for (p, v) in p.as_mut().iter_mut().zip(qd.as_ref()) {
            *p += sign * h * v;
        }
        model.bodies_at(t + sign * h, &p)
    };
    let (bodies, minus, plus) = (model.bodies_at(t, &q), shifted(-1.0), shifted(1.0));
    let g = model.gravity_vector(t).unwrap_or(Vector3::zeros());
    let mut energy = 0.0;
    for ((b, lo), hi) in bodies.iter().zip(&minus).zip(&plus) {
        let v = (hi.centre - lo.centre) * (0.5 / h);
        let w = body_rate(&b.orientation, &lo.orientation, &hi.orientation, h);
        let i = b.inertia.matrix();
        let iw = |k: usize| i[k][0] * w.x + i[k][1] * w.y + i[k][2] * w.z;
        let rotation = w.x * iw(0) + w.y * iw(1) + w.z * iw(2);
        energy += 0.5 * b.mass * v.dot(&v) + 0.5 * rotation - b.mass * g.dot(&b.centre);
    }
    energy
}

/// The worst relative difference over `states` seeded states built by `state`.
fn worst<S: Mechanism>(model: &S, mut state: impl FnMut(&mut XorShift) -> S::State) -> f64 {
    let mut rng = XorShift::new(24);
    (0..20)
        .map(|_| {
            let x = state(&mut rng);
            let e = model.energy(0.0, &x).unwrap();
            let from_bodies = energy_of_bodies(model, 0.0, &x);
            (from_bodies - e).abs() / e.abs().max(1e-3)
        })
        .fold(0.0, f64::max)
}

/// Central differences with h = 1e-6 are good to about 1e-9 here.
const AGREEMENT: f64 = 1e-7;

#[test]
fn the_bicycles_bodies_carry_its_energy() {
    let bike = WhippleBicycle::default();
    let d = worst(&bike, |rng| {
        bike.state_builder()
            .set("psi", rng.uniform(-3.0, 3.0))
            .set("phi", rng.uniform(-0.5, 0.5))
            .set("delta", rng.uniform(-0.5, 0.5))
            .set("theta_r", rng.uniform(-3.0, 3.0))
            .set("roll_rate", rng.uniform(-1.0, 1.0))
            .set("steer_rate", rng.uniform(-1.0, 1.0))
            .set("rear_wheel_rate", rng.uniform(-15.0, -5.0))
            .build()
            .unwrap()
    });
    println!("bicycle: bodies' energy against the model's, worst relative difference {d:.1e}");
    assert!(d < AGREEMENT, "{d:e}");
}

#[test]
fn the_classics_bodies_carry_their_energy() {
    let speeds = |rng: &mut XorShift| [0; 3].map(|_| rng.uniform(-3.0, 3.0));
    let disk = RollingDisk::default();
    let d1 = worst(&disk, |rng| {
        let q = [
            0.1,
            -0.2,
            rng.uniform(-3.0, 3.0),
            rng.uniform(-1.0, 1.0),
            0.4,
        ];
        disk.state_from_speeds(0.0, &q, &speeds(rng)).unwrap()
    });
    let ball = ChaplyginBall::default();
    let d2 = worst(&ball, |rng| {
        let q = [0.0, 0.0, rng.uniform(-3.0, 3.0), rng.uniform(0.5, 2.5), 0.3];
        ball.state_from_speeds(0.0, &q, &speeds(rng)).unwrap()
    });
    let celt = Rattleback::default();
    let d3 = worst(&celt, |rng| {
        celt.state_builder()
            .set("psi", rng.uniform(-3.0, 3.0))
            .set("phi", rng.uniform(-0.3, 0.3))
            .set("theta", rng.uniform(-0.3, 0.3))
            .speeds(&speeds(rng))
            .build()
            .unwrap()
    });
    println!("rolling disk {d1:.1e}, Chaplygin ball {d2:.1e}, rattleback {d3:.1e}");
    for d in [d1, d2, d3] {
        assert!(d < AGREEMENT, "{d:e}");
    }
}

#[test]
fn the_bicycle_names_its_bodies_and_touches_the_ground_where_its_wheels_are() {
    let bike = WhippleBicycle::default();
    assert_eq!(
        WhippleBicycle::BODIES,
        ["rear_wheel", "rear_frame", "front_frame", "front_wheel"]
    );
    let x = bike.state_builder().build().unwrap();
    let q = <WhippleBicycle as HamelSystem>::Coordinates::from_slice(&x[..8]).unwrap();
    let bodies = bike.bodies_at(0.0, &q);
    let contacts = bike.contacts_at(0.0, &q);
    assert_eq!((bodies.len(), contacts.len()), (4, 2));
    // Upright and straight: each wheel's contact lies a radius below its centre, on the
    // ground, the front one a wheelbase ahead.
    let (rear, front) = (contacts[0].point, contacts[1].point);
    assert!((bodies[0].centre - rear - Vector3::new(0.0, 0.0, -bike.r_r)).norm() < 1e-15);
    assert!((bodies[3].centre - front - Vector3::new(0.0, 0.0, -bike.r_f)).norm() < 1e-12);
    assert!((front - Vector3::new(bike.w, 0.0, 0.0)).norm() < 1e-12);
    assert_eq!(
        bike.gravity_vector(0.0),
        Some(Vector3::new(0.0, 0.0, bike.g))
    );
    assert_eq!(ChaplyginBall::default().gravity_vector(0.0), None);
    assert_eq!(ChaplyginBall::BODIES, ["ball"]);
}

#[test]
fn catalogue_models_state_their_units() {
    assert_eq!(WhippleBicycle::unit("phi"), Some("rad"));
    assert_eq!(WhippleBicycle::unit("roll_rate"), Some("rad/s"));
    assert_eq!(WhippleBicycle::unit("steer_torque"), Some("N m"));
    assert_eq!(WhippleBicycle::unit("t"), Some("s"));
    assert_eq!(WhippleBicycle::unit("energy_balance"), Some("J"));
    assert_eq!(WhippleBicycle::unit("front_z"), None);
    assert_eq!(WhippleBicycle::parameter_unit("c"), Some("m"));
    assert_eq!(WhippleBicycle::parameter_unit("i_bxz"), Some("kg m²"));
    // Every coordinate, speed and input of the catalogue's mechanical models has a unit.
    fn all<S: HamelSystem>() -> bool {
        S::STATE
            .iter()
            .chain(S::INPUTS)
            .all(|n| S::unit(n).is_some())
    }
    assert!(all::<WhippleBicycle>() && all::<RollingDisk>() && all::<ChaplyginBall>());
    assert!(all::<Rattleback>() && all::<hamel::models::MobileRobot>());
    assert!(all::<hamel::models::NTrailer2>() && all::<hamel::models::KnifeEdge>());
}
