//! What a scene or a picture needs of a model at one configuration, read once through
//! [`Mechanism`]: its bodies, the shapes their contacts give them, the contacts and the
//! surfaces they touch, gravity, and its names and units. Everything after (shapes given by name, columns shown, the page)
//! works from this alone, so that [`super::Scene`] and [`super::Picture`] are not generic over
//! the model: a model without bodies is then one error, where it is given.

use super::equivalent::short;
use super::error::{ErrorKind, SceneError};
use super::infer::{owner, rolling_shapes};
use hamel_runtime::geometry::{Body, Contact, Mechanism, Shape, Surface, Vector3};

/// A model at one configuration.
#[derive(Clone, Debug)]
pub(crate) struct Snapshot {
    /// The model's type, for a title.
    pub model: &'static str,
    /// The time of the configuration.
    pub t: f64,
    pub names: &'static [&'static str],
    pub coordinates: &'static [&'static str],
    /// The unit of a named quantity (`HamelSystem::unit`).
    pub unit: fn(&str) -> Option<&'static str>,
    pub bodies: Vec<Body>,
    /// The shape each body's contact makes it, if any.
    pub rolling: Vec<Option<Shape>>,
    /// The contact points, and the body each belongs to.
    pub contacts: Vec<(Vector3, Option<usize>)>,
    /// The surfaces the contacts touch, each once, in the order first touched.
    pub surfaces: Vec<Surface>,
    /// Each contact's surface, an index into `surfaces`.
    pub contact_surfaces: Vec<usize>,
    /// Contacts whose point is not on their surface: a surface placed where the bodies do
    /// not meet it (a tilted plane taken as flat), or a configuration not assembled.
    pub warnings: Vec<String>,
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
        let (mut surfaces, mut contact_surfaces) = (Vec::new(), Vec::new());
        let mut warnings = Vec::new();
        let scale = size_of(&bodies);
        for (j, c) in model.contacts_at(t, q).iter().enumerate() {
            if !c.point.to_array().iter().all(|v| v.is_finite()) {
                let what = format!("contact point {}", j + 1);
                return Err(ErrorKind::NonFinite { what, t }.into());
            }
            let body = owner(&c.body, &bodies);
            contacts.push((c.point, body));
            let index = surfaces.iter().position(|s| *s == c.surface);
            contact_surfaces.push(index.unwrap_or(surfaces.len()));
            if index.is_none() {
                surfaces.push(c.surface);
            }
            let name = body.map(|b| M::BODIES[b]);
            warnings.extend(off_surface(j, name, c, scale, t));
        }
        Ok(Snapshot {
            t,
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
            surfaces,
            contact_surfaces,
            warnings,
            gravity: model.gravity_vector(t),
        })
    }
}

impl Snapshot {
    /// The side of surface `surface` (an index into `surfaces`) the bodies are on: 1 where
    /// its height ([`Surface::height`]) is positive, −1 where it is negative. A sphere's
    /// outside and a bowl's inside are positive; a plane's is the side of the centres of the
    /// bodies that roll on it (the plane z = 0 of a model whose z points down has them
    /// below), or else the side against gravity.
    pub(crate) fn side(&self, surface: usize) -> f64 {
        let plane = &self.surfaces[surface];
        let Surface::Plane { orientation, .. } = *plane else {
            return 1.0;
        };
        let heights: f64 = (0..self.bodies.len())
            .filter(|&b| self.rolls_on(b, surface))
            .map(|b| plane.height(self.bodies[b].centre))
            .sum();
        let up = match self.gravity {
            Some(g) => -g.dot(&(orientation * Vector3::z())),
            None => 1.0,
        };
        let side = if heights != 0.0 { heights } else { up };
        if side < 0.0 { -1.0 } else { 1.0 }
    }

    /// Whether body `body` has a contact on surface `surface` (an index into `surfaces`).
    pub(crate) fn rolls_on(&self, body: usize, surface: usize) -> bool {
        self.contacts
            .iter()
            .zip(&self.contact_surfaces)
            .any(|((_, b), s)| *b == Some(body) && *s == surface)
    }
}

/// A contact point farther than this fraction of the bodies' size from its surface is off it.
const OFF_SURFACE: f64 = 1e-6;

/// A warning if contact `j` (of the body called `body`) is off its surface by more than
/// [`OFF_SURFACE`] of `scale`.
pub(crate) fn off_surface(
    j: usize,
    body: Option<&str>,
    contact: &Contact,
    scale: f64,
    t: f64,
) -> Option<String> {
    let height = contact.surface.height(contact.point);
    if height.abs() <= OFF_SURFACE * scale {
        return None;
    }
    let of = body.map_or(String::new(), |b| format!(" (of body `{b}`)"));
    Some(format!(
        "contact point {}{of} is {} from its surface at t = {t}: is the surface where the \
         model's bodies meet it, and the configuration assembled?",
        j + 1,
        short(height)
    ))
}

/// The bodies' size: the largest radius of a shape, or distance between centres, or 1.
fn size_of(bodies: &[Body]) -> f64 {
    let radius = |shape: &Shape| match *shape {
        Shape::Disk { radius, .. } | Shape::Sphere { radius, .. } => radius,
        Shape::Torus { radius, tube, .. } => radius + tube,
        Shape::Ellipsoid { semi_axes, .. } => semi_axes.x.max(semi_axes.y).max(semi_axes.z),
    };
    let shapes = bodies.iter().filter_map(|b| b.shape.as_ref().map(radius));
    let spans = bodies
        .iter()
        .flat_map(|a| bodies.iter().map(move |b| (a.centre - b.centre).norm()));
    let size = shapes.chain(spans).fold(0.0, f64::max);
    if size > 0.0 && size.is_finite() {
        size
    } else {
        1.0
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
