//! A parameter study of the Whipple bicycle (`hamel::models::WhippleBicycle`): its weave and
//! capsize speeds — the ends of the self-stable speed range — over a grid of trail × rider
//! mass, every case on every core (`hamel::Ensemble`), drawn as a figure with the benchmark
//! of Meijaard et al. (2007) marked.
//!
//! ```text
//! cargo run --release --example bicycle_study                     # the grid, on this machine
//! cargo run --release --example bicycle_study -- --write-grid grid.csv
//! cargo run --release --example bicycle_study -- --table grid.csv --shard 3/8 --out results
//! cargo run --release --example bicycle_study -- --help
//! ```
//!
//! Each case finds the speeds where the largest real part of the lateral eigenvalues
//! changes sign: a scan of the linearization over 0 … 10 m/s in steps of 0.5 brackets them,
//! Brent's method locates them (about 40 linearizations a case). The rider is the rear body
//! of the benchmark (frame and rider, 85 kg): a rider of mass m scales its mass and moments
//! of inertia by m/85, its centre of mass staying where it is; the trail is the benchmark's
//! `c`. A case whose speeds the scan does not bracket is a row carrying that error.
//!
//! Without options the study runs the whole grid and writes `bicycle_study.csv` (and
//! `bicycle_study.parquet` when built with `--features parquet`) and the figure
//! `bicycle_study.svg` (and `.png`). With `--table`, `--shard i/n` and `--out DIR` it is one task of a
//! batch engine: it runs the table's rows of shard i of n and writes
//! `DIR/shard-000i-of-000n.parquet` (`.csv` without the feature, or with `--format csv`),
//! whole or not at all; a shard whose file is complete is skipped, so a killed study
//! restarted runs only what is missing. The README shows it as a Slurm job array and as Ray
//! or Dask tasks.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use hamel::ensemble::{Shard, check_writable, is_complete, write_complete};
use hamel::models::WhippleBicycle;
use hamel::plot::{Figure, PALETTE, Panel, Rgb, Series};
use hamel::prelude::*;
use hamel::roots::brent;
use hamel::{Ensemble, ParameterTable, StudyProgress, Table};
use indicatif::{ProgressBar, ProgressStyle};

/// The parameter table's columns.
const PARAMETERS: [&str; 2] = ["trail", "rider_mass"];

/// The lateral states of the benchmark's linear equations.
const LATERAL: [&str; 4] = ["phi", "delta", "roll_rate", "steer_rate"];

/// The benchmark's rear body (frame and rider), which a rider's mass scales.
const BENCHMARK_RIDER: f64 = 85.0;

/// The published weave and capsize speeds (Meijaard et al. 2007, Table 2).
const PUBLISHED: (f64, f64) = (4.29238253634111, 6.02426201538837);

/// Linearizations made so far, for the report.
static LINEARIZATIONS: AtomicUsize = AtomicUsize::new(0);

/// The benchmark bicycle with this trail and rider mass.
fn bicycle(trail: f64, rider_mass: f64) -> WhippleBicycle {
    let k = rider_mass / BENCHMARK_RIDER;
    let b = WhippleBicycle::default();
    WhippleBicycle {
        c: trail,
        m_b: b.m_b * k,
        i_bxx: b.i_bxx * k,
        i_byy: b.i_byy * k,
        i_bzz: b.i_bzz * k,
        i_bxz: b.i_bxz * k,
        ..b
    }
}

/// The largest real part of the lateral eigenvalues at speed v, upright and straight.
fn abscissa(bike: &WhippleBicycle, v: f64) -> Result<f64, Error> {
    LINEARIZATIONS.fetch_add(1, Ordering::Relaxed);
    let x = bike
        .state_builder()
        .set("rear_wheel_rate", -v / bike.r_r)
        .build()?;
    let lateral = bike.linearize(0.0, &x, &[0.0, 0.0])?.reduce(&LATERAL)?;
    Ok(lateral
        .eigenvalues()?
        .iter()
        .map(|l| l.re)
        .fold(f64::NEG_INFINITY, f64::max))
}

/// The weave and capsize speeds: the first crossing of the abscissa from positive to
/// negative over 0 … 10 m/s, and the next from negative to positive, bracketed by a scan in
/// steps of 0.5 m/s and located by Brent's method to 10⁻¹³ m/s.
fn critical_speeds(bike: &WhippleBicycle) -> Result<(f64, f64), Error> {
    let speeds: Vec<f64> = (0..=20).map(|i| 0.5 * i as f64).collect();
    let values = speeds
        .iter()
        .map(|&v| abscissa(bike, v))
        .collect::<Result<Vec<f64>, Error>>()?;
    let crossing = |from: usize, rising: bool| {
        (from..speeds.len() - 1).find(|&i| {
            let (a, b) = (values[i], values[i + 1]);
            if rising {
                a < 0.0 && b >= 0.0
            } else {
                a > 0.0 && b <= 0.0
            }
        })
    };
    let locate =
        |i: usize, what| brent(what, |v| abscissa(bike, v), speeds[i], speeds[i + 1], 1e-13);
    let none = |what, from: usize| Error::RootNotBracketed {
        what,
        a: speeds[from],
        b: speeds[speeds.len() - 1],
        fa: values[from],
        fb: values[speeds.len() - 1],
    };
    let weave_at = crossing(0, false).ok_or_else(|| none("the weave speed's abscissa", 0))?;
    let capsize_at = crossing(weave_at + 1, true)
        .ok_or_else(|| none("the capsize speed's abscissa", weave_at + 1))?;
    Ok((
        locate(weave_at, "the weave speed's abscissa")?,
        locate(capsize_at, "the capsize speed's abscissa")?,
    ))
}

/// The study's columns: the parameters, then the speeds.
fn columns() -> Vec<String> {
    ["trail", "rider_mass", "weave_speed", "capsize_speed"]
        .iter()
        .map(|s| s.to_string())
        .collect()
}

/// Row `i` of `table`: the parameters and the two speeds.
fn case(table: &ParameterTable, i: usize) -> Result<Vec<f64>, Error> {
    let get = |name: &str| table.get(i, name);
    let (trail, mass) = (
        get("trail").unwrap_or(0.08),
        get("rider_mass").unwrap_or(85.0),
    );
    let (weave, capsize) = critical_speeds(&bicycle(trail, mass))?;
    Ok(vec![trail, mass, weave, capsize])
}

/// The grid: trail 0.04 … 0.12 m in steps of 5 mm, rider mass 60 … 110 kg in steps of
/// 2.5 kg (17 × 21 cases; the benchmark, 0.08 m and 85 kg, is one of them).
fn grid() -> ParameterTable {
    let mut rows = Vec::new();
    for i in 0..=16 {
        for j in 0..=20 {
            rows.push(vec![0.04 + 0.005 * i as f64, 60.0 + 2.5 * j as f64]);
        }
    }
    ParameterTable::from_rows(PARAMETERS.iter().map(|s| s.to_string()).collect(), rows)
        .expect("the grid's rows have both columns")
}

/// The study's progress bar (on a terminal only), from any of its threads.
fn bar(total: usize) -> ProgressBar {
    let bar = ProgressBar::new(total as u64);
    if let Ok(style) = ProgressStyle::with_template("{wide_bar} {pos}/{len} cases, {msg}") {
        bar.set_style(style);
    }
    bar
}

fn update(bar: &ProgressBar, p: &StudyProgress) {
    bar.set_position(p.done as u64);
    bar.set_message(format!(
        "{} failed, {:.0} s",
        p.failed,
        p.elapsed.as_secs_f64()
    ));
}

/// What the command line asks for.
#[derive(Default)]
struct Settings {
    write_grid: Option<PathBuf>,
    table: Option<PathBuf>,
    shard: Option<Shard>,
    out: Option<PathBuf>,
    threads: Option<usize>,
    format: Option<String>,
}

const HELP: &str =
    "A parameter study of the Whipple bicycle: weave and capsize speeds over trail and rider mass.

Usage: bicycle_study [options]
  (no options)            the whole grid here: bicycle_study.csv (.parquet), .svg and .png
  --write-grid FILE       write the grid as a parameter table (columns trail, rider_mass)
  --table FILE            run the cases of this parameter table (columns trail, rider_mass) ...
  --shard i/n             ... only shard i of n (0 <= i < n; default 0/1) ...
  --out DIR               ... into DIR/shard-<i>-of-<n>.parquet (skipped if complete)
  --format parquet|csv    the shard files' format (parquet needs --features parquet)
  --threads N             threads (default: every core)
  --help                  this text
";

/// Parses the options; every mistake is a message, never a panic.
fn parse(args: &[String]) -> Result<Option<Settings>, String> {
    let mut s = Settings::default();
    let mut i = 0;
    while i < args.len() {
        let option = args[i].as_str();
        if option == "--help" || option == "-h" {
            return Ok(None);
        }
        let value = args
            .get(i + 1)
            .ok_or_else(|| format!("option `{option}` needs a value (see --help)"))?;
        match option {
            "--write-grid" => s.write_grid = Some(value.into()),
            "--table" => s.table = Some(value.into()),
            "--shard" => s.shard = Some(Shard::parse(value).map_err(|e| e.to_string())?),
            "--out" => s.out = Some(value.into()),
            "--format" if value == "csv" || value == "parquet" => s.format = Some(value.clone()),
            "--format" => return Err(format!("--format is `parquet` or `csv`, not `{value}`")),
            "--threads" => match value.parse::<usize>() {
                Ok(n) if n > 0 => s.threads = Some(n),
                _ => return Err(format!("--threads needs a whole number ≥ 1, not `{value}`")),
            },
            _ => return Err(format!("unknown option `{option}` (see --help)")),
        }
        i += 2;
    }
    if (s.table.is_some() || s.shard.is_some()) != s.out.is_some() {
        return Err(
            "a shard needs --table FILE and --out DIR (and, optionally, --shard i/n)".into(),
        );
    }
    if s.format.as_deref() == Some("parquet") && !cfg!(feature = "parquet") {
        return Err("--format parquet needs the example built with --features parquet".into());
    }
    Ok(Some(s))
}

/// The study of `table`'s rows `rows`, with a progress bar.
fn study(
    table: &ParameterTable,
    rows: std::ops::Range<usize>,
    threads: Option<usize>,
) -> Result<Table, Error> {
    let bar = bar(rows.len());
    let mut ensemble = Ensemble::new(rows.len()).on_progress(|p| update(&bar, p));
    if let Some(n) = threads {
        ensemble = ensemble.threads(n);
    }
    let indices = rows.clone().map(|i| i as u64).collect();
    let result = ensemble.table_of(columns(), indices, |i| case(table, rows.start + i));
    bar.finish_and_clear();
    result
}

/// Writes `result` to `path` whole or not at all, as Parquet or CSV.
fn save(result: &Table, path: &Path, parquet: bool) -> Result<(), Error> {
    let name = path.display().to_string();
    write_complete(path, |file| {
        if parquet {
            #[cfg(feature = "parquet")]
            return hamel::parquet::write(result, file, &name);
        }
        result.write_csv(file).map_err(|e| Error::Io {
            path: name.clone(),
            message: e.to_string(),
        })
    })
}

/// One task of a batch engine: shard `shard` of the table at `table` into `out`.
fn shard_task(s: &Settings, table: &Path, out: &Path) -> Result<(), Error> {
    let shard = s.shard.unwrap_or(Shard::ALL);
    // Everything that can be refused is refused before any case runs.
    check_writable(out)?;
    let cases = ParameterTable::read(table, &PARAMETERS)?;
    let parquet = s
        .format
        .as_deref()
        .map_or(cfg!(feature = "parquet"), |f| f == "parquet");
    let path = out.join(shard.file_name(if parquet { "parquet" } else { "csv" }));
    if is_complete(&path) {
        println!("{} is complete: nothing to do", path.display());
        return Ok(());
    }
    let rows = shard.rows(cases.len());
    let started = Instant::now();
    let result = study(&cases, rows.clone(), s.threads)?;
    save(&result, &path, parquet)?;
    println!(
        "shard {}/{}: rows {}..{} of {}, {} failed, in {:.1} s; wrote {}",
        shard.index,
        shard.count,
        rows.start,
        rows.end,
        cases.len(),
        result.failed(),
        started.elapsed().as_secs_f64(),
        path.display()
    );
    Ok(())
}

/// The figure: the speeds against trail for five rider masses, and against rider mass for
/// five trails, the benchmark marked on both.
fn figure(result: &Table) -> Figure {
    let (trail, mass) = (
        result.column("trail").unwrap(),
        result.column("rider_mass").unwrap(),
    );
    let (weave, capsize) = (
        result.column("weave_speed").unwrap(),
        result.column("capsize_speed").unwrap(),
    );
    let slice = |keep: &dyn Fn(usize) -> bool, x: &[f64], y: &[f64]| {
        let rows = (0..result.len()).filter(|&i| keep(i) && y[i].is_finite());
        rows.map(|i| (x[i], y[i]))
            .unzip::<f64, f64, Vec<f64>, Vec<f64>>()
    };
    let near = |a: f64, b: f64| (a - b).abs() < 1e-9;
    let mut by_trail = Panel::new("Self-stable range against trail")
        .x_label("trail c (m)")
        .y_label("speed (m/s)");
    for (k, m) in [60.0, 72.5, 85.0, 97.5, 110.0].into_iter().enumerate() {
        let (x, w) = slice(&|i| near(mass[i], m), trail, weave);
        let (xc, c) = slice(&|i| near(mass[i], m), trail, capsize);
        by_trail = by_trail
            .series(Series::line(format!("weave, rider {m} kg"), &x, &w).color(PALETTE[k]))
            .series(Series::dashed(format!("capsize, rider {m} kg"), &xc, &c).color(PALETTE[k]));
    }
    let mut by_mass = Panel::new("Self-stable range against rider mass")
        .x_label("rider mass (kg)")
        .y_label("speed (m/s)");
    for (k, c) in [0.04, 0.06, 0.08, 0.1, 0.12].into_iter().enumerate() {
        let (x, w) = slice(&|i| near(trail[i], c), mass, weave);
        let (xc, cs) = slice(&|i| near(trail[i], c), mass, capsize);
        by_mass = by_mass
            .series(Series::line(format!("weave, trail {c} m"), &x, &w).color(PALETTE[k]))
            .series(Series::dashed(format!("capsize, trail {c} m"), &xc, &cs).color(PALETTE[k]));
    }
    let (vw, vc) = PUBLISHED;
    let benchmark = |x: f64| {
        Series::points("benchmark (Meijaard et al. 2007)", &[x, x], &[vw, vc]).color(Rgb(0, 0, 0))
    };
    Figure::new()
        .columns(2)
        .panel(by_trail.series(benchmark(0.08)))
        .panel(by_mass.series(benchmark(BENCHMARK_RIDER)))
        .size(1400, 600)
}

/// The whole grid on this machine, with the table, the figure and the benchmark point.
fn local(s: &Settings) -> Result<(), Error> {
    let cases = grid();
    let started = Instant::now();
    let result = study(&cases, 0..cases.len(), s.threads)?;
    let seconds = started.elapsed().as_secs_f64();
    println!(
        "Whipple bicycle: weave and capsize speeds for {} cases (trail 0.04 … 0.12 m × rider \
         mass 60 … 110 kg), {} linearizations, {} failed, in {seconds:.2} s on {} threads",
        result.len(),
        LINEARIZATIONS.load(Ordering::Relaxed),
        result.failed(),
        s.threads.unwrap_or_else(rayon_threads)
    );
    let at = (0..result.len())
        .find(|&i| cases.get(i, "trail") == Some(0.08) && cases.get(i, "rider_mass") == Some(85.0))
        .expect("the benchmark is on the grid");
    let row = result.row(at).expect("the benchmark's row");
    println!(
        "benchmark point (trail 0.08 m, rider 85 kg): weave {:.14} m/s, capsize {:.14} m/s \
         (published {} and {})",
        row[2], row[3], PUBLISHED.0, PUBLISHED.1
    );
    // Eleven decimals, as the published values agree with the others of the benchmark's
    // literature.
    if (row[2] - PUBLISHED.0).abs() > 1e-11 || (row[3] - PUBLISHED.1).abs() > 1e-11 {
        return Err(Error::InvalidSetting {
            name: "benchmark point",
            value: row[2],
            reason: "the study does not reproduce the published weave and capsize speeds",
        });
    }
    result.save_csv("bicycle_study.csv")?;
    println!(
        "wrote {} rows to bicycle_study.csv ({})",
        result.len(),
        ["case"]
            .iter()
            .map(|s| s.to_string())
            .chain(columns())
            .chain(["error".to_string()])
            .collect::<Vec<_>>()
            .join(",")
    );
    #[cfg(feature = "parquet")]
    {
        save(&result, Path::new("bicycle_study.parquet"), true)?;
        println!("wrote bicycle_study.parquet");
    }
    let plot = figure(&result);
    plot.save("bicycle_study.svg")?;
    plot.save("bicycle_study.png")?;
    println!(
        "wrote bicycle_study.svg and bicycle_study.png (the speeds against trail and against \
         rider mass)"
    );
    Ok(())
}

/// The threads of rayon's global pool: every core.
fn rayon_threads() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

fn run(s: &Settings) -> Result<(), Error> {
    if let Some(path) = &s.write_grid {
        let grid = grid();
        std::fs::write(path, grid.to_csv()).map_err(|e| Error::Io {
            path: path.display().to_string(),
            message: e.to_string(),
        })?;
        println!("wrote {} cases to {}", grid.len(), path.display());
        return Ok(());
    }
    match (&s.table, &s.out) {
        (Some(table), Some(out)) => shard_task(s, table, out),
        _ => local(s),
    }
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match parse(&args) {
        Ok(None) => {
            print!("{HELP}");
            ExitCode::SUCCESS
        }
        Ok(Some(settings)) => match run(&settings) {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("error: {e}");
                ExitCode::FAILURE
            }
        },
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::from(2)
        }
    }
}
