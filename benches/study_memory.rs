//! A study's memory: N rows (default 10⁶) run as one task (`--table grid.csv --out DIR
//! --format parquet`) and streamed to Parquet a block at a time; the task's peak resident
//! memory (`VmHWM`, Linux), read by the task itself at its end. The grid is written first, by
//! this program, and the task runs in a process of its own, so that the peak is the task's.
//!
//! ```text
//! cargo bench -p hamel-benches --features parquet --bench study_memory -- 1000000
//! ```
//!
//! Each case is cheap (four outputs from two parameters): the figure is the machinery's
//! memory — the parameter table held as numbers (16 MB at 10⁶ rows of two parameters), two
//! blocks of rows, one Parquet row group — not a model's.

use std::process::{Command, ExitCode};

use hamel::Error;
use hamel::study::{Study, steps};

/// A study of `side`² cases: x and y on a grid, four outputs.
fn study(side: usize) -> Study<'static> {
    Study::new("memory", "four outputs of two parameters")
        .parameter("x", "", "", steps(0.0, 1e-3, side))
        .parameter("y", "", "", steps(1.0, 1e-3, side))
        .output("product", "", "x y")
        .output("sum", "", "x + y")
        .output("sine", "", "sin x")
        .output("cosine", "", "cos y")
        .case(|row| {
            let (x, y) = (row.get("x")?, row.get("y")?);
            Ok(vec![x * y, x + y, x.sin(), y.cos()])
        })
}

/// This process's peak resident memory in KiB (Linux), if it can be read.
fn peak_kib() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

fn main() -> ExitCode {
    // `cargo bench` adds `--bench`.
    let args: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| a != "--bench")
        .collect();
    if let [task, side, dir] = args.as_slice() {
        if task == "task" {
            return run_task(side.parse().unwrap_or(1000), dir);
        }
    }
    let rows: usize = args
        .first()
        .and_then(|a| a.parse().ok())
        .unwrap_or(1_000_000);
    let side = (rows as f64).sqrt().round() as usize;
    let dir = std::env::temp_dir().join(format!("hamel-study-memory-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("a scratch directory");
    let grid = study(side).grid().expect("the grid");
    std::fs::write(dir.join("grid.csv"), grid.to_csv()).expect("the grid written");
    drop(grid);
    let exe = std::env::current_exe().expect("this program");
    let dir_text = dir.display().to_string();
    let status = Command::new(exe)
        .args(["task", &side.to_string(), &dir_text])
        .status()
        .expect("the task started");
    let _ = std::fs::remove_dir_all(&dir);
    if status.success() {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}

/// The task: the study of the grid in `dir` into `dir/out`, then its peak memory.
fn run_task(side: usize, dir: &str) -> ExitCode {
    let dir = std::path::Path::new(dir);
    let started = std::time::Instant::now();
    let args: Vec<String> = [
        "--table",
        &dir.join("grid.csv").display().to_string(),
        "--out",
        &dir.join("out").display().to_string(),
        "--format",
        "parquet",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    let code = study(side).main_with(&args);
    let peak = peak_kib().map_or("unknown".to_string(), |k| {
        format!("{:.1} MiB", k as f64 / 1024.0)
    });
    let file = dir.join("out").join("shard-0000-of-0001.parquet");
    let read = hamel::parquet::read(&file).map(|t| t.len());
    let bytes = std::fs::metadata(&file).map(|m| m.len()).unwrap_or(0);
    println!(
        "{} rows streamed to Parquet ({:.1} MiB) in {:.1} s; peak resident memory of the task \
         before reading it back: {peak}",
        side * side,
        bytes as f64 / 1048576.0,
        started.elapsed().as_secs_f64()
    );
    match read {
        Ok(n) if n == side * side => code,
        Ok(n) => {
            eprintln!("read back {n} rows, not {}", side * side);
            ExitCode::FAILURE
        }
        Err(e) => {
            let e: Error = e;
            eprintln!("{e}");
            ExitCode::FAILURE
        }
    }
}
