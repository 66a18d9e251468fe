//! `Rotation3`: a rotation of 3-space, built from elementary rotations and composed.

use super::Vector3;
use core::fmt;
use core::ops::{Index, Mul};

/// A rotation of 3-space, as the orthogonal matrix that takes a body's axes to the frame it
/// is expressed in: the columns are the body's axes. Named as nalgebra's `Rotation3`.
///
/// It is always a rotation: it is made from elementary rotations
/// ([`about_x`](Self::about_x), [`about_y`](Self::about_y), [`about_z`](Self::about_z)),
/// a rotation about an axis ([`from_axis_angle`](Self::from_axis_angle)), Euler angles or a
/// quaternion ([`from_quaternion`](Self::from_quaternion)), and products and transposes of
/// those; [`from_matrix_unchecked`](Self::from_matrix_unchecked) trusts its caller. `a * b` applies `b` first, then `a`: a body
/// oriented by `a` that turns by `b` in its own axes is oriented by `a * b` (a
/// body-fixed sequence, SymPy's `orient_body_fixed`).
///
/// ```
/// use hamel_runtime::geometry::{Rotation3, Vector3};
/// // Yaw ψ, then roll φ about the new x axis, then pitch θ about the newest y axis.
/// let (psi, phi, theta) = (0.4, 0.1, -0.2);
/// let frame = Rotation3::about_z(psi) * Rotation3::about_x(phi) * Rotation3::about_y(theta);
/// // The frame's y axis (a wheel's axle, say) in the ground frame:
/// let axle = frame * Vector3::y();
/// assert!((axle.norm() - 1.0).abs() < 1e-15);
/// assert!((frame.inverse() * axle - Vector3::y()).norm() < 1e-15);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rotation3 {
    /// Row-major.
    matrix: [[f64; 3]; 3],
}

impl Rotation3 {
    pub const fn identity() -> Self {
        Rotation3 {
            matrix: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        }
    }

    /// The rotation by `angle` (right-handed) about the x axis.
    pub fn about_x(angle: f64) -> Self {
        let (s, c) = angle.sin_cos();
        Rotation3 {
            matrix: [[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]],
        }
    }

    /// The rotation by `angle` (right-handed) about the y axis.
    pub fn about_y(angle: f64) -> Self {
        let (s, c) = angle.sin_cos();
        Rotation3 {
            matrix: [[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]],
        }
    }

    /// The rotation by `angle` (right-handed) about the z axis.
    pub fn about_z(angle: f64) -> Self {
        let (s, c) = angle.sin_cos();
        Rotation3 {
            matrix: [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]],
        }
    }

    /// The rotation by `angle` (right-handed) about `axis`, which need not have unit length
    /// (it is normalized; the zero vector gives no rotation matrix, every entry NaN):
    /// Rodrigues' formula, R = cos θ I + sin θ \[k\]ₓ + (1 − cos θ) k kᵀ.
    pub fn from_axis_angle(axis: &Vector3, angle: f64) -> Self {
        let k = axis.normalize();
        let (s, c) = angle.sin_cos();
        let v = 1.0 - c;
        Rotation3 {
            matrix: [
                [
                    c + v * k.x * k.x,
                    v * k.x * k.y - s * k.z,
                    v * k.x * k.z + s * k.y,
                ],
                [
                    v * k.y * k.x + s * k.z,
                    c + v * k.y * k.y,
                    v * k.y * k.z - s * k.x,
                ],
                [
                    v * k.z * k.x - s * k.y,
                    v * k.z * k.y + s * k.x,
                    c + v * k.z * k.z,
                ],
            ],
        }
    }

    /// nalgebra's Euler angles: roll about x, then pitch about y, then yaw about z, all about
    /// the fixed axes, R = R_z(yaw) R_y(pitch) R_x(roll).
    pub fn from_euler_angles(roll: f64, pitch: f64, yaw: f64) -> Self {
        Rotation3::about_z(yaw) * Rotation3::about_y(pitch) * Rotation3::about_x(roll)
    }

    /// The rotation of the quaternion w + x i + y j + z k, which need not have unit length
    /// (the rotation of q/|q|; the zero quaternion gives no rotation matrix, every entry NaN):
    /// R = I + 2 (w \[v\]ₓ + \[v\]ₓ²) / |q|² for v = (x, y, z). Orientations by quaternions have
    /// no singularity; nalgebra's `UnitQuaternion::from_quaternion` followed by its rotation
    /// matrix.
    pub fn from_quaternion(w: f64, x: f64, y: f64, z: f64) -> Self {
        let s = 2.0 / (w * w + x * x + y * y + z * z);
        let (wx, wy, wz) = (s * w * x, s * w * y, s * w * z);
        let (xx, xy, xz) = (s * x * x, s * x * y, s * x * z);
        let (yy, yz, zz) = (s * y * y, s * y * z, s * z * z);
        Rotation3 {
            matrix: [
                [1.0 - yy - zz, xy - wz, xz + wy],
                [xy + wz, 1.0 - xx - zz, yz - wx],
                [xz - wy, yz + wx, 1.0 - xx - yy],
            ],
        }
    }

    /// The rotation whose matrix is `matrix` (row by row), taken as it is: it must be
    /// orthogonal with determinant 1 (nalgebra's `Rotation3::from_matrix_unchecked`).
    pub const fn from_matrix_unchecked(matrix: [[f64; 3]; 3]) -> Self {
        Rotation3 { matrix }
    }

    /// The unit quaternion `[w, x, y, z]` of the rotation, with w ≥ 0: the inverse of
    /// [`Rotation3::from_quaternion`] (nalgebra's `UnitQuaternion::from_rotation_matrix`),
    /// for the initial values of a model oriented by a quaternion.
    ///
    /// ```
    /// use hamel_runtime::geometry::Rotation3;
    /// let r = Rotation3::about_z(0.4) * Rotation3::about_x(-1.2);
    /// let [w, x, y, z] = r.to_quaternion();
    /// let back = Rotation3::from_quaternion(w, x, y, z);
    /// let m = (r.matrix(), back.matrix());
    /// assert!((0..9).all(|k| (m.0[k / 3][k % 3] - m.1[k / 3][k % 3]).abs() < 1e-15));
    /// ```
    pub fn to_quaternion(&self) -> [f64; 4] {
        let m = &self.matrix;
        let matrix = nalgebra::Matrix3::new(
            m[0][0], m[0][1], m[0][2], m[1][0], m[1][1], m[1][2], m[2][0], m[2][1], m[2][2],
        );
        let rotation = nalgebra::Rotation3::from_matrix_unchecked(matrix);
        let q = nalgebra::UnitQuaternion::from_rotation_matrix(&rotation);
        let sign = if q.w < 0.0 { -1.0 } else { 1.0 };
        [sign * q.w, sign * q.i, sign * q.j, sign * q.k]
    }

    /// The inverse rotation, Rᵀ.
    pub fn transpose(&self) -> Self {
        let m = &self.matrix;
        Rotation3 {
            matrix: [
                [m[0][0], m[1][0], m[2][0]],
                [m[0][1], m[1][1], m[2][1]],
                [m[0][2], m[1][2], m[2][2]],
            ],
        }
    }

    /// The inverse rotation: the transpose.
    pub fn inverse(&self) -> Self {
        self.transpose()
    }

    /// The matrix, row by row.
    pub const fn matrix(&self) -> [[f64; 3]; 3] {
        self.matrix
    }
}

impl Default for Rotation3 {
    fn default() -> Self {
        Rotation3::identity()
    }
}

impl Index<(usize, usize)> for Rotation3 {
    type Output = f64;

    /// The entry in row `i`, column `j`.
    fn index(&self, (i, j): (usize, usize)) -> &f64 {
        &self.matrix[i][j]
    }
}

impl Mul for Rotation3 {
    type Output = Rotation3;

    /// The composition: `self` after `other`.
    fn mul(self, other: Rotation3) -> Rotation3 {
        let (a, b) = (&self.matrix, &other.matrix);
        let entry = |i: usize, j: usize| a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
        Rotation3 {
            matrix: [
                [entry(0, 0), entry(0, 1), entry(0, 2)],
                [entry(1, 0), entry(1, 1), entry(1, 2)],
                [entry(2, 0), entry(2, 1), entry(2, 2)],
            ],
        }
    }
}

impl Mul<Vector3> for Rotation3 {
    type Output = Vector3;

    /// The rotated vector.
    fn mul(self, v: Vector3) -> Vector3 {
        let m = &self.matrix;
        Vector3::new(
            m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z,
            m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
            m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z,
        )
    }
}

impl fmt::Display for Rotation3 {
    /// The matrix, one bracketed row after another.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, row) in self.matrix.iter().enumerate() {
            let row = Vector3::from(*row);
            let sep = if i == 0 { "" } else { " " };
            match f.precision() {
                Some(p) => write!(f, "{sep}[{:.p$}, {:.p$}, {:.p$}]", row.x, row.y, row.z)?,
                None => write!(f, "{sep}[{}, {}, {}]", row.x, row.y, row.z)?,
            }
        }
        Ok(())
    }
}
