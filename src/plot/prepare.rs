//! The numbers behind a panel, before any drawing: which points are drawn, the axis ranges,
//! the ticks and their labels, lines clipped to the plotting area, the legend's corner.
//! Kept apart from the drawing so that every rule here is a plain function of the data.

use super::error::ErrorKind;
use super::figure::{Legend, PALETTE, Panel, Rgb, Scale, Series, Style};

/// A point in the plot's coordinates: x, and y or log₁₀ y on a logarithmic axis.
pub(crate) type Point = (f64, f64);

/// One axis: its range and ticks in the plot's coordinates (log₁₀ of the value on a
/// logarithmic axis), and how tick values are written.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Axis {
    pub lo: f64,
    pub hi: f64,
    /// Labelled ticks, with a grid line each.
    pub ticks: Vec<f64>,
    /// Unlabelled ticks (a lighter grid): 2×, 3×, … between decades on a log axis.
    pub minor: Vec<f64>,
    labels: Labels,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Labels {
    /// `-0.25`: this many decimals.
    Fixed(usize),
    /// `1.5e-7`: the mantissa with this many decimals, relative to 10^exponent.
    Scientific { exponent: i32, decimals: usize },
    /// `10⁻³`, `2×10⁻³`: the tick is log₁₀ of the value.
    Log,
}

/// A series as drawn: its legend text, colour, style, and the polylines (or, for
/// [`Style::Points`], one list of dots) inside the plotting area.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Drawn {
    pub label: String,
    pub color: Rgb,
    pub style: Style,
    pub parts: Vec<Vec<Point>>,
}

/// Everything needed to draw a panel.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Prepared {
    pub x: Axis,
    pub y: Axis,
    pub series: Vec<Drawn>,
    /// The legend's corner, or `None` for no legend.
    pub legend: Option<Legend>,
}

/// Lays out `panel` for a plotting area of `area` pixels (width, height), its text drawn
/// at `text_scale` times the default size.
pub(crate) fn prepare(
    panel: &Panel,
    area: (f64, f64),
    text_scale: f64,
) -> Result<Prepared, ErrorKind> {
    let log = panel.y_scale == Scale::Log;
    let points = checked_points(panel, log)?;
    let Some(extent) = extent(points.iter().flatten().flatten()) else {
        return Err(ErrorKind::NothingToPlot {
            panel: panel.title.clone(),
            log,
        });
    };
    let has_dots = panel.series.iter().any(|s| s.style() == Style::Points);
    let x_margin = if has_dots || panel.equal_aspect {
        0.03
    } else {
        0.0
    };
    let mut x = range(panel, "x", panel.x_range, extent.0, x_margin, false)?;
    let mut y = range(panel, "y", panel.y_range, extent.1, 0.05, log)?;
    if panel.equal_aspect && !log {
        equalize(&mut x, &mut y, area);
    }
    let series: Vec<Drawn> = panel
        .series
        .iter()
        .zip(&points)
        .enumerate()
        .map(|(i, (s, p))| drawn(s, i, p, (x, y), area, log))
        .collect();
    let legend = legend_corner(panel.legend, &series, (x, y), area, text_scale);
    Ok(Prepared {
        x: linear_axis(x, ticks_for(area.0, 110.0)),
        y: if log {
            log_axis(y, ticks_for(area.1, 45.0))
        } else {
            linear_axis(y, ticks_for(area.1, 60.0))
        },
        series,
        legend,
    })
}

/// How many labelled ticks suit an axis this many pixels long, one per `spacing` pixels.
fn ticks_for(pixels: f64, spacing: f64) -> usize {
    ((pixels / spacing) as usize).clamp(2, 10)
}

/// Each series' points in the plot's coordinates, `None` where a point is left out (not
/// finite, or y ≤ 0 on a log axis), after checking that the panel has series and each has
/// as many x as y values, at least one.
fn checked_points(panel: &Panel, log: bool) -> Result<Vec<Vec<Option<Point>>>, ErrorKind> {
    if panel.series.is_empty() {
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
fn to_plot(x: f64, y: f64, log: bool) -> Option<Point> {
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

/// A series as drawn: colour, legend text, and its parts inside the ranges.
fn drawn(
    series: &Series,
    index: usize,
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
    if points.iter().all(Option::is_none) {
        label += if log {
            " (no positive values)"
        } else {
            " (no finite values)"
        };
    }
    Drawn {
        label,
        color: series
            .chosen_color()
            .unwrap_or(PALETTE[index % PALETTE.len()]),
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
fn inside(v: f64, (lo, hi): (f64, f64)) -> bool {
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
fn clip_segment(
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

/// Where the legend goes: the chosen corner, or for [`Legend::Auto`] the corner whose
/// legend-sized box covers the fewest points of the lines and dots; none for a single
/// series.
fn legend_corner(
    choice: Legend,
    series: &[Drawn],
    (x, y): ((f64, f64), (f64, f64)),
    area: (f64, f64),
    text_scale: f64,
) -> Option<Legend> {
    if series.len() < 2 || choice == Legend::Hidden {
        return None;
    }
    if choice != Legend::Auto {
        return Some(choice);
    }
    // The legend's size as a fraction of the plotting area, from its text (roughly: the
    // renderer's 14 px labels at the default size, 8 px a character, 18 px a line, with the
    // samples and margins).
    let longest = series.iter().map(|s| s.label.chars().count()).max();
    let width = text_scale * (longest.unwrap_or(0) as f64 * 8.0 + 70.0) / area.0;
    let height = text_scale * (series.len() as f64 * 18.0 + 30.0) / area.1;
    let (width, height) = (width.min(1.0), height.min(1.0));
    let corners = [
        (Legend::UpperRight, (1.0 - width, 1.0), (1.0 - height, 1.0)),
        (Legend::UpperLeft, (0.0, width), (1.0 - height, 1.0)),
        (Legend::LowerRight, (1.0 - width, 1.0), (0.0, height)),
        (Legend::LowerLeft, (0.0, width), (0.0, height)),
    ];
    let mut counts = [0usize; 4];
    visit_samples(series, |p| {
        let (u, v) = ((p.0 - x.0) / (x.1 - x.0), (p.1 - y.0) / (y.1 - y.0));
        for (count, (_, cu, cv)) in counts.iter_mut().zip(&corners) {
            *count += usize::from(u >= cu.0 && u <= cu.1 && v >= cv.0 && v <= cv.1);
        }
    });
    let best = (0..4).min_by_key(|&i| counts[i]).unwrap_or(0);
    Some(corners[best].0)
}

/// Calls `f` on every dot, and on points along every line: eight a segment, so that a long
/// segment across a corner counts, not only its ends.
fn visit_samples(series: &[Drawn], mut f: impl FnMut(Point)) {
    const STEPS: u32 = 8;
    for s in series {
        for part in &s.parts {
            if s.style == Style::Points {
                part.iter().copied().for_each(&mut f);
                continue;
            }
            for w in part.windows(2) {
                for k in 0..STEPS {
                    let t = f64::from(k) / f64::from(STEPS);
                    f((
                        w[0].0 + t * (w[1].0 - w[0].0),
                        w[0].1 + t * (w[1].1 - w[0].1),
                    ));
                }
            }
            part.last().copied().into_iter().for_each(&mut f);
        }
    }
}

/// A linear axis over `range` with about `target` ticks at 1, 2 or 5 × 10ᵏ steps.
fn linear_axis(range: (f64, f64), target: usize) -> Axis {
    let (lo, hi) = range;
    let raw = (hi - lo) / target as f64;
    let exponent = raw.log10().floor() as i32;
    let magnitude = 10f64.powi(exponent);
    let (mantissa, exponent) = match raw / magnitude {
        m if m <= 1.0 => (1.0, exponent),
        m if m <= 2.0 => (2.0, exponent),
        m if m <= 5.0 => (5.0, exponent),
        _ => (1.0, exponent + 1),
    };
    let step = mantissa * 10f64.powi(exponent);
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    let ticks = (first..=last)
        .map(|k| k as f64 * step)
        // k·step for k = 0 is exactly 0, never -0 or 1e-17.
        .collect();
    let largest = lo.abs().max(hi.abs());
    let order = largest.log10().floor() as i32;
    let labels = if largest > 0.0 && !(-3..6).contains(&order) {
        Labels::Scientific {
            exponent: order,
            decimals: (order - exponent).max(0) as usize,
        }
    } else {
        Labels::Fixed((-exponent).max(0) as usize)
    };
    Axis {
        lo,
        hi,
        ticks,
        minor: Vec::new(),
        labels,
    }
}

/// A logarithmic axis over `range` (log₁₀ of the values): ticks at powers of ten, every
/// decade or every few, with unlabelled 2×…9× ticks between when every decade is labelled;
/// over less than two decades, ticks at 1, 2 and 5 × 10ᵏ, or at whatever a linear axis
/// would choose when even those are too few.
fn log_axis(range: (f64, f64), target: usize) -> Axis {
    let (lo, hi) = range;
    let (first, last) = (lo.ceil() as i64, hi.floor() as i64);
    let decades = last - first + 1;
    let within = |v: &f64| inside(*v, range);
    let (ticks, minor) = if decades >= 2 {
        let every = (decades as usize).div_ceil(target).max(1) as i64;
        let ticks: Vec<f64> = (first..=last)
            .filter(|k| k % every == 0)
            .map(|k| k as f64)
            .collect();
        let minor = if every == 1 {
            let between = (first - 1..=last)
                .flat_map(|k| (2..10).map(move |m| k as f64 + f64::from(m).log10()));
            between.filter(within).collect()
        } else {
            (first..=last)
                .filter(|k| k % every != 0)
                .map(|k| k as f64)
                .collect()
        };
        (ticks, minor)
    } else {
        let candidates = |mantissas: &'static [u32]| -> Vec<f64> {
            (first - 1..=last + 1)
                .flat_map(|k| {
                    mantissas
                        .iter()
                        .map(move |&m| k as f64 + f64::from(m).log10())
                })
                .filter(within)
                .collect()
        };
        let mut ticks = candidates(&[1, 2, 5]);
        if ticks.len() < 2 {
            ticks = candidates(&[1, 2, 3, 4, 5, 6, 7, 8, 9]);
        }
        if ticks.len() < 2 {
            let linear = linear_axis((10f64.powf(lo), 10f64.powf(hi)), target);
            ticks = linear
                .ticks
                .iter()
                .filter(|&&v| v > 0.0)
                .map(|v| v.log10())
                .collect();
        }
        (ticks, Vec::new())
    };
    Axis {
        lo,
        hi,
        ticks,
        minor,
        labels: Labels::Log,
    }
}

impl Axis {
    /// The label of the tick at `v` (in the plot's coordinates).
    pub fn label(&self, v: f64) -> String {
        match self.labels {
            Labels::Fixed(decimals) => plain(v, decimals),
            Labels::Scientific { exponent, decimals } => {
                if v == 0.0 {
                    "0".to_string()
                } else {
                    format!("{}e{exponent}", plain(v / 10f64.powi(exponent), decimals))
                }
            }
            Labels::Log => power_of_ten(v),
        }
    }
}

/// `v` with `decimals` decimals, never `-0`.
fn plain(v: f64, decimals: usize) -> String {
    let s = format!("{v:.decimals$}");
    if s.starts_with('-') && s[1..].chars().all(|c| c == '0' || c == '.') {
        s[1..].to_string()
    } else {
        s
    }
}

/// 10^`exponent` as `10⁻³`, `2×10⁻³` or `2.5×10⁻³` (three significant digits at most).
fn power_of_ten(exponent: f64) -> String {
    let mut k = exponent.floor();
    let mut mantissa = 10f64.powf(exponent - k);
    // 10^(log10 2) may come out as 1.9999999: round the mantissa to 3 digits first.
    mantissa = (mantissa * 100.0).round() / 100.0;
    if mantissa >= 10.0 {
        mantissa /= 10.0;
        k += 1.0;
    }
    let power = format!("10{}", superscript(k as i64));
    if mantissa == 1.0 {
        power
    } else {
        let m = format!("{mantissa:.2}");
        format!("{}×{power}", m.trim_end_matches('0').trim_end_matches('.'))
    }
}

/// An integer in superscript digits: `⁻¹²`.
fn superscript(n: i64) -> String {
    n.to_string()
        .chars()
        .map(|c| match c {
            '-' => '⁻',
            '0' => '⁰',
            '1' => '¹',
            '2' => '²',
            '3' => '³',
            '4' => '⁴',
            '5' => '⁵',
            '6' => '⁶',
            '7' => '⁷',
            '8' => '⁸',
            _ => '⁹',
        })
        .collect()
}
