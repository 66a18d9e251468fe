//! An LQR steer-torque controller that rides the benchmark bicycle (Meijaard, Papadopoulos,
//! Ruina & Schwab 2007) at 2 m/s, below its weave speed, where it falls over by itself.
//!
//! 1. the nonlinear model `hamel::models::WhippleBicycle` linearized about upright, straight
//!    running at 2 m/s (`linearize`, then its lateral states φ, δ, φ̇, δ̇ and the steer
//!    torque alone);
//! 2. LQR on it: the Riccati equation solved by `hamel::control::solve_care` (the same gains
//!    as scipy's `solve_continuous_are`, to 1e-14 in the validation suite), the gain and
//!    the closed loop's eigenvalues printed;
//! 3. the gain as the input function of a nonlinear run (`Simulation::run_controlled`): the
//!    bicycle starts leaning 0.1 rad and the controller brings it upright; the roll over
//!    time is written to `bicycle_control.csv`.
//!
//! `--animate bicycle_control.html` also writes that run as a 3D scene (`hamel::scene`), the
//! lean, steer and steer torque beside it; `--help` says so, and any other argument is an
//! error.
//!
//! ```text
//! cargo run --release --example bicycle_control
//! cargo run --release --example bicycle_control -- --animate bicycle_control.html
//! ```

use hamel::control::Lqr;
use hamel::models::WhippleBicycle;
use hamel::nalgebra::{self, DMatrix, DVector};
use hamel::prelude::*;
use std::path::PathBuf;
use std::process::ExitCode;

// `main` below keeps its own exit codes (a controller that does not bring the bicycle back
// fails): it reads the command line with `animate::request`, and `animate::main` goes unused.
#[allow(dead_code)]
#[path = "support/animate.rs"]
mod animate;

/// The speed (m/s), the initial lean (rad), and how far back it must come (rad) by when (s).
const SPEED: f64 = 2.0;
const LEAN: f64 = 0.1;
const BACK_WITHIN: f64 = 0.01;
const BY: f64 = 5.0;

/// The columns the scene shows beside the bicycle.
const SHOWN: [&str; 3] = ["phi", "delta", "steer_torque"];

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let animation = match animate::request(&args) {
        Ok(animate::Request::Run(path)) => path,
        Ok(animate::Request::Help) => {
            print!(
                "{}",
                animate::usage(
                    "An LQR steer-torque controller rides the benchmark bicycle at 2 m/s, below \
                     its weave speed: the linearization, the gain, and a nonlinear run from a \
                     0.1 rad lean (bicycle_control.csv)."
                )
            );
            return ExitCode::SUCCESS;
        }
        Err(message) => {
            eprintln!("error: {message}");
            return ExitCode::from(2);
        }
    };
    match run(animation) {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::FAILURE,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run(animation: Option<PathBuf>) -> Result<bool, Error> {
    let bike = WhippleBicycle::default();
    let wheel_rate = -SPEED / bike.r_r;
    let upright = bike
        .state_builder()
        .set("rear_wheel_rate", wheel_rate)
        .build()?;
    let lateral = bike
        .linearize(0.0, &upright, &[0.0, 0.0])?
        .reduce(&["phi", "delta", "roll_rate", "steer_rate"])?
        .with_inputs(&["steer_torque"])?;
    println!("Whipple bicycle (benchmark parameters) at {SPEED} m/s, steer torque only");
    let open: Vec<String> = lateral.modes()?.iter().map(|m| complex(m.value)).collect();
    println!("open-loop eigenvalues   {}", open.join(", "));
    // Weights: the lean most, then the steer angle and the rates.
    let q = DMatrix::from_diagonal(&DVector::from_row_slice(&[10.0, 1.0, 1.0, 0.1]));
    let r = DMatrix::identity(1, 1);
    let lqr = Lqr::new(&lateral, &q, &r)?;
    let gain: Vec<String> = lqr
        .states()
        .iter()
        .zip(lqr.gain().iter())
        .map(|(name, k)| format!("{name} {k:.6}"))
        .collect();
    println!("LQR gain K (steer_torque = -K x): {}", gain.join(", "));
    println!(
        "Riccati residual        {:.1e} (sign-function steps {}, Newton steps {})",
        lqr.riccati().residual,
        lqr.riccati().steps.0,
        lqr.riccati().steps.1
    );
    let closed: Vec<String> = lqr
        .closed_loop_eigenvalues()
        .iter()
        .map(|l| complex(*l))
        .collect();
    println!("closed-loop eigenvalues {}", closed.join(", "));

    let start = bike
        .state_builder()
        .set("phi", LEAN)
        .set("rear_wheel_rate", wheel_rate)
        .build()?;
    let run = Simulation::new(&bike, start)
        .end_time(10.0)
        .sample_interval(0.01)
        .run_controlled(
            &DormandPrince::new(1e-10, 1e-12),
            &lqr.feedback::<WhippleBicycle>()?,
        )?;
    let (t, phi) = (run.times(), run.column("phi").unwrap_or_default());
    let torque = run.column("steer_torque").unwrap_or_default();
    let after = t
        .iter()
        .zip(phi)
        .filter(|(t, _)| **t >= BY)
        .fold(0.0f64, |m, (_, p)| m.max(p.abs()));
    let largest_torque = torque.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    println!(
        "nonlinear closed loop from a lean of {LEAN} rad: |phi| <= {after:.3e} rad from t = {BY} s \
         to 10 s (needed: {BACK_WITHIN}); largest steer torque {largest_torque:.3} N m"
    );
    run.save_csv("bicycle_control.csv")?;
    println!("wrote {} rows to bicycle_control.csv", run.len());
    if let Some(path) = animation {
        animate::write(&bike, &run, &SHOWN, &[], &path)?;
    }
    Ok(after <= BACK_WITHIN && lqr.closed_loop_eigenvalues().iter().all(|l| l.re < 0.0))
}

fn complex(l: nalgebra::Complex<f64>) -> String {
    if l.im == 0.0 {
        format!("{:.4}", l.re)
    } else {
        format!(
            "{:.4} {} {:.4}i",
            l.re,
            if l.im < 0.0 { "-" } else { "+" },
            l.im.abs()
        )
    }
}
