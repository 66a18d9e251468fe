//! The paper's mobile robot drives a look-ahead point along a figure-eight by exact
//! input–output linearization (Isidori, *Nonlinear Control Systems*, §5.2), from the Lie
//! derivatives the macro generates for the model's `#[outputs]`:
//!
//! 1. the outputs are the point p = (px, py) 0.3 m ahead of the axle's centre
//!    (`hamel::models::MobileRobot::look_ahead`); both have relative degree 2 in the wheel
//!    torques, and the decoupling matrix L_g L_f h is regular;
//! 2. u = A(x)⁻¹ (v − L_f² h) with v = p̈_d − 2λ(ṗ − ṗ_d) − λ²(p − p_d), λ = 10/s
//!    (`hamel::control::ExactLinearization`), run as the input function of a simulation;
//! 3. the reference is the figure-eight p_d = (a sin ωt, (a/2) sin 2ωt), a = 1 m, ω = 0.5/s;
//!    the robot starts at rest at the origin, 0.3 m from the reference's start;
//! 4. twice: with the controller's model exact, and with its body 5 % heavier than the
//!    robot's. The tracking error after a 2 s transient is printed, and the path is written
//!    to `robot_tracking.csv` (t, the state, the torques, p, p_d and the error |p − p_d|).
//!
//! `--animate robot_tracking.html` also writes the exact run as a 3D scene of the body and
//! its two wheels, p, p_d and the error beside it, to open in a browser (`hamel::scene`).
//!
//! The pitch α is the zero dynamics of these outputs: the body, an inverted pendulum on the
//! axle with nothing to hold it up, falls over and swings about the axle (it passes through
//! the floor: the model has no contact for the body) while the point is tracked.
//!
//! ```text
//! cargo run --release --example robot_tracking
//! cargo run --release --example robot_tracking -- --animate robot_tracking.html
//! ```

use hamel::control::ExactLinearization;
use hamel::models::MobileRobot;
use hamel::prelude::*;
use hamel::{ControlAffine, Trajectory};
use std::path::PathBuf;
use std::process::ExitCode;

// `main` below keeps its own exit codes (a tracking error above 1e-6 m fails): it reads
// `--animate` with `animate::request`, and `animate::main` goes unused here.
#[allow(dead_code)]
#[path = "support/animate.rs"]
mod animate;

/// The figure-eight's size (m) and rate (1/s); the error dynamics' rate λ (1/s).
const SIZE: f64 = 1.0;
const RATE: f64 = 0.5;
const LAMBDA: f64 = 10.0;
/// The run's length and the transient left out of the error (s).
const T_END: f64 = 20.0;
const TRANSIENT: f64 = 2.0;

/// p_d, ṗ_d, p̈_d for each output.
fn figure_eight(t: f64) -> Vec<Vec<f64>> {
    let (s, c) = (RATE * t).sin_cos();
    let (s2, c2) = (2.0 * RATE * t).sin_cos();
    vec![
        vec![SIZE * s, SIZE * RATE * c, -SIZE * RATE * RATE * s],
        vec![
            0.5 * SIZE * s2,
            SIZE * RATE * c2,
            -2.0 * SIZE * RATE * RATE * s2,
        ],
    ]
}

/// The columns the scene shows beside the robot, and the units of those the run added.
const SHOWN: [&str; 6] = ["px", "py", "px_ref", "py_ref", "error", "alpha"];
const UNITS: [(&str, &str); 5] = [
    ("px", "m"),
    ("py", "m"),
    ("px_ref", "m"),
    ("py_ref", "m"),
    ("error", "m"),
];

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let animation = match animate::request(&args) {
        Ok(animate::Request::Run(path)) => path,
        Ok(animate::Request::Help) => {
            print!(
                "{}",
                animate::usage(
                    "The mobile robot's look-ahead point tracks a figure-eight by exact \
                     input-output linearization; its body, the zero dynamics of these \
                     outputs, falls over as it tracks."
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
    let robot = MobileRobot::default();
    let lie = robot.lie_derivatives(0.0, &[0.0; 8])?;
    let decoupling = lie.decoupling()?;
    println!("Mobile robot: outputs px, py (0.3 m ahead of the axle), inputs tau1, tau2");
    println!(
        "relative degrees {:?}; decoupling matrix at rest {:.4}",
        decoupling.relative_degrees, decoupling.matrix
    );
    let exact = track(&robot, &robot)?;
    let heavier = MobileRobot {
        m0: 1.05 * robot.m0,
        ..robot.clone()
    };
    let mismatched = track(&robot, &heavier)?;
    println!(
        "exact model:      tracking error after {TRANSIENT} s at most {:.3e} m (largest torque {:.3} N m)",
        worst_error(&exact),
        largest_torque(&exact)
    );
    println!(
        "5 % heavier body: tracking error after {TRANSIENT} s at most {:.3e} m (largest torque {:.3} N m)",
        worst_error(&mismatched),
        largest_torque(&mismatched)
    );
    exact.save_csv("robot_tracking.csv")?;
    println!("wrote {} rows to robot_tracking.csv", exact.len());
    if let Some(path) = animation {
        animate::write(&robot, &exact, &SHOWN, &UNITS, &path)?;
    }
    Ok(worst_error(&exact) <= 1e-6)
}

/// A run of `robot` steered by the controller designed on `model`.
fn track(robot: &MobileRobot, model: &MobileRobot) -> Result<Trajectory, Error> {
    let controller = ExactLinearization::new(model, LAMBDA, figure_eight)?;
    let output = |i: usize| move |t: f64, x: &[f64; 8]| robot.output_values(t, x)[i];
    Simulation::new(robot, [0.0; 8])
        .end_time(T_END)
        .sample_interval(0.01)
        .output("px", output(0))
        .output("py", output(1))
        .output("px_ref", |t, _| figure_eight(t)[0][0])
        .output("py_ref", |t, _| figure_eight(t)[1][0])
        .output("error", |t, x| {
            let (p, d) = (robot.output_values(t, x), figure_eight(t));
            (p[0] - d[0][0]).hypot(p[1] - d[1][0])
        })
        .run_controlled(&DormandPrince::new(1e-11, 1e-13), &controller)
}

/// The largest distance of p from p_d after the transient.
fn worst_error(run: &Trajectory) -> f64 {
    let error = run.column("error").unwrap_or_default();
    run.times()
        .iter()
        .zip(error)
        .filter(|(t, _)| **t >= TRANSIENT)
        .fold(0.0, |m, (_, e)| m.max(*e))
}

fn largest_torque(run: &Trajectory) -> f64 {
    ["tau1", "tau2"]
        .iter()
        .flat_map(|name| run.column(name).unwrap_or_default().iter())
        .fold(0.0f64, |m, v| m.max(v.abs()))
}
