//! Holonomic and nonholonomic constraints together: the Chaplygin sleigh written in redundant
//! coordinates — the positions of two points of its axis, held at a fixed distance by a
//! holonomic constraint — against the catalogue's sleigh in minimal coordinates (x, y, θ).
//!
//! Point 1 is the blade's contact point, point 2 lies a distance `l` ahead of it on the
//! body's axis, and the centre of mass a distance `a` ahead of the contact point. The
//! holonomic constraint |p₂ − p₁|² − l² = 0 is differentiated by the macro into a velocity
//! row; it determines x₂ (the user names it). The blade's constraint and the speeds (the
//! forward speed of the centre of mass and the turning rate) are those of the minimal model,
//! so the two states must agree.

use hamel::models::ChaplyginSleigh;
use hamel::{DormandPrince, HamelSystem, Simulation, Trajectory, hamel_system};

#[hamel_system]
#[derive(Clone, Debug)]
pub struct TwoPointSleigh {
    /// mass (kg)
    pub m: f64,
    /// moment of inertia about the centre of mass (kg m²)
    pub inertia: f64,
    /// distance of the centre of mass ahead of the contact point (m)
    pub a: f64,
    /// distance of the second point ahead of the contact point (m)
    pub l: f64,
}

#[hamel_system(coordinates(x1, y1, x2, y2), speeds(v, omega))]
impl TwoPointSleigh {
    /// The centre of mass's velocity and the turning rate from the two points' velocities.
    fn motion(&self, q: &[f64; 4], qd: &[f64; 4]) -> [f64; 3] {
        let (dx, dy) = (q[2] - q[0], q[3] - q[1]);
        let (dxd, dyd) = (qd[2] - qd[0], qd[3] - qd[1]);
        let s = self.a / self.l;
        [
            qd[0] + s * dxd,
            qd[1] + s * dyd,
            (dx * dyd - dy * dxd) / (self.l * self.l),
        ]
    }

    #[kinetic_energy]
    fn kinetic_energy(&self, q: &[f64; 4], qd: &[f64; 4]) -> f64 {
        let [vx, vy, omega] = self.motion(q, qd);
        0.5 * self.m * (vx * vx + vy * vy) + 0.5 * self.inertia * omega * omega
    }

    /// The contact point does not slide across the blade (the axis p₂ − p₁).
    #[constraints]
    fn blade(&self, q: &[f64; 4], qd: &[f64; 4]) -> [f64; 1] {
        [(q[2] - q[0]) * qd[1] - (q[3] - q[1]) * qd[0]]
    }

    /// The two points keep their distance.
    #[holonomic(determines(x2))]
    fn rigid(&self, q: &[f64; 4]) -> [f64; 1] {
        let (dx, dy) = (q[2] - q[0], q[3] - q[1]);
        [dx * dx + dy * dy - self.l * self.l]
    }

    /// Forward speed of the centre of mass along the axis, and the turning rate.
    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 4], qd: &[f64; 4]) -> [f64; 2] {
        let [vx, vy, omega] = self.motion(q, qd);
        [(vx * (q[2] - q[0]) + vy * (q[3] - q[1])) / self.l, omega]
    }
}

const MINIMAL: ChaplyginSleigh = ChaplyginSleigh {
    m: 2.0,
    inertia: 0.5,
    a: 0.4,
};

const REDUNDANT: TwoPointSleigh = TwoPointSleigh {
    m: 2.0,
    inertia: 0.5,
    a: 0.4,
    l: 1.5,
};

/// The redundant configuration of a minimal one: the contact point a behind the centre of
/// mass, the second point l ahead of the contact point.
fn points(x: f64, y: f64, theta: f64) -> [f64; 4] {
    let (s, c) = theta.sin_cos();
    let (x1, y1) = (x - MINIMAL.a * c, y - MINIMAL.a * s);
    [x1, y1, x1 + REDUNDANT.l * c, y1 + REDUNDANT.l * s]
}

fn runs() -> (Trajectory, Trajectory) {
    runs_with(false)
}

/// The minimal and the redundant sleigh over 10 s; the redundant one projected onto the
/// holonomic constraint after every step when `project` is set.
fn runs_with(project: bool) -> (Trajectory, Trajectory) {
    let (x, y, theta, v, omega) = (0.2, -0.1, 0.3, 1.0, 0.5);
    let integrator = DormandPrince::new(1e-12, 1e-12);
    let minimal = Simulation::new(
        &MINIMAL,
        MINIMAL
            .state_from_speeds(0.0, &[x, y, theta], &[v, omega])
            .unwrap(),
    )
    .end_time(10.0)
    .sample_interval(0.1)
    .run_constant(&integrator, [])
    .unwrap();
    let redundant = Simulation::new(
        &REDUNDANT,
        REDUNDANT
            .state_from_speeds(0.0, &points(x, y, theta), &[v, omega])
            .unwrap(),
    )
    .project_holonomic(project)
    .end_time(10.0)
    .sample_interval(0.1)
    .run_constant(&integrator, [])
    .unwrap();
    (minimal, redundant)
}

#[test]
fn redundant_coordinates_give_the_motion_of_minimal_ones() {
    let (minimal, redundant) = runs();
    let column = |t: &Trajectory, name: &str| t.column(name).unwrap().to_vec();
    let (x1, y1, x2, y2) = (
        column(&redundant, "x1"),
        column(&redundant, "y1"),
        column(&redundant, "x2"),
        column(&redundant, "y2"),
    );
    let mut worst = 0.0f64;
    for i in 0..minimal.len() {
        let theta = (y2[i] - y1[i]).atan2(x2[i] - x1[i]);
        let s = REDUNDANT.a / REDUNDANT.l;
        let centre = (x1[i] + s * (x2[i] - x1[i]), y1[i] + s * (y2[i] - y1[i]));
        let pairs = [
            (centre.0, column(&minimal, "x")[i]),
            (centre.1, column(&minimal, "y")[i]),
            (theta, column(&minimal, "theta")[i]),
            (column(&redundant, "v")[i], column(&minimal, "v")[i]),
            (column(&redundant, "omega")[i], column(&minimal, "omega")[i]),
        ];
        for (a, b) in pairs {
            worst = worst.max((a - b).abs());
        }
    }
    println!("redundant vs minimal coordinates: worst difference {worst:e} over 10 s");
    assert!(worst <= 1e-10, "worst difference {worst:e}");
}

#[test]
fn the_holonomic_constraint_holds_without_projection() {
    let (_, redundant) = runs();
    let mut worst = 0.0f64;
    for row in redundant.rows() {
        let q = [row[1], row[2], row[3], row[4]];
        worst = worst.max(REDUNDANT.holonomic_residual(row[0], &q)[0].abs());
    }
    println!("holonomic residual without projection: {worst:e}");
    assert!(worst <= 1e-10, "{worst:e}");
}

#[test]
fn projection_keeps_the_holonomic_constraint_to_rounding() {
    let (minimal, redundant) = runs_with(true);
    let worst = redundant.summary().max_holonomic_residual;
    println!("holonomic residual with projection: {worst:e}");
    assert!(worst <= 1e-13, "{worst:e}");
    // Projecting moves x₂ by the integration error only: the motion is the same.
    let (v, v_ref) = (redundant.column("v").unwrap(), minimal.column("v").unwrap());
    let worst_v = v
        .iter()
        .zip(v_ref)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(worst_v <= 1e-10, "{worst_v:e}");
}

#[test]
fn the_dependent_coordinate_is_solved_from_the_others() {
    // x₂ is left at a rough guess; the builder solves the constraint for it by Newton.
    let exact = points(0.2, -0.1, 0.3);
    let x = REDUNDANT
        .state_builder()
        .set("x1", exact[0])
        .set("y1", exact[1])
        .set("x2", exact[2] + 0.3)
        .set("y2", exact[3])
        .set("v", 1.0)
        .set("omega", 0.5)
        .build()
        .unwrap();
    assert!(
        (x[2] - exact[2]).abs() < 1e-14,
        "x2 = {} vs {}",
        x[2],
        exact[2]
    );
    assert!(REDUNDANT.holonomic_residual(0.0, &[x[0], x[1], x[2], x[3]])[0].abs() < 1e-14);
}

#[test]
fn a_configuration_the_constraint_cannot_reach_is_an_error_naming_it() {
    // y₂ − y₁ = 2 > l = 1.5: no x₂ puts the points at distance l.
    let q = [0.0, 0.0, 1.0, 2.0];
    let e = REDUNDANT.assemble(0.5, &q).unwrap_err();
    let message = e.to_string();
    println!("{message}");
    assert!(message.contains("rigid0"), "{message}");
    assert!(message.contains("x2"), "{message}");
    assert!(message.contains("0.5"), "{message}");
    // And a state built on it is refused, never a NaN trajectory.
    assert!(REDUNDANT.state_from_speeds(0.0, &q, &[1.0, 0.5]).is_err());
}
