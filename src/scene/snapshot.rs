//! What a scene or a picture needs of a model at one configuration, read once through
//! [`Mechanism`]: its bodies, the shapes their contacts give them, the contacts, gravity,
//! and its names and units. Everything after (shapes given by name, columns shown, the page)
//! works from this alone, so that [`super::Scene`] and [`super::Picture`] are not generic over
//! the model: a model without bodies is then one error, where it is given.

use super::error::{ErrorKind, SceneError};
use super::infer::{Rolling, owner, rolling_shapes};
use crate::geometry::{Body, Mechanism, Vector3};

/// A model at one configuration.
#[derive(Clone, Debug)]
pub(crate) struct Snapshot {
    /// The model's type, for a title.
    pub model: &'static str,
    pub names: &'static [&'static str],
    pub coordinates: &'static [&'static str],
    /// The unit of a named quantity (`HamelSystem::unit`).
    pub unit: fn(&str) -> Option<&'static str>,
    pub bodies: Vec<Body>,
    pub rolling: Vec<Option<Rolling>>,
    /// The contact points, and the body each belongs to.
    pub contacts: Vec<(Vector3, Option<usize>)>,
    pub gravity: Option<Vector3>,
}

impl Snapshot {
    /// `model` at (t, q): as many bodies as it names, each with a finite mass, inertia and
    /// pose.
    pub(crate) fn of<M: Mechanism>(
        model: &M,
        t: f64,
        q: &M::Coordinates,
    ) -> Result<Snapshot, SceneError> {
        if M::BODIES.is_empty() {
            return Err(ErrorKind::NoBodies.into());
        }
        let bodies = checked_bodies(model, t, q)?;
        let mut contacts = Vec::new();
        for (j, c) in model.contacts_at(t, q).iter().enumerate() {
            if !c.point.to_array().iter().all(|v| v.is_finite()) {
                let what = format!("contact point {}", j + 1);
                return Err(ErrorKind::NonFinite { what, t }.into());
            }
            contacts.push((c.point, owner(&c.body, &bodies)));
        }
        Ok(Snapshot {
            model: std::any::type_name::<M>()
                .rsplit("::")
                .next()
                .unwrap_or("model"),
            names: M::BODIES,
            coordinates: M::COORDINATES,
            unit: M::unit,
            rolling: rolling_shapes(model, t, q, bodies.len()),
            bodies,
            contacts,
            gravity: model.gravity_vector(t),
        })
    }
}

/// The model's bodies at (t, q), as many as it names, with a finite mass, inertia and pose.
pub(crate) fn checked_bodies<M: Mechanism>(
    model: &M,
    t: f64,
    q: &M::Coordinates,
) -> Result<Vec<Body>, SceneError> {
    let bodies = model.bodies_at(t, q);
    if bodies.len() != M::BODIES.len() {
        return Err(ErrorKind::Count {
            what: "bodies",
            expected: M::BODIES.len(),
            got: bodies.len(),
            t,
        }
        .into());
    }
    for (name, body) in M::BODIES.iter().zip(&bodies) {
        let i = body.inertia;
        let inertia = [body.mass, i.xx, i.yy, i.zz, i.xy, i.yz, i.zx];
        let pose = body
            .centre
            .to_array()
            .into_iter()
            .chain(body.orientation.matrix().into_iter().flatten());
        let what = if !inertia.iter().all(|v| v.is_finite()) {
            "the mass or inertia"
        } else if !pose.clone().all(f64::is_finite) {
            "the pose"
        } else {
            continue;
        };
        return Err(ErrorKind::NonFinite {
            what: format!("{what} of body `{name}`"),
            t,
        }
        .into());
    }
    Ok(bodies)
}
