//! The study's overhead per case over a bare `Ensemble`: the paper's robot run for 10 s from
//! its own tilt and speed (the cases of `benches/ensemble.rs`), its final state kept, as
//!
//! * a bare `Ensemble::table` on a pool of one thread, the rows in memory;
//! * a `hamel::study::Study` task on one thread (`--table grid.csv --out DIR --threads 1`):
//!   the parameter table read, the rows streamed a block at a time to CSV (written while the
//!   next block computes), the shard's file flushed, checksummed and renamed, its manifest
//!   written after it.
//!
//! timed whole, interleaved round by round (the first variant of a round alternating).
//!
//! ```text
//! cargo bench -p hamel-benches --bench study                        # 2000 cases, 9 rounds
//! HAMEL_STUDY_CASES=500 HAMEL_BENCH_ROUNDS=5 cargo bench -p hamel-benches --bench study
//! ```
//!
//! The figure is the median over the rounds of the per-round ratio study / Ensemble, p10–p90
//! beside it. The startup checks that both give the same bits.

use std::hint::black_box;
use std::path::Path;
use std::process::ExitCode;
use std::time::Instant;

use hamel::models::MobileRobot;
use hamel::study::{Study, steps};
use hamel::{DormandPrince, Ensemble, Error, HamelSystem, Outputs, Simulation, Table};
use hamel_benches::interleave::Spread;

/// One case: the robot tilted by α and rolling at v, with small constant torques.
fn case(robot: &MobileRobot, alpha: f64, speed: f64) -> Result<Vec<f64>, Error> {
    let x0 = robot.state_from_speeds(0.0, &[0.0, 0.0, alpha, 0.0, 0.0], &[0.0, speed, 0.4])?;
    let run = Simulation::new(robot, x0)
        .end_time(10.0)
        .sample_interval(0.01)
        .run_constant(&DormandPrince::new(1e-9, 1e-12), [0.01, -0.01])?;
    Outputs::new().final_state().values::<MobileRobot>(&run)
}

/// Case i's tilt and speed.
fn parameters(i: usize, cases: usize) -> (f64, f64) {
    let k = i as f64 / cases as f64;
    (0.2 + 0.2 * k, 0.3 + 0.4 * (1.0 - k))
}

fn env(name: &str, default: usize) -> usize {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// The study: one parameter `i`, the case index (so both variants run the same cases).
fn study<'a>(robot: &'a MobileRobot, cases: usize) -> Study<'a> {
    let mut study = Study::new("robot_study", "the robot's final state").parameter(
        "i",
        "",
        "the case",
        steps(0.0, 1.0, cases),
    );
    for name in Outputs::new().final_state().names::<MobileRobot>() {
        study = study.output(&name, "", "");
    }
    study.case(move |row| {
        let (alpha, speed) = parameters(row.get("i")? as usize, cases);
        case(robot, alpha, speed)
    })
}

/// The bare Ensemble on one thread: the rows in memory.
fn bare(robot: &MobileRobot, cases: usize) -> Table {
    let mut names = vec!["i".to_string()];
    names.extend(Outputs::new().final_state().names::<MobileRobot>());
    Ensemble::new(cases)
        .threads(1)
        .table(names, |i| {
            let (alpha, speed) = parameters(i, cases);
            let mut row = vec![i as f64];
            row.extend(case(robot, alpha, speed)?);
            Ok(row)
        })
        .expect("a valid study")
}

/// The study's task on one thread into `out` (emptied first).
fn task(study: &Study, grid: &Path, out: &Path) -> ExitCode {
    let _ = std::fs::remove_dir_all(out);
    let args: Vec<String> = [
        "--table",
        &grid.display().to_string(),
        "--out",
        &out.display().to_string(),
        "--threads",
        "1",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    study.main_with(&args)
}

fn main() -> ExitCode {
    let cases = env("HAMEL_STUDY_CASES", 2000);
    let rounds = env("HAMEL_BENCH_ROUNDS", 9);
    let robot = MobileRobot::default();
    let dir = std::env::temp_dir().join(format!("hamel-study-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a scratch directory");
    let (grid, out) = (dir.join("grid.csv"), dir.join("out"));
    let s = study(&robot, cases);
    std::fs::write(&grid, s.grid().expect("the grid").to_csv()).expect("the grid written");
    // Both give the same bits.
    assert_eq!(task(&s, &grid, &out), ExitCode::SUCCESS);
    let written = Table::read_csv(out.join("shard-0000-of-0001.csv")).expect("the shard");
    assert_eq!(written, bare(&robot, cases));
    let mut seconds = vec![[0.0; 2]; rounds];
    for (round, times) in seconds.iter_mut().enumerate() {
        for j in 0..2 {
            let v = (round + j) % 2;
            let start = Instant::now();
            if v == 0 {
                black_box(bare(&robot, cases));
            } else {
                black_box(task(&s, &grid, &out));
            }
            times[v] = start.elapsed().as_secs_f64();
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
    let spread =
        |f: &dyn Fn(&[f64; 2]) -> f64| Spread::of(&seconds.iter().map(f).collect::<Vec<_>>());
    let (e, t, ratio) = (
        spread(&|r| r[0]),
        spread(&|r| r[1]),
        spread(&|r| r[1] / r[0]),
    );
    println!("Robot study: {cases} cases of 10 s each on 1 thread, {rounds} rounds interleaved");
    println!(
        "  bare Ensemble::table      {:.3} s (p10–p90 {:.3}–{:.3}), {:.1} µs a case",
        e.median,
        e.p10,
        e.p90,
        e.median / cases as f64 * 1e6
    );
    println!(
        "  Study task (CSV, manifest) {:.3} s (p10–p90 {:.3}–{:.3}), {:.1} µs a case",
        t.median,
        t.p10,
        t.p90,
        t.median / cases as f64 * 1e6
    );
    println!(
        "  overhead of the study over the bare Ensemble: {:.4} (p10–p90 {:.4}–{:.4})",
        ratio.median, ratio.p10, ratio.p90
    );
    ExitCode::SUCCESS
}
