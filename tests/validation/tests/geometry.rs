//! Models stated from geometry (`#[bodies]`, `#[contacts]`): the classics of the catalogue
//! against what nobody here wrote, and the vocabulary against nalgebra.
//!
//! * The rolling disk (`hamel::models::RollingDisk`): straight rolling; a steady turn at a
//!   lean, whose spin the classical steady-motion condition gives (the disk keeps its lean
//!   only with that spin); Euler's disk, spinning on its rim with its centre at rest at
//!   Ω² = 4g/(r cos φ) (Moffatt, Nature 404, 833, 2000).
//! * Chaplygin's ball: the energy, Jellett's integral ⟨M, γ⟩ and |M|² conserved over 20 s
//!   (Chaplygin 1903; Borisov & Mamaev 2002).
//! * The rattleback: the rocking frequencies of a body on a curved base with its axes
//!   aligned; the spectrum of the spinning rattleback, which changes sign with the direction
//!   of spin (time reversal); the spin reversal itself (Walker 1896; Garcia & Hubbard 1988).
//! * `hamel::geometry` against nalgebra: elementary rotations, rotation about an axis, Euler
//!   angles, composition, transposition, rotated vectors, cross and dot products.

use crate::common::xorshift::XorShift;
use hamel::geometry::{Rotation3, Vector3};
use hamel::models::{ChaplyginBall, Rattleback, RollingDisk};
use hamel::{DormandPrince, HamelSystem, Simulation, Trajectory};
use nalgebra as na;
use std::f64::consts::PI;

fn run<S: HamelSystem<Inputs = [f64; 0]>>(model: &S, x0: S::State, seconds: f64) -> Trajectory {
    Simulation::new(model, x0)
        .end_time(seconds)
        .sample_interval(0.01)
        .run_constant(&DormandPrince::new(1e-12, 1e-14), [])
        .unwrap()
}

/// The largest |column − value| over a trajectory.
fn largest_deviation(run: &Trajectory, name: &str, value: f64) -> f64 {
    let column = run.column(name).unwrap();
    column.iter().fold(0.0f64, |m, v| m.max((v - value).abs()))
}

/// The spin rate θ̇ a disk needs to turn steadily at the yaw rate Ω with the lean φ: from
/// the Newton–Euler equations of the disk's steady motion (O'Reilly 1996; Neimark & Fufaev
/// 1972), (C + m r²) Ω ω₃ cos φ − A Ω² sin φ cos φ + m g r sin φ = 0 for the spin about the
/// axle ω₃ = θ̇ + Ω sin φ, A = m r²/4, C = m r²/2.
fn steady_spin(disk: &RollingDisk, lean: f64, yaw_rate: f64) -> f64 {
    let (m, r, g) = (disk.m, disk.r, disk.g);
    let (a, c) = (m * r * r / 4.0, m * r * r / 2.0);
    let (s, co) = lean.sin_cos();
    let axial =
        (a * yaw_rate * yaw_rate * s * co - m * g * r * s) / ((c + m * r * r) * yaw_rate * co);
    axial - yaw_rate * s
}

fn disk_state(disk: &RollingDisk, lean: f64, yaw_rate: f64, spin: f64) -> [f64; 8] {
    disk.state_builder()
        .set("phi", lean)
        .set("yaw_rate", yaw_rate)
        .set("spin_rate", spin)
        .build()
        .unwrap()
}

#[test]
fn an_upright_disk_rolls_straight_at_r_times_its_spin() {
    let disk = RollingDisk::default();
    let (spin, heading) = (-30.0, 0.4);
    let mut x0 = disk_state(&disk, 0.0, 0.0, spin);
    x0[RollingDisk::PSI] = heading;
    let run = run(&disk, x0, 2.0);
    let t = *run.times().last().unwrap();
    let speed = disk.r * spin;
    let x = *run.column("x").unwrap().last().unwrap();
    let y = *run.column("y").unwrap().last().unwrap();
    assert!((x - speed * t * heading.cos()).abs() < 1e-10, "x = {x}");
    assert!((y - speed * t * heading.sin()).abs() < 1e-10, "y = {y}");
    assert!(largest_deviation(&run, "phi", 0.0) < 1e-12);
    assert!(largest_deviation(&run, "spin_rate", spin) < 1e-10);
}

#[test]
fn a_leaning_disk_turns_steadily_with_the_spin_the_steady_motion_condition_gives() {
    let disk = RollingDisk::default();
    let (lean, yaw_rate) = (0.3, 4.0);
    let spin = steady_spin(&disk, lean, yaw_rate);
    let steady = run(&disk, disk_state(&disk, lean, yaw_rate, spin), 3.0);
    let drift = largest_deviation(&steady, "phi", lean);
    println!("lean drift {drift:e} (spin {spin})");
    assert!(drift < 1e-9, "{drift:e}");
    assert!(largest_deviation(&steady, "yaw_rate", yaw_rate) < 1e-8);
    assert!(largest_deviation(&steady, "spin_rate", spin) < 1e-8);
    // The condition is what holds the lean: 1 % more spin, and the disk rises out of it.
    let off = run(&disk, disk_state(&disk, lean, yaw_rate, 1.01 * spin), 3.0);
    let off_drift = largest_deviation(&off, "phi", lean);
    println!("with 1 % more spin the lean drifts by {off_drift:e}");
    assert!(off_drift > 1e-3, "{off_drift:e}");
}

#[test]
fn eulers_disk_spins_on_its_rim_at_moffatts_rate_with_its_centre_at_rest() {
    let disk = RollingDisk::default();
    let lean = 1.2;
    // Moffatt's Ω² = 4g/(a sin α), α the angle between the disk and the table.
    let alpha = PI / 2.0 - lean;
    let yaw_rate = (4.0 * disk.g / (disk.r * alpha.sin())).sqrt();
    // No spin about the axle, ω₃ = θ̇ + Ω sin φ = 0: the centre is at rest.
    let spin = -yaw_rate * lean.sin();
    assert!((spin - steady_spin(&disk, lean, yaw_rate)).abs() < 1e-12 * spin.abs());
    let run = run(&disk, disk_state(&disk, lean, yaw_rate, spin), 2.0);
    assert!(largest_deviation(&run, "phi", lean) < 1e-9);
    assert!(largest_deviation(&run, "yaw_rate", yaw_rate) < 1e-8);
    // The centre, r cos φ above the ground and r sin φ beside the contact, stays put.
    let rows: Vec<Vec<f64>> = run.rows().collect();
    let centre = |row: &[f64]| {
        let (x, y, psi, phi) = (row[1], row[2], row[3], row[4]);
        let up = Rotation3::about_z(psi) * Rotation3::about_x(phi) * Vector3::z();
        Vector3::new(x, y, 0.0) + disk.r * up
    };
    let start = centre(&rows[0]);
    let moved = rows
        .iter()
        .map(|row| (centre(row) - start).norm())
        .fold(0.0f64, f64::max);
    println!("Euler's disk at Ω = {yaw_rate}: the centre moved by {moved:e}");
    assert!(moved < 1e-9, "the centre moved by {moved:e}");
}

/// The ball's invariants at a state: energy, Jellett's ⟨M, γ⟩ and |M|², with M = I ω +
/// m r² (ω − ⟨ω, γ⟩ γ) the angular momentum about the contact point, in the ground frame.
fn ball_invariants(ball: &ChaplyginBall, row: &[f64]) -> [f64; 3] {
    let [alpha, beta, gamma] = [row[3], row[4], row[5]];
    let [da, db, dc] = [row[6], row[7], row[8]];
    let ra = Rotation3::about_y(alpha);
    let rab = ra * Rotation3::about_z(beta);
    let r = rab * Rotation3::about_y(gamma);
    let omega = da * Vector3::y() + db * (ra * Vector3::z()) + dc * (rab * Vector3::y());
    let body = r.transpose() * omega;
    let inertia = Vector3::new(ball.i1 * body.x, ball.i2 * body.y, ball.i3 * body.z);
    let up = Vector3::z();
    let vertical = omega.dot(&up);
    let m_rr = ball.m * ball.r * ball.r;
    let momentum = r * inertia + m_rr * (omega - vertical * up);
    let energy = 0.5 * body.dot(&inertia) + 0.5 * m_rr * (omega - vertical * up).norm_squared();
    [energy, momentum.dot(&up), momentum.norm_squared()]
}

#[test]
fn chaplygins_ball_keeps_its_energy_jellett_and_chaplygin_integrals() {
    let ball = ChaplyginBall::default();
    // The body's z axis (the largest moment) along the ground's y axis, turning mostly about
    // it: the ball rolls along x and wobbles, and its y axis keeps away from the vertical
    // plane's normal, where these Euler angles are singular.
    let x0 = ball
        .state_builder()
        .set("beta", PI / 2.0)
        .set("gamma", PI / 2.0)
        .set("alpha_rate", 6.0)
        .set("beta_rate", 1.5)
        .set("gamma_rate", -1.0)
        .build()
        .unwrap();
    let run = run(&ball, x0, 20.0);
    let rows: Vec<Vec<f64>> = run.rows().collect();
    let first = ball_invariants(&ball, &rows[0]);
    let mut worst = [0.0f64; 3];
    let mut closest_to_singular = f64::INFINITY;
    for row in &rows {
        let now = ball_invariants(&ball, row);
        for k in 0..3 {
            worst[k] = worst[k].max((now[k] - first[k]).abs() / first[k].abs());
        }
        closest_to_singular = closest_to_singular.min(row[4].sin().abs());
    }
    println!(
        "relative drift over 20 s: energy {:e}, Jellett {:e}, |M|² {:e}; min |sin β| {closest_to_singular}",
        worst[0], worst[1], worst[2]
    );
    for (k, name) in ["energy", "Jellett's integral", "|M|²"].iter().enumerate() {
        assert!(worst[k] <= 1e-10, "{name}: {:e}", worst[k]);
    }
    // The Euler angles stayed regular (β away from 0 and π).
    assert!(closest_to_singular > 0.1);
}

fn upright_spin(body: &Rattleback, yaw_rate: f64) -> [f64; 9] {
    body.state_builder()
        .set("z", body.h)
        .set("yaw_rate", yaw_rate)
        .build()
        .unwrap()
}

/// The linearization about upright spin, on the tilt and the rates (x, y and the yaw are
/// cyclic, z is determined by the contact's height).
fn spectrum(body: &Rattleback, yaw_rate: f64) -> Vec<na::Complex<f64>> {
    let mut values = body
        .linearize(0.0, &upright_spin(body, yaw_rate), &[])
        .unwrap()
        .reduce(&["phi", "theta", "roll_rate", "pitch_rate", "yaw_rate"])
        .unwrap()
        .eigenvalues()
        .unwrap();
    values.sort_by(|a, b| a.re.total_cmp(&b.re).then(a.im.total_cmp(&b.im)));
    values
}

/// Without spin and with its axes aligned (δ = 0) the rattleback rocks like a body rolling
/// on a curved base: about its long axis on the base's cross curvature, about its cross
/// axis on the long one, at ω² = m g (R − h)/(I + m h²) (the contact is the instantaneous
/// centre of rotation, h from the centre of mass; the centre of mass rises as (R − h)(1 −
/// cos φ)).
#[test]
fn an_aligned_rattleback_rocks_at_the_frequencies_of_a_body_on_a_curved_base() {
    let body = Rattleback {
        delta: 0.0,
        ..Rattleback::default()
    };
    let (m, g, h) = (body.m, body.g, body.h);
    let roll = (m * g * (body.r2 - h) / (body.a + m * h * h)).sqrt();
    let pitch = (m * g * (body.r1 - h) / (body.b + m * h * h)).sqrt();
    let mut frequencies: Vec<f64> = spectrum(&body, 0.0)
        .iter()
        .filter(|l| l.im > 0.0)
        .map(|l| l.im)
        .collect();
    frequencies.sort_by(f64::total_cmp);
    println!("rocking at {frequencies:?}, closed form {roll}, {pitch}");
    assert_eq!(frequencies.len(), 2);
    assert!((frequencies[0] - roll).abs() <= 1e-12 * roll);
    assert!((frequencies[1] - pitch).abs() <= 1e-12 * pitch);
}

/// Spinning upright, the turned axes (δ ≠ 0) couple rocking and spin: one mode grows and one
/// decays, and reversing the spin reverses every real part (the motion run backwards is a
/// motion with the spin reversed), so that a mode that grows one way decays the other.
#[test]
fn the_spinning_rattlebacks_spectrum_changes_sign_with_its_spin() {
    let body = Rattleback::default();
    let forward = spectrum(&body, 3.0);
    let mut backward: Vec<_> = spectrum(&body, -3.0).iter().map(|l| -l).collect();
    backward.sort_by(|a, b| a.re.total_cmp(&b.re).then(a.im.total_cmp(&b.im)));
    let scale = forward.iter().map(|l| l.norm()).fold(0.0, f64::max);
    for (a, b) in forward.iter().zip(&backward) {
        assert!((a - b).norm() <= 1e-9 * scale, "{a} against {b}");
    }
    let growth = forward
        .iter()
        .map(|l| l.re)
        .fold(f64::NEG_INFINITY, f64::max);
    let decay = forward.iter().map(|l| l.re).fold(f64::INFINITY, f64::min);
    println!("spin 3 rad/s: fastest growth {growth}, fastest decay {decay}");
    assert!(growth > 0.1 && decay < -0.1, "{forward:?}");
}

/// Spun at 3 rad/s with a slight tilt, the rattleback rocks ever harder in pitch, stops and
/// turns the other way, its energy kept.
#[test]
fn the_rattleback_reverses_its_spin() {
    let body = Rattleback::default();
    let x0 = body
        .state_builder()
        .set("phi", 0.005)
        .set("theta", 0.005)
        .set("yaw_rate", 3.0)
        .build()
        .unwrap();
    let run = Simulation::new(&body, x0)
        .end_time(10.0)
        .sample_interval(0.05)
        .run_constant(&DormandPrince::new(1e-10, 1e-12), [])
        .unwrap();
    let yaw = run.column("yaw_rate").unwrap();
    let reversed = yaw.iter().fold(f64::INFINITY, |m, &v| m.min(v));
    let energy = run.column("energy").unwrap();
    let drift = largest_deviation(&run, "energy", energy[0]) / energy[0];
    println!("slowest yaw rate {reversed}, energy drift {drift:e}");
    assert!(reversed < -2.5, "{reversed}");
    assert!(drift < 1e-9, "{drift:e}");
}

fn to_nalgebra(r: &Rotation3) -> na::Matrix3<f64> {
    let m = r.matrix();
    na::Matrix3::from_fn(|i, j| m[i][j])
}

/// The largest entry of |ours − nalgebra's|.
fn difference(ours: &Rotation3, theirs: &na::Rotation3<f64>) -> f64 {
    (to_nalgebra(ours) - theirs.matrix()).amax()
}

/// hamel's vocabulary at run time is nalgebra's arithmetic to rounding: the same rotations
/// about the axes, about any axis (Rodrigues' formula against nalgebra's quaternion-free
/// construction) and from Euler angles; the same compositions, transposes and rotated
/// vectors; the same products of vectors. Each at 100 seeded random angles, axes and
/// vectors, to 4 units in the last place of numbers of order one.
#[test]
fn the_vocabulary_agrees_with_nalgebra() {
    let mut rng = XorShift::new(2026);
    let rounding = 4.0 * f64::EPSILON;
    let mut worst = 0.0f64;
    for _ in 0..100 {
        let mut angle = || rng.uniform(-PI, PI);
        let (a, b, c) = (angle(), angle(), angle());
        let elementary = [
            (
                Rotation3::about_x(a),
                na::Rotation3::from_axis_angle(&na::Vector3::x_axis(), a),
            ),
            (
                Rotation3::about_y(b),
                na::Rotation3::from_axis_angle(&na::Vector3::y_axis(), b),
            ),
            (
                Rotation3::about_z(c),
                na::Rotation3::from_axis_angle(&na::Vector3::z_axis(), c),
            ),
        ];
        for (ours, theirs) in &elementary {
            worst = worst.max(difference(ours, theirs));
        }
        let axis = Vector3::new(
            rng.uniform(-1.0, 1.0),
            rng.uniform(-1.0, 1.0),
            rng.uniform(-1.0, 1.0),
        );
        let na_axis = na::Unit::new_normalize(na::Vector3::new(axis.x, axis.y, axis.z));
        let about = Rotation3::from_axis_angle(&axis, a);
        let na_about = na::Rotation3::from_axis_angle(&na_axis, a);
        worst = worst.max(difference(&about, &na_about));
        worst = worst.max(difference(
            &Rotation3::from_euler_angles(a, b, c),
            &na::Rotation3::from_euler_angles(a, b, c),
        ));
        // Composition, transposition, a rotated vector.
        let composed = about * elementary[1].0 * elementary[2].0.transpose();
        let na_composed = na_about * elementary[1].1 * elementary[2].1.inverse();
        worst = worst.max(difference(&composed, &na_composed));
        let v = Vector3::new(
            rng.uniform(-1.0, 1.0),
            rng.uniform(-1.0, 1.0),
            rng.uniform(-1.0, 1.0),
        );
        let na_v = na::Vector3::new(v.x, v.y, v.z);
        let turned = composed * v;
        let na_turned = na_composed * na_v;
        worst = worst.max((na::Vector3::new(turned.x, turned.y, turned.z) - na_turned).amax());
        let cross = axis.cross(&v);
        let na_cross = na::Vector3::new(axis.x, axis.y, axis.z).cross(&na_v);
        worst = worst.max((na::Vector3::new(cross.x, cross.y, cross.z) - na_cross).amax());
        worst =
            worst.max((axis.dot(&v) - na::Vector3::new(axis.x, axis.y, axis.z).dot(&na_v)).abs());
    }
    println!("largest difference from nalgebra {worst:e}");
    assert!(worst <= rounding, "{worst:e}");
}

/// The Chaplygin sleigh stated from its body, with a torsional spring that the user adds in
/// `#[potential_energy]`, and its blade written with `rate!`: the rate of the contact point
/// across the blade.
#[hamel::hamel_system]
pub struct SprungSleigh {
    pub m: f64,
    pub inertia: f64,
    pub a: f64,
    pub k: f64,
}

#[hamel::hamel_system(coordinates(x, y, theta), speeds(v, omega))]
impl SprungSleigh {
    #[bodies]
    fn bodies(&self, q: &[f64; 3]) -> [hamel::geometry::Body; 1] {
        [hamel::geometry::Body::new(
            self.m,
            hamel::geometry::Inertia::principal(0.0, 0.0, self.inertia),
            Vector3::new(q[0], q[1], 0.0),
            Rotation3::about_z(q[2]),
        )]
    }

    #[potential_energy]
    fn spring(&self, q: &[f64; 3]) -> f64 {
        0.5 * self.k * q[2] * q[2]
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], _qd: &[f64; 3]) -> [f64; 1] {
        let (s, c) = q[2].sin_cos();
        let contact = Vector3::new(q[0] - self.a * c, q[1] - self.a * s, 0.0);
        [hamel::rate!(contact).dot(&Vector3::new(-s, c, 0.0))]
    }

    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[2]]
    }
}

/// The same sleigh and spring written by hand.
#[hamel::hamel_system]
pub struct SprungSleighByHand {
    pub m: f64,
    pub inertia: f64,
    pub a: f64,
    pub k: f64,
}

#[hamel::hamel_system(coordinates(x, y, theta), speeds(v, omega))]
impl SprungSleighByHand {
    #[kinetic_energy]
    fn kinetic_energy(&self, _q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        0.5 * self.m * (qd[0] * qd[0] + qd[1] * qd[1]) + 0.5 * self.inertia * qd[2] * qd[2]
    }

    #[potential_energy]
    fn spring(&self, q: &[f64; 3]) -> f64 {
        0.5 * self.k * q[2] * q[2]
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [-qd[0] * q[2].sin() + qd[1] * q[2].cos() - self.a * qd[2]]
    }

    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[2]]
    }
}

/// A body and a hand-written potential mix: the right-hand side, the energy and the blade's
/// row (which `rate!` gives, and which the generated body computes at run time) are those of
/// the hand-written model.
#[test]
fn bodies_mix_with_a_potential_energy_and_rate_gives_the_blade() {
    let (m, inertia, a, k) = (2.0, 0.5, 0.4, 3.0);
    let ours = SprungSleigh { m, inertia, a, k };
    let theirs = SprungSleighByHand { m, inertia, a, k };
    let mut rng = XorShift::new(5);
    for _ in 0..20 {
        let x: [f64; 5] = std::array::from_fn(|_| rng.uniform(-2.0, 2.0));
        let (mut d1, mut d2) = ([0.0; 5], [0.0; 5]);
        ours.rhs(0.0, &x, &[], &mut d1).unwrap();
        theirs.rhs(0.0, &x, &[], &mut d2).unwrap();
        for (p, q) in d1.iter().zip(&d2) {
            assert!(
                (p - q).abs() <= 1e-14 * (1.0 + q.abs()),
                "{d1:?} against {d2:?}"
            );
        }
        let (e1, e2) = (
            ours.energy(0.0, &x).unwrap(),
            theirs.energy(0.0, &x).unwrap(),
        );
        assert!((e1 - e2).abs() <= 1e-14 * (1.0 + e2.abs()));
        let q = [x[0], x[1], x[2]];
        let qd = [
            rng.uniform(-1.0, 1.0),
            rng.uniform(-1.0, 1.0),
            rng.uniform(-1.0, 1.0),
        ];
        let (r1, r2) = (ours.blade(&q, &qd)[0], theirs.blade(&q, &qd)[0]);
        assert!((r1 - r2).abs() <= 1e-14, "{r1} against {r2}");
    }
}

/// Shared helpers, in a module of their own: the rolling disk's body and contact, written
/// once for the two models below.
mod disks {
    use hamel::geometry::{Body, Contact, Inertia, Rotation3, Vector3};

    pub struct Disks;

    #[hamel::helpers]
    impl Disks {
        /// A thin uniform disk whose axle is its y axis.
        pub fn thin(m: f64, r: f64, centre: Vector3, orientation: Rotation3) -> Body {
            let diameter = m * r * r / 4.0;
            Body::new(
                m,
                Inertia::principal(diameter, 2.0 * diameter, diameter),
                centre,
                orientation,
            )
        }

        /// The disk of radius r rolling at (x, y) with yaw, lean and spin q[2..5].
        pub fn rolling(m: f64, r: f64, q: &[f64; 5]) -> Body {
            let heading = Rotation3::about_z(q[2]) * Rotation3::about_x(q[3]);
            let centre = Vector3::new(q[0], q[1], 0.0) + heading * Vector3::new(0.0, 0.0, r);
            Self::thin(m, r, centre, heading * Rotation3::about_y(q[4]))
        }

        pub fn on_ground(disk: Body, q: &[f64; 5]) -> Contact {
            Contact::ground(disk, Vector3::new(q[0], q[1], 0.0))
        }
    }
}

mod shared {
    use super::disks::Disks;
    use hamel::prelude::*;

    #[hamel_system]
    pub struct Coin {
        pub m: f64,
        pub r: f64,
        pub g: f64,
    }

    #[hamel_system(coordinates(x, y, psi, phi, theta), helpers(Disks))]
    impl Coin {
        #[bodies]
        fn bodies(&self, q: &[f64; 5]) -> [Body; 1] {
            [Disks::rolling(self.m, self.r, q)]
        }

        #[gravity]
        fn gravity(&self) -> Vector3 {
            Vector3::new(0.0, 0.0, -self.g)
        }

        #[contacts]
        fn contacts(&self, q: &[f64; 5]) -> [Contact; 1] {
            [Disks::on_ground(Disks::rolling(self.m, self.r, q), q)]
        }

        #[quasi_velocities]
        fn rates(&self, _q: &[f64; 5], qd: &[f64; 5]) -> [f64; 3] {
            [qd[2], qd[3], qd[4]]
        }
    }

    /// The same coin in a weightless place, written with the same helpers.
    #[hamel_system]
    pub struct FloatingCoin {
        pub m: f64,
        pub r: f64,
    }

    #[hamel_system(coordinates(x, y, psi, phi, theta), helpers(super::disks::Disks))]
    impl FloatingCoin {
        #[bodies]
        fn bodies(&self, q: &[f64; 5]) -> [Body; 1] {
            [Disks::rolling(self.m, self.r, q)]
        }

        #[contacts]
        fn contacts(&self, q: &[f64; 5]) -> [Contact; 1] {
            let [coin] = self.bodies(q);
            [Disks::on_ground(coin, q)]
        }

        #[quasi_velocities]
        fn rates(&self, _q: &[f64; 5], qd: &[f64; 5]) -> [f64; 3] {
            [qd[2], qd[3], qd[4]]
        }
    }
}

/// Two models that call the same shared helpers are the models written without them: the
/// coin is the catalogue's rolling disk, and without gravity it is the disk with g = 0.
#[test]
fn shared_helpers_serve_several_models() {
    let disk = RollingDisk::default();
    let coin = shared::Coin {
        m: disk.m,
        r: disk.r,
        g: disk.g,
    };
    let floating = shared::FloatingCoin {
        m: disk.m,
        r: disk.r,
    };
    let weightless = RollingDisk {
        g: 0.0,
        ..disk.clone()
    };
    let mut rng = XorShift::new(9);
    for _ in 0..20 {
        let x: [f64; 8] = std::array::from_fn(|_| rng.uniform(-1.0, 1.0));
        let mut d = [[0.0; 8]; 4];
        disk.rhs(0.0, &x, &[], &mut d[0]).unwrap();
        coin.rhs(0.0, &x, &[], &mut d[1]).unwrap();
        weightless.rhs(0.0, &x, &[], &mut d[2]).unwrap();
        floating.rhs(0.0, &x, &[], &mut d[3]).unwrap();
        for (ours, theirs) in [(d[1], d[0]), (d[3], d[2])] {
            for (a, b) in ours.iter().zip(&theirs) {
                assert!(
                    (a - b).abs() <= 1e-13 * (1.0 + b.abs()),
                    "{ours:?} against {theirs:?}"
                );
            }
        }
    }
    // Without `constraints(..)`, a contact's rows are named after the function and the
    // contact's index: identifiers, as the force columns of a CSV header must be.
    assert_eq!(shared::Coin::CONSTRAINTS, ["contacts0_x", "contacts0_y"]);
    // At run time the helpers are ordinary functions.
    let body = disks::Disks::rolling(1.0, 0.5, &[0.0; 5]);
    assert_eq!(body.centre, Vector3::new(0.0, 0.0, 0.5));
}

/// The ball on a turntable stated from geometry: the table is a body whose pose is a
/// function of the time (no mass, turned by ∫Ω dt about the vertical), and the ball rolls on
/// it, `Contact::on`: the rows the macro derives carry the table's velocity at the contact,
/// an affine, time-dependent part.
#[hamel::hamel_system]
pub struct TurntableBall {
    pub m: f64,
    pub radius: f64,
    pub inertia: f64,
    pub omega0: f64,
    pub epsilon: f64,
}

#[hamel::hamel_system(coordinates(x, y, phi, theta, psi), speeds(omega_x, omega_y, omega_z))]
impl TurntableBall {
    fn ball(&self, q: &[f64; 5]) -> hamel::geometry::Body {
        let orientation =
            Rotation3::about_z(q[2]) * Rotation3::about_x(q[3]) * Rotation3::about_z(q[4]);
        let i = self.inertia;
        hamel::geometry::Body::new(
            self.m,
            hamel::geometry::Inertia::principal(i, i, i),
            Vector3::new(q[0], q[1], self.radius),
            orientation,
        )
    }

    #[bodies]
    fn bodies(&self, q: &[f64; 5]) -> [hamel::geometry::Body; 1] {
        [self.ball(q)]
    }

    #[contacts]
    fn contacts(&self, t: f64, q: &[f64; 5]) -> [hamel::geometry::Contact; 1] {
        let turned = self.omega0 * t + 0.5 * self.epsilon * t * t;
        let table = hamel::geometry::Body::new(
            0.0,
            hamel::geometry::Inertia::principal(0.0, 0.0, 0.0),
            Vector3::zeros(),
            Rotation3::about_z(turned),
        );
        [hamel::geometry::Contact::on(
            self.ball(q),
            table,
            Vector3::new(q[0], q[1], 0.0),
        )]
    }

    /// The ball's angular velocity in the inertial frame: φ̇ e_z + θ̇ (R_z e_x) + ψ̇ (R_z R_x e_z).
    #[quasi_velocities]
    fn spin(&self, q: &[f64; 5], qd: &[f64; 5]) -> [f64; 3] {
        let nodes = Rotation3::about_z(q[2]);
        let w = qd[2] * Vector3::z()
            + qd[3] * (nodes * Vector3::x())
            + qd[4] * (nodes * Rotation3::about_x(q[3]) * Vector3::z());
        w.to_array()
    }
}

/// A rolling contact on a moving surface (a time-dependent, affine constraint) stated from
/// geometry is the catalogue's ball on a turntable, whose rows are written by hand: the same
/// right-hand side at random states and times.
#[test]
fn a_ball_rolling_on_a_turntable_from_geometry_is_the_hand_written_one() {
    let theirs = hamel::models::BallOnTurntable::default();
    let ours = TurntableBall {
        m: theirs.m,
        radius: theirs.radius,
        inertia: theirs.inertia,
        omega0: theirs.omega0,
        epsilon: theirs.epsilon,
    };
    let mut rng = XorShift::new(31);
    for _ in 0..20 {
        let t = rng.uniform(0.0, 10.0);
        let mut x: [f64; 8] = std::array::from_fn(|_| rng.uniform(-1.0, 1.0));
        x[3] = rng.uniform(0.3, 2.8); // θ away from the ZXZ singularity at 0 and π
        let (mut a, mut b) = ([0.0; 8], [0.0; 8]);
        ours.rhs(t, &x, &[], &mut a).unwrap();
        theirs.rhs(t, &x, &[], &mut b).unwrap();
        for (p, q) in a.iter().zip(&b) {
            assert!(
                (p - q).abs() <= 1e-13 * (1.0 + q.abs()),
                "t = {t}: {a:?} against {b:?}"
            );
        }
    }
    const { assert!(!TurntableBall::CONSERVATIVE && !TurntableBall::REVERSIBLE) };
}
