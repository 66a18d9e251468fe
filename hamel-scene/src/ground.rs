//! The surfaces the contacts touch, as lines on one orthographic view, cut to the part of the
//! view that is drawn: a plane as a hatch of lines along its own x and y axes (one dashed
//! line when seen edge-on; nothing when seen face-on, where it would cover everything), a
//! sphere or a bowl as its dashed outline.

use super::data::round_up;
use super::outline::Line;
use super::view::View;
use hamel_runtime::geometry::{Surface, Vector3};

/// A plane seen this nearly face-on is not drawn.
const FACE_ON: f64 = 0.999;
/// A plane whose normal is this nearly across the view is seen edge-on, as one line.
const EDGE_ON: f64 = 1e-9;

/// A surface's lines on a view, and whether to dash them (an outline, or a plane edge-on)
/// rather than draw them thin (a plane's hatch).
pub(crate) struct SurfaceLines {
    pub lines: Vec<Line>,
    pub dashed: bool,
}

/// The lines of `surface` on `view` within `bounds` (x0, x1, y0, y1), `centre` the point the
/// picture is about (a plane's hatch is laid out around its foot on the plane).
pub(crate) fn surface_lines(
    surface: &Surface,
    view: &View,
    centre: Vector3,
    bounds: (f64, f64, f64, f64),
) -> SurfaceLines {
    let (x0, x1, y0, y1) = bounds;
    let span = (x1 - x0).max(y1 - y0);
    let mut dashed = true;
    let lines = match *surface {
        Surface::Plane {
            origin,
            orientation,
        } => {
            let normal = orientation * Vector3::z();
            let facing = normal.dot(&view.looking()).abs();
            if facing > FACE_ON {
                return SurfaceLines {
                    lines: Vec::new(),
                    dashed,
                };
            }
            let foot = centre - normal.dot(&(centre - origin)) * normal;
            let reach = 1.5 * span;
            if facing < EDGE_ON {
                // Every line in the plane falls on the one along the plane across the view.
                let along = normal.cross(&view.looking()).normalize();
                let line = vec![
                    view.project(foot - reach * along),
                    view.project(foot + reach * along),
                ];
                return SurfaceLines {
                    lines: clip(&line, bounds),
                    dashed,
                };
            }
            dashed = false;
            let (ex, ey) = (orientation * Vector3::x(), orientation * Vector3::y());
            // Lines every `step` along each of the plane's axes, long enough to cross the
            // view whatever the plane's tilt (the view's diagonal is under 1.5 spans, and a
            // plane seen obliquely needs up to 1/cos of that).
            let step = round_up(span / 8.0);
            let reach = (reach / facing).min(1e3 * span);
            let count = (reach / step).ceil() as i64;
            let mut lines = Vec::new();
            for (along, across) in [(ex, ey), (ey, ex)] {
                for k in -count..=count {
                    let base = foot + (k as f64 * step) * across;
                    lines.push(vec![
                        view.project(base - reach * along),
                        view.project(base + reach * along),
                    ]);
                }
            }
            lines
        }
        Surface::Sphere { centre, radius } | Surface::Bowl { centre, radius } => {
            // Fine enough that the chord of a large sphere's arc strays under a two-hundredth
            // of the view from the circle.
            let points = (std::f64::consts::TAU * (radius / (0.005 * span)).sqrt()).ceil();
            let points = points.clamp(72.0, 20_000.0) as usize;
            let (cx, cy) = view.project(centre);
            vec![
                (0..=points)
                    .map(|k| {
                        let angle = std::f64::consts::TAU * k as f64 / points as f64;
                        (cx + radius * angle.cos(), cy + radius * angle.sin())
                    })
                    .collect(),
            ]
        }
    };
    SurfaceLines {
        lines: lines.iter().flat_map(|line| clip(line, bounds)).collect(),
        dashed,
    }
}

/// The parts of a polyline inside the box (x0, x1, y0, y1), each segment cut at the box's
/// edges (Liang–Barsky).
fn clip(line: &Line, (x0, x1, y0, y1): (f64, f64, f64, f64)) -> Vec<Line> {
    let mut parts: Vec<Line> = Vec::new();
    let mut current: Line = Vec::new();
    for pair in line.windows(2) {
        let ((ax, ay), (bx, by)) = (pair[0], pair[1]);
        let (dx, dy) = (bx - ax, by - ay);
        let (mut t0, mut t1) = (0.0_f64, 1.0_f64);
        let mut inside = true;
        for (p, q) in [(-dx, ax - x0), (dx, x1 - ax), (-dy, ay - y0), (dy, y1 - ay)] {
            if p == 0.0 {
                inside &= q >= 0.0;
            } else if p < 0.0 {
                t0 = t0.max(q / p);
            } else {
                t1 = t1.min(q / p);
            }
        }
        if !inside || t0 > t1 {
            if current.len() > 1 {
                parts.push(std::mem::take(&mut current));
            }
            current.clear();
            continue;
        }
        // Ends inside are kept exactly, so that the next segment joins on.
        let start = if t0 == 0.0 {
            pair[0]
        } else {
            (ax + t0 * dx, ay + t0 * dy)
        };
        let end = if t1 == 1.0 {
            pair[1]
        } else {
            (ax + t1 * dx, ay + t1 * dy)
        };
        if current.last() != Some(&start) {
            if current.len() > 1 {
                parts.push(std::mem::take(&mut current));
            }
            current = vec![start];
        }
        current.push(end);
    }
    if current.len() > 1 {
        parts.push(current);
    }
    parts
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::view::{Directions, View};
    use hamel_runtime::geometry::Rotation3;

    #[test]
    fn an_incline_seen_from_the_side_is_one_line_at_its_angle_and_a_sphere_its_circle() {
        let [_, side, top] = View::all(&Directions::new(None));
        let incline = Surface::plane(Vector3::zeros(), Rotation3::about_y(0.3));
        let bounds = (-1.0, 1.0, -1.0, 1.0);
        let SurfaceLines { lines, dashed } =
            surface_lines(&incline, &side, Vector3::zeros(), bounds);
        assert!(dashed && lines.len() == 1);
        // The line lies on z = −x tan 0.3: the plane's x axis is (cos 0.3, 0, −sin 0.3).
        for &(x, z) in lines.iter().flatten() {
            assert!((z + x * 0.3f64.tan()).abs() < 1e-12, "({x}, {z})");
            assert!((-1.0 - 1e-12..=1.0 + 1e-12).contains(&x));
        }
        assert!(!lines.is_empty());
        // From above, the tilted plane is a hatch across the whole view; the ground is not
        // drawn face-on.
        let hatch = surface_lines(&incline, &top, Vector3::zeros(), bounds);
        assert!(!hatch.dashed && hatch.lines.len() > 4);
        let ground = surface_lines(&Surface::ground(), &top, Vector3::zeros(), bounds);
        assert!(ground.lines.is_empty());
        // A sphere of radius 0.5 is its circle, whole inside the view.
        let ball = Surface::sphere(Vector3::new(0.0, 0.0, 0.2), 0.5);
        let lines = surface_lines(&ball, &side, Vector3::zeros(), bounds).lines;
        assert_eq!(lines.len(), 1);
        for &(x, z) in &lines[0] {
            assert!((x.hypot(z - 0.2) - 0.5).abs() < 1e-12);
        }
    }

    #[test]
    fn clipping_keeps_the_part_inside_and_splits_where_a_line_leaves() {
        let bounds = (0.0, 1.0, 0.0, 1.0);
        let parts = clip(&vec![(-1.0, 0.5), (2.0, 0.5)], bounds);
        assert_eq!(parts, vec![vec![(0.0, 0.5), (1.0, 0.5)]]);
        let parts = clip(
            &vec![(0.5, 0.5), (0.5, 2.0), (0.7, 2.0), (0.7, 0.5)],
            bounds,
        );
        assert_eq!(
            parts,
            vec![vec![(0.5, 0.5), (0.5, 1.0)], vec![(0.7, 1.0), (0.7, 0.5)]]
        );
        assert!(clip(&vec![(2.0, 2.0), (3.0, 3.0)], bounds).is_empty());
    }
}
