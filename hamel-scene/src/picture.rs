//! [`Picture`]: a model's bodies at one configuration, in front, side and top views.

use std::path::Path;

use super::error::{ErrorKind, SceneError};
use super::ground::surface_lines;
use super::look::{Look, looks};
use super::outline::{Line, outline};
use super::penetration::{Pose, Through, penetrations};
use super::snapshot::Snapshot;
use super::solid::Solid;
use super::view::{Directions, View, direction_name};
use super::write::write_whole;
use hamel_plot::{Figure, Legend, Panel, Rgb, Series};
use hamel_runtime::geometry::{Body, Mechanism, Surface, Vector3};

/// A model stated from its bodies, drawn at one configuration in three orthographic views
/// (front, side and top), as SVG or PNG: each body as in a [`Scene`](super::Scene) (the
/// disk or sphere its contact makes it, else the uniform ellipsoid of its inertia, or a
/// solid given with [`Picture::shape`]), its axes as a triad (x red, y green, z blue), the
/// contact points and the surfaces they touch, where the model puts them (a plane of any
/// pose as a hatch in its own plane, a sphere as its outline; the ground for a model
/// without contacts). One unit is as long across as up each view. A picture of a model in
/// its reference configuration shows at a glance a sign slip in a body's position, an
/// inertia in the wrong axes, a contact point off its body, or a tilted plane taken as flat
/// (the bodies off the plane drawn; [`Picture::warnings`] says how far).
///
/// ```
/// use hamel::models::RollingDisk;
/// use hamel::prelude::*;
/// use hamel::scene::Picture;
///
/// let disk = RollingDisk::default();
/// let q = [0.0, 0.0, 0.0, 0.3, 0.0]; // leaning by 0.3 rad
/// let svg = Picture::new(&disk, 0.0, &q)?.to_svg()?;
/// assert!(svg.contains("side, looking along y"));
/// # Ok::<(), hamel::Error>(())
/// ```
pub struct Picture {
    model: Snapshot,
    shapes: Vec<(String, Solid)>,
    size: (u32, u32),
}

/// The default size of a picture, in pixels: three views side by side.
pub const PICTURE_SIZE: (u32, u32) = (1500, 520);

impl Picture {
    /// `model` at time `t` and configuration `q`: every value must be finite, and so must
    /// the bodies' poses, masses and inertias and the contact points there.
    pub fn new<M: Mechanism>(model: &M, t: f64, q: &M::Coordinates) -> Result<Self, SceneError> {
        let values = std::iter::once(&t).chain(q.as_ref());
        if let Some((i, _)) = values.enumerate().find(|(_, v)| !v.is_finite()) {
            let what = match i {
                0 => "the time".to_string(),
                i => format!("coordinate `{}`", M::COORDINATES[i - 1]),
            };
            return Err(ErrorKind::NonFinite { what, t }.into());
        }
        Ok(Picture {
            model: Snapshot::of(model, t, q)?,
            shapes: Vec::new(),
            size: PICTURE_SIZE,
        })
    }

    /// Draws the body called `body` as `shape`, one of the model's
    /// [`Shape`](hamel_runtime::geometry::Shape)s or another [`Solid`] (see
    /// [`Scene::shape`](super::Scene::shape)).
    pub fn shape(mut self, body: &str, shape: impl Into<Solid>) -> Self {
        self.shapes.push((body.to_string(), shape.into()));
        self
    }

    /// The picture's size in pixels (default [`PICTURE_SIZE`]).
    pub fn size(mut self, width: u32, height: u32) -> Self {
        self.size = (width, height);
        self
    }

    /// What cannot be drawn as the model states it (see [`Scene::warnings`](super::Scene::warnings)).
    pub fn warnings(&self) -> Result<Vec<String>, SceneError> {
        let looks = looks(&self.model, &self.shapes)?;
        let bodies = looks.iter().filter_map(|l| l.warning.clone());
        let through = self.through(&looks).into_iter().map(|t| t.message);
        Ok(bodies
            .chain(self.model.warnings.iter().cloned())
            .chain(through)
            .collect())
    }

    /// The warnings for bodies drawn as `looks` through a surface the contacts touch.
    fn through(&self, looks: &[Look]) -> Vec<Through> {
        let model = &self.model;
        let poses = |b: usize| -> Box<dyn Iterator<Item = Pose> + '_> {
            let body = &model.bodies[b];
            Box::new(std::iter::once(Pose {
                t: model.t,
                centre: body.centre,
                orientation: body.orientation,
            }))
        };
        penetrations(looks, poses, model)
    }

    /// The three views as a [`Figure`] of three panels, to save or to combine.
    pub fn figure(&self) -> Result<Figure, SceneError> {
        let mut looks = looks(&self.model, &self.shapes)?;
        // A body drawn through a surface says so in the legend.
        for through in self.through(&looks) {
            let look = &mut looks[through.body];
            look.name = format!("{} ({})", look.name, through.short);
        }
        let model = &self.model;
        let contacts: Vec<Vector3> = model.contacts.iter().map(|(p, _)| *p).collect();
        let directions = Directions::new(model.gravity);
        let unit = (model.unit)("x").map_or(String::new(), |u| format!(" ({u})"));
        let centroid = model
            .bodies
            .iter()
            .fold(Vector3::zeros(), |sum, b| sum + b.centre)
            / model.bodies.len() as f64;
        // Where each contact's surface is under it; a model without contacts stands on the
        // ground z = 0 if up is along z.
        let mut feet: Vec<Vector3> = contacts
            .iter()
            .zip(&model.contact_surfaces)
            .map(|(&p, &s)| foot(&model.surfaces[s], p))
            .collect();
        let mut surfaces = model.surfaces.clone();
        if surfaces.is_empty() && directions.up.z.abs() == 1.0 {
            surfaces.push(Surface::ground());
            feet.push(foot(&Surface::ground(), centroid));
        }
        let mut figure = Figure::new().columns(3).size(self.size.0, self.size.1);
        for view in View::all(&directions) {
            let drawn = Drawing {
                looks: &looks,
                bodies: &model.bodies,
                contacts: &contacts,
                surfaces: &surfaces,
                feet: &feet,
                centroid,
            };
            let panel = panel(&view, &drawn, &unit);
            let legend = if view.name == "side" {
                Legend::Auto
            } else {
                Legend::Hidden
            };
            figure = figure.panel(panel.legend(legend));
        }
        Ok(figure)
    }

    /// The picture as an SVG document.
    pub fn to_svg(&self) -> Result<String, SceneError> {
        self.figure()?.to_svg().map_err(drawing)
    }

    /// The picture as the bytes of a PNG file.
    pub fn to_png(&self) -> Result<Vec<u8>, SceneError> {
        self.figure()?.to_png().map_err(drawing)
    }

    /// Writes the picture as SVG, whole or not at all.
    pub fn write_svg(&self, path: impl AsRef<Path>) -> Result<(), SceneError> {
        let path = path.as_ref();
        let svg = self.to_svg().map_err(|e| e.at(path))?;
        write_whole(path, svg.as_bytes())
    }

    /// Writes the picture as PNG, whole or not at all.
    pub fn write_png(&self, path: impl AsRef<Path>) -> Result<(), SceneError> {
        let path = path.as_ref();
        let png = self.to_png().map_err(|e| e.at(path))?;
        write_whole(path, &png)
    }

    /// Writes SVG or PNG, as the path's extension says (in any case).
    pub fn save(&self, path: impl AsRef<Path>) -> Result<(), SceneError> {
        let path = path.as_ref();
        let extension = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match extension.as_deref() {
            Some("svg") => self.write_svg(path),
            Some("png") => self.write_png(path),
            _ => Err(SceneError::from(ErrorKind::UnknownFormat).at(path)),
        }
    }
}

fn drawing(e: hamel_plot::PlotError) -> SceneError {
    ErrorKind::Drawing {
        message: e.to_string(),
    }
    .into()
}

/// The triad's colours: x red, y green, z blue.
const AXES: [(&str, Rgb); 3] = [
    ("x axes", Rgb(214, 39, 40)),
    ("y axes", Rgb(44, 160, 44)),
    ("z axes", Rgb(31, 119, 180)),
];

/// The point of `surface` nearest `p` (for a sphere, the one on the line to its centre).
fn foot(surface: &Surface, p: Vector3) -> Vector3 {
    p - surface.height(p) * surface.normal(p)
}

/// What each view draws.
struct Drawing<'a> {
    looks: &'a [Look],
    bodies: &'a [Body],
    contacts: &'a [Vector3],
    surfaces: &'a [Surface],
    /// Each contact's foot on its surface: the view holds them, so that a gap shows.
    feet: &'a [Vector3],
    centroid: Vector3,
}

/// One view: a line series per body, one per axis of the triads, the contacts and the
/// surfaces, on axes of equal scale that hold everything but the surfaces with a margin.
fn panel(view: &View, drawing: &Drawing, unit: &str) -> Panel {
    let Drawing {
        looks,
        bodies,
        contacts,
        ..
    } = *drawing;
    let title = format!(
        "{}, looking along {}",
        view.name,
        direction_name(view.looking())
    );
    let mut series = Vec::new();
    let mut all: Vec<(f64, f64)> = Vec::new();
    for (look, body) in looks.iter().zip(bodies) {
        let lines = outline(look, body, view);
        all.extend(lines.iter().flatten());
        let name = match look.warning {
            Some(_) => format!("{} (cannot be drawn from its inertia)", look.name),
            None => look.name.clone(),
        };
        series.push(joined(&name, &lines).color(rgb(look.color)));
    }
    for (k, (name, color)) in AXES.iter().enumerate() {
        let lines: Vec<Line> = looks
            .iter()
            .zip(bodies)
            .map(|(look, body)| {
                let axis = body.orientation * [Vector3::x(), Vector3::y(), Vector3::z()][k];
                vec![
                    view.project(body.centre),
                    view.project(body.centre + look.triad * axis),
                ]
            })
            .collect();
        all.extend(lines.iter().flatten());
        series.push(joined(name, &lines).color(*color));
    }
    if !contacts.is_empty() {
        let (x, y): (Vec<f64>, Vec<f64>) = contacts.iter().map(|&p| view.project(p)).unzip();
        all.extend(x.iter().copied().zip(y.iter().copied()));
        series.push(Series::points("contacts", &x, &y).color(Rgb(0, 0, 0)));
    }
    all.extend(drawing.feet.iter().map(|&p| view.project(p)));
    let (mut x0, mut x1, mut y0, mut y1) = bounds(&all);
    let margin = 0.08 * (x1 - x0).max(y1 - y0).max(1e-9);
    (x0, x1, y0, y1) = (x0 - margin, x1 + margin, y0 - margin, y1 + margin);
    // Equal scales widen the shorter side to the longer (the views are about square): the
    // surfaces are cut to that square, so that they reach the frame.
    let half = 0.5 * (x1 - x0).max(y1 - y0);
    let (cx, cy) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
    let square = (cx - half, cx + half, cy - half, cy + half);
    for (k, surface) in drawing.surfaces.iter().enumerate() {
        let drawn = surface_lines(surface, view, drawing.centroid, square);
        if !drawn.lines.is_empty() {
            let name = surface_name(surface, k, drawing.surfaces.len());
            let (x, y) = broken(&drawn.lines);
            // Under the bodies, drawn first.
            series.insert(
                0,
                if drawn.dashed {
                    Series::dashed(name, &x, &y).color(Rgb(120, 120, 120))
                } else {
                    // Tan, apart from the axes' grey grid lines.
                    Series::line(name, &x, &y).color(Rgb(214, 184, 140))
                },
            );
        }
    }
    let mut panel = Panel::new(title)
        .x_label(format!("{}{unit}", direction_name(view.right)))
        .y_label(format!("{}{unit}", direction_name(view.up)))
        .x_range(x0, x1)
        .y_range(y0, y1)
        .equal_aspect();
    for s in series {
        panel = panel.series(s);
    }
    panel
}

/// A surface's name in the legend: "ground" for the plane z = 0 at rest, else its kind,
/// numbered when there are several.
fn surface_name(surface: &Surface, k: usize, count: usize) -> String {
    let kind = match surface {
        s if *s == Surface::ground() => "ground",
        Surface::Plane { .. } => "plane",
        Surface::Sphere { .. } => "sphere",
        Surface::Bowl { .. } => "bowl",
    };
    if count > 1 {
        format!("{kind} {}", k + 1)
    } else {
        kind.to_string()
    }
}

/// One series of several polylines, broken where one ends (a non-finite point breaks a line).
fn joined(name: &str, lines: &[Line]) -> Series {
    let (x, y) = broken(lines);
    Series::line(name, &x, &y)
}

/// Several polylines as one, with a non-finite point between each two.
fn broken(lines: &[Line]) -> (Vec<f64>, Vec<f64>) {
    let (mut x, mut y) = (Vec::new(), Vec::new());
    for (i, line) in lines.iter().enumerate() {
        if i > 0 {
            x.push(f64::NAN);
            y.push(f64::NAN);
        }
        for &(a, b) in line {
            x.push(a);
            y.push(b);
        }
    }
    (x, y)
}

fn bounds(points: &[(f64, f64)]) -> (f64, f64, f64, f64) {
    points.iter().fold(
        (
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ),
        |(x0, x1, y0, y1), &(x, y)| (x0.min(x), x1.max(x), y0.min(y), y1.max(y)),
    )
}

fn rgb(color: u32) -> Rgb {
    Rgb((color >> 16) as u8, (color >> 8) as u8, color as u8)
}
