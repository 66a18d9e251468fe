//! Which way is up, forward and left in a model's world, and so where the views look from.
//!
//! Up is against gravity (+z for a model without gravity: the ground is the plane z = 0).
//! Forward is the ground frame's x axis laid level (its y axis if x is vertical), left is
//! up × forward. The side view looks at the model's right side with forward to the right, the
//! front view looks back at it, the top view looks down with forward to the right: for the
//! Whipple bicycle (x forward, z down) the side view is the paper's Figure 1.

use hamel_runtime::geometry::Vector3;

/// Up, forward and left: a right-handed orthonormal frame (left = up × forward).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Directions {
    pub up: Vector3,
    pub forward: Vector3,
    pub left: Vector3,
}

impl Directions {
    /// The directions of a world with this gravity (or none).
    pub(crate) fn new(gravity: Option<Vector3>) -> Self {
        let up = match gravity {
            Some(g) if g.norm() > 0.0 && g.to_array().iter().all(|v| v.is_finite()) => {
                -g.normalize()
            }
            _ => Vector3::z(),
        };
        let level = |v: Vector3| v - v.dot(&up) * up;
        let forward = if level(Vector3::x()).norm() > 1e-6 {
            level(Vector3::x()).normalize()
        } else {
            level(Vector3::y()).normalize()
        };
        Directions {
            up,
            forward,
            left: up.cross(&forward),
        }
    }
}

/// One of the three orthographic views: the screen's right and up directions in the world,
/// and what the view is called. (Only `Picture` draws views, so only with `plot`.)
#[cfg(feature = "plot")]
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct View {
    pub name: &'static str,
    pub right: Vector3,
    pub up: Vector3,
}

#[cfg(feature = "plot")]
impl View {
    /// Front, side and top, in that order.
    pub(crate) fn all(d: &Directions) -> [View; 3] {
        [
            View {
                name: "front",
                right: d.left,
                up: d.up,
            },
            View {
                name: "side",
                right: d.forward,
                up: d.up,
            },
            View {
                name: "top",
                right: d.forward,
                up: d.left,
            },
        ]
    }

    /// The direction the view looks along (into the screen).
    pub(crate) fn looking(&self) -> Vector3 {
        self.up.cross(&self.right)
    }

    /// A world point on the screen.
    pub(crate) fn project(&self, p: Vector3) -> (f64, f64) {
        (p.dot(&self.right), p.dot(&self.up))
    }
}

/// A direction's name for an axis label: `x`, `−z`, or its components.
#[cfg(feature = "plot")]
pub(crate) fn direction_name(v: Vector3) -> String {
    let axes = [
        ("x", Vector3::x()),
        ("y", Vector3::y()),
        ("z", Vector3::z()),
    ];
    for (name, axis) in axes {
        if (v - axis).norm() < 1e-9 {
            return name.to_string();
        }
        if (v + axis).norm() < 1e-9 {
            return format!("−{name}");
        }
    }
    let c = v.to_array().map(super::equivalent::short);
    format!("({}, {}, {})", c[0], c[1], c[2])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_bicycle_is_seen_from_its_right_and_the_disk_from_its_right_too() {
        // z down: up is −z, left is −y (y points to the bicycle's right).
        let bicycle = Directions::new(Some(Vector3::new(0.0, 0.0, 9.81)));
        assert_eq!(bicycle.up, -Vector3::z());
        assert_eq!(bicycle.forward, Vector3::x());
        assert_eq!(bicycle.left, -Vector3::y());
        let [front, side, top] = View::all(&bicycle);
        // The side view looks from +y towards −y, as the paper's Figure 1.
        assert_eq!(side.looking(), -Vector3::y());
        assert_eq!(front.looking(), -Vector3::x());
        assert_eq!(top.looking(), Vector3::z());
        // z up, no gravity: looking from −y, x to the right.
        let ball = Directions::new(None);
        assert_eq!(ball.left, Vector3::y());
        let [_, side, top] = View::all(&ball);
        assert_eq!(side.looking(), Vector3::y());
        assert_eq!(top.looking(), -Vector3::z());
        assert_eq!(direction_name(-Vector3::z()), "−z");
    }
}
