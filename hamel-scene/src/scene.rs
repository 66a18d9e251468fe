//! [`Scene`]: a trajectory of a model with bodies, animated in one self-contained HTML page.

use std::path::Path;

use super::data::{Contents, Shown, json};
use super::equivalent::short;
use super::error::{ErrorKind, SceneError};
use super::html::page;
use super::look::{Look, looks};
use super::motion::{Motion, POSE, configuration, coordinate_columns, rows_drawn, sample};
use super::penetration::{Pose, penetrations};
use super::snapshot::Snapshot;
use super::solid::Solid;
use super::view::Directions;
use super::write::write_whole;
use hamel_runtime::Trajectory;
use hamel_runtime::geometry::{Mechanism, Rotation3, Vector3};

/// A trajectory of a model stated from its bodies, as a 3D animation in one HTML file that
/// opens from disk in any browser, with no network: three.js is embedded in it.
///
/// Each body is drawn from what the model says: as its [`Shape`](hamel_runtime::geometry::Shape) if
/// it has one, a wheel as the disk its contact runs round, a ball as its sphere, any other
/// body as the uniform ellipsoid of its mass and principal moments of inertia (so a wrong
/// inertia looks wrong), each with its axes as a triad (x red, y green, z blue);
/// [`Scene::shape`] gives a body a solid of your own. The surfaces the contacts touch (a
/// plane as a grid in its own plane, a sphere as a sphere; the ground z = 0 for a model
/// without contacts), gravity's direction and each contact's trace are drawn too. The page plays,
/// pauses, changes speed (real time by default), has a time slider and an orbit camera, and
/// shows the time and the columns chosen with [`Scene::show`] beside the scene. Its frames
/// are the trajectory's samples as computed, nothing interpolated: sample at the frame rate
/// you want to watch (`Simulation::sample_interval(1.0 / 60.0)`).
///
/// ```
/// use hamel::models::RollingDisk;
/// use hamel::prelude::*;
/// use hamel::scene::Scene;
///
/// let disk = RollingDisk::default();
/// let x0 = disk.state_builder().set("phi", 0.1).set("spin_rate", -20.0).build()?;
/// let run = Simulation::new(&disk, x0)
///     .end_time(1.0)
///     .sample_interval(1.0 / 60.0)
///     .run_constant(&DormandPrince::new(1e-8, 1e-10), [])?;
/// let scene = Scene::new(&disk, &run)?.show(["phi", "spin_rate"]).title("a rolling disk");
/// let html = scene.to_html()?;
/// assert!(html.starts_with("<!doctype html>") && html.contains("a rolling disk"));
/// # let dir = std::env::temp_dir().join(format!("hamel-doc-scene-{}", std::process::id()));
/// # std::fs::create_dir_all(&dir).unwrap();
/// # let path = dir.join("disk.html");
/// scene.write_html(&path)?;
/// # std::fs::remove_dir_all(&dir).unwrap();
/// # Ok::<(), hamel::Error>(())
/// ```
///
/// A model without bodies has no scene: `Scene::new` does not compile for it (it needs
/// [`Mechanism`], which `#[hamel_system]` implements for models with `#[bodies]`).
pub struct Scene<'a> {
    trajectory: &'a Trajectory,
    /// The model at the first sample.
    first: Snapshot,
    motion: Motion,
    /// Why not every sample is drawn, if not.
    thinned: Option<String>,
    shown: Option<Vec<String>>,
    units: Vec<(String, String)>,
    shapes: Vec<(String, Solid)>,
    title: Option<String>,
}

/// The most samples a scene's page carries: a quarter of a million, 69 minutes at 60 samples
/// a second (the catalogue bicycle's page, 277 bytes a sample, is then 70 MB).
/// A longer trajectory is drawn at every k-th sample and its last, with a warning, so that
/// the page, and the memory that builds it, stay bounded (10⁷ samples made a page of 1.2 GB
/// and took 6.6 GB to build).
pub const MAX_SCENE_SAMPLES: usize = 250_000;

impl<'a> Scene<'a> {
    /// The scene of `trajectory`, a run of `model`. The trajectory must have a column for
    /// each of the model's coordinates, each column named once, and at least one sample, at
    /// finite times that increase; every body's pose is read here, at every sample drawn,
    /// and must be finite. A trajectory of more than [`MAX_SCENE_SAMPLES`] samples is drawn
    /// at every k-th sample (and its last), and [`Scene::warnings`] says so.
    pub fn new<M: Mechanism>(model: &M, trajectory: &'a Trajectory) -> Result<Self, SceneError> {
        Self::at_most(model, trajectory, MAX_SCENE_SAMPLES)
    }

    /// [`Scene::new`], drawing at most `limit` samples.
    pub(crate) fn at_most<M: Mechanism>(
        model: &M,
        trajectory: &'a Trajectory,
        limit: usize,
    ) -> Result<Self, SceneError> {
        let columns = coordinate_columns::<M>(trajectory)?;
        let times = trajectory.times();
        let q: M::Coordinates = configuration(&columns, 0);
        let rows = rows_drawn(times.len(), limit);
        let thinned = (rows.len() < times.len()).then(|| {
            format!(
                "the trajectory has {} samples, more than a page carries ({limit}): it is \
                 drawn at one sample in {} and the last ({} samples); sample the run less \
                 often (`Simulation::sample_interval`) to choose them",
                times.len(),
                rows.get(1).copied().unwrap_or(1),
                rows.len()
            )
        });
        Ok(Scene {
            trajectory,
            first: Snapshot::of(model, times[0], &q)?,
            motion: sample(model, times, &columns, rows)?,
            thinned,
            shown: None,
            units: Vec::new(),
            shapes: Vec::new(),
            title: None,
        })
    }

    /// The columns shown beside the scene, with their units, at each sample (by default the
    /// model's coordinates). Names not in the trajectory are an error when the page is made.
    pub fn show<I, S>(mut self, columns: I) -> Self
    where
        I: IntoIterator<Item = S>,
        S: Into<String>,
    {
        self.shown = Some(columns.into_iter().map(Into::into).collect());
        self
    }

    /// Shows the column `column` with the unit `unit` (for an output column of the
    /// simulation, or in place of the model's own unit). A column the trajectory does not
    /// have is an error when the page is made.
    pub fn unit(mut self, column: &str, unit: &str) -> Self {
        self.units.push((column.to_string(), unit.to_string()));
        self
    }

    /// Draws the body called `body` (one of [`Mechanism::BODIES`]) as `shape`: one of the
    /// model's [`Shape`](hamel_runtime::geometry::Shape)s or another [`Solid`]. A name that is
    /// not a body's, or a solid with a size that is not finite and positive, is an error when
    /// the page is made.
    pub fn shape(mut self, body: &str, shape: impl Into<Solid>) -> Self {
        self.shapes.push((body.to_string(), shape.into()));
        self
    }

    /// The page's title (by default the model's type and the time span).
    pub fn title(mut self, title: impl Into<String>) -> Self {
        self.title = Some(title.into());
        self
    }

    /// What cannot be drawn as the model states it: a body whose mass and inertia no rigid
    /// body has (inertia not positive definite, principal moments that violate the triangle
    /// inequality) is drawn as a red marker, and the page lists the reason; a contact point
    /// off its surface at the first sample (a surface placed where the bodies do not meet
    /// it) is listed too, and so is a body drawn through a surface the contacts touch, at
    /// any sample: one whose solid is not its shape (drawn from its inertia where it rolls on
    /// its base), or one the model lets pass through (it has no contact with the surface).
    pub fn warnings(&self) -> Result<Vec<String>, SceneError> {
        let looks = looks(&self.first, &self.shapes)?;
        Ok(self.warnings_for(&looks))
    }

    /// The warnings of a scene whose bodies are drawn as `looks`.
    fn warnings_for(&self, looks: &[Look]) -> Vec<String> {
        let bodies = looks.iter().filter_map(|l| l.warning.clone());
        let motion = &self.motion;
        let count = looks.len();
        let poses = |b: usize| -> Box<dyn Iterator<Item = Pose> + '_> {
            Box::new(motion.times.iter().enumerate().map(move |(i, &t)| {
                let at = (i * count + b) * POSE;
                let p = &motion.poses[at..at + POSE];
                Pose {
                    t,
                    centre: Vector3::new(p[0], p[1], p[2]),
                    orientation: Rotation3::from_quaternion(p[6], p[3], p[4], p[5]),
                }
            }))
        };
        let through = penetrations(looks, poses, &self.first)
            .into_iter()
            .map(|t| t.message);
        bodies
            .chain(self.first.warnings.iter().cloned())
            .chain(through)
            .chain(self.thinned.clone())
            .collect()
    }

    /// The page, as one HTML document.
    pub fn to_html(&self) -> Result<String, SceneError> {
        let shown = self.shown_columns()?;
        let looks = looks(&self.first, &self.shapes)?;
        let contact_bodies: Vec<Option<usize>> =
            self.first.contacts.iter().map(|(_, b)| *b).collect();
        // Up is fixed for the whole scene: against gravity at the first sample.
        let gravity = self.first.gravity;
        let warnings = self.warnings_for(&looks);
        let data = json(&Contents {
            looks: &looks,
            surfaces: &self.first.surfaces,
            contact_surfaces: &self.first.contact_surfaces,
            warnings: &warnings,
            motion: &self.motion,
            directions: Directions::new(gravity),
            gravity,
            contact_bodies: &contact_bodies,
            shown: &shown,
            time_unit: (self.first.unit)("t").unwrap_or("s"),
        });
        Ok(page(&self.page_title(), &data))
    }

    /// Writes the page to `path`, whole or not at all: nothing is written if the page
    /// cannot be made, and a failure to write leaves no partial file.
    pub fn write_html(&self, path: impl AsRef<Path>) -> Result<(), SceneError> {
        let path = path.as_ref();
        let html = self.to_html().map_err(|e| e.at(path))?;
        write_whole(path, html.as_bytes())
    }

    fn shown_columns(&self) -> Result<Vec<Shown<'_>>, SceneError> {
        let columns = self.trajectory.names();
        if let Some((name, _)) = self.units.iter().find(|(c, _)| !columns.contains(c)) {
            return Err(ErrorKind::UnknownUnitColumn {
                name: name.clone(),
                known: columns.join(", "),
            }
            .into());
        }
        let names: Vec<&str> = match &self.shown {
            Some(names) => names.iter().map(String::as_str).collect(),
            None => self.first.coordinates.to_vec(),
        };
        names
            .into_iter()
            .map(|name| {
                let found = self.trajectory.names().iter().find(|n| n.as_str() == name);
                let (name, values) = found
                    .and_then(|n| Some((n.as_str(), self.trajectory.column(n)?)))
                    .ok_or_else(|| ErrorKind::UnknownColumn {
                        name: name.to_string(),
                        known: self.trajectory.names().join(", "),
                    })?;
                let given = self.units.iter().rev().find(|(c, _)| c == name);
                let unit = given
                    .map(|(_, u)| u.as_str())
                    .or_else(|| (self.first.unit)(name));
                Ok(Shown { name, unit, values })
            })
            .collect()
    }

    fn page_title(&self) -> String {
        if let Some(title) = &self.title {
            return title.clone();
        }
        let times = &self.motion.times;
        let unit = (self.first.unit)("t").unwrap_or("s");
        let (first, last) = (times[0], times[times.len() - 1]);
        format!(
            "{}, t = {} … {} {unit}",
            self.first.model,
            short(first),
            short(last)
        )
    }
}
