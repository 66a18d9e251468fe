//! The bicycle study's figures: the weave and capsize speeds against trail and against rider
//! mass (`bicycle_study.svg`, `.png`), and the stability maps (`bicycle_stability.svg`,
//! `.png`): the largest real part of the lateral eigenvalues over speed (0 … 10 m/s in steps
//! of 0.1) and trail at the benchmark's rider, and over speed and rider mass at the
//! benchmark's trail, blue where the bicycle is self-stable and red where it is not, with
//! the study's weave and capsize speeds drawn as the boundaries.

use hamel::plot::{ColorScale, Field, Figure, PALETTE, Panel, Rgb, Series, Style};
use hamel::study::Finished;
use hamel::{Ensemble, Error, Table};

use super::bicycle_units;

/// The benchmark's rear body (frame and rider), which a rider's mass scales.
pub const BENCHMARK_RIDER: f64 = 85.0;

/// The published weave and capsize speeds (Meijaard et al. 2007, Table 2).
pub const PUBLISHED: (f64, f64) = (4.29238253634111, 6.02426201538837);

/// The largest real part of the lateral eigenvalues of the bicycle (trail, rider mass) at a
/// speed.
pub type Abscissa<'a> = &'a (dyn Fn(f64, f64, f64) -> Result<f64, Error> + Sync);

/// A line on the standard output, if it can be written: a reader that closed it early
/// (`bicycle_study | head -1`) loses the report's lines, not the files.
fn say(line: std::fmt::Arguments) {
    use std::io::Write as _;
    let _ = writeln!(std::io::stdout(), "{line}");
}

/// The benchmark point's check, the figures and the stability maps.
pub fn report(
    run: &Finished,
    linearizations: &dyn Fn() -> usize,
    abscissa: Abscissa,
) -> Result<(), Error> {
    let (result, count) = (run.table, linearizations());
    say(format_args!(
        "Whipple bicycle: weave and capsize speeds for {} cases (trail 0.04 … 0.12 m × rider \
         mass 60 … 110 kg), {count} linearizations, {} failed, in {:.2} s on {} threads",
        result.len(),
        result.failed(),
        run.elapsed.as_secs_f64(),
        run.threads_used
    ));
    let at = (0..result.len()).find(|&i| result.row(i).is_some_and(|r| r[..2] == [0.08, 85.0]));
    let row = result.row(at.unwrap_or(usize::MAX)).unwrap_or_default();
    let (weave, capsize) = (
        row.get(2).copied().unwrap_or(f64::NAN),
        row.get(3).copied().unwrap_or(f64::NAN),
    );
    say(format_args!(
        "benchmark point (trail 0.08 m, rider 85 kg): weave {weave:.14} m/s, capsize \
         {capsize:.14} m/s (published {} and {})",
        PUBLISHED.0, PUBLISHED.1
    ));
    // Eleven decimals, as the published values agree with the others of the benchmark's
    // literature.
    if !((weave - PUBLISHED.0).abs() <= 1e-11 && (capsize - PUBLISHED.1).abs() <= 1e-11) {
        let reason = "the study does not reproduce the published weave and capsize speeds";
        return Err(Error::InvalidSetting {
            name: "benchmark point",
            value: weave,
            reason,
        });
    }
    let plot = figure(result);
    plot.save("bicycle_study.svg")?;
    plot.save("bicycle_study.png")?;
    say(format_args!(
        "wrote bicycle_study.svg and bicycle_study.png (the speeds against trail and against rider mass)"
    ));
    let maps = stability_figure(result, run.threads, abscissa)?;
    maps.save("bicycle_stability.svg")?;
    maps.save("bicycle_stability.png")?;
    say(format_args!(
        "wrote bicycle_stability.svg and bicycle_stability.png (the largest real part over \
         speed and trail, and over speed and rider mass); {} linearizations in all",
        linearizations()
    ));
    Ok(())
}

/// The figure: the speeds against trail for five rider masses, and against rider mass for
/// five trails, the benchmark marked on both. A colour stands for a rider mass (a trail),
/// the line style for the speed: solid the weave speed, dashed the capsize speed.
pub fn figure(result: &Table) -> Figure {
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
fn abscissa_rows(
    rows: &[Case],
    threads: Option<usize>,
    abscissa: Abscissa,
) -> Result<Vec<Vec<f64>>, Error> {
    let speeds = map_speeds();
    let mut ensemble = Ensemble::new(rows.len());
    if let Some(n) = threads {
        ensemble = ensemble.threads(n);
    }
    let results = ensemble.run(|i| {
        Ok(speeds
            .iter()
            .map(|&v| abscissa(rows[i].0, rows[i].1, v).unwrap_or(f64::NAN))
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
pub fn stability_figure(
    result: &Table,
    threads: Option<usize>,
    abscissa: Abscissa,
) -> Result<Figure, Error> {
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
        &abscissa_rows(&trail_rows, threads, abscissa)?,
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
        &abscissa_rows(&mass_rows, threads, abscissa)?,
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
