//! The figures of record for a whole run: the paper's robot over 10 s (rtol 1e-9, atol
//! 1e-12, samples every 0.01 s, the README's initial state, no torques), integrated by
//! `ode_solvers` 0.6's `Dopri5` (the yardstick), by hamel's `DormandPrince` alone and by a
//! `Simulation` with its default monitors, all three on the same generated right-hand side
//! (`MobileRobot::rhs_prepared`, its parameter-only values prepared once per run).
//!
//! ```text
//! cargo bench -p hamel-benches --bench run                       # 201 rounds
//! HAMEL_BENCH_ROUNDS=21 cargo bench -p hamel-benches --bench run # a quick look
//! cargo bench -p hamel-benches --bench run -- profile simulation 200
//! ```
//!
//! Measured interleaved (`hamel_benches::interleave`): one batch (about 10 ms) of each
//! variant per round,
//! round-robin, and each figure the median over the rounds of the per-round ratio to
//! `ode_solvers`, p10–p90 beside it. The startup checks that the three take the same steps
//! (accepted, rejected, evaluations) and end in the same state to 1e-9 (relative to max(1, |x|)).
//!
//! `profile <variant> <runs>` runs one variant alone, for a profiler
//! (`valgrind --tool=callgrind target/release/deps/run-* profile simulation 200`); the
//! variants are `ode_solvers`, `dormand-prince`, `simulation`, `simulation-progress` (with a
//! progress callback that never cancels), `simulation-bare` (no
//! singular-crossing watch).
//!
//! Figures of record (201 rounds on the shared 2-core machine at a quiet moment, load
//! average about 0.7; per-round ratio to `ode_solvers`, median and p10–p90; ms a run of
//! `ode_solvers` about 0.41):
//!
//! ```text
//!                                 20a32f0               b11e5e0               i19b
//! DormandPrince alone             1.222 (1.201–1.242)   1.040 (1.024–1.064)   0.869 (0.843–0.887)
//! Simulation, default monitors    2.292 (2.246–2.337)   1.250 (1.222–1.281)   1.049 (1.016–1.075)
//! Simulation, no crossing watch   1.833 (1.795–1.870)   1.245 (1.221–1.275)   1.046 (1.019–1.066)
//! ```
//!
//! At 7df9148 (the robot stated from its wheels; 201 rounds, load average 1.2–1.3, ms a run of
//! `ode_solvers` about 0.67): DormandPrince alone 0.976 (0.920–1.020), Simulation with default
//! monitors 1.240 (1.171–1.338), no crossing watch 1.234 (1.162–1.344).
//! Instructions a run at 7df9148: ode_solvers 5.59 M, DormandPrince 5.31 M, Simulation 7.08 M
//! (within 1–3 % of i19b's, so the time ratio's move from 1.049 is not more work per run).
//!
//! On 2026-11-29 (constant inputs checked once, no work integral when the inputs are zero,
//! the progress clock read about once a millisecond; three runs of 401 rounds, load average
//! 2.8–2.9 falling, no other build running, ms a run of `ode_solvers` about 0.57):
//! DormandPrince alone 0.856, 0.856, 0.853; Simulation with default monitors 1.030, 1.014,
//! 1.073; no crossing watch 1.019, 1.005, 1.063; with a progress callback 1.043, 1.034, 1.091.
//! Again at 13:42 (load average 0.6–1.0, ms a run of `ode_solvers` 0.57–0.70): DormandPrince
//! alone 0.955, 0.921, 0.855; Simulation with default monitors 1.175, 1.155, 1.018.
//! Instructions a run: ode_solvers 5.59 M, DormandPrince 5.33 M, Simulation 6.58 M, with a
//! progress callback 6.78 M.
//! At 15:28 (no continuous extension formed for a progress callback alone, its not-due check
//! inlined; load average 1.1–1.4, no other build, ms a run of ode_solvers 0.57): DormandPrince
//! alone 0.846, 0.852, 0.855; Simulation with default monitors 1.000, 1.008, 1.010; no crossing
//! watch 0.993, 1.000, 1.002; with a progress callback 1.010, 1.017, 1.018. A progress
//! callback's instructions a run (`profile simulation-progress 20` less `profile simulation
//! 20`, over 20): 0.12 M, against 0.20 M before.
//! At a9b5dfd (23:35 UTC; three runs of 401 rounds, load average 1.2–1.6 with one other
//! compiler running, ms a run of ode_solvers 0.57): DormandPrince alone 0.762, 0.764, 0.764
//! (p10–p90 within 0.730–0.889); Simulation with default monitors 0.906, 0.911, 0.911; no
//! crossing watch 0.898, 0.900, 0.903; with a progress callback 0.911, 0.915, 0.917 (at
//! 21:11, on f1e11a7, DormandPrince alone 0.838, 0.835, 0.838 and Simulation 0.975, 0.970,
//! 0.975). Again at 23:43 (load average 1.1–1.4): 0.764, 0.768, 0.766 and 0.911, 0.925,
//! 0.915; f1e11a7's runtime right after, one run: 0.842 and 0.977. Instructions a run: ode_solvers 5.59 M, DormandPrince 4.99 M (5.34 M on f1e11a7),
//! Simulation 6.21 M (6.56 M), with a progress callback 6.32 M. What changed: the step-size
//! controller, on whose result the next step waits, computed in logarithms (one logarithm of
//! the squared error and one exponential, where Hairer's form took a square root, two powers
//! and three divisions: −0.18 M instructions and most of the time); the error norm's weights
//! h/scᵢ formed before the last stage and summed in two lanes; a sample inside a step read
//! from the extension's coefficients as they are computed rather than from a formed
//! extension (the same bits); the accepted state written in place rather than returned; the
//! finiteness check of each accepted state without a branch a component. The step sizes
//! differ from Hairer's form in the last bits (the robot's 1001 rows by at most 3.3e-13,
//! relative to max(1, |x|)); the steps, rejections and evaluations are the same (1316, 44,
//! 8162) and the robot example's printed summary is unchanged.
//!
//! (Each column is this file built against the runtime at that commit: 20a32f0 before issue
//! 19, b11e5e0 its first lean path, i19b the branch that reads fresh slopes component by
//! component; the last two were measured one after the other.) Instructions a run
//! (callgrind, `profile <variant> 20` less `profile <variant> 0`, over 20): ode_solvers
//! 5.51 M; DormandPrince 8.70 M at 20a32f0, 5.20 M at b11e5e0, 5.25 M now; Simulation
//! 15.5 M, 7.02 M, 6.93 M.
//!
//! Where the time went: b11e5e0 already matched ode_solvers in instructions and was 4 %
//! slower. The robot's right-hand side stores its eight derivatives one at a time or in
//! pairs that straddle the integrator's (in this build dx₀₁, dx₂, dx₃₄, dx₅, dx₆, dx₇), and
//! the stage combinations loaded the slope just computed two components at a time: a load
//! spanning two stores still on their way to the cache cannot be forwarded from them and
//! waits for them, on the critical path of every stage (each stage needs the last one's
//! slope). The integrator now reads that slope one component at a time (`fresh_component`
//! in `hamel-runtime/src/integrate/mod.rs`): a few more instructions, 16 % less time.
//! ode_solvers loads the same way and keeps the wait. The Simulation's `BalanceOde` copied
//! the derivative out of a local the same way; it now has the right-hand side write in
//! place. Its remaining time over DormandPrince alone: the monitors at the 1001 samples
//! (energy, q̇ and the constraint rows: four sine-cosine pairs a sample, three of them of
//! the yaw angle; about a tenth of the run, as a build whose recorder leaves them out
//! shows), the work integral (a ninth component, the power at every stage fused with the
//! right-hand side) and the recording.

use hamel::models::MobileRobot;
use hamel::{DormandPrince, Error, Grid, HamelSystem, Integrator, Ode, Simulation};
use hamel_benches::interleave::{ratio, round_robin_batches, seconds};
use ode_solvers::{SVector, System};
use std::hint::black_box;

/// The run's settings, as issue 19 measured them.
const T_END: f64 = 10.0;
const DT_OUT: f64 = 0.01;
const RTOL: f64 = 1e-9;
const ATOL: f64 = 1e-12;

/// Seconds a batch takes, about: tens of runs, so that one interruption of the shared
/// machine spoils no round.
const BATCH_SECONDS: f64 = 0.01;

/// The README's initial state: tilted by 0.3 rad, rolling at 0.5 m/s, turning at 0.4 rad/s.
fn initial_state(robot: &MobileRobot) -> [f64; 8] {
    robot
        .state_from_speeds(0.0, &[0.0, 0.0, 0.3, 0.0, 0.0], &[0.0, 0.5, 0.4])
        .expect("the README's state is regular")
}

/// The generated right-hand side with constant (zero) torques, prepared once: what both
/// integrators drive.
struct RobotOde<'a> {
    robot: &'a MobileRobot,
    prepared: Vec<f64>,
}

impl<'a> RobotOde<'a> {
    fn new(robot: &'a MobileRobot) -> Self {
        let mut prepared = vec![0.0; MobileRobot::PREPARED_LEN];
        robot.prepare(&mut prepared);
        RobotOde { robot, prepared }
    }

    fn eval(&self, t: f64, x: &[f64; 8], dx: &mut [f64; 8]) -> bool {
        self.robot
            .rhs_prepared(&self.prepared, t, x, &[0.0, 0.0], dx)
            .is_ok()
    }
}

impl System<f64, SVector<f64, 8>> for RobotOde<'_> {
    fn system(&self, t: f64, y: &SVector<f64, 8>, dy: &mut SVector<f64, 8>) {
        // The storage of an SVector is its array: no copy either way.
        let ok = self.eval(t, &y.data.0[0], &mut dy.data.0[0]);
        debug_assert!(ok);
    }
}

impl Ode for RobotOde<'_> {
    type State = [f64; 8];

    fn rhs(&mut self, t: f64, x: &[f64; 8], dx: &mut [f64; 8]) -> Result<(), Error> {
        if self.eval(t, x, dx) {
            Ok(())
        } else {
            Err(Error::NonFiniteState {
                t,
                state: MobileRobot::named_state(x),
            })
        }
    }
}

/// One whole run of each variant: its cost (steps, rejected, evaluations) and final state.
type Outcome = ((usize, usize, usize), [f64; 8]);

fn run_ode_solvers(robot: &MobileRobot, x0: &[f64; 8]) -> Outcome {
    let ode = RobotOde::new(robot);
    let mut stepper =
        ode_solvers::Dopri5::new(ode, 0.0, T_END, DT_OUT, SVector::from(*x0), RTOL, ATOL);
    let stats = stepper
        .integrate()
        .expect("ode_solvers integrates the robot");
    let last = stepper.y_out().last().expect("samples").data.0[0];
    (
        (
            stats.accepted_steps as usize,
            stats.rejected_steps as usize,
            stats.num_eval as usize,
        ),
        last,
    )
}

fn run_dormand_prince(robot: &MobileRobot, x0: &[f64; 8]) -> Outcome {
    let mut ode = RobotOde::new(robot);
    let grid = Grid::new(0.0, T_END, DT_OUT);
    // Kept as ode_solvers keeps its dense output: times and states.
    let (mut times, mut states) = (Vec::new(), Vec::new());
    let stats = DormandPrince::new(RTOL, ATOL)
        .integrate(&mut ode, 0.0, x0, &grid, &mut |t, x| {
            times.push(t);
            states.push(*x);
            Ok(())
        })
        .expect("DormandPrince integrates the robot");
    black_box(&times);
    (
        (stats.steps, stats.rejected, stats.evaluations),
        *states.last().expect("samples"),
    )
}

fn run_simulation(robot: &MobileRobot, x0: &[f64; 8], watch: bool, progress: bool) -> Outcome {
    let mut simulation = Simulation::new(robot, *x0)
        .end_time(T_END)
        .sample_interval(DT_OUT)
        .watch_singular_crossings(watch);
    if progress {
        simulation = simulation.on_progress(|p| {
            black_box(p);
            std::ops::ControlFlow::Continue(())
        });
    }
    let run = simulation
        .run_constant(&DormandPrince::new(RTOL, ATOL), [0.0, 0.0])
        .expect("the robot runs");
    let s = run.summary();
    let last = run.row(run.len() - 1).expect("samples");
    let mut x = [0.0; 8];
    x.copy_from_slice(&last[1..9]);
    ((s.steps, s.rejected, s.evaluations), x)
}

const VARIANTS: [&str; 5] = [
    "ode_solvers",
    "dormand-prince",
    "simulation",
    "simulation-bare",
    "simulation-progress",
];

fn run_variant(v: usize, robot: &MobileRobot, x0: &[f64; 8]) -> Outcome {
    match v {
        0 => run_ode_solvers(robot, x0),
        1 => run_dormand_prince(robot, x0),
        2 => run_simulation(robot, x0, true, false),
        3 => run_simulation(robot, x0, false, false),
        _ => run_simulation(robot, x0, true, true),
    }
}

/// `profile <variant> <runs>`: one variant alone, for a profiler.
fn profile(args: &[String]) {
    let v = VARIANTS
        .iter()
        .position(|n| Some(*n) == args.first().map(String::as_str))
        .unwrap_or_else(|| panic!("profile <variant> <runs>: the variants are {VARIANTS:?}"));
    let runs: usize = args
        .get(1)
        .map_or(100, |n| n.parse().expect("a number of runs"));
    let robot = MobileRobot::default();
    let x0 = initial_state(&robot);
    for _ in 0..runs {
        black_box(run_variant(v, black_box(&robot), &x0));
    }
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if let Some(i) = args.iter().position(|a| a == "profile") {
        return profile(&args[i + 1..]);
    }
    let robot = MobileRobot::default();
    let x0 = initial_state(&robot);
    let outcomes: Vec<Outcome> = (0..VARIANTS.len())
        .map(|v| run_variant(v, &robot, &x0))
        .collect();
    let (steps, rejected, evaluations) = outcomes[1].0;
    for (v, (cost, x)) in outcomes.iter().enumerate() {
        // ode_solvers evaluates f(t0, x0) twice (in its initial-step heuristic and again
        // for the first step): one evaluation more for the same steps.
        assert_eq!(
            *cost,
            (steps, rejected, evaluations + usize::from(v == 0)),
            "{} takes other steps than hamel's DormandPrince",
            VARIANTS[v]
        );
        let differs = x
            .iter()
            .zip(&outcomes[0].1)
            .map(|(a, b)| (a - b).abs() / b.abs().max(1.0))
            .fold(0.0, f64::max);
        assert!(
            differs < 1e-9,
            "{} ends {differs:e} (relative) away from ode_solvers",
            VARIANTS[v]
        );
    }
    let mut runs: Vec<Box<dyn FnMut()>> = (0..VARIANTS.len())
        .map(|v| {
            let (robot, x0) = (&robot, &x0);
            Box::new(move || {
                black_box(run_variant(v, black_box(robot), x0));
            }) as Box<dyn FnMut()>
        })
        .collect();
    let mut refs: Vec<&mut dyn FnMut()> = runs.iter_mut().map(|f| &mut **f as _).collect();
    let rounds = round_robin_batches(&mut refs, BATCH_SECONDS);
    println!(
        "Robot, whole run: 10 s, rtol {RTOL:e}, atol {ATOL:e}, samples every {DT_OUT} s; \
         {steps} steps, {rejected} rejected, {evaluations} evaluations in every variant \
         (ode_solvers: one more)"
    );
    println!(
        "{} rounds (hamel_benches::interleave), per-round ratio to ode_solvers",
        rounds.len()
    );
    println!(
        "  {:<44} {:>7} {:>13} {:>9} {:>15}",
        "variant", "ratio", "p10–p90", "ms/run", "ms p10–p90"
    );
    let names = [
        "ode_solvers 0.6 Dopri5 (yardstick)",
        "DormandPrince alone",
        "Simulation, default monitors",
        "Simulation, no singular-crossing watch",
        "Simulation, with a progress callback",
    ];
    for (v, name) in names.iter().enumerate() {
        let r = ratio(&rounds, v, 0);
        let t = seconds(&rounds, v).scaled(1e3);
        println!(
            "  {name:<44} {:>7.3} {:>13} {:>9.3} {:>15}",
            r.median,
            format!("{:.3}–{:.3}", r.p10, r.p90),
            t.median,
            format!("{:.3}–{:.3}", t.p10, t.p90),
        );
    }
}
