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
//! `bicycle_study.parquet` when built with `--features parquet`), the figure
//! `bicycle_study.svg` (and `.png`), and the stability maps `bicycle_stability.svg` (and
//! `.png`): the largest real part of the lateral eigenvalues over speed (0 … 10 m/s in steps
//! of 0.1) and trail at the benchmark's rider, and over speed and rider mass at the
//! benchmark's trail (38 rows of 101 linearizations more), blue where the bicycle is
//! self-stable and red where it is not, with the study's weave and capsize speeds drawn as
//! the boundaries. With `--table`, `--shard i/n` and `--out DIR` it is one task of a
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
use hamel::plot::{ColorScale, Field, Figure, PALETTE, Panel, Rgb, Series, Style};
use hamel::prelude::*;
use hamel::roots::brent;
use hamel::{Ensemble, ParameterTable, StudyProgress, Table};
use indicatif::{ProgressBar, ProgressStyle};

#[path = "support/bicycle_units.rs"]
mod bicycle_units;

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
  (no options)            the whole grid here: bicycle_study.csv (.parquet), .svg and .png,
                          and the stability maps bicycle_stability.svg and .png
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
/// five trails, the benchmark marked on both. A colour stands for a rider mass (a trail),
/// the line style for the speed: solid the weave speed, dashed the capsize speed.
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
    let units = bicycle_units::units();
    let speed = units.label("speed", "v");
    let mut by_trail = Panel::new("Self-stable range against trail")
        .x_label(units.label("trail c", "c"))
        .y_label(&speed);
    let kg = units.unit("m_b").map_or(String::new(), |u| format!(" {u}"));
    for (k, m) in [60.0, 72.5, 85.0, 97.5, 110.0].into_iter().enumerate() {
        let (x, w) = slice(&|i| near(mass[i], m), trail, weave);
        let (xc, c) = slice(&|i| near(mass[i], m), trail, capsize);
        by_trail = by_trail
            .series(Series::line(format!("rider {m}{kg}"), &x, &w).color(PALETTE[k]))
            .series(Series::dashed("", &xc, &c).color(PALETTE[k]));
    }
    let mut by_mass = Panel::new("Self-stable range against rider mass")
        .x_label(units.label("rider mass m_b", "m_b"))
        .y_label(&speed);
    let m = units.unit("c").map_or(String::new(), |u| format!(" {u}"));
    for (k, c) in [0.04, 0.06, 0.08, 0.1, 0.12].into_iter().enumerate() {
        let (x, w) = slice(&|i| near(trail[i], c), mass, weave);
        let (xc, cs) = slice(&|i| near(trail[i], c), mass, capsize);
        by_mass = by_mass
            .series(Series::line(format!("trail {c}{m}"), &x, &w).color(PALETTE[k]))
            .series(Series::dashed("", &xc, &cs).color(PALETTE[k]));
    }
    let (vw, vc) = PUBLISHED;
    let finish = |panel: Panel, x: f64| {
        panel
            .series(
                Series::points("benchmark (Meijaard et al. 2007)", &[x, x], &[vw, vc])
                    .color(Rgb(0, 0, 0)),
            )
            .key("weave speed", Style::Line, Rgb(0, 0, 0))
            .key("capsize speed", Style::Dashed, Rgb(0, 0, 0))
    };
    Figure::new()
        .columns(2)
        .panel(finish(by_trail, 0.08))
        .panel(finish(by_mass, BENCHMARK_RIDER))
        .size(1400, 600)
}

/// The stability maps' speeds: 0 … 10 m/s in steps of 0.1.
fn map_speeds() -> Vec<f64> {
    (0..=100).map(|i| 0.1 * f64::from(i)).collect()
}

/// A bicycle of the study: (trail, rider mass).
type Case = (f64, f64);

/// The rows of the stability maps: the grid's trails at the benchmark's rider, and its
/// rider masses at the benchmark's trail.
fn map_rows() -> (Vec<Case>, Vec<Case>) {
    let trails = (0..=16).map(|i| (0.04 + 0.005 * i as f64, BENCHMARK_RIDER));
    let masses = (0..=20).map(|j| (0.08, 60.0 + 2.5 * j as f64));
    (trails.collect(), masses.collect())
}

/// The largest real part of the lateral eigenvalues at every map speed, for each
/// (trail, rider mass) of `rows`, on every core: one row of values per case, NaN where a
/// linearization failed.
fn abscissa_rows(rows: &[Case], threads: Option<usize>) -> Result<Vec<Vec<f64>>, Error> {
    let speeds = map_speeds();
    let mut ensemble = Ensemble::new(rows.len());
    if let Some(n) = threads {
        ensemble = ensemble.threads(n);
    }
    let results = ensemble.run(|i| {
        let bike = bicycle(rows[i].0, rows[i].1);
        Ok(speeds
            .iter()
            .map(|&v| abscissa(&bike, v).unwrap_or(f64::NAN))
            .collect::<Vec<f64>>())
    })?;
    Ok(results
        .into_iter()
        .map(|r| r.unwrap_or_else(|_| vec![f64::NAN; speeds.len()]))
        .collect())
}

/// One stability map: the largest real part over speed (x) and `parameter` (y), with the
/// weave and capsize speeds of the study's rows at those parameters drawn over it, and the
/// benchmark marked.
fn stability_panel(
    title: &str,
    (label, values): (&str, &[f64]),
    abscissae: &[Vec<f64>],
    speeds: (&[f64], &[f64]),
    benchmark: f64,
) -> Panel {
    let units = bicycle_units::units();
    let flat: Vec<f64> = abscissae.iter().flatten().copied().collect();
    // Growth rates span decades, the capsize's a tenth of the weave's at low speed: on a
    // logarithmic scale beyond 0.05 either side reads clearly.
    let field = Field::new(
        units.label("largest Re λ", "λ"),
        &map_speeds(),
        values,
        &flat,
    )
    .scale(ColorScale::SymLog { linear: 0.05 });
    let (vw, vc) = PUBLISHED;
    Panel::new(title)
        .x_label(units.label("forward speed v", "v"))
        .y_label(label)
        .x_range(0.0, 10.0)
        .field(field)
        .series(Series::line("weave speed", speeds.0, values).color(Rgb(0, 0, 0)))
        .series(Series::dashed("capsize speed", speeds.1, values).color(Rgb(0, 0, 0)))
        .series(
            Series::points(
                "benchmark (Meijaard et al. 2007)",
                &[vw, vc],
                &[benchmark; 2],
            )
            .color(PALETTE[2]),
        )
}

/// The stability maps: the largest real part of the lateral eigenvalues over speed and
/// trail (the benchmark's rider) and over speed and rider mass (the benchmark's trail),
/// blue where the bicycle is self-stable, red where it is not, the study's weave and
/// capsize speeds — the boundaries — drawn over them.
fn stability_figure(result: &Table, threads: Option<usize>) -> Result<Figure, Error> {
    let (trail_rows, mass_rows) = map_rows();
    let units = bicycle_units::units();
    let (trail, mass) = (column(result, "trail")?, column(result, "rider_mass")?);
    let (weave, capsize) = (
        column(result, "weave_speed")?,
        column(result, "capsize_speed")?,
    );
    let near = |a: f64, b: f64| (a - b).abs() < 1e-9;
    // The study's speeds at each map row (NaN for a row the study lacks or failed).
    let speeds_at = |rows: &[Case], of: &[f64]| -> Vec<f64> {
        rows.iter()
            .map(|&(c, m)| {
                (0..result.len())
                    .find(|&i| near(trail[i], c) && near(mass[i], m))
                    .map_or(f64::NAN, |i| of[i])
            })
            .collect()
    };
    let unit = |name: &str| units.unit(name).map_or(String::new(), |u| format!(" {u}"));
    let by_trail = stability_panel(
        &format!(
            "Stability against trail (rider {BENCHMARK_RIDER}{})",
            unit("m_b")
        ),
        (
            &units.label("trail c", "c"),
            &trail_rows.iter().map(|r| r.0).collect::<Vec<_>>(),
        ),
        &abscissa_rows(&trail_rows, threads)?,
        (
            &speeds_at(&trail_rows, weave),
            &speeds_at(&trail_rows, capsize),
        ),
        0.08,
    );
    let by_mass = stability_panel(
        &format!("Stability against rider mass (trail 0.08{})", unit("c")),
        (
            &units.label("rider mass m_b", "m_b"),
            &mass_rows.iter().map(|r| r.1).collect::<Vec<_>>(),
        ),
        &abscissa_rows(&mass_rows, threads)?,
        (
            &speeds_at(&mass_rows, weave),
            &speeds_at(&mass_rows, capsize),
        ),
        BENCHMARK_RIDER,
    );
    Ok(Figure::new()
        .columns(1)
        .panel(by_trail)
        .panel(by_mass)
        .size(1100, 1000))
}

/// The study's column `name`.
fn column<'a>(result: &'a Table, name: &str) -> Result<&'a [f64], Error> {
    result.column(name).ok_or_else(|| Error::UnknownName {
        kind: "column",
        name: name.to_string(),
        known: result.names().join(", "),
    })
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
    let maps = stability_figure(&result, s.threads)?;
    maps.save("bicycle_stability.svg")?;
    maps.save("bicycle_stability.png")?;
    println!(
        "wrote bicycle_stability.svg and bicycle_stability.png (the largest real part over \
         speed and trail, and over speed and rider mass); {} linearizations in all",
        LINEARIZATIONS.load(Ordering::Relaxed)
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
