//! Legends: whether a panel has one, its size, where it goes — a corner of the plotting area
//! that no line or dot passes through, or else outside the plotting area, to its right —
//! and drawing it.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::error::ErrorKind;
use super::figure::{Legend, Style};
use super::prepare::{Drawn, Entry, Point, Prepared, clip_segment};
use super::render::{Sizes, drawing, font};

/// Whether the panel shows a legend: for two series or more, or for one drawn on a field
/// (whose colours the colour bar names, not the legend).
pub(crate) fn wanted(prepared: &Prepared, choice: Legend) -> bool {
    let enough =
        prepared.series.len() >= 2 || (prepared.colorbar.is_some() && !prepared.series.is_empty());
    enough && choice != Legend::Hidden
}

/// The legend box's padding, sample width, gap after the sample and row height, in pixels.
struct Metrics {
    pad: i32,
    sample: i32,
    space: i32,
    row: i32,
}

fn metrics(sizes: &Sizes) -> Metrics {
    Metrics {
        pad: (0.6 * f64::from(sizes.gap)).round() as i32,
        sample: 2 * sizes.gap,
        space: (sizes.gap / 2).max(2),
        row: (1.35 * sizes.ticks).ceil() as i32,
    }
}

/// The legend's width and height in pixels, for its entries' labels in the ticks' font.
pub(crate) fn measure<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    series: &[Entry],
    sizes: &Sizes,
) -> Result<(i32, i32), ErrorKind> {
    let m = metrics(sizes);
    let mut widest = 0;
    for s in series {
        let (w, _) = area
            .estimate_text_size(&s.label, &font(sizes.ticks))
            .map_err(drawing)?;
        widest = widest.max(w as i32);
    }
    let rows = i32::try_from(series.len()).unwrap_or(i32::MAX);
    Ok((
        2 * m.pad + m.sample + m.space + widest,
        (2 * m.pad).saturating_add(rows.saturating_mul(m.row)),
    ))
}

/// Where the legend goes. A chosen corner, [`Legend::Outside`] or [`Legend::Hidden`] is
/// kept. [`Legend::Auto`] takes the first corner — upper right, upper left, lower right,
/// lower left — where a box of `size` pixels, `inset` pixels inside the frame, would
/// cover no line and no dot (within `clearance` pixels) of a plotting area of `area`
/// pixels; if every corner would, and always for a panel with a field (which fills the
/// plotting area), the legend goes outside.
pub(crate) fn place(
    choice: Legend,
    prepared: &Prepared,
    area: (f64, f64),
    size: (f64, f64),
    inset: f64,
    clearance: f64,
) -> Option<Legend> {
    if !wanted(prepared, choice) {
        return None;
    }
    if choice != Legend::Auto {
        return Some(choice);
    }
    if prepared.colorbar.is_some() {
        return Some(Legend::Outside);
    }
    let ((x0, x1), (y0, y1)) = prepared.ranges();
    // A box in pixels from the left and from the bottom, in the plot's coordinates.
    let to_plot = |(left, right): (f64, f64), (bottom, top): (f64, f64)| {
        let u = |px: f64| x0 + px / area.0 * (x1 - x0);
        let v = |px: f64| y0 + px / area.1 * (y1 - y0);
        ((u(left), u(right)), (v(bottom), v(top)))
    };
    let (w, h) = (size.0 + 2.0 * clearance, size.1 + 2.0 * clearance);
    let (near, far_x, far_y) = (
        inset - clearance,
        area.0 - inset + clearance,
        area.1 - inset + clearance,
    );
    let corners = [
        (Legend::UpperRight, (far_x - w, far_x), (far_y - h, far_y)),
        (Legend::UpperLeft, (near, near + w), (far_y - h, far_y)),
        (Legend::LowerRight, (far_x - w, far_x), (near, near + h)),
        (Legend::LowerLeft, (near, near + w), (near, near + h)),
    ];
    for (corner, x_span, y_span) in corners {
        let (bx, by) = to_plot(x_span, y_span);
        if !covers_data(&prepared.series, bx, by) {
            return Some(corner);
        }
    }
    Some(Legend::Outside)
}

/// Whether a box (in the plot's coordinates) holds a dot or meets a line of the series.
fn covers_data(series: &[Drawn], bx: (f64, f64), by: (f64, f64)) -> bool {
    let inside = |p: &Point| p.0 >= bx.0 && p.0 <= bx.1 && p.1 >= by.0 && p.1 <= by.1;
    series.iter().any(|s| {
        s.parts.iter().any(|part| match s.style {
            Style::Points => part.iter().any(inside),
            Style::Line | Style::Dashed => {
                part.iter().any(inside)
                    || part
                        .windows(2)
                        .any(|w| clip_segment(w[0], w[1], bx, by).is_some())
            }
        })
    })
}

/// Draws the legend's `entries` with its top left corner at `at` (pixels in `area`): a
/// framed, slightly transparent white box with one row per entry, its sample — a bar for
/// a line, three for a dashed one, a dot for dots — and its label.
pub(crate) fn draw<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    at: (i32, i32),
    series: &[Entry],
    sizes: &Sizes,
) -> Result<(), ErrorKind> {
    let m = metrics(sizes);
    let (w, h) = measure(area, series, sizes)?;
    let corner = (at.0 + w, at.1 + h);
    area.draw(&Rectangle::new([at, corner], WHITE.mix(0.85).filled()))
        .map_err(drawing)?;
    area.draw(&Rectangle::new([at, corner], BLACK.mix(0.4)))
        .map_err(drawing)?;
    let text = font(sizes.ticks).pos(Pos::new(HPos::Left, VPos::Center));
    for (i, s) in series.iter().enumerate() {
        let middle = at.1 + m.pad + m.row * i as i32 + m.row / 2;
        let left = at.0 + m.pad;
        let color = RGBColor(s.color.0, s.color.1, s.color.2);
        // The sample's bars, in 24ths of its width, stroked as the series' lines are: a
        // rectangle's height is one pixel less in SVG than in a bitmap, none at all for
        // one-pixel lines.
        let bar = |from: i32, to: i32| {
            let (x0, x1) = (left + from * m.sample / 24, left + to * m.sample / 24);
            PathElement::new(
                vec![(x0, middle), (x1, middle)],
                color.stroke_width(sizes.line),
            )
        };
        match s.style {
            Style::Line => area.draw(&bar(0, 24)),
            Style::Dashed => area
                .draw(&bar(0, 6))
                .and_then(|_| area.draw(&bar(9, 15)))
                .and_then(|_| area.draw(&bar(18, 24))),
            Style::Points => area.draw(&Circle::new(
                (left + m.sample / 2, middle),
                sizes.dot,
                color.filled(),
            )),
        }
        .map_err(drawing)?;
        area.draw_text(&s.label, &text, (left + m.sample + m.space, middle))
            .map_err(drawing)?;
    }
    Ok(())
}
