//! The vocabulary's operations on the graph: vectors, matrices, rotations and their turns.

use super::{Body, Made, Mat3, Point, Rotation, Spin, Turn, Vec3};
use crate::engine::graph::{Func, Graph, NodeId};

/// The ground at rest, as a body: no mass, at the origin, unrotated.
pub fn ground(g: &mut Graph) -> Body {
    let zero = g.zero();
    Body {
        mass: zero,
        inertia: [zero; 6],
        centre: Point::leaf([zero; 3]),
        orientation: identity(g),
        shape: None,
    }
}

/// A body with no mass carrying a frame at `centre` turned by `orientation`: a surface's
/// frame, whose material velocity is the surface's.
pub fn frame(g: &mut Graph, centre: Point, orientation: Rotation) -> Body {
    let zero = g.zero();
    Body {
        mass: zero,
        inertia: [zero; 6],
        centre,
        orientation,
        shape: None,
    }
}

pub fn identity(g: &mut Graph) -> Rotation {
    let (zero, one) = (g.zero(), g.one());
    Rotation {
        matrix: [[one, zero, zero], [zero, one, zero], [zero, zero, one]],
        turns: Some(Vec::new()),
    }
}

pub fn add(g: &mut Graph, a: Vec3, b: Vec3) -> Vec3 {
    [g.add(a[0], b[0]), g.add(a[1], b[1]), g.add(a[2], b[2])]
}

pub fn sub(g: &mut Graph, a: Vec3, b: Vec3) -> Vec3 {
    [g.sub(a[0], b[0]), g.sub(a[1], b[1]), g.sub(a[2], b[2])]
}

pub fn scale(g: &mut Graph, s: NodeId, a: Vec3) -> Vec3 {
    [g.mul(s, a[0]), g.mul(s, a[1]), g.mul(s, a[2])]
}

pub fn dot(g: &mut Graph, a: Vec3, b: Vec3) -> NodeId {
    let terms = [g.mul(a[0], b[0]), g.mul(a[1], b[1]), g.mul(a[2], b[2])];
    g.sum(&terms)
}

pub fn cross(g: &mut Graph, a: Vec3, b: Vec3) -> Vec3 {
    let component = |g: &mut Graph, i: usize, j: usize| {
        let p = g.mul(a[i], b[j]);
        let q = g.mul(a[j], b[i]);
        g.sub(p, q)
    };
    [component(g, 1, 2), component(g, 2, 0), component(g, 0, 1)]
}

/// M v.
pub fn apply(g: &mut Graph, m: &Mat3, v: Vec3) -> Vec3 {
    [dot(g, m[0], v), dot(g, m[1], v), dot(g, m[2], v)]
}

/// Mᵀ v.
pub fn apply_transposed(g: &mut Graph, m: &Mat3, v: Vec3) -> Vec3 {
    let t = transpose(m);
    apply(g, &t, v)
}

pub fn transpose(m: &Mat3) -> Mat3 {
    [
        [m[0][0], m[1][0], m[2][0]],
        [m[0][1], m[1][1], m[2][1]],
        [m[0][2], m[1][2], m[2][2]],
    ]
}

pub fn product(g: &mut Graph, a: &Mat3, b: &Mat3) -> Mat3 {
    let t = transpose(b);
    let row =
        |g: &mut Graph, i: usize| [dot(g, a[i], t[0]), dot(g, a[i], t[1]), dot(g, a[i], t[2])];
    [row(g, 0), row(g, 1), row(g, 2)]
}

/// The rotation by `angle` about the unit vector `k` (Rodrigues' formula; for a coordinate
/// axis, whose entries are the constants 0 and 1, the graph folds it to the elementary
/// rotation).
pub fn turn(g: &mut Graph, k: Vec3, angle: NodeId) -> Turn {
    let s = g.unary(Func::Sin, angle);
    let c = g.unary(Func::Cos, angle);
    let one = g.one();
    let v = g.sub(one, c);
    let entry = |g: &mut Graph, i: usize, j: usize| {
        let kk = g.mul(k[i], k[j]);
        let outer = g.mul(v, kk);
        if i == j {
            return g.add(c, outer);
        }
        // [k]ₓ: the entry (i, j) is −ε_ijl k_l.
        let l = 3 - i - j;
        let sk = g.mul(s, k[l]);
        if (i + 1) % 3 == j {
            g.sub(outer, sk)
        } else {
            g.add(outer, sk)
        }
    };
    let matrix = [
        [entry(g, 0, 0), entry(g, 0, 1), entry(g, 0, 2)],
        [entry(g, 1, 0), entry(g, 1, 1), entry(g, 1, 2)],
        [entry(g, 2, 0), entry(g, 2, 1), entry(g, 2, 2)],
    ];
    Turn {
        spin: Spin::Axis { axis: k, angle },
        matrix,
    }
}

/// The rotation of the quaternion (w, x, y, z) of any length, the rotation of q/|q|:
/// R = I + 2 (w [v]ₓ + [v]ₓ²) / |q|², as `hamel::geometry::Rotation3::from_quaternion`.
pub fn quaternion_turn(g: &mut Graph, q: [NodeId; 4]) -> Turn {
    let [w, x, y, z] = q;
    let squares = [g.mul(w, w), g.mul(x, x), g.mul(y, y), g.mul(z, z)];
    let norm2 = g.sum(&squares);
    let two = g.constant(2.0);
    let s = g.div(two, norm2);
    let scaled = |g: &mut Graph, a: NodeId, b: NodeId| {
        let ab = g.mul(a, b);
        g.mul(s, ab)
    };
    let (wx, wy, wz) = (scaled(g, w, x), scaled(g, w, y), scaled(g, w, z));
    let (xx, xy, xz) = (scaled(g, x, x), scaled(g, x, y), scaled(g, x, z));
    let (yy, yz, zz) = (scaled(g, y, y), scaled(g, y, z), scaled(g, z, z));
    let one = g.one();
    let diagonal = |g: &mut Graph, a: NodeId, b: NodeId| {
        let ab = g.add(a, b);
        g.sub(one, ab)
    };
    let matrix = [
        [diagonal(g, yy, zz), g.sub(xy, wz), g.add(xz, wy)],
        [g.add(xy, wz), diagonal(g, xx, zz), g.sub(yz, wx)],
        [g.sub(xz, wy), g.add(yz, wx), diagonal(g, xx, yy)],
    ];
    Turn {
        spin: Spin::Quaternion(q),
        matrix,
    }
}

pub fn unit(g: &mut Graph, i: usize) -> Vec3 {
    let (zero, one) = (g.zero(), g.one());
    let mut v = [zero; 3];
    v[i] = one;
    v
}

pub fn single(t: Turn) -> Rotation {
    Rotation {
        matrix: t.matrix,
        turns: Some(vec![t]),
    }
}

pub fn compose(g: &mut Graph, a: &Rotation, b: &Rotation) -> Rotation {
    let turns = match (&a.turns, &b.turns) {
        (Some(x), Some(y)) => Some(x.iter().chain(y).cloned().collect()),
        _ => None,
    };
    Rotation {
        matrix: product(g, &a.matrix, &b.matrix),
        turns,
    }
}

pub fn inverse(g: &mut Graph, r: &Rotation) -> Rotation {
    let turns = r.turns.as_ref().map(|turns| {
        turns
            .iter()
            .rev()
            .map(|t| Turn {
                spin: match t.spin {
                    Spin::Axis { axis, angle } => Spin::Axis {
                        axis,
                        angle: g.neg(angle),
                    },
                    // The conjugate.
                    Spin::Quaternion([w, x, y, z]) => {
                        Spin::Quaternion([w, g.neg(x), g.neg(y), g.neg(z)])
                    }
                },
                matrix: transpose(&t.matrix),
            })
            .collect()
    });
    Rotation {
        matrix: transpose(&r.matrix),
        turns,
    }
}

/// The lowest point of a thin disk (`hamel::geometry::disk_contact`).
pub fn disk_contact(g: &mut Graph, centre: Vec3, axle: Vec3, radius: NodeId, up: Vec3) -> Vec3 {
    let along = dot(g, up, axle);
    let tilted = scale(g, along, axle);
    let descent = sub(g, up, tilted);
    let one = g.one();
    let square = g.mul(along, along);
    let left = g.sub(one, square);
    let length = g.unary(Func::Sqrt, left);
    let factor = g.div(radius, length);
    let offset = scale(g, factor, descent);
    sub(g, centre, offset)
}

/// a + b, remembered as a sum.
pub fn sum(g: &mut Graph, a: Point, b: Point) -> Point {
    let at = add(g, a.at, b.at);
    Point::made(at, Made::Sum(a, b))
}

/// r v, remembered as a rotated vector.
pub fn rotated(g: &mut Graph, r: &Rotation, v: &Point) -> Point {
    let at = apply(g, &r.matrix, v.at);
    Point::made(at, Made::Rotated(r.clone(), v.clone()))
}

/// v / |v|.
pub fn normalize(g: &mut Graph, v: Vec3) -> Vec3 {
    let square = dot(g, v, v);
    let length = g.unary(Func::Sqrt, square);
    [
        g.div(v[0], length),
        g.div(v[1], length),
        g.div(v[2], length),
    ]
}

/// |v|.
pub fn norm(g: &mut Graph, v: Vec3) -> NodeId {
    let square = dot(g, v, v);
    g.unary(Func::Sqrt, square)
}

/// Column `k` of a matrix: the `k`-th axis of a rotation's frame.
pub fn column(m: &Mat3, k: usize) -> Vec3 {
    [m[0][k], m[1][k], m[2][k]]
}

/// −v.
pub fn neg(g: &mut Graph, v: Vec3) -> Vec3 {
    [g.neg(v[0]), g.neg(v[1]), g.neg(v[2])]
}
