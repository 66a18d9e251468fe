//! A field drawn as a heatmap: its grid checked, its cells in the plot's coordinates
//! clipped to the ranges, and its colour bar — laid out here, drawn by the renderer.

use super::axis::linear_axis;
use super::error::ErrorKind;
use super::field::{ColorScale, Field, rd_bu};
use super::figure::Rgb;
use super::prepare::Point;

/// One cell of a heatmap, in the plot's coordinates: its x and y spans and its colour.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Cell {
    pub x: (f64, f64),
    pub y: (f64, f64),
    pub color: Rgb,
}

/// A field's colour scale: the values at its ends and its middle colour, how values map
/// between them, the values marked on the bar, and its label.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct ColorBar {
    pub lo: f64,
    pub center: f64,
    pub hi: f64,
    pub scale: ColorScale,
    /// The values marked on the bar, increasing.
    pub ticks: Vec<f64>,
    pub label: String,
}

impl ColorBar {
    /// Where `value` lies on the scale: −1 at the lowest value, 0 at the centre, 1 at the
    /// highest (clamped beyond them); NaN for NaN.
    pub fn position(&self, value: f64) -> f64 {
        let (c, d) = (self.center, value - self.center);
        let spread = |distance: f64| match self.scale {
            ColorScale::Linear => distance,
            ColorScale::SymLog { linear } => {
                if distance <= linear {
                    distance / linear
                } else {
                    1.0 + (distance / linear).log10()
                }
            }
        };
        let side = if d >= 0.0 { self.hi - c } else { c - self.lo };
        if side <= 0.0 {
            return if d.is_nan() { f64::NAN } else { 0.0 };
        }
        (d.signum() * spread(d.abs()) / spread(side)).clamp(-1.0, 1.0)
    }

    /// The colour of `value`.
    pub fn color(&self, value: f64) -> Rgb {
        rd_bu(self.position(value))
    }

    /// The positions the bar spans, bottom to top: a side of the scale without values is
    /// left out (all of it for a field that is its centre everywhere).
    pub fn span(&self) -> (f64, f64) {
        let (below, above) = (self.lo < self.center, self.hi > self.center);
        match (below, above) {
            (false, false) => (-1.0, 1.0),
            _ => (
                if below { -1.0 } else { 0.0 },
                if above { 1.0 } else { 0.0 },
            ),
        }
    }
}

/// The values to mark on a colour bar: the centre, and on each side about `per_side` round
/// values (for a logarithmic side, the centre plus or minus `linear` times powers of ten).
fn bar_ticks(lo: f64, center: f64, hi: f64, scale: ColorScale, per_side: usize) -> Vec<f64> {
    let mut ticks = vec![center];
    for (end, sign) in [(lo, -1.0), (hi, 1.0)] {
        let span = (end - center).abs();
        if span == 0.0 {
            continue;
        }
        let side: Vec<f64> = match scale {
            ColorScale::SymLog { linear } if span > linear => (0..)
                .map(|k| linear * 10f64.powi(k))
                .take_while(|&d| d <= span * (1.0 + 1e-9))
                .collect(),
            _ => linear_axis((0.0, span), per_side)
                .ticks
                .into_iter()
                .filter(|&d| d > 0.0)
                .collect(),
        };
        ticks.extend(side.into_iter().map(|d| center + sign * d));
    }
    ticks.sort_by(f64::total_cmp);
    ticks
}

/// A field whose grid and values can be drawn: its cells' edges in the plot's coordinates
/// and the span of its colours.
pub(crate) struct Checked<'a> {
    field: &'a Field,
    x_edges: Vec<f64>,
    y_edges: Vec<f64>,
    colors: (f64, f64),
}

/// `field` checked for drawing in the panel `panel` (on a logarithmic y axis when `log`):
/// at least two grid values a side, finite and increasing, a value per grid point, some
/// finite, and a colour range that holds the centre.
pub(crate) fn checked<'a>(
    field: &'a Field,
    panel: &str,
    log: bool,
) -> Result<Checked<'a>, ErrorKind> {
    let invalid = |reason: String| ErrorKind::InvalidField {
        panel: panel.to_string(),
        reason,
    };
    let (x, y) = (field.x(), field.y());
    for (axis, grid) in [("x", x), ("y", y)] {
        if grid.len() < 2 {
            return Err(invalid(format!(
                "it needs at least two grid values along {axis}, not {}",
                grid.len()
            )));
        }
        let bad =
            (0..grid.len()).find(|&i| !grid[i].is_finite() || (i > 0 && grid[i] <= grid[i - 1]));
        if let Some(i) = bad {
            return Err(invalid(format!(
                "its {axis} grid must be finite and increasing, but {axis}[{i}] = {}",
                grid[i]
            )));
        }
    }
    if field.values().len() != x.len() * y.len() {
        return Err(invalid(format!(
            "it has {} values for a grid of {} × {} points",
            field.values().len(),
            x.len(),
            y.len()
        )));
    }
    let x_edges = edges(x);
    let mut y_edges = edges(y);
    if log {
        if y_edges[0] <= 0.0 {
            return Err(invalid(
                "on a logarithmic y axis its cells must lie above 0".to_string(),
            ));
        }
        y_edges.iter_mut().for_each(|e| *e = e.log10());
    }
    let colors = color_range(field).map_err(|reason| invalid(reason.to_string()))?;
    if let ColorScale::SymLog { linear } = field.color_scale() {
        if !(linear.is_finite() && linear > 0.0) {
            return Err(invalid(format!(
                "the linear part of its logarithmic colour scale must be a positive number, \
                 not {linear}"
            )));
        }
    }
    Ok(Checked {
        field,
        x_edges,
        y_edges,
        colors,
    })
}

/// The cells' edges around grid values: midway between neighbours, and half a step beyond
/// the first and last.
fn edges(grid: &[f64]) -> Vec<f64> {
    let n = grid.len();
    let mut e = Vec::with_capacity(n + 1);
    e.push(grid[0] - 0.5 * (grid[1] - grid[0]));
    e.extend(grid.windows(2).map(|w| 0.5 * (w[0] + w[1])));
    e.push(grid[n - 1] + 0.5 * (grid[n - 1] - grid[n - 2]));
    e
}

/// The values the colours span: the given range, or the finite values' extent; either way
/// widened to hold the centre.
fn color_range(field: &Field) -> Result<(f64, f64), &'static str> {
    let center = field.center_level();
    if !center.is_finite() {
        return Err("its centre level must be a finite number");
    }
    let (lo, hi) = match field.given_range() {
        Some((lo, hi)) => {
            if !(lo.is_finite() && hi.is_finite() && lo < hi && lo <= center && center <= hi) {
                return Err("its colour range must be finite, increasing and hold its centre");
            }
            (lo, hi)
        }
        None => {
            let finite = field.values().iter().copied().filter(|v| v.is_finite());
            let (lo, hi) = finite.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                (lo.min(v), hi.max(v))
            });
            if lo > hi {
                return Err("it has no finite value");
            }
            (lo.min(center), hi.max(center))
        }
    };
    Ok((lo, hi))
}

impl Checked<'_> {
    /// The corners of the cells' extent, in the plot's coordinates.
    pub fn extent(&self) -> [Point; 2] {
        let (x, y) = (&self.x_edges, &self.y_edges);
        [(x[0], y[0]), (x[x.len() - 1], y[y.len() - 1])]
    }

    /// The cells, clipped to the ranges (those outside left out), row by row.
    pub fn cells(&self, (x, y): ((f64, f64), (f64, f64))) -> Vec<Cell> {
        let nx = self.x_edges.len() - 1;
        let bar = self.colorbar(2);
        let mut cells = Vec::new();
        for (j, row) in self.y_edges.windows(2).enumerate() {
            let (y0, y1) = (row[0].max(y.0), row[1].min(y.1));
            if y0 >= y1 {
                continue;
            }
            for (i, column) in self.x_edges.windows(2).enumerate() {
                let (x0, x1) = (column[0].max(x.0), column[1].min(x.1));
                if x0 < x1 {
                    let value = self.field.values()[j * nx + i];
                    cells.push(Cell {
                        x: (x0, x1),
                        y: (y0, y1),
                        color: bar.color(value),
                    });
                }
            }
        }
        cells
    }

    /// The colour bar, with about `ticks` labelled values.
    pub fn colorbar(&self, ticks: usize) -> ColorBar {
        let (lo, hi) = self.colors;
        let (center, scale) = (self.field.center_level(), self.field.color_scale());
        ColorBar {
            lo,
            center,
            hi,
            scale,
            ticks: bar_ticks(lo, center, hi, scale, (ticks / 2).max(2)),
            label: self.field.label().to_string(),
        }
    }
}
