//! The shape a body's rolling contact gives it: a wheel is the disk its contact runs round,
//! a ball the sphere.
//!
//! The contact point is read in the body's own axes, p = Rᵀ(P − c), at the configuration and
//! at perturbations of every coordinate. If |p| is the same everywhere and the points spread
//! over a plane through the centre, the body is a disk of that radius normal to the plane;
//! if they spread over more than a plane, a sphere. Anything else (a base whose curvature
//! varies, like the rattleback's, or a contact point fixed in the body) gives no shape, and
//! the body is drawn from its inertia instead. A body given a [`Shape`] in the model is drawn
//! as that shape, and this reading is not needed.

use nalgebra::{Matrix3, SymmetricEigen};

use hamel_runtime::Vector;
use hamel_runtime::geometry::{Body, Mechanism, Shape, Vector3};

/// How far each coordinate is moved: far enough that the contact point travels a visible
/// fraction of a wheel's rim (a tenth of a radian), so that a flat spread stands out from a
/// curved one by many orders of magnitude.
const PERTURBATION: f64 = 0.1;
/// Distances from the centre that agree to this fraction are the same.
const DISTANCE_TOLERANCE: f64 = 1e-9;
/// A moment of the contact points' directions below this fraction of the largest is zero:
/// rounding leaves ~1e-30 in a plane, the perturbations ~1e-3 across one.
const SPREAD_TOLERANCE: f64 = 1e-12;

/// For each body of the model, the shape its first contact gives it, if any, read about the
/// configuration `q` at time `t`.
pub(crate) fn rolling_shapes<M: Mechanism>(
    model: &M,
    t: f64,
    q: &M::Coordinates,
    bodies: usize,
) -> Vec<Option<Shape>> {
    // The contact points, in their body's axes, at every configuration: one list per
    // contact, with the index of the body it belongs to.
    let mut points: Vec<(Option<usize>, Vec<Vector3>)> = Vec::new();
    for configuration in configurations(q) {
        let placed = model.bodies_at(t, &configuration);
        for (j, contact) in model.contacts_at(t, &configuration).iter().enumerate() {
            if points.len() <= j {
                points.push((owner(&contact.body, &placed), Vec::new()));
            }
            let body = &contact.body;
            let local = body.orientation.transpose() * (contact.point - body.centre);
            if local.to_array().iter().all(|v| v.is_finite()) {
                points[j].1.push(local);
            }
        }
    }
    let mut shapes = vec![None; bodies];
    for (owner, local) in points {
        if let Some(b) = owner.filter(|&b| b < bodies) {
            if shapes[b].is_none() {
                shapes[b] = classify(&local);
            }
        }
    }
    shapes
}

/// `q`, then `q` with each coordinate moved by ±[`PERTURBATION`], then moved along three
/// fixed mixed directions.
fn configurations<V: Vector>(q: &V) -> Vec<V> {
    let n = V::LEN;
    let mut all = vec![*q];
    for j in 0..n {
        for sign in [1.0, -1.0] {
            let mut moved = *q;
            moved.as_mut()[j] += sign * PERTURBATION;
            all.push(moved);
        }
    }
    for k in 0..3 {
        let mut moved = *q;
        for (j, v) in moved.as_mut().iter_mut().enumerate() {
            // Weights in [−1, 1] that differ between coordinates and directions.
            *v += PERTURBATION * (1.0 + 3.0 * k as f64 + 7.0 * j as f64).sin();
        }
        all.push(moved);
    }
    all
}

/// Which of `bodies` the contact's body is: the one at the same place and orientation.
pub(crate) fn owner(body: &Body, bodies: &[Body]) -> Option<usize> {
    let same = |a: &Body| {
        let scale = 1.0 + body.centre.norm();
        (a.centre - body.centre).norm() <= 1e-12 * scale
            && a.orientation
                .matrix()
                .iter()
                .flatten()
                .zip(body.orientation.matrix().iter().flatten())
                .all(|(x, y)| (x - y).abs() <= 1e-12)
    };
    bodies.iter().position(same)
}

/// A disk, a sphere or nothing, from the contact points in the body's axes.
fn classify(local: &[Vector3]) -> Option<Shape> {
    if local.len() < 4 {
        return None;
    }
    let radius = local.iter().map(Vector3::norm).sum::<f64>() / local.len() as f64;
    if radius.is_nan()
        || radius <= 0.0
        || local
            .iter()
            .any(|p| (p.norm() - radius).abs() > DISTANCE_TOLERANCE * radius)
    {
        return None;
    }
    // The second moment of the directions: rank 2 for points on a circle through the
    // centre's plane, rank 3 for points spread over a sphere, rank 1 for a fixed point.
    let mut moment = Matrix3::zeros();
    for p in local {
        let u = nalgebra::Vector3::new(p.x, p.y, p.z) / radius;
        moment += u * u.transpose();
    }
    let eigen = SymmetricEigen::new(moment);
    let mut order = [0, 1, 2];
    order.sort_by(|&a, &b| eigen.eigenvalues[a].total_cmp(&eigen.eigenvalues[b]));
    let [least, middle, largest] = order.map(|k| eigen.eigenvalues[k]);
    if middle <= SPREAD_TOLERANCE * largest {
        None
    } else if least <= SPREAD_TOLERANCE * largest {
        let normal = eigen.eigenvectors.column(order[0]);
        Some(Shape::disk(
            radius,
            Vector3::new(normal[0], normal[1], normal[2]),
        ))
    } else {
        Some(Shape::sphere(radius))
    }
}
