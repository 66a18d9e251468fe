//! The work–precision rows of every solver side by side: hamel's (measured by the bench),
//! scipy's and diffsol's (read from the CSVs `run.sh` writes), as tables and as one figure
//! per problem (error against wall time, both logarithmic).

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use hamel::plot::{Figure, Panel};

/// One run: a solver on a problem at a tolerance. Counts are NaN where a solver does not
/// report them.
#[derive(Clone, Debug)]
pub struct Row {
    pub problem: String,
    pub solver: String,
    pub rtol: f64,
    pub error: f64,
    pub steps: f64,
    pub rejected: f64,
    pub evaluations: f64,
    pub jacobians: f64,
    pub factorizations: f64,
    pub wall: f64,
}

const HEADER: &str =
    "problem,solver,rtol,error,steps,rejected,evaluations,jacobians,factorizations,wall";

fn data_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/work_precision")
}

fn figure_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("work_precision")
}

fn write_csv(rows: &[Row], path: &Path) {
    let mut text = format!("{HEADER}\n");
    for r in rows {
        let _ = writeln!(
            text,
            "{},{},{:e},{:e},{},{},{},{},{},{:e}",
            r.problem,
            r.solver,
            r.rtol,
            r.error,
            r.steps,
            r.rejected,
            r.evaluations,
            r.jacobians,
            r.factorizations,
            r.wall
        );
    }
    std::fs::write(path, text).expect("write the CSV");
}

fn read_csv(path: &Path) -> Vec<Row> {
    let Ok(text) = std::fs::read_to_string(path) else {
        return Vec::new();
    };
    text.lines()
        .skip(1)
        .filter_map(|line| {
            let f: Vec<&str> = line.split(',').collect();
            let num = |i: usize| {
                f.get(i)
                    .and_then(|v| v.parse::<f64>().ok())
                    .unwrap_or(f64::NAN)
            };
            (f.len() == 10).then(|| Row {
                problem: f[0].into(),
                solver: f[1].into(),
                rtol: num(2),
                error: num(3),
                steps: num(4),
                rejected: num(5),
                evaluations: num(6),
                jacobians: num(7),
                factorizations: num(8),
                wall: num(9),
            })
        })
        .collect()
}

fn count(v: f64) -> String {
    if v.is_nan() {
        "–".into()
    } else {
        format!("{v:.0}")
    }
}

/// The value of `y` a solver's curve takes at the error `error`, interpolated linearly in
/// log–log between its two runs that bracket it (None outside its range).
fn at_error(curve: &[&Row], error: f64, y: impl Fn(&Row) -> f64) -> Option<f64> {
    let mut points: Vec<(f64, f64)> = curve
        .iter()
        .filter(|r| r.error > 0.0 && y(r) > 0.0 && y(r).is_finite())
        .map(|r| (r.error.ln(), y(r).ln()))
        .collect();
    points.sort_by(|a, b| a.0.total_cmp(&b.0));
    let e = error.ln();
    points.windows(2).find_map(|w| {
        let ((e0, y0), (e1, y1)) = (w[0], w[1]);
        (e0 <= e && e <= e1 && e1 > e0).then(|| (y0 + (y1 - y0) * (e - e0) / (e1 - e0)).exp())
    })
}

/// Prints the tables, the equal-error ratios, and draws the figures.
pub fn report(hamel: Vec<Row>) {
    let dir = data_dir();
    std::fs::create_dir_all(&dir).expect("the data directory");
    write_csv(&hamel, &dir.join("hamel.csv"));
    let mut rows = hamel;
    for other in ["scipy.csv", "diffsol.csv"] {
        rows.extend(read_csv(&dir.join(other)));
    }
    let mut problems: Vec<String> = Vec::new();
    for r in &rows {
        if !problems.contains(&r.problem) {
            problems.push(r.problem.clone());
        }
    }
    for problem in &problems {
        let of: Vec<&Row> = rows.iter().filter(|r| &r.problem == problem).collect();
        println!("\n{problem}\n");
        println!(
            "| solver | rtol | error | steps | rejected | evaluations | Jacobians | LU | wall (ms) |"
        );
        println!("|---|---:|---:|---:|---:|---:|---:|---:|---:|");
        for r in &of {
            println!(
                "| {} | {:.0e} | {:.2e} | {} | {} | {} | {} | {} | {:.3} |",
                r.solver,
                r.rtol,
                r.error,
                count(r.steps),
                count(r.rejected),
                count(r.evaluations),
                count(r.jacobians),
                count(r.factorizations),
                1e3 * r.wall
            );
        }
        draw(problem, &of);
    }
    equal_error(&rows, &problems);
}

/// Per problem: at the errors hamel's Radau5 achieved, the other solvers' evaluations and
/// wall times interpolated to the same error, as ratios hamel/other: the median and the
/// largest over the tolerances where both curves reach the error.
fn equal_error(rows: &[Row], problems: &[String]) {
    println!(
        "\nAt equal achieved error: hamel Radau5 / other median (largest) over the errors both reach\n"
    );
    println!(
        "| problem | evaluations / scipy Radau | wall / scipy Radau | wall / scipy BDF | wall / diffsol BDF | wall / diffsol SDIRK |"
    );
    println!("|---|---:|---:|---:|---:|---:|");
    for problem in problems {
        let curve = |solver: &str| -> Vec<&Row> {
            rows.iter()
                .filter(|r| &r.problem == problem && r.solver == solver)
                .collect()
        };
        let ours = curve("hamel Radau5");
        let median_ratio = |solver: &str, y: &dyn Fn(&Row) -> f64| -> String {
            let theirs = curve(solver);
            let mut ratios: Vec<f64> = ours
                .iter()
                .filter_map(|r| at_error(&theirs, r.error, y).map(|v| y(r) / v))
                .collect();
            if ratios.is_empty() {
                return "–".into();
            }
            ratios.sort_by(f64::total_cmp);
            let (median, worst) = (ratios[ratios.len() / 2], ratios[ratios.len() - 1]);
            let shown = |v: f64| {
                if v < 0.1 {
                    format!("{v:.1e}")
                } else {
                    format!("{v:.2}")
                }
            };
            format!(
                "{} (largest {}, n = {})",
                shown(median),
                shown(worst),
                ratios.len()
            )
        };
        let evaluations = |r: &Row| r.evaluations;
        let wall = |r: &Row| r.wall;
        println!(
            "| {problem} | {} | {} | {} | {} | {} |",
            median_ratio("scipy Radau", &evaluations),
            median_ratio("scipy Radau", &wall),
            median_ratio("scipy BDF", &wall),
            median_ratio("diffsol BDF", &wall),
            median_ratio("diffsol SDIRK", &wall),
        );
    }
}

/// Error against wall time for every solver on `problem`, into `<problem>.svg` (with
/// `hamel::plot`, whose panels have a logarithmic y axis: the x axis is log₁₀ of the time).
fn draw(problem: &str, rows: &[&Row]) {
    let mut by_solver: BTreeMap<&str, Vec<(f64, f64)>> = BTreeMap::new();
    for r in rows {
        if r.error > 0.0 && r.wall > 0.0 {
            by_solver
                .entry(&r.solver)
                .or_default()
                .push((r.wall.log10(), r.error));
        }
    }
    if by_solver.is_empty() {
        return;
    }
    let mut panel = Panel::new(format!("{problem}: achieved error against wall time"))
        .x_label("log10 of the wall time in s (median of runs)")
        .y_label("achieved error")
        .log_y();
    for (solver, mut points) in by_solver {
        points.sort_by(|a, b| a.0.total_cmp(&b.0));
        let (x, y): (Vec<f64>, Vec<f64>) = points.into_iter().unzip();
        panel = panel.line(solver, &x, &y);
    }
    let name = problem.to_lowercase().replace(' ', "_");
    Figure::new()
        .panel(panel)
        .size(720, 480)
        .save_svg(figure_dir().join(format!("{name}.svg")))
        .expect("write the figure");
}
