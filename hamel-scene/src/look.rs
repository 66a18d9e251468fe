//! How each body is drawn: the solid given for it by name, else the body's own shape, else
//! the disk or sphere its contact makes it, else the uniform solid of its mass and inertia;
//! its colour, a line saying what it is drawn as, and a warning when its inertia is no body's.

use super::equivalent::{Equivalent, box_edges, ellipsoid_semi_axes, short};
use super::error::{ErrorKind, SceneError};
use super::snapshot::Snapshot;
use super::solid::{Form, Solid};
use hamel_runtime::geometry::{Body, Shape, Vector3};

/// The bodies' colours, in order (Tableau 10 without its red and green, which the axes use).
pub(crate) const PALETTE: [u32; 8] = [
    0x4e79a7, 0xf28e2b, 0x76b7b2, 0xb07aa1, 0xedc948, 0x9c755f, 0xff9da7, 0xbab0ac,
];
/// A body that cannot be drawn from its inertia is a marker of this colour.
pub(crate) const WARNING_COLOR: u32 = 0xd62728;

/// A solid in a body's axes, about the point `Look::offset`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Drawn {
    /// A thin disk normal to `axis` (a unit vector).
    Disk {
        radius: f64,
        axis: Vector3,
    },
    Sphere {
        radius: f64,
    },
    /// Semi-axes along the columns of `axes`, a rotation.
    Ellipsoid {
        semi_axes: [f64; 3],
        axes: [[f64; 3]; 3],
    },
    /// Edges along the columns of `axes`, a rotation.
    Box {
        edges: [f64; 3],
        axes: [[f64; 3]; 3],
    },
    /// Along `axis` (a unit vector).
    Cylinder {
        radius: f64,
        length: f64,
        axis: Vector3,
    },
    /// A point mass, or a body that cannot be drawn from its inertia: a small sphere.
    Marker {
        radius: f64,
    },
}

impl Drawn {
    /// Half the solid's largest extent; `None` for a marker, whose size follows the others'.
    pub(crate) fn half_size(&self) -> Option<f64> {
        let largest = |v: &[f64; 3]| v.iter().fold(0.0_f64, |m, &x| m.max(x));
        match self {
            Drawn::Disk { radius, .. } | Drawn::Sphere { radius } => Some(*radius),
            Drawn::Ellipsoid { semi_axes, .. } => Some(largest(semi_axes)),
            Drawn::Box { edges, .. } => Some(0.5 * edges.iter().map(|e| e * e).sum::<f64>().sqrt()),
            Drawn::Cylinder { radius, length, .. } => Some(radius.hypot(0.5 * length)),
            Drawn::Marker { .. } => None,
        }
    }
}

/// How one body is drawn.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Look {
    pub name: String,
    pub solid: Drawn,
    /// The solid's centre, in the body's axes from its centre of mass.
    pub offset: Vector3,
    pub color: u32,
    /// What the body is drawn as, and from what ("disk of radius 0.3, from its contact").
    pub description: String,
    /// Why the body is not drawn from its inertia, when its inertia is no body's.
    pub warning: Option<String>,
    /// The length of its axes' triad.
    pub triad: f64,
}

/// Every body's look in `snapshot`, with the solids `given` by name. An unknown name, or a
/// solid given or a shape of the model's that cannot be drawn, is an error.
pub(crate) fn looks(
    snapshot: &Snapshot,
    given: &[(String, Solid)],
) -> Result<Vec<Look>, SceneError> {
    let names = snapshot.names;
    let own = names
        .iter()
        .zip(&snapshot.bodies)
        .filter_map(|(name, body)| Some((name.to_string(), Solid::from(body.shape?))));
    for (name, shape) in given.iter().cloned().chain(own) {
        if !names.contains(&name.as_str()) {
            return Err(ErrorKind::UnknownBody {
                name: name.clone(),
                known: names.join(", "),
            }
            .into());
        }
        if let Some(problem) = shape.problem() {
            return Err(ErrorKind::InvalidShape {
                body: name.clone(),
                problem,
            }
            .into());
        }
    }
    let mut looks: Vec<Look> = names
        .iter()
        .zip(&snapshot.bodies)
        .zip(&snapshot.rolling)
        .enumerate()
        .map(|(i, ((name, body), rolling))| {
            // The last solid given for a body wins.
            let solid = given.iter().rev().find(|(n, _)| n == name).map(|(_, s)| s);
            look(name, body, *rolling, solid, PALETTE[i % PALETTE.len()])
        })
        .collect();
    size_markers_and_triads(&mut looks);
    Ok(looks)
}

/// One body's look, before markers and triads are sized: the solid `given` for it, else its
/// own shape, else the shape its contact makes it (`rolling`), else its inertia's.
fn look(
    name: &str,
    body: &Body,
    rolling: Option<Shape>,
    given: Option<&Solid>,
    color: u32,
) -> Look {
    let mut warning = None;
    let (solid, centre, description) = match (given, body.shape, rolling) {
        (Some(solid), ..) => {
            let (drawn, description) = as_given(solid.form, name, body, &mut warning);
            (drawn, solid.centre, description)
        }
        (None, Some(shape), _) => {
            let (drawn, what) = of_shape(&shape);
            (drawn, shape.centre(), format!("{what}, its shape"))
        }
        (None, None, Some(shape)) => {
            let (drawn, what) = of_shape(&shape);
            (drawn, shape.centre(), format!("{what}, from its contact"))
        }
        (None, None, None) => {
            let (drawn, description) = from_inertia(name, body, false, &mut warning);
            (drawn, Vector3::zeros(), description)
        }
    };
    let color = match (given.and_then(|s| s.color), &warning) {
        (Some(c), _) => c,
        (None, Some(_)) => WARNING_COLOR,
        (None, None) => color,
    };
    Look {
        name: name.to_string(),
        solid,
        offset: centre,
        color,
        description,
        warning,
        triad: 0.0,
    }
}

/// One of the model's shapes as drawn, and what it is. A wheel with a tyre is drawn as the
/// disk of its outer radius.
fn of_shape(shape: &Shape) -> (Drawn, String) {
    match *shape {
        Shape::Disk { axle, radius, .. } => (
            Drawn::Disk {
                radius,
                axis: axle.normalize(),
            },
            format!("disk of radius {}", short(radius)),
        ),
        Shape::Torus {
            axle, radius, tube, ..
        } => (
            Drawn::Disk {
                radius: radius + tube,
                axis: axle.normalize(),
            },
            format!(
                "wheel of radius {} with a tyre of radius {} (drawn as a disk of radius {})",
                short(radius),
                short(tube),
                short(radius + tube)
            ),
        ),
        Shape::Sphere { radius, .. } => (
            Drawn::Sphere { radius },
            format!("sphere of radius {}", short(radius)),
        ),
        Shape::Ellipsoid { semi_axes, .. } => {
            let semi_axes = semi_axes.to_array();
            (
                Drawn::Ellipsoid {
                    semi_axes,
                    axes: IDENTITY,
                },
                format!("ellipsoid, semi-axes {}", sizes(&semi_axes)),
            )
        }
    }
}

/// The uniform box or ellipsoid of the body's mass and inertia, or a marker and a warning.
fn from_inertia(
    name: &str,
    body: &Body,
    as_box: bool,
    warning: &mut Option<String>,
) -> (Drawn, String) {
    match Equivalent::of(body.mass, &body.inertia) {
        Equivalent::PointMass => (Drawn::Marker { radius: 0.0 }, "point mass".to_string()),
        Equivalent::Impossible(reason) => {
            *warning = Some(format!("body `{name}`: {reason}"));
            (
                Drawn::Marker { radius: 0.0 },
                "marker: its inertia is no body's (see the warning)".to_string(),
            )
        }
        Equivalent::Solid { spans, axes } if as_box => {
            let edges = box_edges(spans);
            let text = format!(
                "uniform box of its mass and inertia, edges {}",
                sizes(&edges)
            );
            (Drawn::Box { edges, axes }, text)
        }
        Equivalent::Solid { spans, axes } => {
            let semi_axes = ellipsoid_semi_axes(spans);
            let text = format!(
                "uniform ellipsoid of its mass and inertia, semi-axes {}",
                sizes(&semi_axes)
            );
            (Drawn::Ellipsoid { semi_axes, axes }, text)
        }
    }
}

const IDENTITY: [[f64; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

/// A solid given by name, as drawn.
fn as_given(form: Form, name: &str, body: &Body, warning: &mut Option<String>) -> (Drawn, String) {
    match form {
        Form::InertiaBox => from_inertia(name, body, true, warning),
        Form::InertiaEllipsoid => from_inertia(name, body, false, warning),
        Form::Shape(shape) => {
            let (drawn, what) = of_shape(&shape);
            (drawn, format!("{what}, as given"))
        }
        Form::Box(edges) => (
            Drawn::Box {
                edges,
                axes: IDENTITY,
            },
            format!("box {}, as given", sizes(&edges)),
        ),
        Form::Cylinder(radius, length, axis) => (
            Drawn::Cylinder {
                radius,
                length,
                axis: axis.normalize(),
            },
            format!(
                "cylinder of radius {} and length {}, as given",
                short(radius),
                short(length)
            ),
        ),
    }
}

fn sizes(v: &[f64; 3]) -> String {
    format!("{} × {} × {}", short(v[0]), short(v[1]), short(v[2]))
}

/// Markers get a tenth of the largest body's size (or 0.05 when every body is a marker);
/// each triad reaches past its body's surface, and is never shorter than a quarter of the
/// largest body's size, so that a small body's axes still show.
fn size_markers_and_triads(looks: &mut [Look]) {
    let largest = looks
        .iter()
        .filter_map(|l| l.solid.half_size())
        .fold(0.0_f64, f64::max);
    let largest = if largest > 0.0 { largest } else { 0.5 };
    for look in looks {
        if let Drawn::Marker { radius } = &mut look.solid {
            *radius = 0.1 * largest;
        }
        let own = look.solid.half_size().unwrap_or(0.0) + look.offset.norm();
        look.triad = (1.4 * own).max(0.25 * largest);
    }
}
