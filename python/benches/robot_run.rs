//! The Rust side of `python/benches/speed.py`: the README's robot run (10 s, samples every
//! 0.01 s, Dormand–Prince at rtol 1e-9, atol 1e-12), timed in batches asked for on standard
//! input, so that the Python side can interleave its own batches with these in one process
//! each. Each line read is a batch size n; the answer is one line of n run times in seconds.

use std::io::{BufRead, Write};
use std::time::Instant;

use hamel::models::MobileRobot;
use hamel::{DormandPrince, HamelSystem, Simulation};

fn main() -> Result<(), hamel::Error> {
    let robot = MobileRobot::default();
    let x0 = robot
        .state_builder()
        .set("alpha", 0.3)
        .set("w4", 0.5)
        .set("w5", 0.4)
        .build()?;
    let stdin = std::io::stdin();
    let mut out = std::io::stdout().lock();
    for line in stdin.lock().lines() {
        let Ok(n) = line
            .map_err(|_| ())
            .and_then(|l| l.trim().parse::<usize>().map_err(|_| ()))
        else {
            break;
        };
        let mut times = Vec::with_capacity(n);
        for _ in 0..n {
            let start = Instant::now();
            let run = Simulation::new(&robot, x0)
                .end_time(10.0)
                .sample_interval(0.01)
                .run_constant(&DormandPrince::new(1e-9, 1e-12), [0.0, 0.0])?;
            times.push(start.elapsed().as_secs_f64());
            std::hint::black_box(run);
        }
        let text: Vec<String> = times.iter().map(|t| format!("{t:e}")).collect();
        writeln!(out, "{}", text.join(" ")).ok();
        out.flush().ok();
    }
    Ok(())
}
