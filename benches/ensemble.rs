//! The figures of record for studies (`hamel::Ensemble`): 10⁴ runs of the paper's robot
//! (each 10 s at rtol 1e-9, atol 1e-12, samples every 0.01 s, from its own initial tilt and
//! speed, keeping the final state), timed whole in three variants, interleaved round by round
//! (the first variant of a round moving on by one each round):
//!
//! * a bare loop of `Simulation` runs on one thread, the rows pushed into a vector;
//! * the `Ensemble` on a pool of 1 thread (its overhead per run: the ratio to the loop);
//! * the `Ensemble` on 2 threads (its speed-up: the ratio of the 1-thread time to it).
//!
//! ```text
//! cargo bench -p hamel-benches --bench ensemble                          # 10⁴ runs, 7 rounds
//! HAMEL_ENSEMBLE_RUNS=1000 HAMEL_BENCH_ROUNDS=5 cargo bench -p hamel-benches --bench ensemble
//! ```
//!
//! Every figure is the median over the rounds of a per-round ratio, p10–p90 beside it. The
//! startup checks that the three variants give the same bits.
//!
//! Figures of record (10⁴ runs, 7 rounds, the shared 2-core machine at a quiet moment, load
//! average 1.1 at the start; median and p10–p90 of the per-round ratios):
//!
//! ```text
//! bare loop 4.489 s, Ensemble on 1 thread 4.554 s, on 2 threads 2.325 s
//! overhead of the Ensemble over the bare loop   1.015 (0.999–1.016)
//! speed-up on 2 threads over 1                  1.877 (1.851–2.027), efficiency 94 %
//! ```
//!
//! The speed-up needs both cores free: with another process busy on one (load average
//! about 2), the same bench gave a median of 1.06–1.10, its best rounds 2.0.

use std::hint::black_box;
use std::time::Instant;

use hamel::models::MobileRobot;
use hamel::{DormandPrince, Ensemble, Error, HamelSystem, Outputs, Simulation};
use hamel_benches::interleave::Spread;

/// One case: the robot tilted by α and rolling at v, with small constant torques.
fn case(robot: &MobileRobot, i: usize) -> Result<Vec<f64>, Error> {
    let k = i as f64 / 10_000.0;
    let (alpha, speed) = (0.2 + 0.2 * k, 0.3 + 0.4 * (1.0 - k));
    let x0 = robot.state_from_speeds(0.0, &[0.0, 0.0, alpha, 0.0, 0.0], &[0.0, speed, 0.4])?;
    let run = Simulation::new(robot, x0)
        .end_time(10.0)
        .sample_interval(0.01)
        .run_constant(&DormandPrince::new(1e-9, 1e-12), [0.01, -0.01])?;
    Outputs::new().final_state().values::<MobileRobot>(&run)
}

/// The bare loop: the same cases, one after another.
fn bare(robot: &MobileRobot, runs: usize) -> Vec<Result<Vec<f64>, Error>> {
    (0..runs).map(|i| case(robot, i)).collect()
}

/// The study on `threads` threads.
fn study(robot: &MobileRobot, runs: usize, threads: usize) -> Vec<Result<Vec<f64>, Error>> {
    Ensemble::new(runs)
        .threads(threads)
        .run(|i| case(robot, i))
        .expect("a valid study")
}

fn env(name: &str, default: usize) -> usize {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

fn bits(rows: &[Result<Vec<f64>, Error>]) -> Vec<u64> {
    rows.iter()
        .flat_map(|r| {
            r.as_ref()
                .expect("every case runs")
                .iter()
                .map(|v| v.to_bits())
        })
        .collect()
}

fn main() {
    let runs = env("HAMEL_ENSEMBLE_RUNS", 10_000);
    let rounds = env("HAMEL_BENCH_ROUNDS", 7);
    let robot = MobileRobot::default();
    let reference = bits(&bare(&robot, runs.min(200)));
    assert_eq!(bits(&study(&robot, runs.min(200), 1)), reference);
    assert_eq!(bits(&study(&robot, runs.min(200), 2)), reference);
    let variants: [(&str, &dyn Fn() -> usize); 3] = [
        ("bare loop of Simulation runs, 1 thread", &|| {
            bare(&robot, runs).len()
        }),
        ("Ensemble, 1 thread", &|| study(&robot, runs, 1).len()),
        ("Ensemble, 2 threads", &|| study(&robot, runs, 2).len()),
    ];
    let mut seconds = vec![[0.0; 3]; rounds];
    for (round, times) in seconds.iter_mut().enumerate() {
        for j in 0..3 {
            let v = (round + j) % 3;
            let start = Instant::now();
            black_box(variants[v].1());
            times[v] = start.elapsed().as_secs_f64();
        }
    }
    let ratio =
        |a: usize, b: usize| Spread::of(&seconds.iter().map(|r| r[a] / r[b]).collect::<Vec<_>>());
    println!(
        "Robot studies: {runs} runs of 10 s each, {rounds} rounds interleaved ({} threads available)",
        std::thread::available_parallelism().map_or(1, |n| n.get())
    );
    for (v, (name, _)) in variants.iter().enumerate() {
        let t = Spread::of(&seconds.iter().map(|r| r[v]).collect::<Vec<_>>());
        println!(
            "  {name:<42} {:>8.3} s (p10–p90 {:.3}–{:.3}), {:.1} µs a run",
            t.median,
            t.p10,
            t.p90,
            t.median / runs as f64 * 1e6
        );
    }
    let overhead = ratio(1, 0);
    let speedup = ratio(1, 2);
    println!(
        "  overhead of the Ensemble over the bare loop (1 thread): {:.3} (p10–p90 {:.3}–{:.3})",
        overhead.median, overhead.p10, overhead.p90
    );
    println!(
        "  speed-up on 2 threads over 1: {:.3} (p10–p90 {:.3}–{:.3}), parallel efficiency {:.0} %",
        speedup.median,
        speedup.p10,
        speedup.p90,
        speedup.median / 2.0 * 100.0
    );
}
