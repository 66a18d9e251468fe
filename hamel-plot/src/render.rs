//! Drawing a [`Figure`] with plotters, into an SVG string or an RGB buffer encoded as PNG.

use std::sync::OnceLock;

use plotters::coord::Shift;
use plotters::coord::ranged1d::{DefaultFormatting, KeyPointHint};
use plotters::element::DashedPathElement;
use plotters::prelude::*;

use super::axis::Axis;
use super::colorbar;
use super::error::ErrorKind;
use super::figure::{Figure, Legend, Panel, Style};
use super::legend;
use super::prepare::{Drawn, Prepared, prepare};
#[cfg(feature = "png")]
use super::text::Typeset;

/// The smallest panel drawn, in pixels: below this the axes' labels leave no room to plot.
pub(crate) const MIN_PANEL: (u32, u32) = (160, 120);
/// The largest side of a figure, in pixels (a PNG's buffer is 3 bytes a pixel).
pub(crate) const MAX_SIDE: u32 = 8192;

/// The family every text is set in: for SVG the viewer's own sans-serif font; for PNG (and
/// for laying text out in both) the bundled DejaVu Sans, registered under this name.
const FAMILY: &str = "sans-serif";
static FONT: &[u8] = include_bytes!("font/DejaVuSans.ttf");

/// Registers the bundled font with plotters, once per process. Plotters looks fonts up by
/// family name in a global table, even to lay out SVG text.
pub(crate) fn register_font() -> Result<(), ErrorKind> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED
        .get_or_init(|| plotters::style::register_font(FAMILY, FontStyle::Normal, FONT).is_ok());
    ok.then_some(()).ok_or_else(|| ErrorKind::Drawing {
        message: "the bundled font could not be read".to_string(),
    })
}

/// A plotters failure as an error: it should not happen, since the data is checked first.
pub(crate) fn drawing(e: impl std::fmt::Display) -> ErrorKind {
    ErrorKind::Drawing {
        message: e.to_string(),
    }
}

/// The figure as an SVG document.
pub(crate) fn svg(figure: &Figure) -> Result<String, ErrorKind> {
    let size = checked_size(figure)?;
    register_font()?;
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, size).into_drawing_area();
        draw_figure(&root, figure, false)?;
        root.present().map_err(drawing)?;
    }
    Ok(out)
}

/// The figure as the bytes of a PNG file.
#[cfg(feature = "png")]
pub(crate) fn png(figure: &Figure) -> Result<Vec<u8>, ErrorKind> {
    let (width, height, rgb) = pixels(figure)?;
    encode_png(&rgb, width, height)
}

/// Without the feature `png`, a PNG is an error that names it (after the figure's own checks,
/// so that a figure that cannot be drawn says why first).
#[cfg(not(feature = "png"))]
pub(crate) fn png(figure: &Figure) -> Result<Vec<u8>, ErrorKind> {
    checked_size(figure)?;
    Err(ErrorKind::PngNotBuilt)
}

/// The figure drawn as a PNG file's pixels: width, height and 8-bit RGB, row by row.
#[cfg(feature = "png")]
pub(crate) fn pixels(figure: &Figure) -> Result<(u32, u32, Vec<u8>), ErrorKind> {
    let (width, height) = checked_size(figure)?;
    register_font()?;
    let mut rgb = vec![0u8; width as usize * height as usize * 3];
    {
        let root = bitmap(&mut rgb, (width, height)).into_drawing_area();
        draw_figure(&root, figure, true)?;
        root.present().map_err(drawing)?;
    }
    Ok((width, height, rgb))
}

/// The backend PNG figures are drawn on: 8-bit RGB pixels in `rgb`, row by row, with text
/// in the bundled font set on one baseline ([`Typeset`]).
#[cfg(feature = "png")]
pub(crate) fn bitmap(rgb: &mut [u8], size: (u32, u32)) -> Typeset<BitMapBackend<'_>> {
    Typeset::new(BitMapBackend::with_buffer(rgb, size), FAMILY, FONT)
}

/// 8-bit RGB pixels, row by row, as a PNG file.
#[cfg(feature = "png")]
fn encode_png(rgb: &[u8], width: u32, height: u32) -> Result<Vec<u8>, ErrorKind> {
    let mut out = Vec::new();
    let mut encoder = ::png::Encoder::new(&mut out, width, height);
    encoder.set_color(::png::ColorType::Rgb);
    encoder.set_depth(::png::BitDepth::Eight);
    let mut writer = encoder.write_header().map_err(drawing)?;
    writer.write_image_data(rgb).map_err(drawing)?;
    writer.finish().map_err(drawing)?;
    Ok(out)
}

/// The figure's size, checked against the grid: every panel gets at least [`MIN_PANEL`].
fn checked_size(figure: &Figure) -> Result<(u32, u32), ErrorKind> {
    if figure.panels().is_empty() {
        return Err(ErrorKind::NoPanels);
    }
    let (width, height) = figure.dimensions();
    let (rows, columns) = figure.grid();
    let fits = |side: u32, n: usize, min: u32| {
        side <= MAX_SIDE && u64::from(side) >= n as u64 * u64::from(min)
    };
    if fits(width, columns, MIN_PANEL.0) && fits(height, rows, MIN_PANEL.1) {
        Ok((width, height))
    } else {
        Err(ErrorKind::InvalidSize { width, height })
    }
}

/// Draws every panel; `bitmap` for a pixel backend, whose thick lines need care (see
/// [`Stroke`]).
fn draw_figure<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    figure: &Figure,
    bitmap: bool,
) -> Result<(), ErrorKind> {
    root.fill(&WHITE).map_err(drawing)?;
    let areas = root.split_evenly(figure.grid());
    for (panel, area) in figure.panels().iter().zip(&areas) {
        draw_panel(area, panel, bitmap)?;
    }
    Ok(())
}

/// Sizes of text, lines and dots for a panel: fixed at the default panel size, scaled with
/// larger or smaller panels so that a big PNG is not all thin lines and small print.
pub(crate) struct Sizes {
    pub title: f64,
    pub text: f64,
    pub ticks: f64,
    pub line: u32,
    pub dot: i32,
    pub gap: i32,
}

impl Sizes {
    fn for_area(width: u32, height: u32) -> Sizes {
        let scale = (f64::from(width) / f64::from(super::figure::PANEL_SIZE.0))
            .min(f64::from(height) / f64::from(super::figure::PANEL_SIZE.1))
            .clamp(0.6, 4.0);
        Sizes {
            title: 20.0 * scale,
            text: 16.0 * scale,
            ticks: 14.0 * scale,
            line: (2.0 * scale).round().max(1.0) as u32,
            dot: (3.0 * scale).round().max(2.0) as i32,
            gap: (10.0 * scale).round() as i32,
        }
    }
}

pub(crate) fn font(size: f64) -> TextStyle<'static> {
    TextStyle::from((FAMILY, size).into_font()).color(&BLACK)
}

fn draw_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    panel: &Panel,
    bitmap: bool,
) -> Result<(), ErrorKind> {
    let (width, height) = area.dim_in_pixel();
    let sizes = Sizes::for_area(width, height);
    let area = if panel.title.is_empty() {
        area.clone()
    } else {
        area.titled(&panel.title, font(sizes.title))
            .map_err(drawing)?
    };
    let layout = lay_out(&area, panel, &sizes)?;
    let prepared = &layout.prepared;
    let mut chart = ChartBuilder::on(&area)
        .margin(sizes.gap)
        .margin_right(layout.right)
        .x_label_area_size(layout.x_labels)
        .y_label_area_size(layout.y_labels)
        .build_cartesian_2d(coord(&prepared.x), coord(&prepared.y))
        .map_err(drawing)?;
    draw_mesh(&mut chart, panel, prepared, &sizes)?;
    let cells = prepared.cells.iter().map(|c| {
        let color = RGBColor(c.color.0, c.color.1, c.color.2);
        Rectangle::new([(c.x.0, c.y.0), (c.x.1, c.y.1)], color.filled())
    });
    chart.draw_series(cells).map_err(drawing)?;
    let (x, y) = (&prepared.x, &prepared.y);
    let frame = Rectangle::new([(x.lo, y.lo), (x.hi, y.hi)], BLACK.mix(0.7));
    chart.plotting_area().draw(&frame).map_err(drawing)?;
    let stroke = if bitmap {
        let (w, h) = chart.plotting_area().dim_in_pixel();
        Stroke::Brush(
            (x.hi - x.lo) / f64::from(w.max(1)),
            (y.hi - y.lo) / f64::from(h.max(1)),
        )
    } else {
        Stroke::Native
    };
    draw_series(&mut chart, prepared, &sizes, stroke)?;
    // The plotting area in the panel's pixels: the colour bar and the legend go beside it.
    let (columns, rows) = chart.plotting_area().get_pixel_range();
    let (base_x, base_y) = area.get_base_pixel();
    let plot = (
        columns.start - base_x,
        rows.start - base_y,
        columns.end - 1 - base_x,
        rows.end - 1 - base_y,
    );
    if let Some(bar) = &prepared.colorbar {
        colorbar::draw(&area, plot, bar, &sizes)?;
    }
    if let Some(corner) = prepared.legend {
        let (w, h) = legend::measure(&area, &prepared.entries, &sizes)?;
        let (left, top, right, bottom) = plot;
        let inset = sizes.gap;
        let at = match corner {
            Legend::UpperLeft => (left + inset, top + inset),
            Legend::LowerLeft => (left + inset, bottom - inset - h),
            Legend::LowerRight => (right - inset - w, bottom - inset - h),
            Legend::Outside => (right + layout.beside + sizes.gap, top),
            _ => (right - inset - w, top + inset),
        };
        legend::draw(&area, at, &prepared.entries, &sizes)?;
    }
    Ok(())
}

/// A panel laid out: the heights and widths of the label areas and of the right margin
/// (room for the last tick label, the colour bar and an outside legend), the width of the
/// colour bar beside the plot, and the prepared data.
struct Layout {
    x_labels: i32,
    y_labels: i32,
    right: i32,
    beside: i32,
    prepared: Prepared,
}

/// Lays the panel out. The label areas, the colour bar and the legend take room that the
/// plotting area's size, and so its ticks and the legend's place, depend on: start from a
/// guess, measure, and lay out again until nothing changes (or, at worst, four times; a
/// legend once put outside stays there, so that it cannot flip back and forth).
fn lay_out<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    panel: &Panel,
    sizes: &Sizes,
) -> Result<Layout, ErrorKind> {
    let (width, height) = area.dim_in_pixel();
    let x_labels = x_label_area(area, panel, sizes)?;
    let mut y_labels = 4 * sizes.gap + sizes.text as i32;
    let (mut beside, mut legend_width, mut outside) = (0, 0, panel.legend == Legend::Outside);
    let clearance = f64::from(sizes.dot.max(sizes.line as i32) + 2);
    let mut pass = 1;
    loop {
        let right = 3 * sizes.gap + beside + if outside { legend_width + sizes.gap } else { 0 };
        let plot = plot_size(width, height, (x_labels, y_labels, right), sizes);
        let mut prepared = prepare(panel, plot)?;
        let size = if legend::wanted(&prepared, panel.legend) {
            legend::measure(area, &prepared.entries, sizes)?
        } else {
            (0, 0)
        };
        let choice = if outside {
            Legend::Outside
        } else {
            panel.legend
        };
        let (w, h) = (f64::from(size.0), f64::from(size.1));
        prepared.legend = legend::place(
            choice,
            &prepared,
            plot,
            (w, h),
            f64::from(sizes.gap),
            clearance,
        );
        outside = prepared.legend == Some(Legend::Outside);
        let measured = (
            y_label_area(area, panel, &prepared.y, sizes)?,
            colorbar::width(area, prepared.colorbar.as_ref(), sizes)?,
            if outside { size.0 } else { 0 },
        );
        if measured == (y_labels, beside, legend_width) || pass == 4 {
            return Ok(Layout {
                x_labels,
                y_labels,
                right,
                beside,
                prepared,
            });
        }
        (y_labels, beside, legend_width) = measured;
        pass += 1;
    }
}

/// The size of the plotting area, in pixels, left by the margins (`gap` left, top and bottom,
/// `right` on the right) and the label areas.
fn plot_size(
    width: u32,
    height: u32,
    (x_labels, y_labels, right): (i32, i32, i32),
    sizes: &Sizes,
) -> (f64, f64) {
    let w = i64::from(width) - i64::from(y_labels) - i64::from(sizes.gap) - i64::from(right);
    let h = i64::from(height) - i64::from(x_labels) - i64::from(2 * sizes.gap);
    (w.max(1) as f64, h.max(1) as f64)
}

/// Height of the area under the plot: tick labels, then the axis label.
fn x_label_area<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    panel: &Panel,
    sizes: &Sizes,
) -> Result<i32, ErrorKind> {
    let text_height = |text: &str, size: f64| -> Result<i32, ErrorKind> {
        let (_, h) = area
            .estimate_text_size(text, &font(size))
            .map_err(drawing)?;
        Ok(h as i32)
    };
    let ticks = text_height("0123456789", sizes.ticks)?;
    let (x_label, _) = panel.labels();
    let label = if x_label.is_empty() {
        0
    } else {
        text_height(&x_label, sizes.text)? + sizes.gap
    };
    Ok(ticks + label + 2 * sizes.gap)
}

/// Width of the area left of the plot: the widest tick label, then the axis label.
fn y_label_area<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    panel: &Panel,
    axis: &Axis,
    sizes: &Sizes,
) -> Result<i32, ErrorKind> {
    let mut widest = 0;
    for &tick in &axis.ticks {
        let (w, _) = area
            .estimate_text_size(&axis.label(tick), &font(sizes.ticks))
            .map_err(drawing)?;
        widest = widest.max(w as i32);
    }
    let (_, y_label) = panel.labels();
    let label = if y_label.is_empty() {
        0
    } else {
        let (_, h) = area
            .estimate_text_size(&y_label, &font(sizes.text))
            .map_err(drawing)?;
        h as i32 + sizes.gap
    };
    Ok(widest + label + 2 * sizes.gap)
}

/// An axis as plotters' coordinate, with our ticks instead of its own (plotters' own
/// `WithKeyPoints` over an `f64` range loses the label formatting the mesh needs).
#[derive(Clone)]
struct Ticked {
    lo: f64,
    hi: f64,
    ticks: Vec<f64>,
    minor: Vec<f64>,
}

fn coord(axis: &Axis) -> Ticked {
    Ticked {
        lo: axis.lo,
        hi: axis.hi,
        ticks: axis.ticks.clone(),
        minor: axis.minor.clone(),
    }
}

impl Ranged for Ticked {
    type FormatOption = DefaultFormatting;
    type ValueType = f64;

    /// Linear, as plotters maps an `f64` range (`limit` runs backwards for the y axis).
    fn map(&self, v: &f64, limit: (i32, i32)) -> i32 {
        let fraction = (v - self.lo) / (self.hi - self.lo);
        let pixels = f64::from(limit.1 - limit.0);
        let offset = if pixels >= 0.0 {
            (pixels * fraction + 1e-3).floor()
        } else {
            (pixels * fraction - 1e-3).ceil()
        };
        // `as` saturates: a point far outside lands far outside, never wraps around.
        limit.0.saturating_add(offset as i32)
    }

    fn key_points<H: KeyPointHint>(&self, hint: H) -> Vec<f64> {
        if hint.weight().allow_light_points() {
            self.minor.clone()
        } else {
            self.ticks.clone()
        }
    }

    fn range(&self) -> std::ops::Range<f64> {
        self.lo..self.hi
    }
}

type Chart<'a, DB> = ChartContext<'a, DB, Cartesian2d<Ticked, Ticked>>;

/// Grid, ticks, tick labels and axis labels.
fn draw_mesh<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    panel: &Panel,
    prepared: &Prepared,
    sizes: &Sizes,
) -> Result<(), ErrorKind> {
    let x_format = |v: &f64| prepared.x.label(*v);
    let y_format = |v: &f64| prepared.y.label(*v);
    let mut mesh = chart.configure_mesh();
    mesh.x_label_formatter(&x_format)
        .y_label_formatter(&y_format)
        .label_style(font(sizes.ticks))
        .axis_desc_style(font(sizes.text))
        .bold_line_style(BLACK.mix(0.12))
        .light_line_style(BLACK.mix(0.05))
        .axis_style(BLACK.mix(0.7));
    let (x_label, y_label) = panel.labels();
    if !x_label.is_empty() {
        mesh.x_desc(x_label);
    }
    if !y_label.is_empty() {
        mesh.y_desc(y_label);
    }
    mesh.draw().map_err(drawing)
}

/// How lines are stroked. SVG viewers join thick polylines properly; plotters' bitmap
/// backend turns a thick polyline into one polygon whose joins, at the near-reversals of
/// noisy data, shoot spikes far outside the plot. So in bitmaps a line is drawn one pixel
/// wide, several times, shifted by a pixel each way: a square brush, and no joins.
#[derive(Clone, Copy)]
enum Stroke {
    Native,
    /// The size of a pixel in data units along x and y.
    Brush(f64, f64),
}

/// Each series' lines or dots (the legend is drawn apart: [`legend::draw`]).
fn draw_series<'a, DB: DrawingBackend + 'a>(
    chart: &mut Chart<'a, DB>,
    prepared: &Prepared,
    sizes: &Sizes,
    stroke: Stroke,
) -> Result<(), ErrorKind> {
    let width = sizes.line;
    let (dash, space) = (4 * width as i32 + 2, 3 * width as i32);
    let shifts: Vec<(f64, f64)> = match stroke {
        Stroke::Native => vec![(0.0, 0.0)],
        Stroke::Brush(px, py) => (0..width)
            .flat_map(|i| (0..width).map(move |j| (f64::from(i) * px, f64::from(j) * py)))
            .collect(),
    };
    let line_width = if matches!(stroke, Stroke::Native) {
        width
    } else {
        1
    };
    for series in &prepared.series {
        let Drawn {
            color,
            style,
            parts,
            ..
        } = series;
        let color = RGBColor(color.0, color.1, color.2);
        let line = color.stroke_width(line_width);
        let shifted = shifts.iter().flat_map(|&(dx, dy)| {
            parts
                .iter()
                .map(move |p| p.iter().map(|&(x, y)| (x + dx, y + dy)).collect::<Vec<_>>())
        });
        match style {
            Style::Line => chart.draw_series(shifted.map(|p| PathElement::new(p, line))),
            Style::Dashed => {
                chart.draw_series(shifted.map(|p| DashedPathElement::new(p, dash, space, line)))
            }
            Style::Points => {
                let dots = parts.iter().flatten();
                chart.draw_series(dots.map(|&p| Circle::new(p, sizes.dot, color.filled())))
            }
        }
        .map_err(drawing)?;
    }
    Ok(())
}
