//! Whole runs of the catalogue's models and of two hand-written toy ODEs, one workload per
//! process, for timing two builds of the runtime against each other as whole processes
//! (alternating the two builds' processes, pair by pair: a change to the integrators or the
//! simulation driver touches every model, and a figure measured on one model says little
//! about the others). Prints a checksum of the results, so that the two builds can be seen
//! to compute the same bits.
//!
//! ```text
//! cargo bench -p hamel-benches --bench workloads --no-run    # prints the binary's path
//! target/release/deps/workloads-* <workload> <integrator> <runs>
//! ```
//!
//! The workloads: `robot`, `sleigh`, `contact` (the contact oscillator), `vertical-disk`,
//! `knife-edge`, `chaplygin-ball` and `trailer8`, each a `Simulation` with its default
//! monitors (samples every 0.01 s, over 10 or 20 s) and no inputs; `oscillator` (ẋ = y,
//! ẏ = −x, 100 s, samples every 0.1 s) and `lorenz` (20 s, samples every 0.01 s), hand-written
//! `Ode`s small enough to be inlined into the integrator. The integrators: `dp`
//! (`DormandPrince`, rtol 1e-9, atol 1e-12) and `rk4` (`Rk4`, step 0.005; 0.01 and 0.001 for
//! the toys).
//!
//! Whole-process figures for the change that reads the slope just computed one component at
//! a time (`fresh_component` in `hamel-runtime/src/integrate/mod.rs`): this file built against
//! the runtime with that change and at the commit before it (b11e5e0), the two processes
//! alternating, 9 pairs
//! each, runs chosen so that a process takes about 0.4 s; the median of the per-pair ratios
//! after/before, the same bits printed by both:
//!
//! ```text
//!       robot sleigh contact vertical-disk knife-edge chaplygin-ball trailer8 oscillator lorenz
//! dp    0.86  0.95   0.94    0.87          0.98       0.99           0.98     1.03       1.06
//! rk4   0.78  0.79   0.84    0.59          0.96       0.98           0.95     1.44       1.24
//! ```
//!
//! The models' right-hand sides (sines, a factorization) are called out of line and store
//! their results to memory, from where the slope is read; a toy's is inlined, its slopes need
//! never leave the registers, and the reads one component at a time force them through
//! memory: a few cycles more per stage, which only a right-hand side of a few operations
//! notices.

use std::hint::black_box;
use std::process::ExitCode;

use hamel::models::{
    ChaplyginBall, ChaplyginSleigh, ContactOscillator, KnifeEdge, MobileRobot, NTrailer8,
    VerticalDisk,
};
use hamel::{DormandPrince, Error, Grid, HamelSystem, Integrator, Ode, Rk4, Simulation, Vector};

const USAGE: &str = "usage: workloads <robot|sleigh|contact|vertical-disk|knife-edge|\
                     chaplygin-ball|trailer8|oscillator|lorenz> <dp|rk4> <runs>";

/// A simulation of `system` from `x0` to `end` with its default monitors: the number of
/// samples plus the largest energy drift, as a checksum.
fn simulate<S: HamelSystem, I: Integrator>(
    system: &S,
    x0: Result<S::State, Error>,
    end: f64,
    integrator: &I,
) -> Result<f64, Error> {
    let run = Simulation::new(system, x0?)
        .end_time(end)
        .run_constant(integrator, S::Inputs::zeros())?;
    Ok(run.len() as f64 + run.summary().max_energy_drift)
}

/// ẋ = y, ẏ = −x.
struct Oscillator;

impl Ode for Oscillator {
    type State = [f64; 2];

    fn rhs(&mut self, _t: f64, x: &[f64; 2], dx: &mut [f64; 2]) -> Result<(), Error> {
        *dx = [x[1], -x[0]];
        Ok(())
    }
}

/// Lorenz's system with σ = 10, ρ = 28, β = 8/3.
struct Lorenz;

impl Ode for Lorenz {
    type State = [f64; 3];

    fn rhs(&mut self, _t: f64, x: &[f64; 3], dx: &mut [f64; 3]) -> Result<(), Error> {
        *dx = [
            10.0 * (x[1] - x[0]),
            x[0] * (28.0 - x[2]) - x[1],
            x[0] * x[1] - 8.0 / 3.0 * x[2],
        ];
        Ok(())
    }
}

/// A toy ODE over a grid: the last sample's first component, as a checksum.
fn toy<O: Ode, I: Integrator>(
    ode: &mut O,
    x0: &O::State,
    grid: &Grid,
    integrator: &I,
) -> Result<f64, Error> {
    let mut last = 0.0;
    integrator.integrate(ode, 0.0, x0, grid, &mut |_, x| {
        last = x.as_ref()[0];
        Ok(())
    })?;
    Ok(last)
}

/// One run of `workload`; `None` for a workload that does not exist.
fn run<I: Integrator>(workload: &str, integrator: &I, toy_step: &I) -> Option<Result<f64, Error>> {
    let i = integrator;
    Some(match workload {
        "robot" => {
            let m = MobileRobot::default();
            let x0 = m.state_from_speeds(0.0, &[0.0, 0.0, 0.3, 0.0, 0.0], &[0.0, 0.5, 0.4]);
            simulate(&m, x0, 10.0, i)
        }
        "sleigh" => {
            let m = ChaplyginSleigh::default();
            let x0 = m.state_from_speeds(0.0, &[0.0, 0.0, 0.1], &[1.0, 0.5]);
            simulate(&m, x0, 20.0, i)
        }
        "contact" => {
            let m = ContactOscillator::default();
            simulate(&m, m.start(), 20.0, i)
        }
        "vertical-disk" => {
            let m = VerticalDisk::default();
            let x0 = m.state_from_speeds(0.0, &[0.0; 4], &[2.0, 1.5]);
            simulate(&m, x0, 20.0, i)
        }
        "knife-edge" => {
            let m = KnifeEdge::default();
            let x0 = m.state_from_speeds(0.0, &[0.0; 3], &[1.0, 0.5]);
            simulate(&m, x0, 20.0, i)
        }
        "chaplygin-ball" => {
            let m = ChaplyginBall::default();
            let x0 = m.state_from_speeds(0.0, &[0.0, 0.0, 0.0, 0.5, 0.0], &[1.0, 0.5, 0.3]);
            simulate(&m, x0, 10.0, i)
        }
        "trailer8" => {
            let m = NTrailer8::default();
            let x0 = m.state_from_speeds(0.0, &[0.0; 11], &[1.0, 0.2]);
            simulate(&m, x0, 10.0, i)
        }
        "oscillator" => toy(
            &mut Oscillator,
            &[1.0, 0.0],
            &Grid::new(0.0, 100.0, 0.1),
            toy_step,
        ),
        "lorenz" => toy(
            &mut Lorenz,
            &[1.0, 1.0, 1.0],
            &Grid::new(0.0, 20.0, 0.01),
            toy_step,
        ),
        _ => return None,
    })
}

fn main() -> ExitCode {
    // `cargo bench` passes `--bench`; with no workload named this bench only says how to run
    // it, so that `cargo bench -p hamel-benches` runs through.
    let args: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with("--"))
        .collect();
    if args.is_empty() {
        println!("{USAGE}");
        return ExitCode::SUCCESS;
    }
    let (Some(workload), Some(integrator), Some(Ok(runs))) = (
        args.first(),
        args.get(1),
        args.get(2).map(|n| n.parse::<usize>()),
    ) else {
        eprintln!("{USAGE}");
        return ExitCode::FAILURE;
    };
    let mut checksum = 0.0;
    for _ in 0..runs {
        let result = match integrator.as_str() {
            "dp" => run(
                workload,
                &DormandPrince::new(1e-9, 1e-12),
                &DormandPrince::new(1e-9, 1e-12),
            ),
            "rk4" => {
                let toy_step = if workload == "oscillator" {
                    0.01
                } else {
                    0.001
                };
                run(workload, &Rk4::new(0.005), &Rk4::new(toy_step))
            }
            _ => {
                eprintln!("{USAGE}");
                return ExitCode::FAILURE;
            }
        };
        match result {
            Some(Ok(value)) => checksum += black_box(value),
            Some(Err(e)) => {
                eprintln!("{workload}: {e}");
                return ExitCode::FAILURE;
            }
            None => {
                eprintln!("{USAGE}");
                return ExitCode::FAILURE;
            }
        }
    }
    println!("{checksum:e}");
    ExitCode::SUCCESS
}
