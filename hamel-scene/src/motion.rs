//! The motion to animate: every body's pose and every contact point at each sample of the
//! trajectory, as computed (no sample is added, dropped or smoothed).

use nalgebra::{Matrix3, UnitQuaternion};

use super::error::{ErrorKind, SceneError};
use super::snapshot::checked_bodies;
use hamel_runtime::geometry::{Mechanism, Vector3};
use hamel_runtime::{Trajectory, Vector};

/// The poses and contact points at every sample drawn.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Motion {
    /// The trajectory's rows drawn: every row, or every k-th and the last of a trajectory
    /// of more than [`MAX_SCENE_SAMPLES`](super::MAX_SCENE_SAMPLES) samples.
    pub rows: Vec<usize>,
    pub times: Vec<f64>,
    /// Per sample, per body: the centre (x, y, z), then the orientation as a unit
    /// quaternion (x, y, z, w).
    pub poses: Vec<f64>,
    /// How many contacts the model has.
    pub contacts: usize,
    /// Per sample, per contact: the point (x, y, z).
    pub points: Vec<f64>,
    /// The smallest and largest coordinates of any centre or contact point.
    pub low: [f64; 3],
    pub high: [f64; 3],
}

/// Values per body per sample in [`Motion::poses`].
pub(crate) const POSE: usize = 7;

/// The trajectory's columns for the model's coordinates, in order; an error names the first
/// one missing. An empty trajectory is an error too, and so is a column name given twice or
/// a time that is not finite or not after the one before.
pub(crate) fn coordinate_columns<M: Mechanism>(
    trajectory: &Trajectory,
) -> Result<Vec<&[f64]>, SceneError> {
    let names = trajectory.names();
    let mut seen = std::collections::HashSet::new();
    if let Some(name) = names.iter().find(|name| !seen.insert(name.as_str())) {
        return Err(ErrorKind::DuplicateColumn { name: name.clone() }.into());
    }
    let times = trajectory.times();
    for (sample, &t) in times.iter().enumerate() {
        let before = sample.checked_sub(1).map(|i| times[i]);
        let bad = !t.is_finite() || before.is_some_and(|b| t <= b);
        if bad {
            let before = before.filter(|_| t.is_finite());
            return Err(ErrorKind::Time { sample, t, before }.into());
        }
    }
    let columns = M::COORDINATES
        .iter()
        .map(|name| {
            trajectory.column(name).ok_or_else(|| {
                SceneError::from(ErrorKind::MissingCoordinate {
                    name: name.to_string(),
                    known: trajectory.names().join(", "),
                })
            })
        })
        .collect::<Result<Vec<_>, _>>()?;
    if trajectory.is_empty() {
        return Err(ErrorKind::EmptyTrajectory.into());
    }
    Ok(columns)
}

/// The configuration at sample `i`.
pub(crate) fn configuration<V: Vector>(columns: &[&[f64]], i: usize) -> V {
    let mut q = V::zeros();
    for (value, column) in q.as_mut().iter_mut().zip(columns) {
        *value = column[i];
    }
    q
}

/// Every body's pose and every contact point at the trajectory's `rows`; a value that is not
/// finite is an error naming it and the time.
pub(crate) fn sample<M: Mechanism>(
    model: &M,
    times: &[f64],
    columns: &[&[f64]],
    rows: Vec<usize>,
) -> Result<Motion, SceneError> {
    let mut motion = Motion {
        times: rows.iter().map(|&r| times[r]).collect(),
        poses: Vec::with_capacity(rows.len() * M::BODIES.len() * POSE),
        contacts: 0,
        points: Vec::new(),
        low: [f64::INFINITY; 3],
        high: [f64::NEG_INFINITY; 3],
        rows: Vec::new(),
    };
    for (i, &row) in rows.iter().enumerate() {
        let t = times[row];
        let q: M::Coordinates = configuration(columns, row);
        // Finite poses (checked_bodies), so every quaternion exists.
        for body in checked_bodies(model, t, &q)? {
            let rotation = quaternion(&body.orientation.matrix()).unwrap_or([0.0, 0.0, 0.0, 1.0]);
            motion.poses.extend(body.centre.to_array());
            motion.poses.extend(rotation);
            motion.extend_bounds(body.centre);
        }
        let contacts = model.contacts_at(t, &q);
        if i == 0 {
            motion.contacts = contacts.len();
        } else if contacts.len() != motion.contacts {
            return Err(ErrorKind::Count {
                what: "contacts",
                expected: motion.contacts,
                got: contacts.len(),
                t,
            }
            .into());
        }
        for (j, contact) in contacts.iter().enumerate() {
            let point = finite(contact.point, || format!("contact point {}", j + 1), t)?;
            motion.points.extend(point.to_array());
            motion.extend_bounds(point);
        }
    }
    motion.rows = rows;
    Ok(motion)
}

/// The rows of a trajectory of `samples` samples that a scene draws: all of them up to
/// `limit`, else every k-th, the smallest k that keeps them within it, and the last.
pub(crate) fn rows_drawn(samples: usize, limit: usize) -> Vec<usize> {
    if samples <= limit {
        return (0..samples).collect();
    }
    // Every k-th of 0 … n − 2, and n − 1: ⌈(n − 1)/k⌉ + 1 ≤ limit.
    let limit = limit.max(2);
    let k = (samples - 1).div_ceil(limit - 1);
    let mut rows: Vec<usize> = (0..samples - 1).step_by(k).collect();
    rows.push(samples - 1);
    rows
}

impl Motion {
    fn extend_bounds(&mut self, p: Vector3) {
        for (k, v) in p.to_array().into_iter().enumerate() {
            self.low[k] = self.low[k].min(v);
            self.high[k] = self.high[k].max(v);
        }
    }

    /// Body `b`'s centre at sample `i`.
    pub(crate) fn centre(&self, i: usize, b: usize, bodies: usize) -> [f64; 3] {
        let at = (i * bodies + b) * POSE;
        [self.poses[at], self.poses[at + 1], self.poses[at + 2]]
    }
}

fn finite(p: Vector3, what: impl Fn() -> String, t: f64) -> Result<Vector3, SceneError> {
    if p.to_array().iter().all(|v| v.is_finite()) {
        Ok(p)
    } else {
        Err(ErrorKind::NonFinite { what: what(), t }.into())
    }
}

/// A rotation matrix as a unit quaternion (x, y, z, w), by nalgebra; `None` if not finite.
pub(crate) fn quaternion(m: &[[f64; 3]; 3]) -> Option<[f64; 4]> {
    if !m.iter().flatten().all(|v| v.is_finite()) {
        return None;
    }
    let matrix = Matrix3::from_fn(|i, j| m[i][j]);
    let q =
        UnitQuaternion::from_rotation_matrix(&nalgebra::Rotation3::from_matrix_unchecked(matrix));
    let c = q.coords;
    Some([c[0], c[1], c[2], c[3]])
}

#[cfg(test)]
mod tests {
    use super::quaternion;
    use hamel_runtime::geometry::{Rotation3, Vector3};

    /// The page turns a body by its quaternion as three.js does (v' = v + 2w (q × v) +
    /// 2 q × (q × v)): each of the body's axes must land on the orientation's column, as
    /// `Body::point` places it.
    #[test]
    fn the_quaternion_turns_a_bodys_axes_as_its_orientation_does() {
        let r = Rotation3::about_z(0.7) * Rotation3::about_x(0.4) * Rotation3::about_y(1.3);
        let [x, y, z, w] = quaternion(&r.matrix()).unwrap();
        let q = Vector3::new(x, y, z);
        for axis in [Vector3::x(), Vector3::y(), Vector3::z()] {
            let turned = axis + 2.0 * w * q.cross(&axis) + 2.0 * q.cross(&q.cross(&axis));
            assert!(
                (turned - r * axis).norm() < 1e-14,
                "{turned} against {}",
                r * axis
            );
        }
    }
}
