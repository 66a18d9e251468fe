//! A ball rolling on a turntable (`hamel::models::BallOnTurntable`): affine, time-dependent
//! constraints, against the closed form of the literature.
//!
//! With z = x + i y the ball's centre in the inertial frame, the rolling constraints
//! ż − ρ(ω_y − i ω_x) = i Ω(t) z and the ball's equations m z̈ = F, I ω̇ = (−ρ e_z) × F give
//! z̈ = i k d/dt(Ω z), k = I/(I + mρ²) — for a homogeneous ball k = 2/7 (Burns, Am. J. Phys.
//! 49, 56 (1981); Weltner, Am. J. Phys. 47, 984 (1979)). Integrated once,
//!
//!   ż = i k Ω(t) z + c,   c = ż(0) − i k Ω(0) z(0),
//!
//! so z(t) = e^{iΘ(t)} (z₀ + c ∫₀ᵗ e^{−iΘ(s)} ds) with Θ(t) = k ∫₀ᵗ Ω. For Ω = Ω₀ the centre
//! circles about the fixed point i c/(kΩ₀) at the rate kΩ₀ = 2/7 Ω₀; for Ω = Ω₀ + εt (ε > 0),
//! completing the square in Θ turns the integral into Fresnel integrals:
//!
//!   ∫₀ᵗ e^{−iΘ(s)} ds = e^{i kΩ₀²/(2ε)} √(π/(kε)) [C(u) − i S(u)] from u(0) to u(t),
//!   u(s) = √(kε/π) (s + Ω₀/ε),
//!
//! C and S as in Abramowitz & Stegun 7.3.1–2 (evaluated here by their power series 7.3.11–12,
//! checked against A&S Table 7.7 and against Gauss–Legendre quadrature of the integral).

use hamel::models::BallOnTurntable;
use hamel::{DormandPrince, HamelSystem, Simulation, Trajectory};
use std::f64::consts::PI;

/// Complex numbers, as much of them as the closed form needs.
#[derive(Clone, Copy, Debug)]
struct C(f64, f64);

impl C {
    fn mul(self, o: C) -> C {
        C(self.0 * o.0 - self.1 * o.1, self.0 * o.1 + self.1 * o.0)
    }
    fn add(self, o: C) -> C {
        C(self.0 + o.0, self.1 + o.1)
    }
    fn scale(self, s: f64) -> C {
        C(self.0 * s, self.1 * s)
    }
    fn expi(phase: f64) -> C {
        C(phase.cos(), phase.sin())
    }
}

/// Fresnel integrals C(u), S(u) by their power series (A&S 7.3.11, 7.3.12); for |u| ≤ 3 the
/// largest term is below 1e5, so the sum keeps ~11 significant digits at worst and ~14 in the
/// range used here.
fn fresnel(u: f64) -> (f64, f64) {
    let x = PI / 2.0 * u * u;
    let (mut c, mut s) = (0.0, 0.0);
    // term_n = (−1)^n x^{2n} / (2n)!  for C, (−1)^n x^{2n+1} / (2n+1)! for S, each divided by
    // the odd number 4n+1 or 4n+3 and multiplied by u.
    let mut even = 1.0; // (−1)^n x^{2n}/(2n)!
    for n in 0..60 {
        let odd = even * x / (2 * n + 1) as f64; // (−1)^n x^{2n+1}/(2n+1)!
        c += even / (4 * n + 1) as f64;
        s += odd / (4 * n + 3) as f64;
        even = -odd * x / (2 * n + 2) as f64;
        if even.abs() < 1e-30 {
            break;
        }
    }
    (u * c, u * s)
}

/// The table's parameters and the ball's initial centre position and velocity.
struct Case {
    k: f64,
    omega0: f64,
    epsilon: f64,
    z0: C,
    zd0: C,
}

impl Case {
    fn c(&self) -> C {
        // c = ż(0) − i k Ω₀ z(0)
        self.zd0.add(C(0.0, -self.k * self.omega0).mul(self.z0))
    }

    fn theta(&self, t: f64) -> f64 {
        self.k * (self.omega0 * t + 0.5 * self.epsilon * t * t)
    }

    /// ∫₀ᵗ e^{−iΘ(s)} ds in closed form.
    fn integral(&self, t: f64) -> C {
        let (k, w0, eps) = (self.k, self.omega0, self.epsilon);
        if eps == 0.0 {
            // (1 − e^{−ikΩ₀t}) / (ikΩ₀)
            let num = C(1.0, 0.0).add(C::expi(-k * w0 * t).scale(-1.0));
            return num.mul(C(0.0, -1.0 / (k * w0)));
        }
        let u = |s: f64| (k * eps / PI).sqrt() * (s + w0 / eps);
        let (c1, s1) = fresnel(u(t));
        let (c0, s0) = fresnel(u(0.0));
        let bracket = C(c1 - c0, -(s1 - s0));
        C::expi(k * w0 * w0 / (2.0 * eps))
            .mul(bracket)
            .scale((PI / (k * eps)).sqrt())
    }

    fn centre(&self, t: f64) -> C {
        C::expi(self.theta(t)).mul(self.z0.add(self.c().mul(self.integral(t))))
    }
}

/// ∫₀ᵗ e^{−iΘ(s)} ds by 20-point Gauss–Legendre on 200 panels: an independent check of the
/// Fresnel evaluation.
fn integral_by_quadrature(case: &Case, t: f64) -> C {
    // Nodes and weights of the 8-point rule, enough on short panels.
    const X: [f64; 4] = [
        0.183_434_642_495_649_8,
        0.525_532_409_916_329,
        0.796_666_477_413_626_7,
        0.960_289_856_497_536_3,
    ];
    const W: [f64; 4] = [
        0.362_683_783_378_362,
        0.313_706_645_877_887_3,
        0.222_381_034_453_374_5,
        0.101_228_536_290_376_3,
    ];
    let panels = 400;
    let h = t / panels as f64;
    let mut sum = C(0.0, 0.0);
    for p in 0..panels {
        let mid = (p as f64 + 0.5) * h;
        for (x, w) in X.iter().zip(W) {
            for s in [mid - 0.5 * h * x, mid + 0.5 * h * x] {
                sum = sum.add(C::expi(-case.theta(s)).scale(w * 0.5 * h));
            }
        }
    }
    sum
}

/// A homogeneous ball (k = 2/7). The radius does not enter the centre's path; a large one
/// keeps the ball's rotation slow, so that the Euler angles stay far from their singular
/// θ = 0, π over the run.
fn ball(epsilon: f64) -> BallOnTurntable {
    let (m, radius) = (1.0, 10.0);
    BallOnTurntable {
        m,
        radius,
        inertia: 0.4 * m * radius * radius,
        omega0: 1.0,
        epsilon,
    }
}

/// Runs the ball from centre (0.5, 0.2) moving at (0.1, −0.3), spinning at 0.05 rad/s about
/// the vertical, for 10 s; returns the run and the closed form's case.
fn run(epsilon: f64) -> (Trajectory, Case) {
    let model = ball(epsilon);
    let (x0, y0, xd0, yd0) = (0.5, 0.2, 0.1, -0.3);
    let rho = model.radius;
    // The rolling constraints at t = 0 give the horizontal spin from the centre's velocity.
    let speeds = [
        (model.omega0 * x0 - yd0) / rho,
        (xd0 + model.omega0 * y0) / rho,
        0.05,
    ];
    let q = [x0, y0, 0.3, 1.2, 0.1];
    let x = model.state_from_speeds(0.0, &q, &speeds).unwrap();
    let trajectory = Simulation::new(&model, x)
        .end_time(10.0)
        .sample_interval(0.05)
        .run_constant(&DormandPrince::new(1e-13, 1e-13), [])
        .unwrap();
    let k = model.inertia / (model.inertia + model.m * rho * rho);
    let case = Case {
        k,
        omega0: model.omega0,
        epsilon,
        z0: C(x0, y0),
        zd0: C(xd0, yd0),
    };
    (trajectory, case)
}

/// The largest distance between the simulated centre and the closed form's.
fn worst_error(trajectory: &Trajectory, case: &Case) -> f64 {
    let (t, x, y) = (
        trajectory.times(),
        trajectory.column("x").unwrap(),
        trajectory.column("y").unwrap(),
    );
    (0..t.len())
        .map(|i| {
            let z = case.centre(t[i]);
            (x[i] - z.0).hypot(y[i] - z.1)
        })
        .fold(0.0, f64::max)
}

#[test]
fn fresnel_series_matches_the_tables_and_quadrature() {
    // Abramowitz & Stegun, Table 7.7.
    for (u, c, s) in [
        (0.5, 0.492_344_225_871_446_4, 0.064_732_432_859_999_28),
        (1.0, 0.779_893_400_376_822_8, 0.438_259_147_390_354_8),
        (1.5, 0.445_261_176_039_821_5, 0.697_504_960_082_093),
        (2.0, 0.488_253_406_075_340_8, 0.343_415_678_363_698_2),
    ] {
        let (fc, fs) = fresnel(u);
        assert!(
            (fc - c).abs() < 1e-14 && (fs - s).abs() < 1e-14,
            "u = {u}: {fc}, {fs}"
        );
    }
    let case = Case {
        k: 2.0 / 7.0,
        omega0: 1.0,
        epsilon: 0.1,
        z0: C(0.5, 0.2),
        zd0: C(0.1, -0.3),
    };
    for t in [1.0, 4.5, 10.0] {
        let (a, b) = (case.integral(t), integral_by_quadrature(&case, t));
        assert!(
            (a.0 - b.0).abs() < 1e-13 && (a.1 - b.1).abs() < 1e-13,
            "t = {t}"
        );
    }
}

#[test]
fn constant_rate_the_centre_circles_at_two_sevenths_of_the_table_rate() {
    let (trajectory, case) = run(0.0);
    assert!((case.k - 2.0 / 7.0).abs() < 1e-15);
    let worst = worst_error(&trajectory, &case);
    assert!(worst <= 1e-9, "centre off the closed form by {worst:e}");
    // The circle: about the fixed point of ż = ikΩ₀z + c, i c/(kΩ₀), at a constant distance.
    let centre = case.c().mul(C(0.0, 1.0 / (case.k * case.omega0)));
    let (x, y) = (
        trajectory.column("x").unwrap(),
        trajectory.column("y").unwrap(),
    );
    let radius = (x[0] - centre.0).hypot(y[0] - centre.1);
    for (xi, yi) in x.iter().zip(y) {
        assert!(((xi - centre.0).hypot(yi - centre.1) - radius).abs() < 1e-9);
    }
    println!("ε = 0: worst centre error {worst:e} over 10 s");
}

#[test]
fn accelerating_table_the_centre_follows_the_fresnel_solution() {
    let (trajectory, case) = run(0.1);
    let worst = worst_error(&trajectory, &case);
    assert!(worst <= 1e-9, "centre off the closed form by {worst:e}");
    println!("ε = 0.1: worst centre error {worst:e} over 10 s");
    let summary = trajectory.summary();
    assert!(summary.max_constraint_residual < 1e-12, "{summary}");
}

#[test]
fn the_table_drives_the_ball_the_constraint_forces_do_the_work() {
    // The energy changes (the table does work on the ball through the contact); its rate is
    // the power of the constraint forces, dE/dt = −λᵀa.
    let model = ball(0.1);
    let q = [0.5, 0.2, 0.3, 1.2, 0.1];
    let x = model
        .state_from_speeds(0.0, &q, &[0.02, 0.03, 0.05])
        .unwrap();
    let p = model.power(2.0, &x, &[]).unwrap();
    let e = |t: f64, x: &[f64; 8]| model.energy(t, x).unwrap();
    // Central difference of E along the motion.
    let mut dx = [0.0; 8];
    model.rhs(2.0, &x, &[], &mut dx).unwrap();
    let h = 1e-5;
    let ahead: [f64; 8] = std::array::from_fn(|i| x[i] + h * dx[i]);
    let behind: [f64; 8] = std::array::from_fn(|i| x[i] - h * dx[i]);
    let rate = (e(2.0 + h, &ahead) - e(2.0 - h, &behind)) / (2.0 * h);
    assert!(p.abs() > 1e-3, "the table does work: {p}");
    assert!(
        (rate - p).abs() < 1e-8 * p.abs().max(1.0),
        "dE/dt {rate} vs power {p}"
    );
    // Checked when the test compiles: the affine rows make the energy a non-integral.
    const { assert!(!BallOnTurntable::CONSERVATIVE && !BallOnTurntable::POWER_VANISHES_WITHOUT_INPUTS) };
}
