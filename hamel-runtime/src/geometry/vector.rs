//! `Vector3`: a vector of three `f64`, with the operations a model's geometry needs.

use core::fmt;
use core::ops::{Add, AddAssign, Div, DivAssign, Index, Mul, MulAssign, Neg, Sub, SubAssign};

/// A vector in 3-space: a position, a velocity, an axis. Named as nalgebra's `Vector3`.
///
/// ```
/// use hamel_runtime::geometry::Vector3;
/// let a = Vector3::new(1.0, 0.0, 0.0);
/// let b = Vector3::new(0.0, 2.0, 0.0);
/// assert_eq!(a.cross(&b), Vector3::new(0.0, 0.0, 2.0));
/// assert_eq!(a.dot(&b), 0.0);
/// assert_eq!((a + b).norm_squared(), 5.0);
/// assert_eq!((2.0 * a - b)[1], -2.0);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Vector3 {
    pub x: f64,
    pub y: f64,
    pub z: f64,
}

impl Vector3 {
    pub const fn new(x: f64, y: f64, z: f64) -> Self {
        Vector3 { x, y, z }
    }

    /// The zero vector.
    pub const fn zeros() -> Self {
        Vector3::new(0.0, 0.0, 0.0)
    }

    /// The unit vector along x.
    pub const fn x() -> Self {
        Vector3::new(1.0, 0.0, 0.0)
    }

    /// The unit vector along y.
    pub const fn y() -> Self {
        Vector3::new(0.0, 1.0, 0.0)
    }

    /// The unit vector along z.
    pub const fn z() -> Self {
        Vector3::new(0.0, 0.0, 1.0)
    }

    /// The components as an array, `[x, y, z]`.
    pub const fn to_array(self) -> [f64; 3] {
        [self.x, self.y, self.z]
    }

    pub fn dot(&self, other: &Vector3) -> f64 {
        self.x * other.x + self.y * other.y + self.z * other.z
    }

    pub fn cross(&self, other: &Vector3) -> Vector3 {
        Vector3::new(
            self.y * other.z - self.z * other.y,
            self.z * other.x - self.x * other.z,
            self.x * other.y - self.y * other.x,
        )
    }

    /// |v|².
    pub fn norm_squared(&self) -> f64 {
        self.dot(self)
    }

    /// |v|.
    pub fn norm(&self) -> f64 {
        self.norm_squared().sqrt()
    }

    /// v / |v| (not finite for the zero vector).
    pub fn normalize(&self) -> Vector3 {
        *self / self.norm()
    }
}

impl From<[f64; 3]> for Vector3 {
    fn from([x, y, z]: [f64; 3]) -> Self {
        Vector3::new(x, y, z)
    }
}

impl From<Vector3> for [f64; 3] {
    fn from(v: Vector3) -> Self {
        v.to_array()
    }
}

impl Index<usize> for Vector3 {
    type Output = f64;

    /// Component 0, 1 or 2 (x, y, z); panics beyond, as an array does.
    fn index(&self, i: usize) -> &f64 {
        match i {
            0 => &self.x,
            1 => &self.y,
            2 => &self.z,
            _ => panic!("index {i} is out of bounds for a Vector3 (0, 1 or 2)"),
        }
    }
}

impl Add for Vector3 {
    type Output = Vector3;
    fn add(self, o: Vector3) -> Vector3 {
        Vector3::new(self.x + o.x, self.y + o.y, self.z + o.z)
    }
}

impl Sub for Vector3 {
    type Output = Vector3;
    fn sub(self, o: Vector3) -> Vector3 {
        Vector3::new(self.x - o.x, self.y - o.y, self.z - o.z)
    }
}

impl Neg for Vector3 {
    type Output = Vector3;
    fn neg(self) -> Vector3 {
        Vector3::new(-self.x, -self.y, -self.z)
    }
}

impl Mul<f64> for Vector3 {
    type Output = Vector3;
    fn mul(self, s: f64) -> Vector3 {
        Vector3::new(self.x * s, self.y * s, self.z * s)
    }
}

impl Mul<Vector3> for f64 {
    type Output = Vector3;
    fn mul(self, v: Vector3) -> Vector3 {
        Vector3::new(self * v.x, self * v.y, self * v.z)
    }
}

impl Div<f64> for Vector3 {
    type Output = Vector3;
    fn div(self, s: f64) -> Vector3 {
        Vector3::new(self.x / s, self.y / s, self.z / s)
    }
}

impl AddAssign for Vector3 {
    fn add_assign(&mut self, o: Vector3) {
        *self = *self + o;
    }
}

impl SubAssign for Vector3 {
    fn sub_assign(&mut self, o: Vector3) {
        *self = *self - o;
    }
}

impl MulAssign<f64> for Vector3 {
    fn mul_assign(&mut self, s: f64) {
        *self = *self * s;
    }
}

impl DivAssign<f64> for Vector3 {
    fn div_assign(&mut self, s: f64) {
        *self = *self / s;
    }
}

impl fmt::Display for Vector3 {
    /// `(x, y, z)`, each component as `f64` displays it (a precision applies to each).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match f.precision() {
            Some(p) => write!(f, "({:.p$}, {:.p$}, {:.p$})", self.x, self.y, self.z),
            None => write!(f, "({}, {}, {})", self.x, self.y, self.z),
        }
    }
}
