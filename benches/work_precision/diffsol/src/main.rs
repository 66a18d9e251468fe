//! diffsol's BDF and ESDIRK34 (its SDIRK) on the stiff test set of
//! `benches/work_precision.rs`: the same problems (their right-hand sides and Jacobians from
//! `tests/validation/tests/common/stiff_problems.rs`), tolerances and mixed error; wall time
//! the median of 5 runs. diffsol takes the Jacobian as a Jacobian–vector product: here the
//! problem's dense Jacobian times v (one Jacobian evaluation per product, a few hundred
//! nanoseconds for these sizes). diffsol exposes no evaluation counts through this
//! interface: the CSV's counts are empty.
//!
//!     cargo run --release --manifest-path benches/work_precision/diffsol/Cargo.toml -- OUT.csv

#[allow(dead_code)]
#[path = "../../../../tests/validation/tests/common/stiff_problems.rs"]
mod stiff_problems;

use std::fmt::Write as _;
use std::time::Instant;

use diffsol::{DenseMatrix, MatrixCommon, NalgebraLU, NalgebraMat, OdeBuilder, OdeSolverMethod};

/// The last column of a solution matrix.
fn last_column(ys: &NalgebraMat<f64>) -> Vec<f64> {
    let last = ys.ncols() - 1;
    (0..ys.nrows()).map(|i| ys.get_index(i, last)).collect()
}
use stiff_problems::{Hires, Oregonator, Pollution, Robertson, StiffProblem, VanDerPol, mixed_error};

const TOLERANCES: [f64; 7] = [1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10];

fn to_state<P: StiffProblem>(x: &[f64]) -> P::State {
    let mut s = <P::State as hamel::Vector>::zeros();
    s.as_mut().copy_from_slice(x);
    s
}

/// A diffsol vector's components.
fn components(x: &(impl std::ops::Index<usize, Output = f64> + ?Sized), n: usize) -> Vec<f64> {
    (0..n).map(|i| x[i]).collect()
}

/// One run of `method` ("bdf" or "esdirk34") on `P`: the end state, or None if it failed.
fn run<P: StiffProblem>(method: &str, rtol: f64) -> Option<Vec<f64>> {
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
    let end = match method {
        "bdf" => {
            let mut solver = problem.bdf::<NalgebraLU<f64>>().ok()?;
            let (ys, _, _) = solver.solve(P::T_END).ok()?;
            last_column(&ys)
        }
        _ => {
            let mut solver = problem.esdirk34::<NalgebraLU<f64>>().ok()?;
            let (ys, _, _) = solver.solve(P::T_END).ok()?;
            last_column(&ys)
        }
    };
    Some(end)
}

fn rows<P: StiffProblem>(out: &mut String) {
    for (method, label) in [("bdf", "diffsol BDF"), ("esdirk34", "diffsol SDIRK")] {
        for rtol in TOLERANCES {
            let mut walls = Vec::new();
            let mut end = None;
            for _ in 0..5 {
                let start = Instant::now();
                end = run::<P>(method, rtol);
                walls.push(start.elapsed().as_secs_f64());
                if end.is_none() {
                    break;
                }
            }
            let Some(end) = end else {
                eprintln!("{} {label} {rtol:e}: failed", P::NAME);
                continue;
            };
            walls.sort_by(f64::total_cmp);
            let error = mixed_error::<P>(&to_state::<P>(&end));
            let line = format!(
                "{},{label},{rtol:e},{error:e},,,,,,{:e}",
                P::NAME,
                walls[walls.len() / 2]
            );
            println!("{line}");
            let _ = writeln!(out, "{line}");
        }
    }
}

fn main() {
    let path = std::env::args().nth(1).expect("the CSV to write");
    let mut out = String::from(
        "problem,solver,rtol,error,steps,rejected,evaluations,jacobians,factorizations,wall\n",
    );
    rows::<Robertson>(&mut out);
    rows::<VanDerPol>(&mut out);
    rows::<Hires>(&mut out);
    rows::<Oregonator>(&mut out);
    rows::<Pollution>(&mut out);
    std::fs::write(path, out).expect("write the CSV");
}
