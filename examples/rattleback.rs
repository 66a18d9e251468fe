//! The rattleback reversing its spin (Walker 1896; Garcia & Hubbard, Proc. R. Soc. A 418,
//! 1988): the catalogue's `hamel::models::Rattleback`, spun about the vertical one way and
//! then the other, from upright with a small roll rate. Either way the spin dies into
//! rocking and comes back reversed, much sooner one way than the other; without friction to
//! take energy out it then goes on reversing back and forth. The example prints the yaw rate
//! every two seconds and the times the spin changes sign, and with
//! `--animate rattleback.html` writes the run spun the quick way as a 3D scene to open in a
//! browser (`hamel::scene`).
//!
//! ```text
//! cargo run --release --example rattleback
//! cargo run --release --example rattleback -- --animate rattleback.html
//! ```

use std::process::ExitCode;

use hamel::models::Rattleback;
use hamel::prelude::*;

#[path = "support/animate.rs"]
mod animate;

/// How fast it is spun (rad/s), its initial roll rate (rad/s) and how long it runs (s).
const SPIN: f64 = 3.0;
const ROLL_RATE: f64 = 0.02;
const SECONDS: f64 = 30.0;

/// A run from upright, spun at `spin` about the vertical, sampled at 60 per second; the event
/// `reversed` marks each change of the spin's sign.
fn spun(celt: &Rattleback, spin: f64) -> Result<Trajectory, Error> {
    let x0 = celt
        .state_builder()
        .set("yaw_rate", spin)
        .set("roll_rate", ROLL_RATE)
        .build()?;
    let yaw_rate = Rattleback::STATE.iter().position(|n| *n == "yaw_rate");
    let yaw_rate = yaw_rate.unwrap_or(Rattleback::STATE.len() - 3);
    Simulation::new(celt, x0)
        .end_time(SECONDS)
        .sample_interval(1.0 / 60.0)
        .project_holonomic(true)
        .event(Event::on(celt, "reversed", move |_t, x| x[yaw_rate]))
        .run_constant(&DormandPrince::new(1e-10, 1e-12), [])
}

fn run(animate: Option<std::path::PathBuf>) -> Result<(), Error> {
    let celt = Rattleback::default();
    println!(
        "Rattleback: the base's axes of curvature turned by δ = {} rad against the principal \
         axes of inertia; spun at ±{SPIN} rad/s from upright with a roll rate of {ROLL_RATE} rad/s",
        celt.delta
    );
    let runs = [spun(&celt, SPIN)?, spun(&celt, -SPIN)?];
    let column = |run: &Trajectory| run.column("yaw_rate").unwrap_or(&[]).to_vec();
    let (plus, minus) = (column(&runs[0]), column(&runs[1]));
    println!("\n   t (s)   spun at +{SPIN}   spun at -{SPIN}   (yaw rate, rad/s)");
    for (i, t) in runs[0].times().iter().enumerate().step_by(120) {
        println!("{t:>8.1}  {:>+11.4}  {:>+11.4}", plus[i], minus[i]);
    }
    println!();
    for (run, spin) in runs.iter().zip([SPIN, -SPIN]) {
        match run.event_times("reversed").first() {
            Some(t) => {
                println!("spun at {spin:+} rad/s, the spin first changes sign at t = {t:.2} s")
            }
            None => println!("spun at {spin:+} rad/s, the spin keeps its sign for {SECONDS} s"),
        }
    }
    if let Some(path) = animate {
        // The run that reverses first.
        let first = |run: &Trajectory| run.event_times("reversed").first().copied();
        let quick = match (first(&runs[0]), first(&runs[1])) {
            (Some(a), Some(b)) if b < a => &runs[1],
            (None, Some(_)) => &runs[1],
            _ => &runs[0],
        };
        animate::write(
            &celt,
            quick,
            &["yaw_rate", "roll_rate", "pitch_rate"],
            &[],
            &path,
        )?;
    }
    Ok(())
}

fn main() -> ExitCode {
    animate::main(run)
}
