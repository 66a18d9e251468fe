//! What a figure shows: [`Figure`] (a grid of panels and a size), [`Panel`] (axes, labels,
//! ranges) and [`Series`] (named data drawn in one style). Building one draws nothing; the
//! figure is rendered when saved.

use std::path::Path;

use super::error::{ErrorKind, PlotError};
use super::field::Field;
use super::render;
use super::units::Units;

/// The default size of one panel, in pixels: a figure without [`Figure::size`] is this
/// times its grid.
pub const PANEL_SIZE: (u32, u32) = (720, 480);

/// How values map onto the y axis.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Scale {
    /// Evenly spaced values.
    #[default]
    Linear,
    /// Evenly spaced powers of ten. Only positive values can be drawn: a point whose y is
    /// zero or negative is left out, like a non-finite one (see [`Panel`]).
    Log,
}

/// How a series is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Style {
    /// A solid line through the points in order.
    Line,
    /// A dashed line through the points in order.
    Dashed,
    /// A dot at each point.
    Points,
}

/// A colour, as red, green and blue from 0 to 255.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rgb(pub u8, pub u8, pub u8);

/// The colours series get, in order, when none is set (Tableau 10: distinct, and readable
/// by most colour-blind readers).
pub const PALETTE: [Rgb; 10] = [
    Rgb(31, 119, 180),
    Rgb(255, 127, 14),
    Rgb(44, 160, 44),
    Rgb(214, 39, 40),
    Rgb(148, 103, 189),
    Rgb(140, 86, 75),
    Rgb(227, 119, 194),
    Rgb(127, 127, 127),
    Rgb(188, 189, 34),
    Rgb(23, 190, 207),
];

/// Where a panel's legend goes. A panel shows one when it has more than one series, or a
/// series drawn on a [`Field`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Legend {
    /// In the first corner of the plotting area — upper right, upper left, lower right,
    /// lower left — where it hides no line and no dot; outside the plotting area, to its
    /// right, where every corner would hide some, and always beside a [`Field`] (which
    /// fills the plotting area).
    #[default]
    Auto,
    /// In the upper left corner.
    UpperLeft,
    /// In the upper right corner.
    UpperRight,
    /// In the lower left corner.
    LowerLeft,
    /// In the lower right corner.
    LowerRight,
    /// Outside the plotting area, to its right (and to the right of a colour bar), its top
    /// level with the plot's.
    Outside,
    /// No legend.
    Hidden,
}

/// Named data, drawn in one style and colour: the points (x\[i\], y\[i\]). A series named
/// `""` is drawn without a legend entry (see [`Panel::key`]).
///
/// ```
/// use hamel::plot::{Rgb, Series, Style};
///
/// let speeds = [0.0, 1.0, 2.0];
/// let s = Series::dashed("Im λ₁", &speeds, &[3.1, 2.4, 0.0]).color(Rgb(0, 0, 0));
/// assert_eq!((s.name(), s.style()), ("Im λ₁", Style::Dashed));
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    name: String,
    x: Vec<f64>,
    y: Vec<f64>,
    style: Style,
    color: Option<Rgb>,
}

impl Series {
    /// The points (x\[i\], y\[i\]) in the given style. The data is copied. Lengths are
    /// checked when the figure is drawn.
    pub fn new(name: impl Into<String>, x: &[f64], y: &[f64], style: Style) -> Self {
        Series {
            name: name.into(),
            x: x.to_vec(),
            y: y.to_vec(),
            style,
            color: None,
        }
    }

    /// A solid line through the points.
    pub fn line(name: impl Into<String>, x: &[f64], y: &[f64]) -> Self {
        Series::new(name, x, y, Style::Line)
    }

    /// A dashed line through the points.
    pub fn dashed(name: impl Into<String>, x: &[f64], y: &[f64]) -> Self {
        Series::new(name, x, y, Style::Dashed)
    }

    /// A dot at each point.
    pub fn points(name: impl Into<String>, x: &[f64], y: &[f64]) -> Self {
        Series::new(name, x, y, Style::Points)
    }

    /// This colour instead of the panel's next one from [`PALETTE`].
    pub fn color(mut self, color: Rgb) -> Self {
        self.color = Some(color);
        self
    }

    /// The name, shown in the legend.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// How the series is drawn.
    pub fn style(&self) -> Style {
        self.style
    }

    pub(crate) fn x(&self) -> &[f64] {
        &self.x
    }

    pub(crate) fn y(&self) -> &[f64] {
        &self.y
    }

    pub(crate) fn chosen_color(&self) -> Option<Rgb> {
        self.color
    }
}

/// One plot: a title, labelled axes and any number of series, with a legend when there is
/// more than one.
///
/// Which points are drawn: a point with a non-finite coordinate (NaN, ±∞) is left out, and
/// so, on a logarithmic y axis, is a point whose y is zero or negative. A line is broken
/// where a point is left out rather than joined across the gap, so that it never suggests
/// values that were not there. A series none of whose points can be drawn keeps its legend
/// entry, marked "(no finite values)" or "(no positive values)"; a panel none of whose
/// points can be drawn is an error ([`ErrorKind::NothingToPlot`]). Lines and dots are
/// thinned to the figure's resolution: a point within half a pixel of the last one drawn
/// is skipped, which moves nothing visibly.
///
/// The axes span the data (with a margin) unless [`Panel::x_range`] or [`Panel::y_range`]
/// fix them; lines are then clipped at the edges of the plotting area.
///
/// ```
/// use hamel::plot::{Figure, Panel};
///
/// let t: Vec<f64> = (0..100).map(|i| f64::from(i) * 0.1).collect();
/// let drift: Vec<f64> = t.iter().map(|t| 1e-12 * t * t).collect(); // 0 at t = 0: left out
/// let panel = Panel::new("energy drift")
///     .x_label("t (s)")
///     .y_label("|E − E₀| (J)")
///     .log_y()
///     .line("|E − E₀|", &t, &drift);
/// let svg = Figure::from(panel).to_svg()?;
/// assert!(svg.contains("energy drift") && svg.contains("t (s)"));
/// # Ok::<(), hamel::plot::PlotError>(())
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Panel {
    pub(crate) title: String,
    pub(crate) x_label: String,
    pub(crate) y_label: String,
    pub(crate) y_scale: Scale,
    pub(crate) x_range: Option<(f64, f64)>,
    pub(crate) y_range: Option<(f64, f64)>,
    pub(crate) equal_aspect: bool,
    pub(crate) legend: Legend,
    pub(crate) series: Vec<Series>,
    pub(crate) field: Option<Field>,
    /// Legend entries without data: (name, style, colour).
    pub(crate) keys: Vec<(String, Style, Rgb)>,
    /// The quantities each axis shows (for a trajectory's panels: column names), whose
    /// units [`Panel::units`] adds to the labels.
    pub(crate) quantities: [Vec<String>; 2],
    /// The labels with units, once [`Panel::units`] has found some.
    pub(crate) with_units: [Option<String>; 2],
}

impl Panel {
    /// An empty panel with this title (which may be empty).
    pub fn new(title: impl Into<String>) -> Self {
        Panel {
            title: title.into(),
            ..Panel::default()
        }
    }

    /// The label under the x axis, as given (with its unit, if it has one: see
    /// [`Units::label`]).
    pub fn x_label(mut self, label: impl Into<String>) -> Self {
        self.x_label = label.into();
        self.quantities[0].clear();
        self.with_units[0] = None;
        self
    }

    /// The label beside the y axis, as given (with its unit, if it has one: see
    /// [`Units::label`]).
    pub fn y_label(mut self, label: impl Into<String>) -> Self {
        self.y_label = label.into();
        self.quantities[1].clear();
        self.with_units[1] = None;
        self
    }

    /// The axes that show named quantities — those of a trajectory's panels
    /// ([`Panel::time_series`], [`Panel::xy`], [`Panel::energy_drift`], the time axis of
    /// [`Panel::constraint_residual`]) — labelled with their units: `y (m)`, `t (s)`,
    /// `energy error (J)`, or `v (m/s), omega (rad/s)` for quantities of different units.
    /// A quantity without a unit keeps its bare name; an axis labelled with
    /// [`Panel::x_label`] or [`Panel::y_label`] keeps its label.
    ///
    /// ```
    /// use hamel::models::KnifeEdge;
    /// use hamel::plot::{Panel, Units};
    /// use hamel::{DormandPrince, HamelSystem, Simulation};
    ///
    /// let skate = KnifeEdge::default();
    /// let x0 = skate.state_from_speeds(0.0, &[0.0, 0.0, 0.0], &[1.0, 0.5])?;
    /// let run = Simulation::new(&skate, x0)
    ///     .end_time(1.0)
    ///     .run_constant(&DormandPrince::new(1e-8, 1e-10), [])?;
    /// let units = Units::of::<KnifeEdge>().with("x", "m").with("y", "m").with("t", "s");
    /// let panel = Panel::xy(&run, "x", "y")?.units(&units);
    /// assert_eq!(panel.labels(), ("x (m)".to_string(), "y (m)".to_string()));
    /// # Ok::<(), hamel::Error>(())
    /// ```
    pub fn units(mut self, units: &Units) -> Self {
        let labels = [&self.x_label, &self.y_label];
        self.with_units = [0, 1].map(|axis| {
            let names = &self.quantities[axis];
            (!names.is_empty()).then(|| units.axis_label(labels[axis], names))
        });
        self
    }

    /// The labels of the x and y axes as drawn, with their units.
    pub fn labels(&self) -> (String, String) {
        let shown = |axis: usize, label: &String| {
            self.with_units[axis]
                .clone()
                .unwrap_or_else(|| label.clone())
        };
        (shown(0, &self.x_label), shown(1, &self.y_label))
    }

    /// The quantities the axes show, whose units [`Panel::units`] looks up.
    pub(crate) fn quantities(mut self, x: &[&str], y: &[&str]) -> Self {
        let owned = |names: &[&str]| names.iter().map(|n| n.to_string()).collect();
        self.quantities = [owned(x), owned(y)];
        self
    }

    /// A linear or logarithmic y axis.
    pub fn y_scale(mut self, scale: Scale) -> Self {
        self.y_scale = scale;
        self
    }

    /// A logarithmic y axis: `y_scale(Scale::Log)`.
    pub fn log_y(self) -> Self {
        self.y_scale(Scale::Log)
    }

    /// The x axis spans exactly `lo` to `hi` (finite, `lo < hi`), whatever the data.
    pub fn x_range(mut self, lo: f64, hi: f64) -> Self {
        self.x_range = Some((lo, hi));
        self
    }

    /// The y axis spans exactly `lo` to `hi` (finite, `lo < hi`, and `lo > 0` on a
    /// logarithmic axis), whatever the data.
    pub fn y_range(mut self, lo: f64, hi: f64) -> Self {
        self.y_range = Some((lo, hi));
        self
    }

    /// One unit is as long on the y axis as on the x axis (for paths in a plane): the
    /// shorter of the two ranges, given or not, is widened about its middle to match. Has no
    /// effect on a logarithmic y axis.
    pub fn equal_aspect(mut self) -> Self {
        self.equal_aspect = true;
        self
    }

    /// Where the legend goes (by default the emptiest corner).
    pub fn legend(mut self, legend: Legend) -> Self {
        self.legend = legend;
        self
    }

    /// Draws `field` as a heatmap under the series, with its colour bar beside the plot
    /// (see [`Field`]); a panel has one field at most, the last given. The axes span the
    /// field's cells unless [`Panel::x_range`] or [`Panel::y_range`] fix them, and the
    /// legend, if any, goes outside the plotting area.
    pub fn field(mut self, field: Field) -> Self {
        self.field = Some(field);
        self
    }

    /// Adds a series.
    pub fn series(mut self, series: Series) -> Self {
        self.series.push(series);
        self
    }

    /// Adds a legend entry without data: a sample in `style` and `color`, then `name`. For
    /// what several series share — a line style standing for one quantity, a colour for
    /// one parameter value — so that the legend explains it once rather than per series
    /// (a series named `""` has no entry of its own). Entries follow the series'.
    ///
    /// ```
    /// use hamel::plot::{Figure, PALETTE, Panel, Rgb, Series, Style};
    ///
    /// let x = [0.0, 1.0, 2.0];
    /// let mut panel = Panel::new("bounds");
    /// for (k, m) in [1.0, 2.0].into_iter().enumerate() {
    ///     let (low, high): (Vec<f64>, Vec<f64>) = x.iter().map(|x| (m * x, m * x + 1.0)).unzip();
    ///     panel = panel
    ///         .series(Series::line(format!("m = {m}"), &x, &low).color(PALETTE[k]))
    ///         .series(Series::dashed("", &x, &high).color(PALETTE[k]));
    /// }
    /// let panel = panel
    ///     .key("lower bound", Style::Line, Rgb(0, 0, 0))
    ///     .key("upper bound", Style::Dashed, Rgb(0, 0, 0));
    /// let svg = Figure::from(panel).to_svg()?;
    /// assert!(svg.contains("m = 2") && svg.contains("upper bound"));
    /// # Ok::<(), hamel::plot::PlotError>(())
    /// ```
    pub fn key(mut self, name: impl Into<String>, style: Style, color: Rgb) -> Self {
        self.keys.push((name.into(), style, color));
        self
    }

    /// Adds a solid line: `series(Series::line(name, x, y))`.
    pub fn line(self, name: impl Into<String>, x: &[f64], y: &[f64]) -> Self {
        self.series(Series::line(name, x, y))
    }

    /// Adds a dashed line: `series(Series::dashed(name, x, y))`.
    pub fn dashed(self, name: impl Into<String>, x: &[f64], y: &[f64]) -> Self {
        self.series(Series::dashed(name, x, y))
    }

    /// Adds dots: `series(Series::points(name, x, y))`.
    pub fn points(self, name: impl Into<String>, x: &[f64], y: &[f64]) -> Self {
        self.series(Series::points(name, x, y))
    }

    /// The title.
    pub fn title(&self) -> &str {
        &self.title
    }

    /// The series, in the order they were added (and drawn).
    pub fn series_list(&self) -> &[Series] {
        &self.series
    }
}

/// The file formats a figure can be written in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Scalable vector graphics: text stays text, drawn in the viewer's sans-serif font.
    Svg,
    /// A bitmap, its text drawn with the bundled DejaVu Sans.
    Png,
}

impl Format {
    /// The format a path's extension names (`.svg` or `.png`, in any case).
    pub fn from_path(path: impl AsRef<Path>) -> Option<Format> {
        let extension = path.as_ref().extension()?.to_str()?;
        if extension.eq_ignore_ascii_case("svg") {
            Some(Format::Svg)
        } else if extension.eq_ignore_ascii_case("png") {
            Some(Format::Png)
        } else {
            None
        }
    }
}

/// Panels in a grid, filled row by row, and the size of the whole in pixels.
///
/// ```no_run
/// use hamel::plot::{Figure, Panel};
///
/// let t = [0.0, 1.0, 2.0, 3.0];
/// Figure::new()
///     .columns(2)
///     .panel(Panel::new("x").x_label("t").y_label("x").line("x", &t, &[0.0, 1.0, 4.0, 9.0]))
///     .panel(Panel::new("y").x_label("t").y_label("y").line("y", &t, &[1.0, 0.5, 0.2, 0.1]))
///     .size(1200, 400)
///     .save("figure.png")?;
/// # Ok::<(), hamel::plot::PlotError>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Figure {
    panels: Vec<Panel>,
    columns: usize,
    size: Option<(u32, u32)>,
}

impl Default for Figure {
    fn default() -> Self {
        Figure::new()
    }
}

/// A figure of this one panel.
impl From<Panel> for Figure {
    fn from(panel: Panel) -> Self {
        Figure::new().panel(panel)
    }
}

impl Figure {
    /// A figure with no panel yet, one column wide.
    pub fn new() -> Self {
        Figure {
            panels: Vec::new(),
            columns: 1,
            size: None,
        }
    }

    /// Adds a panel at the next place in the grid.
    pub fn panel(mut self, panel: Panel) -> Self {
        self.panels.push(panel);
        self
    }

    /// The grid has this many columns (0 is taken as 1; more than there are panels, as the
    /// number of panels); the rows follow from the number of panels.
    pub fn columns(mut self, columns: usize) -> Self {
        self.columns = columns.max(1);
        self
    }

    /// The whole figure is `width` × `height` pixels (by default [`PANEL_SIZE`] times the
    /// grid). For SVG this is the nominal size; the drawing scales.
    pub fn size(mut self, width: u32, height: u32) -> Self {
        self.size = Some((width, height));
        self
    }

    /// The panels, in grid order.
    pub fn panels(&self) -> &[Panel] {
        &self.panels
    }

    /// The grid: (rows, columns).
    pub fn grid(&self) -> (usize, usize) {
        let columns = self.columns.min(self.panels.len()).max(1);
        (self.panels.len().div_ceil(columns).max(1), columns)
    }

    /// The size in pixels the figure is drawn at: (width, height).
    pub fn dimensions(&self) -> (u32, u32) {
        self.size.unwrap_or_else(|| {
            let (rows, columns) = self.grid();
            let scale = |n: usize, px: u32| u32::try_from(n).map_or(u32::MAX, |n| n * px);
            (scale(columns, PANEL_SIZE.0), scale(rows, PANEL_SIZE.1))
        })
    }

    /// Writes the figure in the format the path's extension names, `.svg` or `.png`
    /// ([`ErrorKind::UnknownFormat`] otherwise). The file is created or truncated, and only
    /// once the figure has been drawn: a figure that cannot be drawn leaves no file.
    pub fn save(&self, path: impl AsRef<Path>) -> Result<(), PlotError> {
        let path = path.as_ref();
        match Format::from_path(path) {
            Some(format) => self.save_as(path, format),
            None => Err(PlotError::from(ErrorKind::UnknownFormat).at(path)),
        }
    }

    /// Writes the figure as SVG, whatever the path's extension.
    pub fn save_svg(&self, path: impl AsRef<Path>) -> Result<(), PlotError> {
        self.save_as(path.as_ref(), Format::Svg)
    }

    /// Writes the figure as PNG, whatever the path's extension.
    pub fn save_png(&self, path: impl AsRef<Path>) -> Result<(), PlotError> {
        self.save_as(path.as_ref(), Format::Png)
    }

    /// Writes the figure in `format`.
    pub fn save_as(&self, path: impl AsRef<Path>, format: Format) -> Result<(), PlotError> {
        let path = path.as_ref();
        let bytes = match format {
            Format::Svg => self.to_svg().map(String::into_bytes),
            Format::Png => self.to_png(),
        }
        .map_err(|e| e.at(path))?;
        std::fs::write(path, bytes).map_err(|e| {
            PlotError::from(ErrorKind::Io {
                message: e.to_string(),
            })
            .at(path)
        })
    }

    /// The figure as an SVG document.
    pub fn to_svg(&self) -> Result<String, PlotError> {
        render::svg(self).map_err(PlotError::from)
    }

    /// The figure as the bytes of a PNG file (8-bit RGB).
    pub fn to_png(&self) -> Result<Vec<u8>, PlotError> {
        render::png(self).map_err(PlotError::from)
    }
}
