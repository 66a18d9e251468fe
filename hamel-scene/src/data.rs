//! The data a scene page carries, as one JSON object: the bodies' looks, the directions, the
//! surfaces (a plane with its grid), the camera's reach and, base64-encoded, the samples.

use super::json::{array, f32_base64, f64_base64, number, numbers, object, string};
use super::look::{Drawn, Look};
use super::motion::Motion;
use super::view::Directions;
use hamel_runtime::geometry::{Rotation3, Surface, Vector3};

/// A column shown beside the scene: its name, unit and values.
pub(crate) struct Shown<'t> {
    pub name: &'t str,
    pub unit: Option<&'t str>,
    pub values: &'t [f64],
}

/// Everything the page needs besides three.js.
pub(crate) struct Contents<'a> {
    pub looks: &'a [Look],
    pub motion: &'a Motion,
    pub directions: Directions,
    pub gravity: Option<Vector3>,
    /// The body each contact belongs to, if it is one of the model's.
    pub contact_bodies: &'a [Option<usize>],
    /// The surfaces the contacts touch, and each contact's (an index into `surfaces`).
    pub surfaces: &'a [Surface],
    pub contact_surfaces: &'a [usize],
    pub warnings: &'a [String],
    pub shown: &'a [Shown<'a>],
    pub time_unit: &'a str,
}

/// The JSON object of the page's data.
pub(crate) fn json(c: &Contents) -> String {
    let bodies: Vec<String> = c.looks.iter().map(body).collect();
    let contacts: Vec<String> = c
        .contact_bodies
        .iter()
        .zip(c.contact_surfaces)
        .map(|(b, s)| {
            object(&[
                ("body", b.map_or("null".into(), |b| number(b as f64))),
                ("surface", number(*s as f64)),
            ])
        })
        .collect();
    let columns: Vec<String> = c
        .shown
        .iter()
        .map(|s| {
            object(&[
                ("name", string(s.name)),
                ("unit", s.unit.map_or("null".into(), string)),
            ])
        })
        .collect();
    let warnings: Vec<String> = c.warnings.iter().map(|w| string(w)).collect();
    let samples = c.motion.rows.len();
    let mut values = Vec::with_capacity(samples * c.shown.len());
    for &row in &c.motion.rows {
        values.extend(c.shown.iter().map(|s| s.values[row]));
    }
    let size = largest_size(c.looks);
    // A model without contacts stands on the ground z = 0.
    let ground = [Surface::ground()];
    let surfaces = if c.surfaces.is_empty() {
        &ground[..]
    } else {
        c.surfaces
    };
    let surfaces: Vec<String> = surfaces
        .iter()
        .map(|s| surface(s, c.motion, size))
        .collect();
    object(&[
        ("up", numbers(&c.directions.up.to_array())),
        ("forward", numbers(&c.directions.forward.to_array())),
        ("left", numbers(&c.directions.left.to_array())),
        (
            "gravity",
            c.gravity.map_or("null".into(), |g| numbers(&g.to_array())),
        ),
        ("bodies", array(&bodies)),
        ("contacts", array(&contacts)),
        ("columns", array(&columns)),
        ("warnings", array(&warnings)),
        ("time_unit", string(c.time_unit)),
        ("radius", number(reach(c.looks, c.motion))),
        ("surfaces", array(&surfaces)),
        ("times", f64_base64(&c.motion.times)),
        ("poses", f32_base64(&c.motion.poses)),
        ("points", f32_base64(&c.motion.points)),
        ("values", f64_base64(&values)),
    ])
}

fn body(look: &Look) -> String {
    object(&[
        ("name", string(&look.name)),
        ("color", number(f64::from(look.color))),
        ("description", string(&look.description)),
        ("triad", number(look.triad)),
        ("offset", numbers(&look.offset.to_array())),
        ("solid", solid(&look.solid)),
    ])
}

fn solid(s: &Drawn) -> String {
    let kind = |k: &str| ("kind", string(k));
    match s {
        Drawn::Disk { radius, axis } => object(&[
            kind("disk"),
            ("radius", number(*radius)),
            ("axis", numbers(&axis.to_array())),
        ]),
        Drawn::Sphere { radius } => object(&[kind("sphere"), ("radius", number(*radius))]),
        Drawn::Marker { radius } => object(&[kind("marker"), ("radius", number(*radius))]),
        Drawn::Ellipsoid { semi_axes, axes } => object(&[
            kind("ellipsoid"),
            ("semi_axes", numbers(semi_axes)),
            ("rotation", numbers(&rotation(axes))),
        ]),
        Drawn::Box { edges, axes } => object(&[
            kind("box"),
            ("edges", numbers(edges)),
            ("rotation", numbers(&rotation(axes))),
        ]),
        Drawn::Cylinder {
            radius,
            length,
            axis,
        } => object(&[
            kind("cylinder"),
            ("radius", number(*radius)),
            ("length", number(*length)),
            ("axis", numbers(&axis.to_array())),
        ]),
    }
}

/// The rotation whose columns are `axes`, as a quaternion (x, y, z, w).
fn rotation(axes: &[[f64; 3]; 3]) -> [f64; 4] {
    super::motion::quaternion(axes).unwrap_or([0.0, 0.0, 0.0, 1.0])
}

/// Half the largest body's size.
pub(crate) fn largest_size(looks: &[Look]) -> f64 {
    looks
        .iter()
        .map(|l| match l.solid {
            Drawn::Marker { radius } => radius,
            s => s.half_size().unwrap_or(0.0),
        })
        .fold(0.0, f64::max)
}

/// How far the mechanism reaches from its centroid at the first sample: what the camera
/// frames.
fn reach(looks: &[Look], motion: &Motion) -> f64 {
    let bodies = looks.len();
    let centres: Vec<[f64; 3]> = (0..bodies).map(|b| motion.centre(0, b, bodies)).collect();
    let mut centroid = [0.0; 3];
    for c in &centres {
        for k in 0..3 {
            centroid[k] += c[k] / bodies as f64;
        }
    }
    let size = largest_size(looks);
    let reach = looks
        .iter()
        .zip(&centres)
        .map(|(look, c)| {
            let d = Vector3::from(*c) - Vector3::from(centroid);
            d.norm() + look.offset.norm() + look.solid.half_size().unwrap_or(size)
        })
        .fold(0.0, f64::max);
    if reach > 0.0 { reach } else { 1.0 }
}

/// A surface as the page draws it: a plane with its pose and the grid drawn in it, a sphere
/// or a bowl with its centre and radius.
fn surface(s: &Surface, motion: &Motion, size: f64) -> String {
    match *s {
        Surface::Plane {
            origin,
            orientation,
        } => object(&[
            ("kind", string("plane")),
            ("origin", numbers(&origin.to_array())),
            ("rotation", numbers(&rotation(&orientation.matrix()))),
            ("grid", grid(motion, origin, orientation, size)),
        ]),
        Surface::Sphere { centre, radius } | Surface::Bowl { centre, radius } => object(&[
            (
                "kind",
                string(if matches!(s, Surface::Bowl { .. }) {
                    "bowl"
                } else {
                    "sphere"
                }),
            ),
            ("centre", numbers(&centre.to_array())),
            ("radius", number(radius)),
        ]),
    }
}

/// The grid drawn in a plane under the whole motion, in the plane's own x and y: its centre,
/// its side and its step, a round number at least the largest body's half-size (coarser if
/// the motion would need more than 100 lines: in software rendering the grid's lines are a
/// fifth of a frame's cost), an even number of steps so that lines pass through round
/// coordinates. The motion's extent is its bounding box seen in the plane.
fn grid(motion: &Motion, origin: Vector3, orientation: Rotation3, size: f64) -> String {
    let size = if size > 0.0 { size } else { 1.0 };
    let margin = 3.0 * size;
    let (mut low, mut high) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for corner in 0..8 {
        let pick = |k: usize| {
            if corner >> k & 1 == 0 {
                motion.low[k]
            } else {
                motion.high[k]
            }
        };
        let local = orientation.transpose() * (Vector3::new(pick(0), pick(1), pick(2)) - origin);
        for (k, v) in [local.x, local.y].into_iter().enumerate() {
            (low[k], high[k]) = (low[k].min(v), high[k].max(v));
        }
    }
    let span = (high[0] - low[0]).max(high[1] - low[1]).max(0.0) + 2.0 * margin;
    let step = round_up(size).max(round_up(span / 100.0));
    let steps = (span / step).ceil() as u64;
    let steps = steps + steps % 2;
    let middle = |k: usize| ((low[k] + high[k]) / (2.0 * step)).round() * step;
    object(&[
        ("centre", numbers(&[middle(0), middle(1)])),
        ("size", number(steps as f64 * step)),
        ("step", number(step)),
    ])
}

/// The smallest of 1, 2 and 5 times a power of ten that is at least `x` (> 0).
pub(crate) fn round_up(x: f64) -> f64 {
    let power = 10f64.powf(x.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * power)
        .find(|v| *v >= x * (1.0 - 1e-12))
        .unwrap_or(10.0 * power)
}

#[cfg(test)]
mod tests {
    use super::round_up;

    #[test]
    fn grid_steps_are_round() {
        assert_eq!(round_up(0.3), 0.5);
        assert_eq!(round_up(0.05), 0.05);
        assert_eq!(round_up(1.2), 2.0);
        assert_eq!(round_up(7.0), 10.0);
    }
}
