//! Bodies drawn through the surfaces the contacts touch: a warning for each, so that a
//! drawing that is not the body's shape (the uniform ellipsoid of a rattleback's inertia sits
//! 5.8 mm into the floor its base rolls on), or a body that the model lets pass through a
//! surface (a pendulum hanging under an axle, with no contact of its own), is not shown
//! without a word.
//!
//! A solid's reach along a direction is its support function: for a disk of radius r about
//! the axis a, r √(1 − (a·d)²); for an ellipsoid of semi-axes sₖ along the axes aₖ,
//! √Σ (sₖ aₖ·d)²; for a box of edges eₖ, Σ eₖ/2 |aₖ·d|; for a cylinder, its disk's and half
//! its length times |a·d|. The depth of a solid in a surface is its reach towards the surface
//! less the height of its centre above it (exact for a plane; for a sphere or a bowl, along
//! the line through the sphere's centre).

use super::equivalent::short;
use super::look::{Drawn, Look};
use super::snapshot::Snapshot;
use hamel_runtime::geometry::{Rotation3, Surface, Vector3};

/// A solid that reaches past a surface by more than this fraction of its size is drawn
/// through it: below it, the overlap does not show at any scale the page or picture draws.
const PENETRATION: f64 = 1e-3;

/// A body's pose at one sample.
pub(crate) struct Pose {
    pub t: f64,
    pub centre: Vector3,
    pub orientation: Rotation3,
}

/// The deepest a body reaches into one surface, and when.
#[derive(Clone, Copy, Debug)]
struct Deepest {
    depth: f64,
    t: f64,
}

/// A body drawn through a surface.
pub(crate) struct Through {
    /// The body's index.
    pub body: usize,
    /// In a few words, for a picture's legend: "drawn into the plane".
    pub short: String,
    /// The warning.
    pub message: String,
}

/// The bodies drawn as `looks` that reach through the surfaces the contacts touch, at the
/// poses `poses(b)` gives for body b (the snapshot says where the surfaces are, which side of
/// each the bodies are on, and which bodies roll on which).
pub(crate) fn penetrations<'p>(
    looks: &[Look],
    poses: impl Fn(usize) -> Box<dyn Iterator<Item = Pose> + 'p>,
    snapshot: &Snapshot,
) -> Vec<Through> {
    let surfaces = &snapshot.surfaces;
    let sides: Vec<f64> = (0..surfaces.len()).map(|s| snapshot.side(s)).collect();
    let unit = (snapshot.unit)("x").map_or(String::new(), |u| format!(" {u}"));
    let mut warnings = Vec::new();
    for (b, look) in looks.iter().enumerate() {
        let Some(size) = look.solid.half_size().filter(|s| *s > 0.0) else {
            continue;
        };
        let mut deepest: Vec<Option<Deepest>> = vec![None; surfaces.len()];
        for pose in poses(b) {
            let centre = pose.centre + pose.orientation * look.offset;
            for (s, surface) in surfaces.iter().enumerate() {
                let depth = depth(&look.solid, centre, pose.orientation, surface, sides[s]);
                let deeper = deepest[s].is_none_or(|d| depth > d.depth);
                if depth > PENETRATION * size && deeper {
                    deepest[s] = Some(Deepest { depth, t: pose.t });
                }
            }
        }
        for (s, found) in deepest.iter().enumerate() {
            if let Some(d) = found {
                warnings.push(Through {
                    body: b,
                    short: format!("drawn into {}", name(&surfaces[s])),
                    message: message(look, &surfaces[s], *d, snapshot.rolls_on(b, s), &unit),
                });
            }
        }
    }
    warnings
}

/// How far `solid`, centred at `centre` and turned by `orientation`, reaches into
/// `surface`, whose bodies are on its `side` (negative: it stays that far out).
fn depth(
    solid: &Drawn,
    centre: Vector3,
    orientation: Rotation3,
    surface: &Surface,
    side: f64,
) -> f64 {
    let outward = match *surface {
        Surface::Plane { orientation, .. } => side * (orientation * Vector3::z()),
        Surface::Sphere { centre: c, .. } => (centre - c).normalize(),
        Surface::Bowl { centre: c, .. } => (c - centre).normalize(),
    };
    // The solid's reach towards the surface, read in its body's axes.
    let reach = support(solid, orientation.transpose() * outward);
    if !reach.is_finite() || !outward.norm().is_finite() {
        return 0.0;
    }
    reach - side * surface.height(centre)
}

/// The solid's support function along the unit vector `d` (body axes): how far it reaches
/// from its centre in that direction. A marker is a point.
fn support(solid: &Drawn, d: Vector3) -> f64 {
    let column = |axes: &[[f64; 3]; 3], k: usize| Vector3::new(axes[0][k], axes[1][k], axes[2][k]);
    let across = |axis: Vector3| (1.0 - axis.dot(&d).powi(2)).max(0.0).sqrt();
    match *solid {
        Drawn::Disk { radius, axis } => radius * across(axis),
        Drawn::Sphere { radius } => radius,
        Drawn::Ellipsoid { semi_axes, axes } => (0..3)
            .map(|k| (semi_axes[k] * column(&axes, k).dot(&d)).powi(2))
            .sum::<f64>()
            .sqrt(),
        Drawn::Box { edges, axes } => (0..3)
            .map(|k| 0.5 * edges[k] * column(&axes, k).dot(&d).abs())
            .sum(),
        Drawn::Cylinder {
            radius,
            length,
            axis,
        } => radius * across(axis) + 0.5 * length * axis.dot(&d).abs(),
        Drawn::Marker { .. } => 0.0,
    }
}

/// The surface, in words.
fn name(surface: &Surface) -> &'static str {
    match surface {
        Surface::Plane { .. } => "the plane",
        Surface::Sphere { .. } => "the sphere",
        Surface::Bowl { .. } => "the bowl's wall",
    }
}

/// The warning for a body drawn `deepest` into `surface` (lengths in `unit`).
fn message(look: &Look, surface: &Surface, deepest: Deepest, rolls_on: bool, unit: &str) -> String {
    let what = name(surface);
    let (name, depth, t) = (&look.name, short(deepest.depth), short(deepest.t));
    let solid = &look.description;
    if rolls_on {
        format!(
            "body `{name}` is drawn {depth}{unit} into {what} it rolls on (the deepest, at t = \
             {t}): the solid drawn, {solid}, is not the body's shape, which stays on its side \
             of the surface; give the body its shape (`Scene::shape`, or a `Shape` in the \
             model)"
        )
    } else {
        format!(
            "body `{name}` is drawn {depth}{unit} through {what} the contacts touch (the \
             deepest, at t = {t}): it has no contact with it, so nothing in the model keeps it \
             out; either the motion takes it through, or the solid drawn, {solid}, is larger \
             than the body (give its shape with `Scene::shape`)"
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn identity() -> [[f64; 3]; 3] {
        [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
    }

    /// The support functions against their solids' extreme points, along a direction
    /// that is no axis.
    #[test]
    fn each_solid_reaches_as_far_as_its_farthest_point() {
        let d = Vector3::new(0.3, -0.4, 0.5).normalize();
        let ellipsoid = Drawn::Ellipsoid {
            semi_axes: [3.0, 2.0, 1.0],
            axes: identity(),
        };
        // The farthest point of the ellipsoid along d is S² d / |S d|.
        let (sx, sy, sz) = (3.0 * d.x, 2.0 * d.y, d.z);
        let far = (sx * sx + sy * sy + sz * sz).sqrt();
        assert!((support(&ellipsoid, d) - far).abs() < 1e-14);
        let cube = Drawn::Box {
            edges: [1.0, 2.0, 3.0],
            axes: identity(),
        };
        let corner = 0.5 * d.x.abs() + d.y.abs() + 1.5 * d.z.abs();
        assert!((support(&cube, d) - corner).abs() < 1e-14);
        // A disk normal to z: its rim's farthest point is along d's part in the xy plane.
        let disk = Drawn::Disk {
            radius: 2.0,
            axis: Vector3::z(),
        };
        assert!((support(&disk, d) - 2.0 * d.x.hypot(d.y)).abs() < 1e-14);
        // A wheel standing on the ground touches it, and no more.
        let upright = Drawn::Disk {
            radius: 0.3,
            axis: Vector3::y(),
        };
        let ground = Surface::ground();
        let (centre, turned) = (Vector3::new(1.0, 2.0, 0.3), Rotation3::about_z(0.7));
        let on = depth(&upright, centre, turned, &ground, 1.0);
        assert!(on.abs() < 1e-15, "{on}");
        // Under a ground whose bodies are below it (z down), it is as far in as it is wide.
        let under = depth(&upright, centre, turned, &ground, -1.0);
        assert!((under - 0.6).abs() < 1e-15, "{under}");
    }
}
