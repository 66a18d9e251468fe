//! Long runs: how the integrators keep the energy over 10⁴–10⁶ s, and what a stiff system
//! costs each. `cargo bench -p hamel-benches --bench long_runs` (about three minutes of one
//! core in release), or `-- --quick` for the same runs 100 times shorter (a smoke test, not
//! figures).
//!
//! Problems (the P1–P3):
//! * **P1** McLachlan and Perlmutter's contact oscillator (`ContactOscillator`, ε = 0.3,
//!   H₀ = 1.5, H_y = 0.5, `ContactOscillator::start`) at their step h = 2 sin(π/40), to
//!   T = 10⁴ (6.4·10⁴ steps); its invariants H, H_y = ½(y² + ẏ²) and H − H_y.
//! * **P2** the vertical rolling disk (`VerticalDisk`, θ̇ = 2, φ̇ = 1.5) to T = 10⁴ with
//!   h = 0.05: its speeds are constant under every Runge–Kutta method, so its energy is exact
//!   and the figure is the position error against the closed form (Bloch §1.4).
//! * **P3** the force-free robot (`MobileRobot`, body hanging at α = 3 rad and swinging,
//!   driving round at w4 = 1 m/s, turning at w5 = 0.8 rad/s) to T = 10⁵ with h = 0.01
//!   (10⁷ steps), and the Chaplygin sleigh to T = 10⁴ with h = 0.05.
//!
//! Each problem is run with Gauss–Legendre with two stages at its step, and with the
//! implicit midpoint rule, RK4 and Dormand–Prince with fixed steps at **equal work**: steps
//! chosen so that their right-hand-side evaluations match Gauss 2's (the Jacobians the
//! implicit methods evaluate, by dual numbers, come on top; their count is listed). Figures:
//! max |H − H₀| over the run, the least-squares slope of H(t) − H₀ against t, and the wall
//! time of the run (one run each, on a shared machine: ±20 %; no ratio is quoted from them).
//! Then the must-hold of bounded energy: Gauss 2's error over 10⁷ steps against its error over
//! the first 10⁵, and Dormand–Prince's at equal work, on P1 and the robot. Last, the stiff
//! disk (a torsional spring and damper with modes e^(−t) and e^(−10⁶t), closed form in
//! `tests/validation/tests/common/disk_closed_forms.rs`) to T = 10: Dormand–Prince at rtol =
//! atol = 10⁻⁸ against Radau5 at the loosest tolerance that is as accurate.
//!
//! # Figures of record
//!
//! Measured with `cargo bench -p hamel-benches --bench long_runs` (release, one core of the
//! shared two-core machine; the wall times re-measured after the explicit methods began to
//! read the slope just computed one component at a time, every other figure the same):
//!
//! P1, contact oscillator, T = 10011
//!
//! | method | steps | evaluations | max abs(H − H₀) | drift slope (1/s) | wall (s) | |
//! |---|---:|---:|---:|---:|---:|---|
//! | Gauss 2, h = 0.1569 | 63800 | 951084 | 5.16e-6 | +1.12e-11 | 0.13 | max abs ΔH_y 3.4e-14, max abs Δ(H − H_y) 5.2e-6 |
//! | midpoint, h = 0.0908 | 110374 | 916702 | 8.20e-4 | -1.04e-9 | 0.12 | max abs ΔH_y 2.4e-14, max abs Δ(H − H_y) 8.2e-4 |
//! | RK4, h = 0.0421 | 237974 | 951896 | 3.59e-5 | -3.58e-9 | 0.01 | max abs ΔH_y 9.2e-6, max abs Δ(H − H_y) 2.7e-5 |
//! | DP5, h = 0.0632 | 158514 | 951085 | 9.09e-6 | -9.08e-10 | 0.02 | max abs ΔH_y 2.8e-6, max abs Δ(H − H_y) 6.3e-6 |
//!
//! P2, vertical disk, T = 10000
//!
//! | method | steps | evaluations | max abs(H − H₀) | drift slope (1/s) | wall (s) | |
//! |---|---:|---:|---:|---:|---:|---|
//! | Gauss 2, h = 0.0500 | 200000 | 800002 | 0.00e0 | +0.00e0 | 0.23 | max position error 2.3e-8 m |
//! | midpoint, h = 0.0250 | 400000 | 800001 | 0.00e0 | +0.00e0 | 0.16 | max position error 7.5e-5 m |
//! | RK4, h = 0.0500 | 201000 | 804000 | 0.00e0 | +0.00e0 | 0.01 | max position error 4.5e-8 m |
//! | DP5, h = 0.0750 | 133334 | 800005 | 0.00e0 | +0.00e0 | 0.02 | max position error 1.5e-8 m |
//!
//! P3, force-free robot, T = 100000
//!
//! | method | steps | evaluations | max abs(H − H₀) | drift slope (1/s) | wall (s) | |
//! |---|---:|---:|---:|---:|---:|---|
//! | Gauss 2, h = 0.0100 | 10000000 | 82656280 | 3.12e-9 | -1.74e-15 | 31.45 |  |
//! | midpoint, h = 0.0063 | 15870000 | 75786340 | 4.44e-6 | -4.53e-14 | 19.32 |  |
//! | RK4, h = 0.0048 | 20670000 | 82680000 | 1.07e-4 | -1.07e-9 | 2.87 |  |
//! | DP5, h = 0.0073 | 13776047 | 82656283 | 3.21e-5 | -3.21e-10 | 3.11 |  |
//! | DP5, adaptive, rtol = atol = 1e-9 | 8248942 | 49493654 | 6.74e-4 | -6.74e-9 | 2.31 |  |
//!
//! P3, Chaplygin sleigh, T = 10000
//!
//! | method | steps | evaluations | max abs(H − H₀) | drift slope (1/s) | wall (s) | |
//! |---|---:|---:|---:|---:|---:|---|
//! | Gauss 2, h = 0.0500 | 200000 | 403014 | 3.57e-14 | +4.09e-20 | 0.31 |  |
//! | midpoint, h = 0.0549 | 182000 | 184327 | 2.26e-14 | -2.30e-20 | 0.09 |  |
//! | RK4, h = 0.0993 | 101000 | 404000 | 3.39e-8 | -2.03e-14 | 0.11 |  |
//! | DP5, h = 0.1489 | 67169 | 403015 | 1.15e-7 | -6.86e-14 | 0.19 |  |
//!
//! Bounded energy: max abs(H − H₀) after 10⁵ and 10⁷ steps of Gauss 2, and DP5 at equal work
//!
//! | problem | method | after 10⁵ steps | after 10⁷ steps | ratio | drift slope (1/s) | wall (s) |
//! |---|---|---:|---:|---:|---:|---:|
//! | P1 | Gauss 2 | 5.09e-6 | 5.19e-6 | 1.02 | +1.96e-15 | 19.0 |
//! | P1 | DP5 | 1.42e-5 | 1.43e-3 | 100.01 | -9.08e-10 | 2.6 |
//! | P1 | slope ratio abs(Gauss 2 / DP5) | | | 2.2e-6 | | |
//! | robot | Gauss 2 | 2.95e-9 | 3.12e-9 | 1.06 | -1.74e-15 | 31.3 |
//! | robot | DP5 | 3.21e-7 | 3.21e-5 | 100.00 | -3.21e-10 | 3.1 |
//! | robot | slope ratio abs(Gauss 2 / DP5) | | | 5.4e-6 | | |
//!
//! Stiff disk (k = 10⁶, c = 10⁶ + 1), T = 10: max state error at 100 samples (Radau5's real and
//! complex LU of a step counted apart, as scipy counts them: twice the figures recorded before
//! that convention, for the same runs)
//!
//! | method | steps | rejected | evaluations | Jacobians | LU factorizations | max error | wall (s) |
//! |---|---:|---:|---:|---:|---:|---:|---:|
//! | DP5, rtol = atol = 1e-8 | 3024314 | 5 | 18145916 | 0 | 0 | 1.39e-8 | 0.53 |
//! | Radau5, rtol = atol = 1e-6 | 31 | 2 | 172 | 7 | 54 | 4.92e-5 | 0.00 |
//! | Radau5, rtol = atol = 1e-7 | 40 | 2 | 229 | 11 | 66 | 1.34e-5 | 0.00 |
//! | Radau5, rtol = atol = 1e-8 | 54 | 2 | 309 | 17 | 82 | 2.89e-6 | 0.00 |
//! | Radau5, rtol = atol = 1e-9 | 75 | 2 | 438 | 25 | 100 | 4.89e-7 | 0.00 |
//! | Radau5, rtol = atol = 1e-10 | 107 | 2 | 641 | 30 | 112 | 9.20e-8 | 0.00 |
//! | Radau5, rtol = atol = 1e-11 | 152 | 2 | 923 | 31 | 120 | 1.29e-8 | 0.00 |
//!
//! Radau5 at 1e-11 is as accurate as DP5 with 19660× fewer right-hand-side evaluations (and 31 Jacobians, each at most 6 passes of dual numbers through the right-hand side)
//!
//! (The Radau5 rows re-measured after it came to keep its step, and so its LUs, also where its
//! controller would shrink the step; the code just before gave 108 LUs and 4.86e-7 at 1e-9,
//! 634 evaluations, 126 LUs and 6.71e-8 at 1e-10, 911, 136 and 1.61e-8 at 1e-11, and the rows
//! at 1e-6…1e-8 as now. DP5's row is the earlier run's: the same counts today, its wall time
//! 1.16 s at load average 5.)
//!
//! Gauss 2 pays for its bounded energy error in time: at equal evaluations its runs above
//! take several times Dormand–Prince's wall time on these small systems (a Newton iteration
//! solves a 2n × 2n linear system besides its two evaluations; single runs, not interleaved,
//! so no ratio is claimed).

#[allow(dead_code)]
#[path = "../tests/validation/tests/common/disk_closed_forms.rs"]
mod disk_closed_forms;

use std::time::Instant;

use disk_closed_forms::{FreeDisk, StiffDisk, StiffMotion};
use hamel::models::{ChaplyginSleigh, ContactOscillator, MobileRobot, VerticalDisk};
use hamel::{
    DormandPrince, Error, GaussLegendre, HamelSystem, ImplicitMidpoint, Integrator, Ode, Radau5,
    Rk4, Simulation, Stats, Trajectory, Vector,
};

/// The step limit of every run: the long ones take more than the default 10⁷.
const LIMIT: usize = 1_000_000_000;

/// The spans are divided by this (`--quick`: 100).
fn shortening() -> f64 {
    if std::env::args().any(|a| a == "--quick") {
        100.0
    } else {
        1.0
    }
}

/// A run and its wall time.
fn timed<S: HamelSystem, I: Integrator>(
    sim: &Simulation<'_, S>,
    integrator: &I,
    u: S::Inputs,
) -> (Trajectory, f64) {
    let start = Instant::now();
    let run = sim.run_constant(integrator, u).expect("the run");
    (run, start.elapsed().as_secs_f64())
}

/// max |H − H₀| over the samples up to `until`, and the least-squares slope of H − H₀
/// against t over them.
fn energy_figures(run: &Trajectory, until: f64) -> (f64, f64) {
    let (t, e) = (run.times(), run.column("energy").unwrap());
    let n = t.iter().take_while(|&&s| s <= until).count();
    let errors: Vec<f64> = e[..n].iter().map(|v| v - e[0]).collect();
    let max = errors.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let (mt, me) = (
        t[..n].iter().sum::<f64>() / n as f64,
        errors.iter().sum::<f64>() / n as f64,
    );
    let sxy: f64 = t[..n]
        .iter()
        .zip(&errors)
        .map(|(a, b)| (a - mt) * (b - me))
        .sum();
    let sxx: f64 = t[..n].iter().map(|a| (a - mt).powi(2)).sum();
    (max, sxy / sxx)
}

/// One line of a table.
struct Line {
    method: String,
    run: Trajectory,
    wall: f64,
    /// The problem's own figure (position error, invariants), if any.
    extra: String,
}

fn print_table(problem: &str, lines: &[Line]) {
    println!("\n{problem}\n");
    println!("| method | steps | evaluations | max abs(H − H₀) | drift slope (1/s) | wall (s) | |");
    println!("|---|---:|---:|---:|---:|---:|---|");
    for line in lines {
        let s = line.run.summary();
        let (max, slope) = energy_figures(&line.run, f64::INFINITY);
        println!(
            "| {} | {} | {} | {max:.2e} | {slope:+.2e} | {:.2} | {} |",
            line.method, s.steps, s.evaluations, line.wall, line.extra
        );
    }
}

/// Gauss 2 at step h, then the midpoint rule, RK4 and DP5 with as many evaluations; each
/// line with the problem's own figure from `extra`.
fn equal_work<S: HamelSystem>(
    (sys, x0): (&S, S::State),
    sim: &Simulation<'_, S>,
    u: S::Inputs,
    h: f64,
    extra: &dyn Fn(&Trajectory) -> String,
) -> Vec<Line> {
    let (gauss, wall) = timed(sim, &GaussLegendre::new(2, h).with_max_steps(LIMIT), u);
    let per_step = gauss.summary().evaluations as f64 / gauss.summary().steps as f64;
    // The midpoint rule's evaluations per step, from a short calibration run.
    let calibration = Simulation::new(sys, x0)
        .end_time(2000.0 * h)
        .sample_interval(2000.0 * h)
        .watch_singular_crossings(false)
        .run_constant(&ImplicitMidpoint::new(h), u)
        .expect("the calibration run");
    let midpoint_per_step =
        calibration.summary().evaluations as f64 / calibration.summary().steps as f64;
    let mut lines = vec![Line {
        method: format!("Gauss 2, h = {h:.4}"),
        extra: extra(&gauss),
        run: gauss,
        wall,
    }];
    let h_mid = h * midpoint_per_step / per_step;
    let (run, wall) = timed(sim, &ImplicitMidpoint::new(h_mid).with_max_steps(LIMIT), u);
    lines.push(Line {
        method: format!("midpoint, h = {h_mid:.4}"),
        extra: extra(&run),
        run,
        wall,
    });
    let h_rk4 = h * 4.0 / per_step;
    let (run, wall) = timed(sim, &Rk4::new(h_rk4).with_max_steps(LIMIT), u);
    lines.push(Line {
        method: format!("RK4, h = {h_rk4:.4}"),
        extra: extra(&run),
        run,
        wall,
    });
    let h_dp = h * 6.0 / per_step;
    let (run, wall) = timed(
        sim,
        &DormandPrince::new(1e-6, 1e-6)
            .with_fixed_step(h_dp)
            .with_max_steps(LIMIT),
        u,
    );
    lines.push(Line {
        method: format!("DP5, h = {h_dp:.4}"),
        extra: extra(&run),
        run,
        wall,
    });
    lines
}

/// P1 at T = 10⁴, with its other invariants.
fn p1(short: f64) {
    let sys = ContactOscillator::default();
    let x0 = sys.start().unwrap();
    let h = 2.0 * (std::f64::consts::PI / 40.0).sin();
    let t_end = (1e4 / short / (100.0 * h)).ceil() * 100.0 * h;
    let sim = Simulation::new(&sys, x0)
        .end_time(t_end)
        .sample_interval(100.0 * h)
        .watch_singular_crossings(false);
    let invariants = |run: &Trajectory| {
        let rows: Vec<Vec<f64>> = run.rows().collect();
        let hy = |r: &Vec<f64>| ContactOscillator::y_energy(&[r[1], r[2], r[3], r[4], r[5]]);
        let energy = run.column("energy").unwrap();
        let (hy0, rest0) = (hy(&rows[0]), energy[0] - hy(&rows[0]));
        let (mut dy, mut drest) = (0.0f64, 0.0f64);
        for (r, e) in rows.iter().zip(energy) {
            dy = dy.max((hy(r) - hy0).abs());
            drest = drest.max((e - hy(r) - rest0).abs());
        }
        format!("max abs ΔH_y {dy:.1e}, max abs Δ(H − H_y) {drest:.1e}")
    };
    let lines = equal_work((&sys, x0), &sim, [], h, &invariants);
    print_table(&format!("P1, contact oscillator, T = {t_end:.0}"), &lines);
}

/// P2 at T = 10⁴, with the position error against the closed form.
fn p2(short: f64) {
    let sys = VerticalDisk::default();
    let motion = FreeDisk {
        m: sys.m,
        r: sys.r,
        start: [0.3, -0.2, 0.1, 0.4],
        roll: 2.0,
        turn: 1.5,
    };
    let x0 = sys
        .state_from_speeds(0.0, &motion.start, &[motion.roll, motion.turn])
        .unwrap();
    let t_end = 1e4 / short;
    let sim = Simulation::new(&sys, x0)
        .end_time(t_end)
        .sample_interval(10.0)
        .watch_singular_crossings(false);
    let position = |run: &Trajectory| {
        let error = run
            .rows()
            .map(|r| {
                let exact = motion.state(r[0]);
                (r[1] - exact[0]).abs().max((r[2] - exact[1]).abs())
            })
            .fold(0.0f64, f64::max);
        format!("max position error {error:.1e} m")
    };
    let lines = equal_work((&sys, x0), &sim, [], 0.05, &position);
    print_table(&format!("P2, vertical disk, T = {t_end:.0}"), &lines);
}

fn robot_start(robot: &MobileRobot) -> [f64; 8] {
    robot
        .state_from_speeds(0.0, &[0.0, 0.0, 3.0, 0.0, 0.0], &[0.5, 1.0, 0.8])
        .unwrap()
}

/// P3: the force-free robot at T = 10⁵ and the sleigh at T = 10⁴.
fn p3(short: f64) {
    let robot = MobileRobot::default();
    let t_end = 1e5 / short;
    let x0 = robot_start(&robot);
    let sim = Simulation::new(&robot, x0)
        .end_time(t_end)
        .sample_interval(10.0)
        .watch_singular_crossings(false);
    let none = |_: &Trajectory| String::new();
    let mut lines = equal_work((&robot, x0), &sim, [0.0, 0.0], 0.01, &none);
    let (run, wall) = timed(
        &sim,
        &DormandPrince::new(1e-9, 1e-9).with_max_steps(LIMIT),
        [0.0, 0.0],
    );
    lines.push(Line {
        method: "DP5, adaptive, rtol = atol = 1e-9".into(),
        run,
        wall,
        extra: String::new(),
    });
    print_table(&format!("P3, force-free robot, T = {t_end:.0}"), &lines);

    let sleigh = ChaplyginSleigh::default();
    let x0 = sleigh
        .state_from_speeds(0.0, &[0.0, 0.0, 0.3], &[0.2, 1.5])
        .unwrap();
    let t_end = 1e4 / short;
    let sim = Simulation::new(&sleigh, x0)
        .end_time(t_end)
        .sample_interval(10.0)
        .watch_singular_crossings(false);
    let lines = equal_work((&sleigh, x0), &sim, [], 0.05, &none);
    print_table(&format!("P3, Chaplygin sleigh, T = {t_end:.0}"), &lines);
}

/// Must-hold 1: Gauss 2's energy error after 10⁷ steps against after 10⁵, and DP5's at
/// equal work, on P1 and the robot.
fn bounded(short: f64) {
    println!(
        "\nBounded energy: max abs(H − H₀) after 10⁵ and 10⁷ steps of Gauss 2, and DP5 at equal work\n"
    );
    println!(
        "| problem | method | after 10⁵ steps | after 10⁷ steps | ratio | drift slope (1/s) | wall (s) |"
    );
    println!("|---|---|---:|---:|---:|---:|---:|");
    let oscillator = ContactOscillator::default();
    let h = 2.0 * (std::f64::consts::PI / 40.0).sin();
    let sim = Simulation::new(&oscillator, oscillator.start().unwrap())
        .end_time(1e7 * h / short)
        .sample_interval(1000.0 * h)
        .watch_singular_crossings(false);
    bounded_pair("P1", &sim, [], h);
    let robot = MobileRobot::default();
    let sim = Simulation::new(&robot, robot_start(&robot))
        .end_time(1e7 * 0.01 / short)
        .sample_interval(10.0)
        .watch_singular_crossings(false);
    bounded_pair("robot", &sim, [0.0, 0.0], 0.01);
}

fn bounded_pair<S: HamelSystem>(problem: &str, sim: &Simulation<'_, S>, u: S::Inputs, h: f64) {
    let (gauss, wall) = timed(sim, &GaussLegendre::new(2, h).with_max_steps(LIMIT), u);
    let per_step = gauss.summary().evaluations as f64 / gauss.summary().steps as f64;
    let (dp, dp_wall) = timed(
        sim,
        &DormandPrince::new(1e-6, 1e-6)
            .with_fixed_step(h * 6.0 / per_step)
            .with_max_steps(LIMIT),
        u,
    );
    let mut slopes = Vec::new();
    for (method, run, wall) in [("Gauss 2", &gauss, wall), ("DP5", &dp, dp_wall)] {
        // Gauss 2's step count sets the spans for both (DP5 did as much work over them).
        let (early, _) = energy_figures(run, 1e5 * h * 1.000001);
        let (all, slope) = energy_figures(run, f64::INFINITY);
        slopes.push(slope);
        println!(
            "| {problem} | {method} | {early:.2e} | {all:.2e} | {:.2} | {slope:+.2e} | {wall:.1} |",
            all / early
        );
    }
    println!(
        "| {problem} | slope ratio abs(Gauss 2 / DP5) | | | {:.1e} | | |",
        (slopes[0] / slopes[1]).abs()
    );
}

/// A model without inputs as an `Ode` with its exact Jacobian: for the stiff comparison,
/// whose figures include the Jacobians (a `Simulation`'s summary does not count them).
struct Free<'s, S>(&'s S);

impl<S: HamelSystem> Ode for Free<'_, S> {
    type State = S::State;

    fn rhs(&mut self, t: f64, x: &S::State, dx: &mut S::State) -> Result<(), Error> {
        self.0
            .rhs(t, x, &S::Inputs::zeros(), dx)
            .map_err(|s| S::singular(s, t, x))
    }

    fn jacobian(&mut self, t: f64, x: &S::State, j: &mut [f64]) -> Result<bool, Error> {
        let (jx, _) = self
            .0
            .jacobian(t, x, &S::Inputs::zeros())
            .map_err(|s| S::singular(s, t, x))?;
        j.copy_from_slice(jx.as_ref());
        Ok(true)
    }
}

/// The stiff disk's run with `integrator`: its statistics, its largest error at the samples
/// against the closed form, and its wall time.
fn stiff_run<I: Integrator>(
    integrator: &I,
    (sys, x0): (&StiffDisk, [f64; 6]),
    samples: &[f64],
    motion: &StiffMotion,
) -> (Stats, f64, f64) {
    let mut error = 0.0f64;
    let start = Instant::now();
    let stats = integrator
        .integrate(&mut Free(sys), 0.0, &x0, samples, &mut |t, x| {
            let exact = motion.state(t);
            for i in 0..6 {
                error = error.max((x[i] - exact[i]).abs());
            }
            Ok(())
        })
        .expect("the run");
    (stats, error, start.elapsed().as_secs_f64())
}

/// The stiff disk to T = 10: DP5 at 10⁻⁸ against Radau5 at the loosest tolerance that is as
/// accurate; the error is the largest over 100 samples against the closed form.
fn stiff(short: f64) {
    let sys = StiffDisk::default();
    let start = [0.0, 0.0, 0.1, 0.2];
    let (roll0, turn) = (-0.2, 1.0);
    let motion = StiffMotion::new(sys.r, start, roll0, turn, (-1.0, -1e6));
    let x0 = sys.state_from_speeds(0.0, &start, &[roll0, turn]).unwrap();
    let t_end = 10.0 / short;
    let samples: Vec<f64> = (1..=100).map(|i| t_end * i as f64 / 100.0).collect();
    println!("\nStiff disk (k = 10⁶, c = 10⁶ + 1), T = {t_end}: max state error at 100 samples\n");
    println!(
        "| method | steps | rejected | evaluations | Jacobians | LU factorizations | max error | wall (s) |"
    );
    println!("|---|---:|---:|---:|---:|---:|---:|---:|");
    let row = |label: &str, (s, e, wall): (Stats, f64, f64)| {
        println!(
            "| {label} | {} | {} | {} | {} | {} | {e:.2e} | {wall:.2} |",
            s.steps, s.rejected, s.evaluations, s.jacobians, s.factorizations
        );
    };
    let problem = (&sys, x0);
    let dp = stiff_run(&DormandPrince::new(1e-8, 1e-8), problem, &samples, &motion);
    row("DP5, rtol = atol = 1e-8", dp);
    for tol in [1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11] {
        let rd = stiff_run(&Radau5::new(tol, tol), problem, &samples, &motion);
        row(&format!("Radau5, rtol = atol = {tol:e}"), rd);
        if rd.1 <= dp.1 {
            println!(
                "\nRadau5 at {tol:e} is as accurate as DP5 with {:.0}× fewer right-hand-side \
                 evaluations (and {} Jacobians, each at most {} passes of dual numbers through \
                 the right-hand side)",
                dp.0.evaluations as f64 / rd.0.evaluations as f64,
                rd.0.jacobians,
                <StiffDisk as HamelSystem>::State::LEN
            );
            break;
        }
    }
}

fn main() {
    let short = shortening();
    p1(short);
    p2(short);
    p3(short);
    bounded(short);
    stiff(short);
}
