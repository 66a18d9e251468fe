//! A field's colour bar, beside the plotting area: the scale's colours from the lowest
//! value (bottom) to the highest (top), the centre level marked across it, ticks with their
//! values, and the field's label.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::axis::short;
use super::error::ErrorKind;
use super::field::rd_bu;
use super::heatmap::ColorBar;
use super::render::{Sizes, drawing, font};

/// The bar's parts, in pixels: the space before it, its width, a tick's length.
fn parts(sizes: &Sizes) -> (i32, i32, i32) {
    (
        2 * sizes.gap,
        (1.5 * f64::from(sizes.gap)).round() as i32,
        (sizes.gap / 2).max(2),
    )
}

/// The space between the tick labels and the bar's label. Turned upright, the label's
/// glyphs reach a quarter of its size beyond its layout box towards the ticks (plotters
/// sets the baseline half the size below the box's top, and digits and capitals rise
/// three quarters of it), so the space allows for that.
fn label_space(sizes: &Sizes) -> i32 {
    sizes.gap + (0.25 * sizes.text).ceil() as i32
}

/// The width the colour bar takes beside the plotting area, in pixels (0 without one):
/// the space before the bar, the bar, its ticks and their widest label, and its label
/// turned upright.
pub(crate) fn width<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    bar: Option<&ColorBar>,
    sizes: &Sizes,
) -> Result<i32, ErrorKind> {
    let Some(bar) = bar else {
        return Ok(0);
    };
    let (space, thickness, tick) = parts(sizes);
    let mut widest = 0;
    for &t in &bar.ticks {
        let (w, _) = area
            .estimate_text_size(&short(t), &font(sizes.ticks))
            .map_err(drawing)?;
        widest = widest.max(w as i32);
    }
    let label = if bar.label.is_empty() {
        0
    } else {
        let (_, h) = area
            .estimate_text_size(&bar.label, &font(sizes.text))
            .map_err(drawing)?;
        h as i32 + label_space(sizes)
    };
    Ok(space + thickness + tick + sizes.gap / 2 + widest + label)
}

/// Draws the colour bar beside the plotting area `plot` (left, top, right, bottom, in the
/// panel's pixels), as tall as it.
pub(crate) fn draw<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    plot: (i32, i32, i32, i32),
    bar: &ColorBar,
    sizes: &Sizes,
) -> Result<(), ErrorKind> {
    let (space, thickness, tick) = parts(sizes);
    let (_, top, right, bottom) = plot;
    let (left, bar_right) = (right + space, right + space + thickness);
    // Rows run linearly over the scale's positions (each side of the centre half the bar
    // when both have values), top to bottom; row y shows the position at its middle.
    let (p_lo, p_hi) = bar.span();
    let span = f64::from((bottom - top).max(1));
    let position_at = |y: i32| p_hi - (f64::from(y - top) + 0.5) / span * (p_hi - p_lo);
    let row_of = |v: f64| top + ((p_hi - bar.position(v)) / (p_hi - p_lo) * span).round() as i32;
    for y in top..=bottom {
        let c = rd_bu(position_at(y));
        let color = RGBColor(c.0, c.1, c.2);
        // A filled row a pixel tall: a line would be anti-aliased across two rows in SVG.
        area.draw(&Rectangle::new(
            [(left, y), (bar_right, y + 1)],
            color.filled(),
        ))
        .map_err(drawing)?;
    }
    // The centre level, across the bar: where the colours change side.
    if p_lo < 0.0 && p_hi > 0.0 {
        let y = row_of(bar.center);
        area.draw(&PathElement::new(
            vec![(left, y), (bar_right, y)],
            BLACK.stroke_width(1),
        ))
        .map_err(drawing)?;
    }
    area.draw(&Rectangle::new(
        [(left, top), (bar_right, bottom)],
        BLACK.mix(0.7),
    ))
    .map_err(drawing)?;
    let text = font(sizes.ticks).pos(Pos::new(HPos::Left, VPos::Center));
    let mut widest = 0;
    for t in legible(bar, row_of, sizes.ticks) {
        let y = row_of(t);
        area.draw(&PathElement::new(
            vec![(bar_right, y), (bar_right + tick, y)],
            BLACK.mix(0.7),
        ))
        .map_err(drawing)?;
        let label = short(t);
        area.draw_text(&label, &text, (bar_right + tick + sizes.gap / 2, y))
            .map_err(drawing)?;
        let (w, _) = area
            .estimate_text_size(&label, &font(sizes.ticks))
            .map_err(drawing)?;
        widest = widest.max(w as i32);
    }
    if !bar.label.is_empty() {
        // Upright, reading upwards, like the y axis' label.
        let label = font(sizes.text)
            .transform(FontTransform::Rotate270)
            .pos(Pos::new(HPos::Center, VPos::Top));
        let x = bar_right + tick + sizes.gap / 2 + widest + label_space(sizes);
        area.draw_text(&bar.label, &label, (x, (top + bottom) / 2))
            .map_err(drawing)?;
    }
    Ok(())
}

/// The bar's ticks that can be labelled without their labels overlapping, text of `size`
/// pixels at the rows `row_of` gives: the centre first, then each side outward, a tick left
/// out when it is nearer the last one kept on its side than a line of text.
fn legible(bar: &ColorBar, row_of: impl Fn(f64) -> i32, size: f64) -> Vec<f64> {
    let line = size.ceil() as i32;
    let (below, above): (Vec<f64>, Vec<f64>) = bar.ticks.iter().partition(|&&t| t < bar.center);
    let mut kept = vec![bar.center];
    for side in [below.into_iter().rev().collect::<Vec<_>>(), above] {
        let mut last = row_of(bar.center);
        for t in side.into_iter().filter(|&t| t != bar.center) {
            let row = row_of(t);
            if (row - last).abs() >= line {
                kept.push(t);
                last = row;
            }
        }
    }
    kept
}
