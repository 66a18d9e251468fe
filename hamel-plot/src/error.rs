//! Why a figure could not be made: [`PlotError`], and what it converts into.

use core::fmt;

/// Why a figure could not be drawn or written: the kind of failure, and the file concerned
/// when there is one. Converts into [`hamel::Error::Io`](hamel_runtime::Error::Io) (`?` in a
/// function returning `hamel::Error`), whose message then names the file and the reason.
///
/// ```
/// use hamel::plot::{ErrorKind, Figure, Panel};
///
/// let panel = Panel::new("empty").line("y", &[], &[]);
/// let err = Figure::from(panel).save("never-written.svg").unwrap_err();
/// assert!(matches!(err.kind(), ErrorKind::EmptySeries { .. }));
/// assert_eq!(err.path(), Some("never-written.svg"));
/// let err: hamel::Error = err.into();
/// assert_eq!(
///     err.to_string(),
///     "cannot write never-written.svg: series `y` of panel `empty` has no points"
/// );
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct PlotError {
    path: Option<String>,
    kind: ErrorKind,
}

/// What went wrong; see [`PlotError`]. Panels and series are named by their titles and
/// names.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum ErrorKind {
    /// Creating or writing the file failed.
    Io {
        /// The operating system's message.
        message: String,
    },
    /// The path's extension is neither `.svg` nor `.png` (in any case).
    UnknownFormat,
    /// A PNG was asked for, and this build of hamel has no PNG encoder: it needs hamel's
    /// feature `png` (SVG needs none).
    PngNotBuilt,
    /// The figure has no panel.
    NoPanels,
    /// A panel has no series (and no field).
    NoSeries {
        /// The panel's title.
        panel: String,
    },
    /// A series has no points.
    EmptySeries {
        /// The panel's title.
        panel: String,
        /// The series' name.
        series: String,
    },
    /// A series' x and y have different lengths.
    LengthMismatch {
        /// The panel's title.
        panel: String,
        /// The series' name.
        series: String,
        /// The number of x values.
        x: usize,
        /// The number of y values.
        y: usize,
    },
    /// No point of any series of the panel can be drawn: every one has a non-finite
    /// coordinate, or, on a logarithmic y axis, a y that is not positive.
    NothingToPlot {
        /// The panel's title.
        panel: String,
        /// Whether the y axis is logarithmic.
        log: bool,
    },
    /// An axis range that cannot be drawn: given with bounds that are not finite, not
    /// increasing, or not positive on a logarithmic axis; or the data's own extent, when
    /// it overflows (values near `f64::MAX` of both signs).
    InvalidRange {
        /// The panel's title.
        panel: String,
        /// `"x"` or `"y"`.
        axis: &'static str,
        /// The lower bound, as given or as in the data.
        lo: f64,
        /// The upper bound, as given or as in the data.
        hi: f64,
    },
    /// The figure's size is too small for its grid of panels, or too large to render.
    InvalidSize {
        /// The figure's width in pixels.
        width: u32,
        /// The figure's height in pixels.
        height: u32,
    },
    /// A panel's [`super::Field`] cannot be drawn: fewer than two grid values along an
    /// axis, a grid that is not finite and increasing, another number of values than grid
    /// points, no finite value, a colour range that is not finite and increasing or does
    /// not hold the centre, or cells at or below 0 on a logarithmic axis.
    InvalidField {
        /// The panel's title.
        panel: String,
        /// What is wrong, and where.
        reason: String,
    },
    /// A trajectory has no column of this name.
    UnknownColumn {
        /// The name asked for.
        name: String,
        /// The trajectory's column names, separated by commas.
        known: String,
    },
    /// The drawing library failed (not expected: please report it).
    Drawing {
        /// The drawing library's message.
        message: String,
    },
}

impl PlotError {
    /// The kind of failure.
    pub fn kind(&self) -> &ErrorKind {
        &self.kind
    }

    /// The file being written, if the failure happened while saving one.
    pub fn path(&self) -> Option<&str> {
        self.path.as_deref()
    }

    /// The same error, concerning the file `path`.
    pub(crate) fn at(mut self, path: &std::path::Path) -> Self {
        self.path = Some(path.display().to_string());
        self
    }
}

impl From<ErrorKind> for PlotError {
    fn from(kind: ErrorKind) -> Self {
        PlotError { path: None, kind }
    }
}

impl fmt::Display for PlotError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.path {
            Some(path) => write!(f, "cannot write {path}: {}", self.kind),
            None => write!(f, "cannot draw the figure: {}", self.kind),
        }
    }
}

impl fmt::Display for ErrorKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ErrorKind::Io { message } => f.write_str(message),
            ErrorKind::UnknownFormat => {
                f.write_str("the file name must end in .svg or .png (or use save_svg or save_png)")
            }
            ErrorKind::PngNotBuilt => f.write_str(
                "PNG figures need hamel's feature `png` (`cargo run --features png`, or \
                 `features = [\"png\"]` where hamel is a dependency); SVG needs none",
            ),
            ErrorKind::NoPanels => f.write_str("the figure has no panel"),
            ErrorKind::NoSeries { panel } => write!(f, "panel `{panel}` has no series"),
            ErrorKind::EmptySeries { panel, series } => {
                write!(f, "series `{series}` of panel `{panel}` has no points")
            }
            ErrorKind::LengthMismatch {
                panel,
                series,
                x,
                y,
            } => write!(
                f,
                "series `{series}` of panel `{panel}` has {x} x values but {y} y values"
            ),
            ErrorKind::NothingToPlot { panel, log } => {
                let what = if *log {
                    "finite point with a positive y (the y axis is logarithmic)"
                } else {
                    "finite point"
                };
                write!(f, "panel `{panel}` has no {what}")
            }
            ErrorKind::InvalidRange {
                panel,
                axis,
                lo,
                hi,
            } => write!(
                f,
                "the {axis} range {lo} to {hi} of panel `{panel}` cannot be drawn: the bounds \
                 must be finite, increasing and not so far apart that their difference \
                 overflows, and positive on a logarithmic axis"
            ),
            ErrorKind::InvalidSize { width, height } => write!(
                f,
                "a figure of {width} × {height} pixels is too small for its panels or too \
                 large (each panel needs at least {} × {} pixels; at most {} a side)",
                super::render::MIN_PANEL.0,
                super::render::MIN_PANEL.1,
                super::render::MAX_SIDE
            ),
            ErrorKind::InvalidField { panel, reason } => {
                write!(f, "the field of panel `{panel}` cannot be drawn: {reason}")
            }
            ErrorKind::UnknownColumn { name, known } => {
                write!(
                    f,
                    "the trajectory has no column `{name}`; its columns are {known}"
                )
            }
            ErrorKind::Drawing { message } => write!(f, "drawing failed: {message}"),
        }
    }
}

impl std::error::Error for PlotError {}

/// Every plot error is a failure to write a figure, so it becomes
/// [`hamel::Error::Io`](hamel_runtime::Error::Io): the runtime's error type cannot gain variants
/// from this crate.
impl From<PlotError> for hamel_runtime::Error {
    fn from(e: PlotError) -> Self {
        hamel_runtime::Error::Io {
            path: e.path.unwrap_or_else(|| "the figure".to_string()),
            message: e.kind.to_string(),
        }
    }
}
