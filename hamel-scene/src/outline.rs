//! A body's solid as lines on one orthographic view: the exact silhouette of a sphere or an
//! ellipsoid, the rim of a disk, the edges of a box, the rims and four lines of a cylinder.

use nalgebra::{Matrix2, Matrix3, SymmetricEigen};

use super::look::{Drawn, Look};
use super::view::View;
use hamel_runtime::geometry::{Body, Rotation3, Vector3};

/// Points per full circle or ellipse.
const ROUND: usize = 72;

/// A polyline on the view.
pub(crate) type Line = Vec<(f64, f64)>;

/// The lines that draw `look` for `body` on `view`.
pub(crate) fn outline(look: &Look, body: &Body, view: &View) -> Vec<Line> {
    let r = body.orientation;
    let centre = body.point(look.offset);
    let (cx, cy) = view.project(centre);
    match look.solid {
        Drawn::Disk { radius, axis } => vec![ring(view, centre, r * axis, radius)],
        Drawn::Sphere { radius } | Drawn::Marker { radius } => {
            vec![ellipse((cx, cy), Matrix2::identity() * (radius * radius))]
        }
        Drawn::Ellipsoid { semi_axes, axes } => {
            // The silhouette of {x : xᵀ A x ≤ 1} seen along the view is the ellipse
            // {y : yᵀ (P A⁻¹ Pᵀ)⁻¹ y ≤ 1}, P the view's two screen directions.
            let world = matrix(&r) * matrix_of(&axes);
            let inverse = world
                * Matrix3::from_diagonal(&semi_axes.map(|a| a * a).into())
                * world.transpose();
            let p = nalgebra::Matrix2x3::from_rows(&[
                vector(view.right).transpose(),
                vector(view.up).transpose(),
            ]);
            vec![ellipse((cx, cy), p * inverse * p.transpose())]
        }
        Drawn::Box { edges, axes } => {
            let world = matrix(&r) * matrix_of(&axes);
            let corner = |signs: [f64; 3]| {
                let local = nalgebra::Vector3::from_fn(|k, _| 0.5 * signs[k] * edges[k]);
                let p = world * local;
                view.project(centre + Vector3::new(p[0], p[1], p[2]))
            };
            let mut lines = Vec::with_capacity(12);
            for k in 0..3 {
                // The four edges along axis k, at each pair of signs on the other two.
                let (j, l) = ((k + 1) % 3, (k + 2) % 3);
                for (a, b) in [(-1.0, -1.0), (-1.0, 1.0), (1.0, -1.0), (1.0, 1.0)] {
                    let mut from = [0.0; 3];
                    (from[j], from[l], from[k]) = (a, b, -1.0);
                    let mut to = from;
                    to[k] = 1.0;
                    lines.push(vec![corner(from), corner(to)]);
                }
            }
            lines
        }
        Drawn::Cylinder {
            radius,
            length,
            axis,
        } => {
            let along = r * axis;
            let ends = [centre - 0.5 * length * along, centre + 0.5 * length * along];
            let (e1, e2) = perpendiculars(along);
            let mut lines: Vec<Line> = ends.iter().map(|&e| ring(view, e, along, radius)).collect();
            for k in 0..4 {
                let angle = k as f64 * std::f64::consts::FRAC_PI_2;
                let offset = radius * (angle.cos() * e1 + angle.sin() * e2);
                lines.push(vec![
                    view.project(ends[0] + offset),
                    view.project(ends[1] + offset),
                ]);
            }
            lines
        }
    }
}

/// The circle of radius `radius` about `centre` normal to `normal`, on the view.
fn ring(view: &View, centre: Vector3, normal: Vector3, radius: f64) -> Line {
    let (e1, e2) = perpendiculars(normal);
    (0..=ROUND)
        .map(|k| {
            let angle = std::f64::consts::TAU * k as f64 / ROUND as f64;
            view.project(centre + radius * (angle.cos() * e1 + angle.sin() * e2))
        })
        .collect()
}

/// The ellipse {c + y : yᵀ M⁻¹ y = 1}, M symmetric positive semi-definite (a segment when M
/// is singular): c + V √Λ (cos s, sin s) for M = V Λ Vᵀ.
fn ellipse(c: (f64, f64), m: Matrix2<f64>) -> Line {
    let eigen = SymmetricEigen::new(m);
    let v = eigen.eigenvectors;
    let s = eigen.eigenvalues.map(|l| l.max(0.0).sqrt());
    (0..=ROUND)
        .map(|k| {
            let angle = std::f64::consts::TAU * k as f64 / ROUND as f64;
            let (a, b) = (s[0] * angle.cos(), s[1] * angle.sin());
            (
                c.0 + v[(0, 0)] * a + v[(0, 1)] * b,
                c.1 + v[(1, 0)] * a + v[(1, 1)] * b,
            )
        })
        .collect()
}

/// Two unit vectors that complete `n` to an orthonormal frame.
fn perpendiculars(n: Vector3) -> (Vector3, Vector3) {
    let n = n.normalize();
    let helper = if n.x.abs() < 0.9 {
        Vector3::x()
    } else {
        Vector3::y()
    };
    let e1 = n.cross(&helper).normalize();
    (e1, n.cross(&e1))
}

fn vector(v: Vector3) -> nalgebra::Vector3<f64> {
    nalgebra::Vector3::new(v.x, v.y, v.z)
}

fn matrix(r: &Rotation3) -> Matrix3<f64> {
    matrix_of(&r.matrix())
}

fn matrix_of(rows: &[[f64; 3]; 3]) -> Matrix3<f64> {
    Matrix3::from_fn(|i, j| rows[i][j])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::view::{Directions, View};

    fn look(solid: Drawn) -> Look {
        Look {
            name: "b".into(),
            solid,
            offset: Vector3::zeros(),
            color: 0,
            description: String::new(),
            warning: None,
            triad: 1.0,
        }
    }

    fn extent(lines: &[Line]) -> (f64, f64, f64, f64) {
        let points = lines.iter().flatten();
        let fold = |f: fn(f64, f64) -> f64, init: f64, pick: fn(&(f64, f64)) -> f64| {
            points.clone().map(pick).fold(init, f)
        };
        (
            fold(f64::min, f64::INFINITY, |p| p.0),
            fold(f64::max, f64::NEG_INFINITY, |p| p.0),
            fold(f64::min, f64::INFINITY, |p| p.1),
            fold(f64::max, f64::NEG_INFINITY, |p| p.1),
        )
    }

    #[test]
    fn an_ellipsoids_silhouette_is_as_wide_as_its_extent_along_the_view() {
        // Semi-axes 3, 2, 1 along the body's x, y, z; the body turned about z by 0.5 rad.
        let identity = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        let solid = Drawn::Ellipsoid {
            semi_axes: [3.0, 2.0, 1.0],
            axes: identity,
        };
        let body = Body::new(
            1.0,
            hamel_runtime::geometry::Inertia::principal(1.0, 1.0, 1.0),
            Vector3::new(1.0, 2.0, 3.0),
            Rotation3::about_z(0.5),
        );
        let [front, side, top] = View::all(&Directions::new(None));
        // Seen from the side (screen right = x, up = z): half-widths √(9 cos² + 4 sin²) and 1.
        let (x0, x1, y0, y1) = extent(&outline(&look(solid), &body, &side));
        let half = (9.0 * 0.5f64.cos().powi(2) + 4.0 * 0.5f64.sin().powi(2)).sqrt();
        assert!(((x1 - x0) / 2.0 - half).abs() < 1e-2 * half, "{x0} {x1}");
        assert!(((x0 + x1) / 2.0 - 1.0).abs() < 1e-12);
        assert!(((y1 - y0) / 2.0 - 1.0).abs() < 1e-2 && ((y0 + y1) / 2.0 - 3.0).abs() < 1e-12);
        // From the front (screen right = y): √(9 sin² + 4 cos²).
        let (x0, x1, ..) = extent(&outline(&look(solid), &body, &front));
        let half = (9.0 * 0.5f64.sin().powi(2) + 4.0 * 0.5f64.cos().powi(2)).sqrt();
        assert!(((x1 - x0) / 2.0 - half).abs() < 1e-2 * half);
        // From above, the full 3 × 2 ellipse, turned.
        let (x0, x1, y0, y1) = extent(&outline(&look(solid), &body, &top));
        assert!((x1 - x0) / 2.0 <= 3.0 + 1e-9 && (y1 - y0) / 2.0 <= 3.0 + 1e-9);
        // A disk normal to the body's y axis, seen from the side, is its full circle.
        let disk = Drawn::Disk {
            radius: 0.5,
            axis: Vector3::y(),
        };
        let upright = Body::new(1.0, body.inertia, Vector3::zeros(), Rotation3::identity());
        let (x0, x1, y0, y1) = extent(&outline(&look(disk), &upright, &side));
        assert!((x1 - x0 - 1.0).abs() < 1e-12 && (y1 - y0 - 1.0).abs() < 1e-12);
        // A box has twelve edges.
        let cube = Drawn::Box {
            edges: [1.0, 2.0, 3.0],
            axes: identity,
        };
        let lines = outline(&look(cube), &upright, &side);
        assert_eq!(lines.len(), 12);
        let (x0, x1, y0, y1) = extent(&lines);
        assert_eq!((x0, x1, y0, y1), (-0.5, 0.5, -1.5, 1.5));
    }
}
