//! Orientations made of three turns about fixed axes (Euler or Tait–Bryan angles) and their
//! singularity: where two of the turns are about one axis, the angular velocity no longer
//! determines the three rates. A run that stops there (a singular velocity transformation or
//! mass matrix) is told so, and pointed to a quaternion orientation, which has none — not
//! to other quasi-velocities, which cannot help.

use super::{Rotation3, Vector3};
use crate::error::Error;

/// |det| of the turns' axes in the ground frame below which the orientation counts as at its
/// singularity (det = ±sin of the middle angle, or its cosine for a Tait–Bryan sequence).
const SINGULAR: f64 = 1e-6;

/// An orientation `R = R_a(θ₁) R_b(θ₂) R_c(θ₃)` of three turns about the fixed axes `axes`
/// (0 = x, 1 = y, 2 = z), written as `written` in the model, by the coordinates `angles`.
pub struct ThreeTurns<'a> {
    pub axes: [usize; 3],
    pub angles: [f64; 3],
    pub written: &'a str,
}

impl ThreeTurns<'_> {
    /// Whether the angular velocity of the orientation is singular in the turns' rates:
    /// ω = a θ̇₁ + R_a(θ₁) b θ̇₂ + R_a(θ₁) R_b(θ₂) c θ̇₃, its three directions coplanar.
    ///
    /// ```
    /// use hamel_runtime::geometry::ThreeTurns;
    /// let at = |beta: f64| ThreeTurns { axes: [1, 2, 1], angles: [0.3, beta, -0.2], written: "" };
    /// assert!(at(0.0).is_singular());
    /// assert!(!at(0.1).is_singular());
    /// ```
    pub fn is_singular(&self) -> bool {
        let unit = |k: usize| [Vector3::x(), Vector3::y(), Vector3::z()][k.min(2)];
        let [a, b, c] = self.axes.map(unit);
        let first = Rotation3::from_axis_angle(&a, self.angles[0]);
        let second = first * Rotation3::from_axis_angle(&b, self.angles[1]);
        let det = a.dot(&(first * b).cross(&(second * c)));
        det.abs() <= SINGULAR
    }
}

/// `error`, or — when it is a singular velocity transformation or mass matrix and one of
/// `orientations` is at its singularity — [`Error::SingularOrientation`] saying so.
pub fn at_singular_orientation(error: Error, orientations: &[ThreeTurns<'_>]) -> Error {
    if !matches!(
        error,
        Error::SingularTransformation { .. } | Error::SingularMassMatrix { .. }
    ) {
        return error;
    }
    match orientations.iter().find(|o| o.is_singular()) {
        Some(o) => Error::SingularOrientation {
            orientation: o.written.to_string(),
            cause: Box::new(error),
        },
        None => error,
    }
}
