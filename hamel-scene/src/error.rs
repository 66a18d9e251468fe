//! Why a scene or a picture could not be made: [`SceneError`], and what it converts into.

use core::fmt;

/// Why a scene or a picture could not be made or written: the kind of failure, and the file
/// concerned when there is one. Nothing is written when one is returned (a file is written
/// whole or not at all). Converts into [`hamel::Error::Io`](hamel_runtime::Error::Io), so `?`
/// works in a function returning `hamel::Error`.
///
/// ```
/// use hamel::scene::{ErrorKind, SceneError};
///
/// let err = SceneError::from(ErrorKind::EmptyTrajectory);
/// assert_eq!(err.to_string(), "cannot make the scene: the trajectory has no samples");
/// let err: hamel::Error = err.into();
/// assert!(err.to_string().contains("no samples"));
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct SceneError {
    path: Option<String>,
    kind: ErrorKind,
}

/// What went wrong; see [`SceneError`].
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum ErrorKind {
    /// The trajectory lacks a column for one of the model's coordinates, so the bodies
    /// cannot be placed.
    MissingCoordinate {
        /// The coordinate.
        name: String,
        /// The trajectory's columns, separated by commas.
        known: String,
    },
    /// A column asked for with `show` is not in the trajectory.
    UnknownColumn {
        /// The name asked for.
        name: String,
        /// The trajectory's columns, separated by commas.
        known: String,
    },
    /// A body named in `shape` is not one of the model's.
    UnknownBody {
        /// The name given.
        name: String,
        /// The model's bodies, separated by commas.
        known: String,
    },
    /// A unit given with `unit` is for a column the trajectory does not have.
    UnknownUnitColumn {
        /// The name given.
        name: String,
        /// The trajectory's columns, separated by commas.
        known: String,
    },
    /// Two of the trajectory's columns have one name.
    DuplicateColumn {
        /// The name.
        name: String,
    },
    /// A sample's time is not finite, or not after the time of the sample before.
    Time {
        /// The sample, counted from 0.
        sample: usize,
        /// Its time.
        t: f64,
        /// The time of the sample before, if the time is finite.
        before: Option<f64>,
    },
    /// The trajectory has no samples.
    EmptyTrajectory,
    /// The model states no bodies at run time.
    NoBodies,
    /// The model gave a different number of bodies than it names (a hand-written
    /// [`hamel::geometry::Mechanism`](hamel_runtime::geometry::Mechanism) whose `bodies_at`
    /// and `BODIES` disagree), or a different number of contacts at different times.
    Count {
        /// `"bodies"` or `"contacts"`.
        what: &'static str,
        /// How many were expected.
        expected: usize,
        /// How many the model gave.
        got: usize,
        /// At this time.
        t: f64,
    },
    /// A body's pose, mass or inertia, or a contact point, is not finite.
    NonFinite {
        /// Which value: a body's centre, orientation, mass or inertia, or a contact point.
        what: String,
        /// At this time.
        t: f64,
    },
    /// A shape given with `shape` has a size that is not finite and positive.
    InvalidShape {
        /// The body it was given for.
        body: String,
        /// What is wrong with it.
        problem: String,
    },
    /// The path's extension is neither `.svg` nor `.png` (pictures), in any case.
    UnknownFormat,
    /// Creating, writing or renaming the file failed.
    Io {
        /// The operating system's message.
        message: String,
    },
    /// Drawing a picture failed (see `hamel::plot::PlotError`).
    Drawing {
        /// The drawing's message.
        message: String,
    },
}

impl SceneError {
    /// The kind of failure.
    pub fn kind(&self) -> &ErrorKind {
        &self.kind
    }

    /// The file being written, if the failure concerns one.
    pub fn path(&self) -> Option<&str> {
        self.path.as_deref()
    }

    /// The same error, concerning the file `path`.
    pub(crate) fn at(mut self, path: &std::path::Path) -> Self {
        self.path = Some(path.display().to_string());
        self
    }
}

impl From<ErrorKind> for SceneError {
    fn from(kind: ErrorKind) -> Self {
        SceneError { path: None, kind }
    }
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.path {
            Some(path) => write!(f, "cannot write {path}: {}", self.kind),
            None => write!(f, "cannot make the scene: {}", self.kind),
        }
    }
}

impl fmt::Display for ErrorKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ErrorKind::MissingCoordinate { name, known } => write!(
                f,
                "the trajectory has no column `{name}`, a coordinate of the model, so its \
                 bodies cannot be placed; its columns are {known} (record the model's own \
                 run, or a run of a model with the same coordinates)"
            ),
            ErrorKind::UnknownColumn { name, known } => write!(
                f,
                "the trajectory has no column `{name}` to show; its columns are {known}"
            ),
            ErrorKind::UnknownBody { name, known } => {
                write!(f, "the model has no body `{name}`; its bodies are {known}")
            }
            ErrorKind::UnknownUnitColumn { name, known } => write!(
                f,
                "a unit is given for `{name}`, which is not a column of the trajectory; its \
                 columns are {known}"
            ),
            ErrorKind::DuplicateColumn { name } => write!(
                f,
                "the trajectory has two columns named `{name}`, and which one is meant cannot \
                 be told"
            ),
            ErrorKind::Time { sample, t, before } => match before {
                None => write!(
                    f,
                    "the time of sample {sample} is {t}: a scene's times must be finite"
                ),
                Some(before) if t == before => write!(
                    f,
                    "samples {} and {sample} have the same time, {t}: a scene's times must \
                     increase, one sample at each",
                    sample - 1
                ),
                Some(before) => write!(
                    f,
                    "the time of sample {sample}, {t}, is before the time of sample {}, \
                     {before}: a scene's times must increase",
                    sample - 1
                ),
            },
            ErrorKind::EmptyTrajectory => f.write_str("the trajectory has no samples"),
            ErrorKind::NoBodies => f.write_str("the model states no bodies to draw"),
            ErrorKind::Count {
                what,
                expected,
                got,
                t,
            } => write!(
                f,
                "the model gave {got} {what} at t = {t}, but {expected} were expected (its \
                 `Mechanism` implementation names {expected} or gave {expected} before)"
            ),
            ErrorKind::NonFinite { what, t } => {
                write!(f, "{what} is not finite at t = {t}")
            }
            ErrorKind::InvalidShape { body, problem } => {
                write!(f, "the shape given for body `{body}` {problem}")
            }
            ErrorKind::UnknownFormat => f.write_str(
                "the file name must end in .svg or .png (or use write_svg or write_png)",
            ),
            ErrorKind::Io { message } => f.write_str(message),
            ErrorKind::Drawing { message } => write!(f, "drawing failed: {message}"),
        }
    }
}

impl std::error::Error for SceneError {}

/// Every scene error is a failure to produce a file, so it becomes
/// [`hamel::Error::Io`](hamel_runtime::Error::Io): the runtime's error type cannot gain variants
/// from this crate.
impl From<SceneError> for hamel_runtime::Error {
    fn from(e: SceneError) -> Self {
        hamel_runtime::Error::Io {
            path: e.path.unwrap_or_else(|| "the scene".to_string()),
            message: e.kind.to_string(),
        }
    }
}
