//! Legends hide no data: a corner the lines and dots leave free, or outside the plot.

use super::super::legend;
use super::super::prepare::prepare;
use super::super::render::pixels;
use super::super::*;
use super::{texts, two_series};

/// The pixels of `panel` drawn at 480 × 320.
fn drawn(panel: Panel) -> Vec<u8> {
    pixels(&Figure::from(panel).size(480, 320)).unwrap().2
}

/// Whether an RGB pixel has a series' colour rather than the white, greys and black of the
/// background, grid, frame and text.
fn colored(p: &[u8]) -> bool {
    let (lo, hi) = (p[0].min(p[1]).min(p[2]), p[0].max(p[1]).max(p[2]));
    hi - lo > 60
}

#[test]
fn a_legend_inside_covers_no_pixel_of_the_data() {
    // Waves through the middle and the right; the upper left corner is free.
    let x: Vec<f64> = (0..200).map(|i| f64::from(i) * 0.05).collect();
    let wave = |k: f64| {
        x.iter()
            .map(|x| (x * k).sin() * 0.3 + 0.2 * x)
            .collect::<Vec<_>>()
    };
    let panel =
        Panel::new("")
            .line("slow wave", &x, &wave(1.0))
            .dashed("fast wave", &x, &wave(3.0));
    let (without, with) = (
        drawn(panel.clone().legend(Legend::Hidden)),
        drawn(panel.clone()),
    );
    let hidden = without
        .chunks(3)
        .zip(with.chunks(3))
        .filter(|(a, b)| colored(a) && a != b)
        .count();
    let data = without.chunks(3).filter(|p| colored(p)).count();
    assert!(data > 1000, "{data} data pixels");
    assert_eq!(
        hidden, 0,
        "the legend covers {hidden} of {data} data pixels"
    );
    // And it is drawn: the same panel with its legend differs from the one without.
    assert_ne!(without, with);
}

#[test]
fn where_every_corner_has_data_the_legend_goes_outside() {
    // A band of lines across the whole plotting area.
    let x: Vec<f64> = (0..100).map(f64::from).collect();
    let mut panel = Panel::new("crowded").x_label("x").y_label("y");
    for k in 0..6 {
        let y: Vec<f64> = x.iter().map(|x| (x * 0.2 + f64::from(k)).sin()).collect();
        panel = panel.line(format!("wave {k}"), &x, &y);
    }
    let mut prepared = prepare(&panel, (600.0, 400.0)).unwrap();
    let placed = legend::place(
        Legend::Auto,
        &prepared,
        (600.0, 400.0),
        (120.0, 100.0),
        10.0,
        4.0,
    );
    assert_eq!(placed, Some(Legend::Outside));
    // A chosen corner is kept, and a single series has no legend.
    prepared.legend = None;
    let corner = legend::place(
        Legend::LowerLeft,
        &prepared,
        (600.0, 400.0),
        (120.0, 100.0),
        10.0,
        4.0,
    );
    assert_eq!(corner, Some(Legend::LowerLeft));
    let single = prepare(&Panel::new("").line("only", &x, &x), (600.0, 400.0)).unwrap();
    assert_eq!(
        legend::place(
            Legend::Auto,
            &single,
            (600.0, 400.0),
            (10.0, 10.0),
            10.0,
            4.0
        ),
        None
    );

    // Drawn, the labels stand right of the plot: beyond the last x tick's label (80, of
    // data up to 99).
    let svg = Figure::from(panel).size(720, 480).to_svg().unwrap();
    let x_of = |text: &str| -> f64 {
        let at = svg
            .find(&format!(">\n{text}\n<"))
            .unwrap_or_else(|| panic!("{text}"));
        let start = svg[..at].rfind("<text x=\"").unwrap() + 9;
        svg[start..].split('"').next().unwrap().parse().unwrap()
    };
    let (label, tick) = (x_of("wave 0"), x_of("80"));
    assert!(
        label > tick + 50.0,
        "legend at {label}, last tick at {tick}"
    );
}

#[test]
fn keys_explain_styles_and_unnamed_series_have_no_entry() {
    let (x, y) = super::ramp(20);
    let panel = Panel::new("keys")
        .line("m = 1", &x, &y)
        .dashed("", &x, &y)
        .key("lower bound", Style::Line, Rgb(0, 0, 0))
        .key("upper bound", Style::Dashed, Rgb(0, 0, 0));
    let prepared = prepare(&panel, (600.0, 400.0)).unwrap();
    let labels: Vec<&str> = prepared.entries.iter().map(|e| e.label.as_str()).collect();
    assert_eq!(labels, ["m = 1", "lower bound", "upper bound"]);
    let svg = Figure::from(panel).to_svg().unwrap();
    let texts = texts(&svg);
    assert!(texts.contains(&"upper bound") && !texts.contains(&""));
    // Two series, one of them unnamed: one entry, no legend.
    let panel = two_series().series(Series::line("", &x, &y));
    assert_eq!(prepare(&panel, (600.0, 400.0)).unwrap().entries.len(), 2);
}
