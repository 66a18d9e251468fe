//! The memory of a long run, streamed against recorded in memory: the knife edge on an
//! inclined plane (`hamel::models::KnifeEdge`, 7 columns) for N samples, 0.01 s apart, either
//! streamed through a `CsvSink` (into `std::io::sink()`, so that only the program's own
//! memory is measured, or into a file) or recorded into a `Trajectory` with
//! `Simulation::run`.
//!
//! ```text
//! cargo bench -p hamel-benches --bench stream_memory -- stream 10000000   # CSV into io::sink()
//! cargo bench -p hamel-benches --bench stream_memory -- stream 10000000 run.csv
//! cargo bench -p hamel-benches --bench stream_memory -- memory 10000000
//! /usr/bin/time -f %M target/release/deps/stream_memory-* stream 10000000  # peak memory
//! ```
//!
//! Peak resident memory of the whole process (`/usr/bin/time -f %M`, Linux x86-64, release
//! build; the same in each of three runs):
//!
//! | samples | streamed | in memory |
//! |--------:|---------:|----------:|
//! | 10⁵     | 2.7 MiB  | 8.0 MiB   |
//! | 10⁶     | 2.7 MiB  | 56.2 MiB  |
//! | 10⁷     | 2.8 MiB  | 536.8 MiB |
//!
//! Streaming needs the same memory at any length. In memory the samples take 8 bytes × 7
//! columns each, 534 MiB at 10⁷, and the peak is that plus the streamed run's few MiB.

use hamel::models::KnifeEdge;
use hamel::{CsvSink, DormandPrince, HamelSystem, Simulation};
use std::process::ExitCode;

const USAGE: &str = "usage: stream_memory (stream|memory) SAMPLES [CSV_FILE]";

fn run(args: &[String]) -> Result<String, String> {
    let (mode, count) = match args {
        [mode, count] | [mode, count, _] => (mode.as_str(), count),
        _ => return Err(USAGE.into()),
    };
    let samples: u32 = count
        .parse()
        .map_err(|_| format!("`{count}` is not a number of samples\n{USAGE}"))?;
    if samples < 2 {
        return Err(format!("at least 2 samples\n{USAGE}"));
    }
    let skate = KnifeEdge::default();
    let x0 = skate
        .state_from_speeds(0.0, &[0.0, 0.0, 0.0], &[1.0, 0.5])
        .map_err(|e| e.to_string())?;
    let dt = 0.01;
    let simulation = Simulation::new(&skate, x0)
        .end_time(f64::from(samples - 1) * dt)
        .sample_interval(dt);
    let integrator = DormandPrince::new(1e-8, 1e-10);
    match (mode, args.get(2)) {
        ("stream", file) => {
            let (summary, rows) = match file {
                Some(path) => {
                    let mut sink = CsvSink::create(path).map_err(|e| e.to_string())?;
                    let summary = simulation.stream(&integrator, |_, _| [], &mut sink);
                    (summary, sink.rows())
                }
                None => {
                    let mut sink = CsvSink::new(std::io::sink(), "io::sink()");
                    let summary = simulation.stream(&integrator, |_, _| [], &mut sink);
                    (summary, sink.rows())
                }
            };
            let summary = summary.map_err(|e| e.to_string())?;
            Ok(format!(
                "streamed {rows} rows; {} steps, relative energy drift {:e}",
                summary.steps, summary.relative_energy_drift
            ))
        }
        ("memory", None) => {
            let trajectory = simulation
                .run(&integrator, |_, _| [])
                .map_err(|e| e.to_string())?;
            let summary = trajectory.summary();
            Ok(format!(
                "recorded {} rows of {} columns; {} steps, relative energy drift {:e}",
                trajectory.len(),
                trajectory.names().len(),
                summary.steps,
                summary.relative_energy_drift
            ))
        }
        _ => Err(USAGE.into()),
    }
}

fn main() -> ExitCode {
    // `cargo bench` adds `--bench`.
    let args: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| a != "--bench")
        .collect();
    match run(&args) {
        Ok(report) => {
            println!("{report}");
            ExitCode::SUCCESS
        }
        Err(message) => {
            eprintln!("{message}");
            ExitCode::from(2)
        }
    }
}
