//! The work–precision rows of every solver side by side: hamel's, scipy's and diffsol's, read
//! from the CSVs `run.sh` has the three write round by round, as tables and as one figure per
//! problem (error against wall time, both logarithmic).
//!
//! Wall-time ratios are taken per round, between runs made close together (`run.sh`
//! alternates the solvers problem by problem), and only then summarized over the rounds: the
//! machine's speed drifts, and cancels from a ratio of runs made close together.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::io::Write as _;
use std::path::{Path, PathBuf};

use hamel::plot::{Figure, Panel, Rgb, Series, Style};
use hamel_benches::interleave::Spread;

/// The solvers whose rows are measured here, and the others' labels in their CSVs.
pub const RADAU5: &str = "hamel Radau5";
pub const RODAS5P: &str = "hamel Rodas5P";
pub const RADAU5_DIFFERENCED: &str = "hamel Radau5 (differences)";
pub const RODAS5P_DIFFERENCED: &str = "hamel Rodas5P (differences)";
/// hamel's methods with the exact Jacobian.
const EXACT: [&str; 2] = [RADAU5, RODAS5P];
const OTHERS: [&str; 7] = [
    "scipy Radau",
    "scipy BDF",
    "scipy LSODA",
    "Hairer RADAU5",
    "Hairer RODAS",
    "diffsol BDF",
    "diffsol ESDIRK34",
];
/// scipy's Radau without the Jacobian (num_jac), its evaluations every call.
const SCIPY_DIFFERENCED: &str = "scipy Radau (differences)";

/// The tightest rtol of the points compared. Radau5 also runs tighter, so that its curve
/// reaches the errors the others reach at 10⁻¹⁰ (`RADAU5_TOLERANCES` in
/// `benches/work_precision.rs`); those runs serve as the curve others are read on, not as
/// points of their own.
const TIGHTEST: f64 = 1e-10;

/// The loosest rtol of the points compared. Rodas5P also runs looser, so that its curve
/// reaches the errors Radau5 reaches at 10⁻³ (`RODAS5P_TOLERANCES`).
const LOOSEST: f64 = 1e-3;

/// Whether `r` is one of the points compared: a run at rtol 10⁻³…10⁻¹⁰.
fn compared(r: &Row) -> bool {
    r.rtol >= 0.999 * TIGHTEST && r.rtol <= 1.001 * LOOSEST
}

/// One run: a solver on a problem at a tolerance, in a round of `run.sh`. Counts are NaN
/// where a solver does not report them.
#[derive(Clone, Debug)]
pub struct Row {
    pub round: usize,
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
    "round,problem,solver,rtol,error,steps,rejected,evaluations,jacobians,factorizations,wall";

/// Where `run.sh` has the solvers write their CSVs.
pub fn data_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/work_precision")
}

fn figure_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("work_precision")
}

/// Appends `rows` to the CSV at `path`, with the header if the file is new.
pub fn append_csv(rows: &[Row], path: &Path) {
    let text = csv_text(rows, !path.exists());
    std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(path)
        .and_then(|mut file| file.write_all(text.as_bytes()))
        .expect("append to the CSV");
}

/// `rows` as CSV lines, after the header if `header`.
pub fn csv_text(rows: &[Row], header: bool) -> String {
    let mut text = String::new();
    if header {
        text = format!("{HEADER}\n");
    }
    for r in rows {
        let _ = writeln!(
            text,
            "{},{},{},{:e},{:e},{},{},{},{},{},{:e}",
            r.round,
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
    text
}

/// The rows of a CSV that `append_csv`, `scipy_stiff.py` or the diffsol crate wrote (none if
/// the file is missing).
pub fn read_csv(path: &Path) -> Vec<Row> {
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
            (f.len() == 11).then(|| Row {
                round: f[0].parse().unwrap_or(0),
                problem: f[1].into(),
                solver: f[2].into(),
                rtol: num(3),
                error: num(4),
                steps: num(5),
                rejected: num(6),
                evaluations: num(7),
                jacobians: num(8),
                factorizations: num(9),
                wall: num(10),
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

fn median(values: impl Iterator<Item = f64>) -> f64 {
    Spread::of(&values.collect::<Vec<_>>()).median
}

/// One row per problem, solver and tolerance: each field's median over the rounds (the
/// counts and errors are the same in every round; the wall time is not).
fn medians(rows: &[Row]) -> Vec<Row> {
    let mut groups: Vec<Vec<&Row>> = Vec::new();
    for r in rows {
        let same = |g: &&mut Vec<&Row>| {
            g[0].problem == r.problem && g[0].solver == r.solver && g[0].rtol == r.rtol
        };
        match groups.iter_mut().find(same) {
            Some(group) => group.push(r),
            None => groups.push(vec![r]),
        }
    }
    groups
        .into_iter()
        .map(|g| {
            let of = |field: fn(&Row) -> f64| median(g.iter().map(|r| field(r)));
            Row {
                round: 0,
                problem: g[0].problem.clone(),
                solver: g[0].solver.clone(),
                rtol: g[0].rtol,
                error: of(|r| r.error),
                steps: of(|r| r.steps),
                rejected: of(|r| r.rejected),
                evaluations: of(|r| r.evaluations),
                jacobians: of(|r| r.jacobians),
                factorizations: of(|r| r.factorizations),
                wall: of(|r| r.wall),
            }
        })
        .collect()
}

/// Prints every solver's table per problem (medians over the rounds) and, if other solvers'
/// rows are there, the equal-error ratios; draws the figures if `figures`.
pub fn report(rows: &[Row], figures: bool) {
    let mut rounds: Vec<usize> = rows.iter().map(|r| r.round).collect();
    rounds.sort_unstable();
    rounds.dedup();
    let points = medians(rows);
    let mut problems: Vec<&str> = Vec::new();
    for r in &points {
        if !problems.contains(&r.problem.as_str()) {
            problems.push(&r.problem);
        }
    }
    for &problem in &problems {
        let of: Vec<&Row> = points.iter().filter(|r| r.problem == problem).collect();
        println!(
            "\n{problem} (wall time: median of {} rounds)\n",
            rounds.len()
        );
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
        if figures {
            draw(problem, &of);
        }
    }
    if rows.iter().any(|r| !r.solver.starts_with("hamel")) {
        for mine in EXACT {
            equal_error(
                rows,
                &points,
                &problems,
                &rounds,
                mine,
                "scipy Radau",
                &OTHERS,
            );
        }
        for mine in [RADAU5_DIFFERENCED, RODAS5P_DIFFERENCED] {
            equal_error(
                rows,
                &points,
                &problems,
                &rounds,
                mine,
                SCIPY_DIFFERENCED,
                &[SCIPY_DIFFERENCED, "diffsol BDF"],
            );
        }
        faster_of_the_two(rows, &points, &problems, &rounds);
        rodas_against_radau(rows, &problems, &rounds);
    }
}

/// `mine`'s wall time over `solver`'s at each error `mine` reached that `solver`'s curve also
/// reaches, among `rows` (one round's), keyed by `mine`'s rtol.
fn wall_ratios(rows: &[&Row], mine: &str, solver: &str) -> Vec<(f64, f64)> {
    let theirs: Vec<&Row> = rows
        .iter()
        .copied()
        .filter(|r| r.solver == solver)
        .collect();
    rows.iter()
        .filter(|r| r.solver == mine && compared(r))
        .filter_map(|r| at_error(&theirs, r.error, |r| r.wall).map(|v| (r.rtol, r.wall / v)))
        .collect()
}

fn shown(v: f64) -> String {
    if v < 0.1 {
        format!("{v:.1e}")
    } else {
        format!("{v:.2}")
    }
}

/// One problem's curve of `solver` (the medians over the rounds).
fn curve<'a>(points: &'a [Row], problem: &str, solver: &str) -> Vec<&'a Row> {
    points
        .iter()
        .filter(|r| r.problem == problem && r.solver == solver)
        .collect()
}

/// `mine` / `theirs` of a count at the errors `mine` reached that `theirs` reaches: the median
/// and the largest, as a table cell.
fn count_ratio(mine: &[&Row], theirs: &[&Row], field: fn(&Row) -> f64) -> String {
    let mut ratios: Vec<f64> = mine
        .iter()
        .filter(|r| compared(r))
        .filter_map(|r| at_error(theirs, r.error, field).map(|v| field(r) / v))
        .collect();
    ratios.sort_by(f64::total_cmp);
    match ratios.last() {
        Some(&largest) => format!(
            "{} ({}, n = {})",
            shown(median(ratios.iter().copied())),
            shown(largest),
            ratios.len()
        ),
        None => "–".into(),
    }
}

/// The wall-time ratio of `mine` over `solver` on `problem`: in each round the median over
/// the errors both reach, then the median and p10–p90 of these, and the largest per-error
/// median, as a table cell.
fn wall_cell(rows: &[Row], problem: &str, rounds: &[usize], mine: &str, solver: &str) -> String {
    let mut per_round = Vec::new();
    let mut per_error: BTreeMap<u64, Vec<f64>> = BTreeMap::new();
    for &round in rounds {
        let of: Vec<&Row> = rows
            .iter()
            .filter(|r| r.problem == problem && r.round == round)
            .collect();
        let ratios = wall_ratios(&of, mine, solver);
        if !ratios.is_empty() {
            per_round.push(median(ratios.iter().map(|&(_, v)| v)));
        }
        for (rtol, v) in ratios {
            per_error.entry(rtol.to_bits()).or_default().push(v);
        }
    }
    if per_round.is_empty() {
        return "–".into();
    }
    let spread = Spread::of(&per_round);
    let largest = per_error
        .values()
        .map(|v| median(v.iter().copied()))
        .fold(0.0, f64::max);
    format!(
        "{} ({}–{}), max {}, n = {}",
        shown(spread.median),
        shown(spread.p10),
        shown(spread.p90),
        shown(largest),
        per_error.len()
    )
}

/// Per problem, `mine` / other at equal achieved error: evaluations and LUs against
/// `counted` (the same in every round: the median and the largest over `mine`'s errors that
/// the other's curve reaches), wall times against each of `others`.
fn equal_error(
    rows: &[Row],
    points: &[Row],
    problems: &[&str],
    rounds: &[usize],
    mine: &str,
    counted: &str,
    others: &[&str],
) {
    println!(
        "\nAt equal achieved error, {mine} / other. Evaluations and LUs: median (largest) over \
         the errors both reach. Wall: median over {} rounds of each round's median over those \
         errors (p10–p90 over the rounds), the largest over the errors of the per-error medians\n",
        rounds.len()
    );
    println!(
        "| problem | evaluations / {counted} | LU / {counted} | wall / {} |",
        others.join(" | wall / ")
    );
    println!("|---|---:|---:{}|", "|---:".repeat(others.len()));
    for &problem in problems {
        let ours = curve(points, problem, mine);
        if ours.is_empty()
            || !rows
                .iter()
                .any(|r| r.problem == problem && r.solver == counted)
        {
            continue;
        }
        let theirs = curve(points, problem, counted);
        let mut line = format!(
            "| {problem} | {} | {}",
            count_ratio(&ours, &theirs, |r| r.evaluations),
            count_ratio(&ours, &theirs, |r| r.factorizations)
        );
        for solver in others {
            let _ = write!(
                line,
                " | {}",
                wall_cell(rows, problem, rounds, mine, solver)
            );
        }
        println!("{line} |");
    }
}

/// The condition at every rtol: at the error each of Radau5 and Rodas5P reaches, the
/// faster of the two there (their wall times interpolated at that error, medians over the
/// rounds) against scipy's Radau in evaluations and diffsol's BDF in wall time (per round,
/// then the median).
fn faster_of_the_two(rows: &[Row], points: &[Row], problems: &[&str], rounds: &[usize]) {
    println!(
        "\nThe faster of hamel's Radau5 and Rodas5P at each error either reaches at rtol \
         1e-3…1e-10 (its rtol given; Radau5's curve runs on to rtol 1e-13): its evaluations / \
         scipy Radau's and its wall time / diffsol BDF's (median of the per-round ratios) at \
         that error\n"
    );
    println!(
        "| problem | rtol | faster | error | evaluations / scipy Radau | wall / diffsol BDF |"
    );
    println!("|---|---:|---|---:|---:|---:|");
    for &problem in problems {
        let (radau, rodas) = (
            curve(points, problem, RADAU5),
            curve(points, problem, RODAS5P),
        );
        if radau.is_empty() || rodas.is_empty() {
            continue;
        }
        let scipy = curve(points, problem, "scipy Radau");
        for r in radau.iter().chain(&rodas).filter(|r| compared(r)) {
            let other = if r.solver == RADAU5 { &rodas } else { &radau };
            let faster = match at_error(other, r.error, |r| r.wall) {
                Some(w) if w < r.wall => other[0].solver.as_str(),
                _ => r.solver.as_str(),
            };
            let faster_curve = curve(points, problem, faster);
            let evaluations = at_error(&faster_curve, r.error, |r| r.evaluations)
                .zip(at_error(&scipy, r.error, |r| r.evaluations))
                .map(|(a, b)| shown(a / b))
                .unwrap_or_else(|| "–".into());
            let walls: Vec<f64> = rounds
                .iter()
                .filter_map(|&round| {
                    let of: Vec<&Row> = rows
                        .iter()
                        .filter(|x| x.problem == problem && x.round == round)
                        .collect();
                    let pick = |solver: &str| -> Vec<&Row> {
                        of.iter().copied().filter(|x| x.solver == solver).collect()
                    };
                    let mine = at_error(&pick(faster), r.error, |x| x.wall)?;
                    let bdf = at_error(&pick("diffsol BDF"), r.error, |x| x.wall)?;
                    Some(mine / bdf)
                })
                .collect();
            let wall = if walls.is_empty() {
                "–".into()
            } else {
                shown(median(walls.into_iter()))
            };
            println!(
                "| {problem} | {:.0e} ({}) | {} | {:.1e} | {evaluations} | {wall} |",
                r.rtol,
                r.solver.trim_start_matches("hamel "),
                faster.trim_start_matches("hamel "),
                r.error
            );
        }
    }
}

/// Rodas5P's wall time over Radau5's at equal error, at Rodas5P's rtol 10⁻³…10⁻⁶ (per round,
/// then the median and p10–p90 over the rounds).
fn rodas_against_radau(rows: &[Row], problems: &[&str], rounds: &[usize]) {
    println!(
        "\nRodas5P / Radau5 wall time at equal error, at Rodas5P's rtol 1e-3…1e-6 (median over \
         the rounds, p10–p90)\n"
    );
    println!("| problem | 1e-3 | 1e-4 | 1e-5 | 1e-6 |");
    println!("|---|---:|---:|---:|---:|");
    for &problem in problems {
        let mut line = format!("| {problem}");
        for rtol in [1e-3, 1e-4, 1e-5, 1e-6] {
            let ratios: Vec<f64> = rounds
                .iter()
                .filter_map(|&round| {
                    let of: Vec<&Row> = rows
                        .iter()
                        .filter(|x| x.problem == problem && x.round == round)
                        .collect();
                    let rodas = of.iter().find(|x| x.solver == RODAS5P && x.rtol == rtol)?;
                    let radau: Vec<&Row> =
                        of.iter().copied().filter(|x| x.solver == RADAU5).collect();
                    at_error(&radau, rodas.error, |x| x.wall).map(|w| rodas.wall / w)
                })
                .collect();
            if ratios.is_empty() {
                line += " | –";
            } else {
                let spread = Spread::of(&ratios);
                let _ = write!(
                    line,
                    " | {} ({}–{})",
                    shown(spread.median),
                    shown(spread.p10),
                    shown(spread.p90)
                );
            }
        }
        println!("{line} |");
    }
}

/// Each solver's colour and line in the figures, a pair of its own for each of the twelve
/// series (the plot's palette has ten colours and repeated two): a method's colour, dashed
/// for its runs without a Jacobian (hamel's Radau5 and Rodas5P, scipy's Radau). A solver not
/// listed gets black dots only.
const LOOKS: [(&str, Rgb, Style); 12] = [
    (RADAU5, Rgb(214, 39, 40), Style::Line),
    (RODAS5P, Rgb(31, 119, 180), Style::Line),
    (RADAU5_DIFFERENCED, Rgb(214, 39, 40), Style::Dashed),
    (RODAS5P_DIFFERENCED, Rgb(31, 119, 180), Style::Dashed),
    ("scipy Radau", Rgb(255, 127, 14), Style::Line),
    (SCIPY_DIFFERENCED, Rgb(255, 127, 14), Style::Dashed),
    ("scipy BDF", Rgb(188, 189, 34), Style::Line),
    ("scipy LSODA", Rgb(23, 190, 207), Style::Line),
    ("Hairer RADAU5", Rgb(0, 0, 0), Style::Line),
    ("Hairer RODAS", Rgb(127, 127, 127), Style::Line),
    ("diffsol BDF", Rgb(44, 160, 44), Style::Line),
    ("diffsol ESDIRK34", Rgb(148, 103, 189), Style::Line),
];

/// Error against wall time for every solver on `problem`, into `<problem>.svg` (with
/// `hamel::plot`, whose panels have a logarithmic y axis: the x axis is log₁₀ of the time),
/// each run a dot on its solver's line.
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
        .x_label("log10 of the wall time in s (median of rounds)")
        .y_label("achieved error")
        .log_y();
    // In LOOKS's order, so that the legend groups hamel's, scipy's, Hairer's and diffsol's.
    let order = |solver: &str| LOOKS.iter().position(|(s, ..)| *s == solver);
    let mut solvers: Vec<_> = by_solver.into_iter().collect();
    solvers.sort_by_key(|(solver, _)| order(solver).unwrap_or(LOOKS.len()));
    for (solver, mut points) in solvers {
        points.sort_by(|a, b| a.0.total_cmp(&b.0));
        let (x, y): (Vec<f64>, Vec<f64>) = points.into_iter().unzip();
        let (color, style) = match order(solver) {
            Some(i) => (LOOKS[i].1, LOOKS[i].2),
            None => (Rgb(0, 0, 0), Style::Points),
        };
        panel = panel.series(Series::new(solver, &x, &y, style).color(color));
        if style != Style::Points {
            // Unnamed: a dot at each run, without a legend entry of its own.
            panel = panel.series(Series::points("", &x, &y).color(color));
        }
    }
    let name = problem.to_lowercase().replace(' ', "_");
    Figure::new()
        .panel(panel)
        .size(960, 600)
        .save_svg(figure_dir().join(format!("{name}.svg")))
        .expect("write the figure");
}
