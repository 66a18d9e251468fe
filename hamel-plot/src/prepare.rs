//! The numbers behind a panel, before any drawing: which points are drawn, the axis ranges,
//! the ticks and their labels, lines clipped to the plotting area, a field's cells. Kept
//! apart from the drawing so that every rule here is a plain function of the data.

use super::axis::{Axis, linear_axis, log_axis};
use super::error::ErrorKind;
use super::figure::{Legend, PALETTE, Panel, Rgb, Scale, Series, Style};
use super::heatmap::{self, Cell, ColorBar};

/// A point in the plot's coordinates: x, and y or log₁₀ y on a logarithmic axis.
pub(crate) type Point = (f64, f64);

/// A series as drawn: its legend text, colour, style, and the polylines (or, for
/// [`Style::Points`], one list of dots) inside the plotting area.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Drawn {
    pub label: String,
    pub color: Rgb,
    pub style: Style,
    pub parts: Vec<Vec<Point>>,
}

/// A legend entry: a sample in a style and colour, and a label.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Entry {
    pub label: String,
    pub color: Rgb,
    pub style: Style,
}

/// Everything needed to draw a panel.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Prepared {
    pub x: Axis,
    pub y: Axis,
    pub series: Vec<Drawn>,
    /// The legend's entries: the named series', then the keys.
    pub entries: Vec<Entry>,
    /// The field's cells inside the ranges, in drawing order.
    pub cells: Vec<Cell>,
    /// The field's colour scale, when the panel has a field.
    pub colorbar: Option<ColorBar>,
    /// Where the legend goes, or `None` for no legend: set by [`super::legend::place`] once
    /// its size is known.
    pub legend: Option<Legend>,
}

impl Prepared {
    /// The x and y ranges, in the plot's coordinates.
    pub fn ranges(&self) -> ((f64, f64), (f64, f64)) {
        ((self.x.lo, self.x.hi), (self.y.lo, self.y.hi))
    }
}

/// Lays out `panel` for a plotting area of `area` pixels (width, height); the legend is
/// placed afterwards ([`super::legend::place`]).
pub(crate) fn prepare(panel: &Panel, area: (f64, f64)) -> Result<Prepared, ErrorKind> {
    let log = panel.y_scale == Scale::Log;
    let points = checked_points(panel, log)?;
    let field = match &panel.field {
        Some(field) => Some(heatmap::checked(field, &panel.title, log)?),
        None => None,
    };
    let field_extent = field.as_ref().map(|f| f.extent());
    let Some(extent) = extent(
        points
            .iter()
            .flatten()
            .flatten()
            .chain(field_extent.iter().flatten()),
    ) else {
        return Err(ErrorKind::NothingToPlot {
            panel: panel.title.clone(),
            log,
        });
    };
    // A field fills the plotting area; dots and paths get a margin so that none sits on
    // the frame.
    let has_dots = panel.series.iter().any(|s| s.style() == Style::Points);
    let (x_margin, y_margin) = if field.is_some() {
        (0.0, 0.0)
    } else if has_dots || panel.equal_aspect {
        (0.03, 0.05)
    } else {
        (0.0, 0.05)
    };
    let mut x = range(panel, "x", panel.x_range, extent.0, x_margin, false)?;
    let mut y = range(panel, "y", panel.y_range, extent.1, y_margin, log)?;
    if panel.equal_aspect && !log {
        equalize(&mut x, &mut y, area);
    }
    let series: Vec<Drawn> = panel
        .series
        .iter()
        .zip(&points)
        .enumerate()
        .map(|(i, (s, p))| {
            let palette: &[Rgb] = if field.is_some() { &ON_FIELD } else { &PALETTE };
            drawn(s, palette[i % palette.len()], p, (x, y), area, log)
        })
        .collect();
    let named = series
        .iter()
        .filter(|s| !s.label.is_empty())
        .map(|s| Entry {
            label: s.label.clone(),
            color: s.color,
            style: s.style,
        });
    let keys = panel.keys.iter().map(|(label, style, color)| Entry {
        label: label.clone(),
        color: *color,
        style: *style,
    });
    let entries = named.chain(keys).collect();
    let (cells, colorbar) = match &field {
        Some(f) => (f.cells((x, y)), Some(f.colorbar(ticks_for(area.1, 60.0)))),
        None => (Vec::new(), None),
    };
    Ok(Prepared {
        x: linear_axis(x, ticks_for(area.0, 110.0)),
        y: if log {
            log_axis(y, ticks_for(area.1, 45.0))
        } else {
            linear_axis(y, ticks_for(area.1, 60.0))
        },
        series,
        entries,
        cells,
        colorbar,
        legend: None,
    })
}

/// How many labelled ticks suit an axis this many pixels long, one per `spacing` pixels (to
/// the nearest: the ticks then fall at the next round step, so that there are never more).
pub(crate) fn ticks_for(pixels: f64, spacing: f64) -> usize {
    ((pixels / spacing).round() as usize).clamp(2, 10)
}

/// Each series' points in the plot's coordinates, `None` where a point is left out (not
/// finite, or y ≤ 0 on a log axis), after checking that the panel has series (or a field)
/// and each has as many x as y values, at least one.
fn checked_points(panel: &Panel, log: bool) -> Result<Vec<Vec<Option<Point>>>, ErrorKind> {
    if panel.series.is_empty() && panel.field.is_none() {
        return Err(ErrorKind::NoSeries {
            panel: panel.title.clone(),
        });
    }
    let mut all = Vec::with_capacity(panel.series.len());
    for s in &panel.series {
        let (x, y) = (s.x(), s.y());
        if x.len() != y.len() {
            return Err(ErrorKind::LengthMismatch {
                panel: panel.title.clone(),
                series: s.name().to_string(),
                x: x.len(),
                y: y.len(),
            });
        }
        if x.is_empty() {
            return Err(ErrorKind::EmptySeries {
                panel: panel.title.clone(),
                series: s.name().to_string(),
            });
        }
        all.push(x.iter().zip(y).map(|(&x, &y)| to_plot(x, y, log)).collect());
    }
    Ok(all)
}

/// A data point in the plot's coordinates, or `None` if it cannot be drawn.
pub(crate) fn to_plot(x: f64, y: f64, log: bool) -> Option<Point> {
    let y = if log {
        if y > 0.0 { y.log10() } else { return None }
    } else {
        y
    };
    (x.is_finite() && y.is_finite()).then_some((x, y))
}

/// The smallest box holding every point: ((x_min, x_max), (y_min, y_max)).
fn extent<'a>(points: impl Iterator<Item = &'a Point>) -> Option<((f64, f64), (f64, f64))> {
    points.fold(None, |acc, &(x, y)| {
        let ((x0, x1), (y0, y1)) = acc.unwrap_or(((x, x), (y, y)));
        Some(((x0.min(x), x1.max(x)), (y0.min(y), y1.max(y))))
    })
}

/// An axis range in the plot's coordinates: the given one, checked, or the data's widened
/// by `margin` of its length on each side (a single value gets a range around it).
fn range(
    panel: &Panel,
    axis: &'static str,
    given: Option<(f64, f64)>,
    data: (f64, f64),
    margin: f64,
    log: bool,
) -> Result<(f64, f64), ErrorKind> {
    let invalid = |(lo, hi): (f64, f64)| ErrorKind::InvalidRange {
        panel: panel.title.clone(),
        axis,
        lo,
        hi,
    };
    let (lo, hi) = match given {
        Some((lo, hi)) => {
            let valid = lo.is_finite() && hi.is_finite() && lo < hi && (!log || lo > 0.0);
            let plot = if log {
                (lo.log10(), hi.log10())
            } else {
                (lo, hi)
            };
            if !valid || !(plot.1 - plot.0).is_finite() {
                return Err(invalid((lo, hi)));
            }
            return Ok(plot);
        }
        None => widen_degenerate(data.0, data.1, log),
    };
    let pad = (hi - lo) * margin;
    let (lo, hi) = (lo - pad, hi + pad);
    if (hi - lo).is_finite() {
        Ok((lo, hi))
    } else if log {
        Err(invalid((10f64.powf(data.0), 10f64.powf(data.1))))
    } else {
        Err(invalid(data))
    }
}

/// A range whose ends (nearly) coincide, as for a constant, widened to show it: a decade
/// each way on a log axis, 10 % of the value (or 1 around 0) on a linear one. "Nearly":
/// a spread of rounding errors alone would otherwise fill the axis.
fn widen_degenerate(lo: f64, hi: f64, log: bool) -> (f64, f64) {
    let scale = lo.abs().max(hi.abs());
    if log && hi - lo < 1e-9 {
        (lo - 1.0, hi + 1.0)
    } else if !log && hi - lo <= 1e-12 * scale {
        let middle = 0.5 * (lo + hi);
        let half = if scale == 0.0 { 1.0 } else { 0.1 * scale };
        (middle - half, middle + half)
    } else {
        (lo, hi)
    }
}

/// Widens the range that is short for its pixels so that a unit spans as many pixels on
/// both axes.
fn equalize(x: &mut (f64, f64), y: &mut (f64, f64), area: (f64, f64)) {
    let per_pixel = ((x.1 - x.0) / area.0).max((y.1 - y.0) / area.1);
    for (r, pixels) in [(x, area.0), (y, area.1)] {
        let (middle, half) = (0.5 * (r.0 + r.1), 0.5 * per_pixel * pixels);
        *r = (middle - half, middle + half);
    }
}

/// The colours series on a field get, in order, when none is set: those of [`PALETTE`]
/// that stand apart from the field's blues, reds and near-white (black first).
const ON_FIELD: [Rgb; 5] = [Rgb(0, 0, 0), PALETTE[2], PALETTE[4], PALETTE[6], PALETTE[8]];

/// A series as drawn: colour (its own, or `default`), legend text, and its parts inside
/// the ranges.
fn drawn(
    series: &Series,
    default: Rgb,
    points: &[Option<Point>],
    (x, y): ((f64, f64), (f64, f64)),
    area: (f64, f64),
    log: bool,
) -> Drawn {
    let mut parts = match series.style() {
        Style::Points => {
            let inside = |&(px, py): &Point| inside(px, x) && inside(py, y);
            vec![points.iter().flatten().copied().filter(inside).collect()]
        }
        Style::Line | Style::Dashed => clip_lines(points, x, y),
    };
    let pixel = ((x.1 - x.0) / area.0, (y.1 - y.0) / area.1);
    for part in &mut parts {
        thin(part, pixel);
    }
    let mut label = series.name().to_string();
    if points.iter().all(Option::is_none) && !label.is_empty() {
        label += if log {
            " (no positive values)"
        } else {
            " (no finite values)"
        };
    }
    Drawn {
        label,
        color: series.chosen_color().unwrap_or(default),
        style: series.style(),
        parts,
    }
}

/// Drops the points within half a pixel, on both axes, of the last point kept (keeping the
/// last point of all): the drawing moves by less than a pixel, and a long run's line
/// needs a few points per pixel, not thousands (an SVG file stays small, drawing fast).
fn thin(points: &mut Vec<Point>, pixel: (f64, f64)) {
    let Some(&last) = points.last() else {
        return;
    };
    let (half_x, half_y) = (0.5 * pixel.0, 0.5 * pixel.1);
    let mut kept: Option<Point> = None;
    points.retain(|&p| {
        let keep = kept.is_none_or(|k| (p.0 - k.0).abs() >= half_x || (p.1 - k.1).abs() >= half_y);
        if keep {
            kept = Some(p);
        }
        keep
    });
    if points.last() != Some(&last) {
        points.push(last);
    }
}

/// Whether `v` lies in the range, allowing for rounding at its ends.
pub(crate) fn inside(v: f64, (lo, hi): (f64, f64)) -> bool {
    let slack = 1e-9 * (hi - lo);
    v >= lo - slack && v <= hi + slack
}

/// The polylines through consecutive drawable points, clipped to the box: a gap (a point
/// left out) or a crossing of the box's edge ends a polyline, so nothing is drawn across.
fn clip_lines(points: &[Option<Point>], x: (f64, f64), y: (f64, f64)) -> Vec<Vec<Point>> {
    let mut lines = Vec::new();
    let mut current: Vec<Point> = Vec::new();
    for pair in points.windows(2) {
        let clipped = match (pair[0], pair[1]) {
            (Some(a), Some(b)) => clip_segment(a, b, x, y),
            _ => None,
        };
        let Some((a, b, a_moved, b_moved)) = clipped else {
            flush(&mut lines, &mut current);
            continue;
        };
        if a_moved || current.is_empty() {
            flush(&mut lines, &mut current);
            current.push(a);
        }
        current.push(b);
        if b_moved {
            flush(&mut lines, &mut current);
        }
    }
    flush(&mut lines, &mut current);
    lines
}

/// Moves a polyline of at least two points into `lines`, and empties `current`.
fn flush(lines: &mut Vec<Vec<Point>>, current: &mut Vec<Point>) {
    if current.len() >= 2 {
        lines.push(std::mem::take(current));
    } else {
        current.clear();
    }
}

/// The part of segment a–b inside the box (Liang–Barsky), and whether each end moved.
pub(crate) fn clip_segment(
    a: Point,
    b: Point,
    x: (f64, f64),
    y: (f64, f64),
) -> Option<(Point, Point, bool, bool)> {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    // Each edge as p·t ≤ q: left, right, bottom, top.
    for (p, q) in [
        (-dx, a.0 - x.0),
        (dx, x.1 - a.0),
        (-dy, a.1 - y.0),
        (dy, y.1 - a.1),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else if p < 0.0 {
            t0 = t0.max(q / p);
        } else {
            t1 = t1.min(q / p);
        }
    }
    if t0 > t1 {
        return None;
    }
    let at = |t: f64| (a.0 + t * dx, a.1 + t * dy);
    let start = if t0 > 0.0 { at(t0) } else { a };
    let end = if t1 < 1.0 { at(t1) } else { b };
    Some((start, end, t0 > 0.0, t1 < 1.0))
}
