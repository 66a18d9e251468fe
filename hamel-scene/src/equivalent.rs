//! The uniform solid with a body's mass and principal moments of inertia: what a body that
//! touches nothing is drawn as, so that a wrong inertia looks wrong.
//!
//! For a uniform ellipsoid of mass m and semi-axes a₁, a₂, a₃ along its principal axes,
//! I₁ = m (a₂² + a₃²) / 5 and so on; for a uniform box of edges l₁, l₂, l₃,
//! I₁ = m (l₂² + l₃²) / 12. Solved for the sizes, aᵢ² = 5 (Iⱼ + Iₖ − Iᵢ) / (2m) and
//! lᵢ² = 6 (Iⱼ + Iₖ − Iᵢ) / m: real exactly when the moments are non-negative and satisfy the
//! triangle inequality Iᵢ ≤ Iⱼ + Iₖ, which every rigid body's do. A body whose inertia does
//! not is drawn as a marker with a warning.

use nalgebra::{Matrix3, SymmetricEigen};

use hamel_runtime::geometry::Inertia;

/// Moments within this fraction of the largest count as equal (for the triangle
/// inequality) or as zero: rounding in the eigen-decomposition is far below it, and a
/// thin disk's or a rod's moments satisfy the inequality with equality.
const RELATIVE_TOLERANCE: f64 = 1e-9;

/// The principal moments of an inertia, ascending, and its principal axes: the columns of
/// `axes`, a proper rotation from the principal axes to the body's axes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Principal {
    pub moments: [f64; 3],
    pub axes: [[f64; 3]; 3],
}

/// nalgebra's symmetric eigen-decomposition, sorted, with the axes made right-handed.
pub(crate) fn principal(inertia: &Inertia) -> Principal {
    let rows = inertia.matrix();
    let tensor = Matrix3::from_fn(|i, j| rows[i][j]);
    let eigen = SymmetricEigen::new(tensor);
    let mut order = [0, 1, 2];
    order.sort_by(|&a, &b| eigen.eigenvalues[a].total_cmp(&eigen.eigenvalues[b]));
    let moments = order.map(|k| eigen.eigenvalues[k]);
    let mut axes = [[0.0; 3]; 3];
    for (column, &k) in order.iter().enumerate() {
        for (row, axis) in axes.iter_mut().enumerate() {
            axis[column] = eigen.eigenvectors[(row, k)];
        }
    }
    let determinant = Matrix3::from_fn(|i, j| axes[i][j]).determinant();
    if determinant < 0.0 {
        for row in &mut axes {
            row[2] = -row[2];
        }
    }
    Principal { moments, axes }
}

/// What a body's mass and inertia make of it.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Equivalent {
    /// No inertia of its own: a point mass (or a massless marker).
    PointMass,
    /// A uniform solid: `spans[i]` is (Iⱼ + Iₖ − Iᵢ) / m along principal axis i (a column of
    /// `axes`), never negative.
    Solid {
        spans: [f64; 3],
        axes: [[f64; 3]; 3],
    },
    /// No uniform solid has this mass and inertia; the reason, to show as a warning.
    Impossible(String),
}

impl Equivalent {
    /// The mass and inertia of a body, read as a uniform solid.
    pub(crate) fn of(mass: f64, inertia: &Inertia) -> Self {
        let Principal { moments, axes } = principal(inertia);
        let largest = moments.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        if largest == 0.0 && mass >= 0.0 {
            return Equivalent::PointMass;
        }
        if mass <= 0.0 {
            return Equivalent::Impossible(format!(
                "its mass is {mass}, but its inertia is not zero: no body has that"
            ));
        }
        let tolerance = RELATIVE_TOLERANCE * largest;
        let [a, b, c] = moments;
        if a < -tolerance {
            return Equivalent::Impossible(format!(
                "its inertia is not positive definite: its principal moments are {}, {}, {}",
                short(a),
                short(b),
                short(c)
            ));
        }
        if c > a + b + tolerance {
            return Equivalent::Impossible(format!(
                "its principal moments {}, {}, {} violate the triangle inequality (the \
                 largest exceeds the sum of the other two), which no body's do: are they \
                 about its centre of mass, in its own axes?",
                short(a),
                short(b),
                short(c)
            ));
        }
        let span = |i: f64, j: f64, k: f64| ((j + k - i) / mass).max(0.0);
        Equivalent::Solid {
            spans: [span(a, b, c), span(b, c, a), span(c, a, b)],
            axes,
        }
    }
}

/// The semi-axes of the uniform ellipsoid with these spans: aᵢ = √(5 sᵢ / 2).
pub(crate) fn ellipsoid_semi_axes(spans: [f64; 3]) -> [f64; 3] {
    thickened(spans.map(|s| (2.5 * s).sqrt()))
}

/// The edges of the uniform box with these spans: lᵢ = √(6 sᵢ).
pub(crate) fn box_edges(spans: [f64; 3]) -> [f64; 3] {
    thickened(spans.map(|s| (6.0 * s).sqrt()))
}

/// A flat or thin solid (a disk's or a rod's inertia, exactly) gets a drawable thickness: a
/// fiftieth of its largest size.
fn thickened(sizes: [f64; 3]) -> [f64; 3] {
    let largest = sizes.iter().fold(0.0_f64, |m, &v| m.max(v));
    sizes.map(|s| s.max(0.02 * largest))
}

/// A number in four significant digits, for messages and labels.
pub(crate) fn short(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let magnitude = x.abs().log10().floor() as i32;
    if (-3..5).contains(&magnitude) {
        let decimals = (3 - magnitude).max(0) as usize;
        let text = format!("{x:.decimals$}");
        if text.contains('.') {
            text.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            text
        }
    } else {
        format!("{x:.3e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_uniform_ellipsoid_and_box_are_recovered_from_their_inertia() {
        // Ellipsoid of mass 3 and semi-axes 0.1, 0.2, 0.3, turned about z by 0.4 rad.
        let (m, [a, b, c]) = (3.0, [0.1, 0.2, 0.3]);
        let moments = [
            m * (b * b + c * c) / 5.0,
            m * (a * a + c * c) / 5.0,
            m * (a * a + b * b) / 5.0,
        ];
        let (s, co) = 0.4_f64.sin_cos();
        let ixx = co * co * moments[0] + s * s * moments[1];
        let iyy = s * s * moments[0] + co * co * moments[1];
        let ixy = co * s * (moments[0] - moments[1]);
        let inertia = Inertia::new(ixx, iyy, moments[2], ixy, 0.0, 0.0);
        let Equivalent::Solid { spans, axes } = Equivalent::of(m, &inertia) else {
            panic!("a real body's inertia")
        };
        // Ascending moments: the largest semi-axis comes first.
        let semi = ellipsoid_semi_axes(spans);
        for (got, want) in semi.iter().zip([c, b, a]) {
            assert!((got - want).abs() < 1e-12, "{semi:?}");
        }
        // The first principal axis is the body's z axis, the second its y axis turned by 0.4
        // about z, (−sin 0.4, cos 0.4, 0).
        assert!((axes[2][0].abs() - 1.0).abs() < 1e-12);
        assert!((axes[0][1].abs() - s).abs() < 1e-12 && (axes[1][1].abs() - co).abs() < 1e-12);
        let det = Matrix3::from_fn(|i, j| axes[i][j]).determinant();
        assert!((det - 1.0).abs() < 1e-12);
        // A box of edges l: I₁ = m (l₂² + l₃²) / 12.
        let [l1, l2, l3] = [0.5, 0.4, 0.1];
        let cube = Inertia::principal(
            m * (l2 * l2 + l3 * l3) / 12.0,
            m * (l1 * l1 + l3 * l3) / 12.0,
            m * (l1 * l1 + l2 * l2) / 12.0,
        );
        let Equivalent::Solid { spans, .. } = Equivalent::of(m, &cube) else {
            panic!("a box's inertia")
        };
        let edges = box_edges(spans);
        for (got, want) in edges.iter().zip([l1, l2, l3]) {
            assert!((got - want).abs() < 1e-12, "{edges:?}");
        }
    }

    #[test]
    fn impossible_inertias_are_named_not_drawn_as_nan() {
        let negative = Equivalent::of(1.0, &Inertia::principal(1.0, -0.5, 1.0));
        assert!(
            matches!(&negative, Equivalent::Impossible(m) if m.contains("not positive definite")),
            "{negative:?}"
        );
        let triangle = Equivalent::of(1.0, &Inertia::principal(1.0, 1.0, 3.0));
        assert!(
            matches!(&triangle, Equivalent::Impossible(m) if m.contains("triangle inequality")),
            "{triangle:?}"
        );
        let massless = Equivalent::of(0.0, &Inertia::principal(1.0, 1.0, 1.0));
        assert!(matches!(massless, Equivalent::Impossible(_)));
        assert_eq!(
            Equivalent::of(2.0, &Inertia::principal(0.0, 0.0, 0.0)),
            Equivalent::PointMass
        );
        // A thin disk satisfies the inequality with equality: flat, but drawn with a
        // thickness of a fiftieth of its diameter.
        let disk = Equivalent::of(1.0, &Inertia::principal(0.25, 0.25, 0.5));
        let Equivalent::Solid { spans, .. } = disk else {
            panic!("a disk's inertia is a body's")
        };
        let semi = ellipsoid_semi_axes(spans);
        assert!(semi.iter().all(|s| s.is_finite() && *s > 0.0));
        assert!((semi[2] - 0.02 * semi[0]).abs() < 1e-15);
    }

    #[test]
    fn short_numbers_keep_four_significant_digits() {
        assert_eq!(short(0.3), "0.3");
        assert_eq!(short(1.23456), "1.235");
        assert_eq!(short(-12.5), "-12.5");
        assert_eq!(short(0.0603), "0.0603");
        assert_eq!(short(2e-5), "2.000e-5");
        assert_eq!(short(85.0), "85");
    }
}
