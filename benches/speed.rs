//! The figures of record for the speed of the generated right-hand side (`rhs.rs`, with
//! criterion, shows trends): `cargo bench -p hamel-benches --bench speed`, or with
//! `HAMEL_BENCH_ROUNDS=21` for a quick run (201 rounds by default). A change to the macro is
//! measured against the commit before it with `bash benches/speed_ab.sh NEW OLD`, which builds
//! this benchmark at both and runs them in alternating pairs.
//!
//! Measured interleaved (see `hamel_benches::interleave`): short batches (about 1 ms) of
//! each variant alternate round-robin, and each figure is the median over the rounds of a
//! per-round figure, p10–p90 beside it.
//!
//! The generated right-hand sides are timed as a simulation calls them: `rhs_prepared`, with
//! the values that depend on the parameters alone computed once beforehand (`prepare`); the
//! robot's two generated variants are also timed through `rhs`, which computes those values
//! at every call, as the hand-written closed form does.
//!
//! * The robot (`MobileRobot`: stated from its body and its two wheels rolling on the ground)
//!   over the same 64 seeded states and inputs as `rhs.rs`, in three variants: (c) the
//!   hand-written closed form (`tests/validation/tests/common/robot_closed_form.rs`), (b)
//!   generated, B = A⁻¹ by the generated LU, (a) generated with the inverse B given
//!   (`#[velocities]`): the robot written by hand from its energies, constraints and
//!   quasi-velocities (as the catalogue had it before it was stated from its wheels) with the
//!   paper's B added, [`RobotWithInverse`] below. The startup
//!   checks that (a) and (b) agree to 1e-12 on every sample. The catalogue's
//!   `MobileRobotPaper` (L̃ given with B, the paper's input form) is timed beside them.
//! * The Whipple bicycle stated from its bodies and contacts (the catalogue's
//!   `WhippleBicycle`, velocities and constraints derived by the macro) against the same
//!   bicycle written by hand (`tests/validation/tests/common/whipple_by_hand.rs`), over 64
//!   seeded states; the startup checks that they agree to 1e-12.
//! * The N-trailer (`hamel::n_trailer!`) for N = 1, 2, 4, 8, 16, 24 over 64 seeded states
//!   each: ns per right-hand side, its ratio to N = 1, and the growth exponent, the
//!   least-squares slope of log t against log N, taken per round (median, p10–p90) and of
//!   the median times (the steadier figure when some rounds are disturbed).

use hamel::models::{
    MobileRobot, MobileRobotPaper, NTrailer1, NTrailer2, NTrailer8, NTrailer24, WhippleBicycle,
};
use hamel::{HamelSystem, Vector, hamel_system};
use hamel_benches::interleave::{Spread, ratio, round_robin, rounds, seconds, slope};
use hamel_benches::{Uniform, robot_samples};
use std::hint::black_box;

#[path = "../tests/validation/tests/common/robot_closed_form.rs"]
mod closed_form;
#[path = "../tests/validation/tests/common/whipple_by_hand.rs"]
mod whipple_by_hand;

hamel::n_trailer!(
    /// A tractor with four trailers.
    pub NTrailer4, trailers = 4, axles = 5
);

hamel::n_trailer!(
    /// A tractor with sixteen trailers.
    pub NTrailer16, trailers = 16, axles = 17
);

/// The robot written by hand from its energies (`tests/validation/tests/common/
/// robot_by_hand.rs`, the catalogue's `MobileRobot` before it was stated from its wheels) with
/// the inverse B given: the `#[velocities]` of `MobileRobotPaper` (the same rows A).
#[hamel_system]
#[derive(Clone, Debug, PartialEq)]
pub struct RobotWithInverse {
    /// mass of the body (kg)
    pub m0: f64,
    /// mass of one wheel (kg)
    pub mw: f64,
    /// body's principal moment of inertia about its x axis (forward) (kg m²)
    pub jx: f64,
    /// body's principal moment of inertia about its y axis (the axle) (kg m²)
    pub jy: f64,
    /// body's principal moment of inertia about its z axis (vertical) (kg m²)
    pub jz: f64,
    /// wheel radius (m)
    pub r: f64,
    /// axle length, wheel to wheel (m)
    pub b: f64,
    /// distance of the body's centre of gravity from the axle (m)
    pub l: f64,
    /// gravitational acceleration (m/s²)
    pub g: f64,
}

impl From<&MobileRobot> for RobotWithInverse {
    fn from(p: &MobileRobot) -> Self {
        RobotWithInverse {
            m0: p.m0,
            mw: p.mw,
            jx: p.jx,
            jy: p.jy,
            jz: p.jz,
            r: p.r,
            b: p.b,
            l: p.l,
            g: p.g,
        }
    }
}

#[hamel_system(
    coordinates(x, y, alpha, phi1, phi2),
    speeds(w3, w4, w5),
    inputs(tau1, tau2)
)]
impl RobotWithInverse {
    #[kinetic_energy]
    pub fn kinetic_energy(&self, q: &[f64; 5], qd: &[f64; 5]) -> f64 {
        let [_, _, alpha, phi1, phi2] = *q;
        let [xd, yd, alphad, phi1d, phi2d] = *qd;
        let theta = self.r * (phi1 - phi2) / self.b;
        let thetad = self.r * (phi1d - phi2d) / self.b;
        let (s, c) = theta.sin_cos();
        let (sa, ca) = alpha.sin_cos();
        let vx = xd + self.l * alphad * ca * c - self.l * sa * thetad * s;
        let vy = yd + self.l * alphad * ca * s + self.l * sa * thetad * c;
        let vz = -self.l * alphad * sa;
        let body = 0.5 * self.m0 * (vx * vx + vy * vy + vz * vz)
            + 0.5 * (self.jx * sa * sa + self.jz * ca * ca) * thetad * thetad
            + 0.5 * self.jy * alphad * alphad;
        let half = 0.5 * self.b * thetad;
        let (c1x, c1y) = (xd + half * c, yd + half * s);
        let (c2x, c2y) = (xd - half * c, yd - half * s);
        let quarter = 0.25 * self.mw * self.r * self.r;
        let wheels = 0.5 * self.mw * (c1x * c1x + c1y * c1y + c2x * c2x + c2y * c2y)
            + quarter * ((alphad + phi1d).powi(2) + (alphad + phi2d).powi(2))
            + quarter * thetad * thetad;
        body + wheels
    }

    #[potential_energy]
    pub fn potential_energy(&self, q: &[f64; 5]) -> f64 {
        self.m0 * self.g * self.l * q[2].cos()
    }

    #[constraints]
    pub fn no_slip(&self, q: &[f64; 5], qd: &[f64; 5]) -> [f64; 2] {
        let theta = self.r * (q[3] - q[4]) / self.b;
        let (s, c) = theta.sin_cos();
        [
            qd[0] * s - qd[1] * c,
            self.r * qd[2] + 0.5 * self.r * (qd[3] + qd[4]) - (qd[0] * c + qd[1] * s),
        ]
    }

    #[quasi_velocities]
    pub fn speeds(&self, q: &[f64; 5], qd: &[f64; 5]) -> [f64; 3] {
        let theta = self.r * (q[3] - q[4]) / self.b;
        [
            qd[2],
            qd[0] * theta.cos() + qd[1] * theta.sin(),
            self.r / self.b * (qd[3] - qd[4]),
        ]
    }

    /// q̇ = B(q) ω, the inverse of the five rows above.
    #[velocities]
    pub fn velocities(&self, q: &[f64; 5], w: &[f64; 5]) -> [f64; 5] {
        let theta = self.r * (q[3] - q[4]) / self.b;
        let (s, c) = theta.sin_cos();
        let roll = (w[1] + w[3]) / self.r - w[2];
        let turn = 0.5 * self.b / self.r * w[4];
        [
            w[0] * s + w[3] * c,
            -w[0] * c + w[3] * s,
            w[2],
            roll + turn,
            roll - turn,
        ]
    }

    #[forces]
    pub fn torques(&self, _t: f64, _q: &[f64; 5], _qd: &[f64; 5], u: &[f64; 2]) -> [f64; 5] {
        [0.0, 0.0, 0.0, u[0], u[1]]
    }
}

/// The largest difference between two right-hand sides over the samples, relative to
/// max(1, |ẋ|) component by component.
fn worst_difference(
    a: impl Fn(&[f64; 8], &[f64; 2]) -> [f64; 8],
    b: impl Fn(&[f64; 8], &[f64; 2]) -> [f64; 8],
    samples: &[([f64; 8], [f64; 2])],
) -> f64 {
    samples
        .iter()
        .flat_map(|(x, u)| {
            let (da, db) = (a(x, u), b(x, u));
            (0..8)
                .map(move |i| (da[i] - db[i]).abs() / da[i].abs().max(1.0))
                .collect::<Vec<_>>()
        })
        .fold(0.0, f64::max)
}

/// A generated right-hand side at a sample; panics on a singular configuration.
fn generated<S: HamelSystem<State = [f64; 8], Inputs = [f64; 2]>>(
    system: &S,
    x: &[f64; 8],
    u: &[f64; 2],
) -> [f64; 8] {
    let mut dx = [0.0; 8];
    system
        .rhs(0.0, x, u, &mut dx)
        .expect("the samples are regular");
    dx
}

/// One call per sample of a generated right-hand side as a simulation calls it: with the
/// parameter-only values prepared once (`HamelSystem::rhs_prepared`).
fn sweep<S: HamelSystem>(system: &S, samples: &[(S::State, S::Inputs)]) -> impl FnMut() {
    let mut prepared = vec![0.0; S::PREPARED_LEN];
    system.prepare(&mut prepared);
    move || {
        let mut dx = S::State::zeros();
        for (x, u) in samples {
            let ok = system
                .rhs_prepared(
                    black_box(&prepared),
                    0.0,
                    black_box(x),
                    black_box(u),
                    &mut dx,
                )
                .is_ok();
            black_box((ok, &dx));
        }
    }
}

/// One call per sample of `HamelSystem::rhs`, which computes the parameter-only values
/// every time.
fn sweep_unprepared<S: HamelSystem>(system: &S, samples: &[(S::State, S::Inputs)]) -> impl FnMut() {
    move || {
        let mut dx = S::State::zeros();
        for (x, u) in samples {
            let ok = system.rhs(0.0, black_box(x), black_box(u), &mut dx).is_ok();
            black_box((ok, &dx));
        }
    }
}

fn robot() {
    let everyday = MobileRobot::default();
    let with_inverse = RobotWithInverse::from(&everyday);
    let paper = MobileRobotPaper::from(&everyday);
    let samples = robot_samples();

    let agreement = worst_difference(
        |x, u| generated(&everyday, x, u),
        |x, u| generated(&with_inverse, x, u),
        &samples,
    );
    assert!(
        agreement <= 1e-12,
        "RobotWithInverse differs from MobileRobot by {agreement:e}"
    );
    let hand = |x: &[f64; 8], u: &[f64; 2]| {
        let mut dx = [0.0; 8];
        closed_form::robot_rhs(&everyday, x, u, &mut dx);
        dx
    };
    let closed = worst_difference(|x, u| generated(&everyday, x, u), hand, &samples);
    assert!(
        closed <= 1e-12,
        "the closed form differs from MobileRobot by {closed:e}"
    );

    let mut c = || {
        let mut dx = [0.0; 8];
        for (x, u) in &samples {
            closed_form::robot_rhs(&everyday, black_box(x), black_box(u), &mut dx);
            black_box(&dx);
        }
    };
    let mut b = sweep(&everyday, &samples);
    let mut a = sweep(&with_inverse, &samples);
    let mut p = sweep(&paper, &samples);
    let mut b_plain = sweep_unprepared(&everyday, &samples);
    let mut a_plain = sweep_unprepared(&with_inverse, &samples);
    let rounds = round_robin(&mut [&mut c, &mut b, &mut a, &mut p, &mut b_plain, &mut a_plain]);
    let per_call = 1e9 / samples.len() as f64;

    println!(
        "Robot right-hand side, {} rounds over {} states ({} rounds × 6 batches of ~1 ms)",
        rounds.len(),
        samples.len(),
        rounds.len()
    );
    println!(
        "  checks: with inverse vs MobileRobot {agreement:.1e}, closed form vs MobileRobot {closed:.1e}"
    );
    println!(
        "  {:<44} {:>10} {:>15} {:>9} {:>17}",
        "variant", "ratio", "p10–p90", "ns/call", "ns p10–p90"
    );
    let names = [
        "(c) closed form, hand-written",
        "(b) generated, no inverse (MobileRobot)",
        "(a) generated, inverse given (#[velocities])",
        "    MobileRobotPaper (L̃ and B given)",
        "(b) unprepared: rhs, parameters every call",
        "(a) unprepared: rhs, parameters every call",
    ];
    for (v, name) in names.iter().enumerate() {
        let r = ratio(&rounds, v, 0);
        let t = seconds(&rounds, v).scaled(per_call);
        println!(
            "  {name:<44} {:>10.3} {:>15} {:>9.1} {:>17}",
            r.median,
            format!("{:.3}–{:.3}", r.p10, r.p90),
            t.median,
            format!("{:.1}–{:.1}", t.p10, t.p90),
        );
    }
    let r = ratio(&rounds, 1, 2);
    println!(
        "  no inverse / inverse given: {:.3} (p10–p90 {:.3}–{:.3})",
        r.median, r.p10, r.p90
    );
}

/// 64 seeded states of an N-trailer: positions in [−3, 3), headings with neighbours at most
/// 0.5 apart (a train as it drives), speeds in [−1, 1); inputs in [−1, 1).
fn train_samples<S: HamelSystem>(seed: u64) -> Vec<(S::State, S::Inputs)> {
    let mut rng = Uniform::new(seed);
    let n = S::N;
    (0..64)
        .map(|_| {
            let mut x = S::State::zeros();
            let v = x.as_mut();
            v[0] = 3.0 * rng.sample();
            v[1] = 3.0 * rng.sample();
            v[2] = 3.0 * rng.sample();
            for i in 3..n {
                v[i] = v[i - 1] + 0.5 * rng.sample();
            }
            for s in &mut v[n..] {
                *s = rng.sample();
            }
            let mut u = S::Inputs::zeros();
            for s in u.as_mut() {
                *s = rng.sample();
            }
            (x, u)
        })
        .collect()
}

/// Panics if the right-hand side is singular at a sample.
fn regular<S: HamelSystem>(system: &S, samples: &[(S::State, S::Inputs)]) {
    for (x, u) in samples {
        let mut dx = S::State::zeros();
        if let Err(e) = system.rhs(0.0, x, u, &mut dx) {
            panic!("singular sample for N + 3 = {}: {e:?}", S::N);
        }
    }
}

fn n_trailer() {
    const SEED: u64 = 0x2545_F491_4F6C_DD1D;
    let (t1, t2, t4) = (
        NTrailer1::default(),
        NTrailer2::default(),
        NTrailer4::default(),
    );
    let (t8, t16, t24) = (
        NTrailer8::default(),
        NTrailer16::default(),
        NTrailer24::default(),
    );
    let (s1, s2, s4) = (
        train_samples::<NTrailer1>(SEED),
        train_samples::<NTrailer2>(SEED),
        train_samples::<NTrailer4>(SEED),
    );
    let (s8, s16, s24) = (
        train_samples::<NTrailer8>(SEED),
        train_samples::<NTrailer16>(SEED),
        train_samples::<NTrailer24>(SEED),
    );
    // A singular sample would time the error path: check none is.
    regular(&t1, &s1);
    regular(&t2, &s2);
    regular(&t4, &s4);
    regular(&t8, &s8);
    regular(&t16, &s16);
    regular(&t24, &s24);

    let (mut f1, mut f2, mut f4) = (sweep(&t1, &s1), sweep(&t2, &s2), sweep(&t4, &s4));
    let (mut f8, mut f16, mut f24) = (sweep(&t8, &s8), sweep(&t16, &s16), sweep(&t24, &s24));
    let ns: [f64; 6] = [1.0, 2.0, 4.0, 8.0, 16.0, 24.0];
    let rounds = round_robin(&mut [&mut f1, &mut f2, &mut f4, &mut f8, &mut f16, &mut f24]);
    let per_call = 1e9 / 64.0;
    println!(
        "\nN-trailer right-hand side, {} rounds over 64 states for each N (round-robin across N)",
        rounds.len()
    );
    println!(
        "  {:>3} {:>6} {:>9} {:>17} {:>9} {:>15}",
        "N", "states", "ns/call", "ns p10–p90", "/ N=1", "p10–p90"
    );
    for (v, n) in ns.iter().enumerate() {
        let t = seconds(&rounds, v).scaled(per_call);
        let r = ratio(&rounds, v, 0);
        println!(
            "  {:>3} {:>6} {:>9.1} {:>17} {:>9.2} {:>15}",
            n,
            *n as usize + 5,
            t.median,
            format!("{:.1}–{:.1}", t.p10, t.p90),
            r.median,
            format!("{:.2}–{:.2}", r.p10, r.p90),
        );
    }
    let exponent = |from: usize| {
        let x: Vec<f64> = ns[from..].iter().map(|n| n.ln()).collect();
        let per_round: Vec<f64> = rounds
            .iter()
            .map(|r| {
                let y: Vec<f64> = r[from..].iter().map(|t| t.ln()).collect();
                slope(&x, &y)
            })
            .collect();
        Spread::of(&per_round)
    };
    let medians: Vec<f64> = (0..ns.len())
        .map(|v| seconds(&rounds, v).median.ln())
        .collect();
    for (from, label) in [(0, "N = 1…24"), (2, "N = 4…24")] {
        let e = exponent(from);
        let x: Vec<f64> = ns[from..].iter().map(|n| n.ln()).collect();
        println!(
            "  growth exponent (slope of log t on log N), {label}: per round {:.3} \
             (p10–p90 {:.3}–{:.3}); of the median times {:.3}",
            e.median,
            e.p10,
            e.p90,
            slope(&x, &medians[from..])
        );
    }
}

/// 64 seeded states of the bicycle: angles in [−1, 1) (the pitch in [−0.3, 0.3)), speeds
/// in [−5, 5), inputs in [−0.5, 0.5).
fn bicycle_samples() -> Vec<([f64; 11], [f64; 2])> {
    let mut rng = Uniform::new(0x9E37_79B9_7F4A_7C15);
    (0..64)
        .map(|_| {
            let x = std::array::from_fn(|i| {
                let spread = match i {
                    WhippleBicycle::THETA => 0.3,
                    i if i < WhippleBicycle::N => 1.0,
                    _ => 5.0,
                };
                spread * rng.sample()
            });
            (x, [0.5 * rng.sample(), 0.5 * rng.sample()])
        })
        .collect()
}

fn bicycle() {
    let from_bodies = WhippleBicycle::default();
    let by_hand = whipple_by_hand::WhippleByHand::from(&from_bodies);
    let samples = bicycle_samples();
    let mut worst = 0.0f64;
    for (x, u) in &samples {
        let (mut a, mut b) = ([0.0; 11], [0.0; 11]);
        from_bodies
            .rhs(0.0, x, u, &mut a)
            .expect("the samples are regular");
        by_hand
            .rhs(0.0, x, u, &mut b)
            .expect("the samples are regular");
        let scale = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for (p, q) in a.iter().zip(&b) {
            worst = worst.max((p - q).abs() / scale);
        }
    }
    assert!(worst <= 1e-12, "the bicycles differ by {worst:e}");
    let mut hand = sweep(&by_hand, &samples);
    let mut bodies = sweep(&from_bodies, &samples);
    let mut hand_plain = sweep_unprepared(&by_hand, &samples);
    let mut bodies_plain = sweep_unprepared(&from_bodies, &samples);
    let rounds = round_robin(&mut [&mut hand, &mut bodies, &mut hand_plain, &mut bodies_plain]);
    let per_call = 1e9 / samples.len() as f64;
    println!(
        "\nWhipple bicycle right-hand side, {} rounds over {} states (agreement {worst:.1e})",
        rounds.len(),
        samples.len()
    );
    println!(
        "  {:<44} {:>10} {:>15} {:>9} {:>17}",
        "variant", "ratio", "p10–p90", "ns/call", "ns p10–p90"
    );
    let names = [
        "written by hand",
        "stated from bodies and contacts",
        "written by hand, unprepared (rhs)",
        "from bodies and contacts, unprepared (rhs)",
    ];
    for (v, name) in names.iter().enumerate() {
        let r = ratio(&rounds, v, if v < 2 { 0 } else { 2 });
        let t = seconds(&rounds, v).scaled(per_call);
        println!(
            "  {name:<44} {:>10.3} {:>15} {:>9.1} {:>17}",
            r.median,
            format!("{:.3}–{:.3}", r.p10, r.p90),
            t.median,
            format!("{:.1}–{:.1}", t.p10, t.p90),
        );
    }
}

fn main() {
    println!("hamel speed benchmark: {} rounds", rounds());
    robot();
    bicycle();
    n_trailer();
}
