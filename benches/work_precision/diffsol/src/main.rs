//! diffsol's BDF and ESDIRK34 (its SDIRK) on the stiff test set of
//! `benches/work_precision.rs`: the same problems (their right-hand sides and Jacobians from
//! `tests/validation/tests/common/stiff_problems.rs`), tolerances and mixed error. One round
//! of `run.sh` on one problem: each method at each tolerance, a batch of runs of at least
//! 0.1 s (after an untimed warm-up run), one row per batch appended to OUT.csv.
//!
//! diffsol takes the Jacobian as a Jacobian–vector product: here the problem's dense Jacobian
//! times v (one Jacobian evaluation per product, a few hundred nanoseconds for these sizes).
//! Its statistics give the accepted steps, the error-test failures (the rejected column) and
//! the Jacobian/LU setups (the LU column); it counts no right-hand-side evaluations or
//! Jacobians, whose columns stay empty.
//!
//!     cargo run --release --manifest-path benches/work_precision/diffsol/Cargo.toml -- \
//!         OUT.csv ROUND PROBLEM

#[allow(dead_code)]
#[path = "../../../../tests/validation/tests/common/stiff_problems.rs"]
mod stiff_problems;

use std::fmt::Write as _;
use std::fs::OpenOptions;
use std::io::Write as _;
use std::path::Path;
use std::time::Instant;

use diffsol::ode_solver::OdeSolverStatistics;
use diffsol::{DenseMatrix, MatrixCommon, NalgebraLU, NalgebraMat, OdeBuilder, OdeSolverMethod};

/// The last column of a solution matrix.
fn last_column(ys: &NalgebraMat<f64>) -> Vec<f64> {
    let last = ys.ncols() - 1;
    (0..ys.nrows()).map(|i| ys.get_index(i, last)).collect()
}
use stiff_problems::{
    Hires, Oregonator, Pollution, Robertson, StiffProblem, VanDerPol, mixed_error,
};

const TOLERANCES: [f64; 8] = [1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10];

fn to_state<P: StiffProblem>(x: &[f64]) -> P::State {
    let mut s = <P::State as hamel::Vector>::zeros();
    s.as_mut().copy_from_slice(x);
    s
}

/// A diffsol vector's components.
fn components(x: &(impl std::ops::Index<usize, Output = f64> + ?Sized), n: usize) -> Vec<f64> {
    (0..n).map(|i| x[i]).collect()
}

/// One run of `method` ("bdf" or "esdirk34") on `P`: the end state and the solver's
/// statistics, or None if it failed.
fn run<P: StiffProblem>(method: &str, rtol: f64) -> Option<(Vec<f64>, OdeSolverStatistics)> {
    let n = <P::State as hamel::Vector>::LEN;
    let problem = OdeBuilder::<NalgebraMat<f64>>::new()
        .rtol(rtol)
        .atol(vec![rtol * P::ATOL_RATIO; n])
        .rhs_implicit(
            move |x, _p, t, y| {
                let mut f = <P::State as hamel::Vector>::zeros();
                P::default()
                    .rhs(t, &to_state::<P>(&components(x, n)), &mut f)
                    .unwrap();
                for (i, v) in f.as_ref().iter().enumerate() {
                    y[i] = *v;
                }
            },
            move |x, _p, t, v, y| {
                let mut j = vec![0.0; n * n];
                P::default()
                    .jacobian(t, &to_state::<P>(&components(x, n)), &mut j)
                    .unwrap();
                for r in 0..n {
                    y[r] = (0..n).map(|c| j[r * n + c] * v[c]).sum();
                }
            },
        )
        .init(
            move |_p, _t, y| {
                for (i, v) in P::start().as_ref().iter().enumerate() {
                    y[i] = *v;
                }
            },
            n,
        )
        .build()
        .ok()?;
    Some(match method {
        "bdf" => {
            let mut solver = problem.bdf::<NalgebraLU<f64>>().ok()?;
            let (ys, _, _) = solver.solve(P::T_END).ok()?;
            (last_column(&ys), solver.get_statistics().clone())
        }
        _ => {
            let mut solver = problem.esdirk34::<NalgebraLU<f64>>().ok()?;
            let (ys, _, _) = solver.solve(P::T_END).ok()?;
            (last_column(&ys), solver.get_statistics().clone())
        }
    })
}

/// The least time a batch of runs takes, as in `benches/work_precision.rs` (see there).
const BATCH_SECONDS: f64 = 0.1;

/// `f`'s last result and its mean wall time over a batch of at least [`BATCH_SECONDS`].
fn batch<T>(mut f: impl FnMut() -> T) -> (T, f64) {
    let start = Instant::now();
    let mut runs = 0;
    loop {
        let result = f();
        runs += 1;
        let elapsed = start.elapsed().as_secs_f64();
        if elapsed >= BATCH_SECONDS {
            return (result, elapsed / runs as f64);
        }
    }
}

/// One round on `P`: the CSV rows of each method at each tolerance.
fn rows<P: StiffProblem>(round: usize) -> String {
    run::<P>("bdf", TOLERANCES[0]);
    let mut out = String::new();
    for (method, label) in [("bdf", "diffsol BDF"), ("esdirk34", "diffsol ESDIRK34")] {
        for rtol in TOLERANCES {
            let (end, wall) = batch(|| run::<P>(method, rtol));
            let Some((end, stats)) = end else {
                eprintln!("{} {label} {rtol:e}: failed", P::NAME);
                continue;
            };
            let error = mixed_error::<P>(&to_state::<P>(&end));
            let _ = writeln!(
                out,
                "{round},{},{label},{rtol:e},{error:e},{},{},,,{},{wall:e}",
                P::NAME,
                stats.number_of_steps,
                stats.number_of_error_test_failures,
                stats.number_of_linear_solver_setups,
            );
        }
    }
    out
}

/// One round on a problem: its CSV rows.
type Round = fn(usize) -> String;

/// The problems by name, each with its round.
const PROBLEMS: [(&str, Round); 5] = [
    (Robertson::NAME, rows::<Robertson>),
    (VanDerPol::NAME, rows::<VanDerPol>),
    (Hires::NAME, rows::<Hires>),
    (Oregonator::NAME, rows::<Oregonator>),
    (Pollution::NAME, rows::<Pollution>),
];

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let found = match &args[..] {
        [path, round, problem] => round
            .parse::<usize>()
            .ok()
            .zip(PROBLEMS.iter().find(|(name, _)| name == problem))
            .map(|(round, (_, rows))| (path, round, rows)),
        _ => None,
    };
    let Some((path, round, rows)) = found else {
        let names: Vec<&str> = PROBLEMS.iter().map(|(name, _)| *name).collect();
        eprintln!("usage: work-precision-diffsol OUT.csv ROUND PROBLEM, PROBLEM one of {names:?}");
        std::process::exit(2);
    };
    let mut text = String::new();
    if !Path::new(path).exists() {
        text += "round,problem,solver,rtol,error,steps,rejected,evaluations,jacobians,factorizations,wall\n";
    }
    text += &rows(round);
    OpenOptions::new()
        .create(true)
        .append(true)
        .open(path)
        .and_then(|mut file| file.write_all(text.as_bytes()))
        .expect("append to the CSV");
}
