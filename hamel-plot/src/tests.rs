//! Files are written and well formed (SVG text with its labels, a PNG with the right
//! header), the rules for what is drawn, and every error. No test compares pixels.

use std::path::PathBuf;

use super::axis::Axis;
use super::legend;
use super::prepare::{Prepared, prepare};
use super::render::MIN_PANEL as MIN_PANEL_SIZE;
use super::*;
use hamel::models::{KnifeEdge, MobileRobot};
use hamel::{DormandPrince, HamelSystem, Simulation, Trajectory};

/// A fresh directory for one test's files.
fn scratch(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("hamel-plot-{}-{test}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The panel laid out for a 600 × 400 plotting area, its legend placed as a box of 150 ×
/// 60 pixels 10 pixels inside the frame, kept 5 pixels from the data.
fn lay_out(panel: &Panel) -> Result<Prepared, ErrorKind> {
    let mut prepared = prepare(panel, (600.0, 400.0))?;
    prepared.legend = legend::place(
        panel.legend,
        &prepared,
        (600.0, 400.0),
        (150.0, 60.0),
        10.0,
        5.0,
    );
    Ok(prepared)
}

fn ramp(n: usize) -> (Vec<f64>, Vec<f64>) {
    let x: Vec<f64> = (0..n).map(|i| i as f64 * 0.1).collect();
    let y = x.iter().map(|x| (x * 2.0).sin()).collect();
    (x, y)
}

fn two_series() -> Panel {
    let (x, y) = ramp(50);
    let z: Vec<f64> = y.iter().map(|y| 0.5 * y).collect();
    Panel::new("waves")
        .x_label("time t")
        .y_label("height h")
        .line("first wave", &x, &y)
        .dashed("second wave", &x, &z)
}

/// The width and height a PNG file's IHDR chunk declares, after checking the signature.
fn png_size(bytes: &[u8]) -> (u32, u32) {
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "PNG signature");
    assert_eq!(&bytes[8..12], &13u32.to_be_bytes(), "IHDR length");
    assert_eq!(&bytes[12..16], b"IHDR");
    let be = |at: usize| u32::from_be_bytes(bytes[at..at + 4].try_into().unwrap());
    (be(16), be(20))
}

/// The texts of an SVG document's `<text>` elements, trimmed.
fn texts(svg: &str) -> Vec<&str> {
    svg.split("<text")
        .skip(1)
        .filter_map(|t| Some(t.split_once('>')?.1.split_once("</text>")?.0.trim()))
        .collect()
}

/// An SVG document: starts with `<svg`, closes it, and has no NaN or infinity.
fn check_svg(svg: &str) {
    assert!(svg.starts_with("<svg"), "{}", &svg[..svg.len().min(80)]);
    assert!(svg.trim_end().ends_with("</svg>"));
    for bad in ["NaN", "inf"] {
        assert!(!svg.contains(bad), "{bad} in the SVG");
    }
}

#[test]
fn svg_has_title_axis_labels_and_legend() {
    let svg = Figure::from(two_series()).to_svg().unwrap();
    check_svg(&svg);
    let texts = texts(&svg);
    for text in ["waves", "time t", "height h", "first wave", "second wave"] {
        assert!(texts.contains(&text), "`{text}` missing from {texts:?}");
    }
}

#[test]
fn a_single_series_has_no_legend() {
    let (x, y) = ramp(10);
    let panel = Panel::new("alone").line("the only series", &x, &y);
    let svg = Figure::from(panel).to_svg().unwrap();
    assert!(!svg.contains("the only series"));
}

#[test]
fn text_is_escaped_in_svg() {
    let (x, y) = ramp(10);
    let panel = Panel::new("a < b & c").line("p", &x, &y).line("q", &x, &y);
    let svg = Figure::from(panel).to_svg().unwrap();
    assert!(svg.contains("a &lt; b &amp; c"));
}

#[test]
fn png_has_the_requested_size() {
    let figure = Figure::from(two_series()).size(640, 360);
    assert_eq!(png_size(&figure.to_png().unwrap()), (640, 360));
    // By default PANEL_SIZE a panel: two columns, two rows for three panels.
    let grid = Figure::new()
        .columns(2)
        .panel(two_series())
        .panel(two_series())
        .panel(two_series());
    assert_eq!(grid.grid(), (2, 2));
    let (w, h) = png_size(&grid.to_png().unwrap());
    assert_eq!((w, h), (2 * PANEL_SIZE.0, 2 * PANEL_SIZE.1));
}

#[test]
fn save_picks_the_format_from_the_extension() {
    let dir = scratch("save");
    let figure = Figure::from(two_series()).size(400, 300);
    figure.save(dir.join("a.svg")).unwrap();
    figure.save(dir.join("b.PNG")).unwrap();
    figure.save_png(dir.join("c.image")).unwrap();
    figure.save_svg(dir.join("d.image")).unwrap();
    check_svg(&std::fs::read_to_string(dir.join("a.svg")).unwrap());
    assert_eq!(
        png_size(&std::fs::read(dir.join("b.PNG")).unwrap()),
        (400, 300)
    );
    assert_eq!(
        png_size(&std::fs::read(dir.join("c.image")).unwrap()),
        (400, 300)
    );
    check_svg(&std::fs::read_to_string(dir.join("d.image")).unwrap());

    let err = figure.save(dir.join("e.pdf")).unwrap_err();
    assert_eq!(err.kind(), &ErrorKind::UnknownFormat);
    assert!(err.to_string().contains("e.pdf"));
    assert!(!dir.join("e.pdf").exists());
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn io_errors_name_the_file() {
    let dir = scratch("io");
    let path = dir.join("no such directory").join("figure.svg");
    let err = Figure::from(two_series()).save(&path).unwrap_err();
    assert!(matches!(err.kind(), ErrorKind::Io { .. }));
    assert_eq!(err.path(), Some(path.display().to_string().as_str()));
    let err: hamel::Error = err.into();
    assert!(matches!(&err, hamel::Error::Io { path: p, .. } if p.ends_with("figure.svg")));
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn log_axis_leaves_out_zeros_negatives_and_non_finite_values() {
    let x = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0];
    let y = [0.0, 1e-12, -3.0, 1e-9, f64::NAN, f64::INFINITY, 1e-6];
    let zeros = [0.0; 7];
    let panel = Panel::new("drift")
        .log_y()
        .line("drift", &x, &y)
        .line("exact", &x, &zeros);
    let svg = Figure::from(panel.clone()).to_svg().unwrap();
    check_svg(&svg);
    assert!(svg.contains("exact (no positive values)"));
    assert!(svg.contains("10⁻⁹"), "decade labels");
    png_size(&Figure::from(panel.clone()).to_png().unwrap());

    // Lines are broken where points are left out: 1e-12 stands alone between 0 and -3, and
    // NaN and ∞ separate 1e-9 from 1e-6, so no segment is left.
    let prepared = lay_out(&panel).unwrap();
    assert!(prepared.series[0].parts.is_empty());
    assert!(prepared.y.lo < -12.0 && prepared.y.hi > -6.0);

    let only_zeros = Panel::new("nothing").log_y().line("exact", &x, &zeros);
    let err = Figure::from(only_zeros).to_svg().unwrap_err();
    let expected = ErrorKind::NothingToPlot {
        panel: "nothing".into(),
        log: true,
    };
    assert_eq!(err.kind(), &expected);
}

#[test]
fn non_finite_values_never_reach_the_file() {
    let x = [0.0, 1.0, f64::NAN, 3.0, 4.0, 5.0];
    let y = [1.0, f64::NEG_INFINITY, 2.0, 3.0, f64::NAN, 1.0];
    let panel = Panel::new("holes").line("y", &x, &y).points("dots", &x, &y);
    check_svg(&Figure::from(panel).to_svg().unwrap());
    let all_nan = Panel::new("nan").line("y", &[f64::NAN], &[1.0]);
    let err = Figure::from(all_nan).to_svg().unwrap_err();
    assert!(matches!(
        err.kind(),
        ErrorKind::NothingToPlot { log: false, .. }
    ));
}

#[test]
fn lines_are_clipped_at_a_given_range_and_broken_at_gaps() {
    let x = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0];
    let y = [0.0, 20.0, 0.0, f64::NAN, 1.0, 2.0];
    let panel = Panel::new("clip").y_range(-5.0, 5.0).line("y", &x, &y);
    let prepared = lay_out(&panel).unwrap();
    let parts = &prepared.series[0].parts;
    // Up to the top edge, down from it, and the piece after the gap.
    assert_eq!(parts.len(), 3, "{parts:?}");
    assert_eq!(parts[0], vec![(0.0, 0.0), (0.25, 5.0)]);
    assert_eq!(parts[1], vec![(1.75, 5.0), (2.0, 0.0)]);
    assert_eq!(parts[2], vec![(4.0, 1.0), (5.0, 2.0)]);
    assert_eq!((prepared.y.lo, prepared.y.hi), (-5.0, 5.0));
    assert_eq!(prepared.y.ticks, vec![-4.0, -2.0, 0.0, 2.0, 4.0]);
}

#[test]
fn axis_ranges_and_tick_labels() {
    let label_all = |a: &Axis| a.ticks.iter().map(|&t| a.label(t)).collect::<Vec<_>>();
    let (x, y) = ([0.0, 10.0], [-0.25, 0.25]);
    let p = lay_out(&Panel::new("").line("y", &x, &y)).unwrap();
    assert_eq!((p.x.lo, p.x.hi), (0.0, 10.0), "no margin on x for lines");
    assert_eq!(label_all(&p.x), ["0", "2", "4", "6", "8", "10"]);
    assert!(label_all(&p.y).contains(&"-0.2".to_string()));
    assert!(label_all(&p.y).contains(&"0.0".to_string()));

    // Tiny values get exponents; a constant gets a range around it.
    let p = lay_out(&Panel::new("").line("y", &x, &[1e-7, 3e-7])).unwrap();
    assert!(
        label_all(&p.y).iter().all(|l| l.ends_with("e-7")),
        "{:?}",
        label_all(&p.y)
    );
    let p = lay_out(&Panel::new("").line("y", &x, &[2.0, 2.0])).unwrap();
    assert!(p.y.lo < 2.0 && p.y.hi > 2.0);

    // Log axes: powers of ten, or 1-2-5 within a decade.
    let p = lay_out(&Panel::new("").log_y().line("y", &x, &[1e-15, 1e-3]));
    let labels = label_all(&p.unwrap().y);
    assert!(labels.contains(&"10⁻¹²".to_string()), "{labels:?}");
    let p = lay_out(&Panel::new("").log_y().line("y", &x, &[1.5e-3, 8e-3]));
    let labels = label_all(&p.unwrap().y);
    assert_eq!(labels, ["2×10⁻³", "5×10⁻³"]);
}

#[test]
fn equal_aspect_matches_the_scales() {
    let panel = Panel::new("")
        .equal_aspect()
        .line("path", &[0.0, 10.0], &[0.0, 1.0]);
    let p = prepare(&panel, (600.0, 300.0)).unwrap();
    let per_pixel_x = (p.x.hi - p.x.lo) / 600.0;
    let per_pixel_y = (p.y.hi - p.y.lo) / 300.0;
    assert!((per_pixel_x / per_pixel_y - 1.0).abs() < 1e-12);
    assert!(p.y.lo < 0.0 && p.y.hi > 1.0);
}

#[test]
fn the_legend_avoids_the_data() {
    // A rising line fills the lower-left and upper-right corners.
    let x: Vec<f64> = (0..100).map(f64::from).collect();
    let panel = Panel::new("").line("a", &x, &x).line("b", &x, &x);
    let p = lay_out(&panel).unwrap();
    assert!(matches!(
        p.legend,
        Some(Legend::UpperLeft | Legend::LowerRight)
    ));
    let p = lay_out(&panel.clone().legend(Legend::Hidden)).unwrap();
    assert_eq!(p.legend, None);
}

#[test]
fn errors() {
    let kind = |figure: Figure| figure.to_svg().unwrap_err().kind().clone();
    assert_eq!(kind(Figure::new()), ErrorKind::NoPanels);
    assert!(matches!(
        kind(Panel::new("p").into()),
        ErrorKind::NoSeries { .. }
    ));
    let empty = Panel::new("p").line("s", &[], &[]);
    assert!(matches!(kind(empty.into()), ErrorKind::EmptySeries { .. }));
    let uneven = Panel::new("p").line("s", &[1.0, 2.0], &[1.0]);
    assert_eq!(
        kind(uneven.into()),
        ErrorKind::LengthMismatch {
            panel: "p".into(),
            series: "s".into(),
            x: 2,
            y: 1
        }
    );
    let (x, y) = ramp(10);
    let ranged = |p: Panel| kind(p.line("s", &x, &y).into());
    for bad in [
        Panel::new("p").x_range(1.0, 1.0),
        Panel::new("p").x_range(f64::NAN, 1.0),
        Panel::new("p").y_range(2.0, 1.0),
        Panel::new("p").log_y().y_range(0.0, 1.0),
        Panel::new("p").y_range(-f64::MAX, f64::MAX),
    ] {
        assert!(matches!(ranged(bad), ErrorKind::InvalidRange { .. }));
    }
    let huge = Panel::new("p").line("s", &[0.0, 1.0], &[-f64::MAX, f64::MAX]);
    assert!(matches!(kind(huge.into()), ErrorKind::InvalidRange { .. }));
    for (w, h) in [(100, 100), (0, 400), (100_000, 400)] {
        let small = Figure::from(two_series()).size(w, h);
        assert_eq!(
            kind(small.clone()),
            ErrorKind::InvalidSize {
                width: w,
                height: h
            }
        );
        assert!(matches!(
            small.to_png().unwrap_err().kind(),
            ErrorKind::InvalidSize { .. }
        ));
    }
    let message = hamel::Error::from(PlotError::from(ErrorKind::NoPanels)).to_string();
    assert_eq!(message, "cannot write the figure: the figure has no panel");
}

fn knife_edge_run() -> Trajectory {
    let skate = KnifeEdge::default();
    let x0 = skate
        .state_from_speeds(0.0, &[0.0, 0.0, 0.0], &[1.0, 0.8])
        .unwrap();
    Simulation::new(&skate, x0)
        .end_time(5.0)
        .sample_interval(0.05)
        .run_constant(&DormandPrince::new(1e-8, 1e-10), [])
        .unwrap()
}

#[test]
fn trajectory_figures() {
    let run = knife_edge_run();
    let dir = scratch("trajectory");
    time_series(&run, &["v", "omega"], dir.join("speeds.svg")).unwrap();
    let svg = std::fs::read_to_string(dir.join("speeds.svg")).unwrap();
    check_svg(&svg);
    let texts = texts(&svg);
    for text in ["v, omega against t", "t", "v, omega", "v", "omega"] {
        assert!(texts.contains(&text), "`{text}` missing from {texts:?}");
    }
    xy(&run, "x", "y", dir.join("path.png")).unwrap();
    png_size(&std::fs::read(dir.join("path.png")).unwrap());
    energy_drift(&run, dir.join("energy.svg")).unwrap();
    let svg = std::fs::read_to_string(dir.join("energy.svg")).unwrap();
    check_svg(&svg);
    assert!(svg.contains("energy drift") && svg.contains("energy error"));
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn unknown_columns_are_listed() {
    let run = knife_edge_run();
    let err = time_series(&run, &["v", "speed"], "never.svg").unwrap_err();
    let expected = ErrorKind::UnknownColumn {
        name: "speed".into(),
        known: "t, x, y, phi, v, omega, energy".into(),
    };
    assert_eq!(err.kind(), &expected);
    assert_eq!(err.path(), Some("never.svg"));
    assert!(xy(&run, "x", "z", "never.svg").is_err());
    let err = Panel::time_series(&run, &[]).unwrap_err();
    assert!(matches!(err.kind(), ErrorKind::NoSeries { .. }));
    assert!(!std::path::Path::new("never.svg").exists());
}

#[test]
fn energy_drift_shows_the_energy_balance_when_forces_work() {
    let robot = MobileRobot::default();
    let q = [0.0, 0.0, 0.3, 0.0, 0.0];
    let x0 = robot.state_from_speeds(0.0, &q, &[0.0, 0.5, 0.4]).unwrap();
    let run = Simulation::new(&robot, x0)
        .end_time(1.0)
        .sample_interval(0.05)
        .run_constant(&DormandPrince::new(1e-8, 1e-10), [0.1, -0.1])
        .unwrap();
    assert!(run.column("energy_balance").is_some());
    let panel = Panel::energy_drift(&run).unwrap();
    assert_eq!(panel.series_list().len(), 2);
    let figure = Figure::new()
        .columns(3)
        .panel(Panel::xy(&run, "x", "y").unwrap())
        .panel(Panel::time_series(&run, &["alpha"]).unwrap())
        .panel(panel);
    let svg = figure.to_svg().unwrap();
    check_svg(&svg);
    assert!(svg.contains("|E − E₀ − W|"));
    assert_eq!(
        png_size(&figure.to_png().unwrap()),
        (3 * PANEL_SIZE.0, PANEL_SIZE.1)
    );
}

#[test]
fn constraint_residual_at_the_rounding_level() {
    let robot = MobileRobot::default();
    let q = [0.0, 0.0, 0.3, 0.0, 0.0];
    let x0 = robot.state_from_speeds(0.0, &q, &[0.0, 0.5, 0.4]).unwrap();
    let run = Simulation::new(&robot, x0)
        .end_time(2.0)
        .sample_interval(0.05)
        .run_constant(&DormandPrince::new(1e-8, 1e-10), [0.1, -0.1])
        .unwrap();
    let panel = Panel::constraint_residual(&robot, &run).unwrap();
    let names: Vec<&str> = panel.series_list().iter().map(|s| s.name()).collect();
    assert_eq!(names, ["max |A_c q̇ + a_c|", "ε·max(1, |q̇|)"]);
    let dir = scratch("residual");
    constraint_residual(&robot, &run, dir.join("residual.svg")).unwrap();
    let svg = std::fs::read_to_string(dir.join("residual.svg")).unwrap();
    check_svg(&svg);
    assert!(texts(&svg).contains(&"constraint residual"));
    constraint_residual(&robot, &run, dir.join("residual.png")).unwrap();
    assert_eq!(
        png_size(&std::fs::read(dir.join("residual.png")).unwrap()),
        PANEL_SIZE
    );
    // A trajectory of another system lacks the state's columns: an error naming one.
    let err = Panel::constraint_residual(&robot, &knife_edge_run()).unwrap_err();
    assert!(matches!(err.kind(), ErrorKind::UnknownColumn { name, .. } if name == "alpha"));
    std::fs::remove_dir_all(dir).unwrap();
}

/// Values that stress the layout: huge, tiny, of both signs, non-finite.
fn awkward(seed: &mut u64) -> f64 {
    // A 64-bit LCG (Knuth's MMIX constants): reproducible, with no dependency.
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    let r = (*seed >> 11) as f64 / (1u64 << 53) as f64;
    match *seed >> 60 {
        0 => f64::NAN,
        1 => f64::INFINITY,
        2 => 0.0,
        3 => 1e300 * (r - 0.5),
        4 => 1e-300 * r,
        5 => 1.0 + 1e-15 * r,
        _ => 10f64.powf(40.0 * r - 20.0) * if r < 0.3 { -1.0 } else { 1.0 },
    }
}

#[test]
fn awkward_data_gives_a_figure_or_an_error_never_a_panic() {
    let (mut seed, mut drawn) = (7, 0);
    for case in 0..200 {
        let n = 1 + case % 7;
        let x: Vec<f64> = (0..n).map(|_| awkward(&mut seed)).collect();
        let y: Vec<f64> = (0..n).map(|_| awkward(&mut seed)).collect();
        let mut panel = Panel::new(format!("case {case}"))
            .x_label("x")
            .y_label("y")
            .line("line", &x, &y)
            .points("dots", &y, &x);
        if case % 2 == 0 {
            panel = panel.log_y();
        }
        if case % 3 == 0 {
            panel = panel.equal_aspect();
        }
        if case % 5 == 0 {
            panel = panel.y_range(1e-3, 1e3).x_range(-1.0, 1.0);
        }
        let figure = Figure::from(panel).size(MIN_PANEL_SIZE.0, MIN_PANEL_SIZE.1);
        if let Ok(svg) = figure.to_svg() {
            check_svg(&svg);
            png_size(&figure.to_png().unwrap());
            drawn += 1;
        }
    }
    assert!(drawn > 50, "only {drawn} of 200 cases drawn");
}

#[test]
fn long_runs_are_thinned_to_the_resolution() {
    let n = 100_000;
    let t: Vec<f64> = (0..n).map(|i| f64::from(i) * 1e-4).collect();
    let y: Vec<f64> = t.iter().map(|t| (3.0 * t).sin()).collect();
    let panel = Panel::new("long").line("y", &t, &y);
    let prepared = lay_out(&panel).unwrap();
    let part = &prepared.series[0].parts[0];
    // One point a half pixel along the curve (about 8000 pixels up and down, 600 across)
    // at most, and the ends kept.
    assert!(part.len() < 20_000, "{} points", part.len());
    assert_eq!(part.first(), Some(&(0.0, 0.0)));
    assert_eq!(part.last(), Some(&(t[n as usize - 1], y[n as usize - 1])));
    let svg = Figure::from(panel).to_svg().unwrap();
    assert!(svg.len() < 200_000, "{} bytes", svg.len());
}

mod fields;
mod legends;
mod text;
mod units;
