//! The Rust side of `python/benches/speed.py`: the README's robot run (10 s, samples every
//! 0.01 s, Dormand–Prince at rtol 1e-9, atol 1e-12), timed in batches asked for on standard
//! input, so that the Python side can interleave its own batches with these in one process
//! each. Each line read is a batch size n; the answer is two lines of n run times in seconds:
//! the wall clock's, then the thread's CPU clock's (which a machine loaded by other processes
//! inflates less: time spent waiting for a core is not counted). With the argument
//! `--progress` each run has a progress callback that does nothing, as the Python package
//! gives each run one to look for Ctrl-C: the runtime's cost of watching a run.

use std::io::{BufRead, Write};
use std::ops::ControlFlow;
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
    let progress = std::env::args().any(|a| a == "--progress");
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
        let mut cpu_times = Vec::with_capacity(n);
        for _ in 0..n {
            let cpu_start = thread_cpu_time();
            let start = Instant::now();
            let mut sim = Simulation::new(&robot, x0)
                .end_time(10.0)
                .sample_interval(0.01);
            if progress {
                sim = sim.on_progress(|_| ControlFlow::Continue(()));
            }
            let run = sim.run_constant(&DormandPrince::new(1e-9, 1e-12), [0.0, 0.0])?;
            times.push(start.elapsed().as_secs_f64());
            cpu_times.push(thread_cpu_time() - cpu_start);
            std::hint::black_box(run);
        }
        for list in [&times, &cpu_times] {
            let text: Vec<String> = list.iter().map(|t| format!("{t:e}")).collect();
            writeln!(out, "{}", text.join(" ")).ok();
        }
        out.flush().ok();
    }
    Ok(())
}

/// The CPU time this thread has used, in seconds (`CLOCK_THREAD_CPUTIME_ID`, the clock of
/// Python's `time.thread_time`).
fn thread_cpu_time() -> f64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid timespec for the call to write into.
    unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9
}
