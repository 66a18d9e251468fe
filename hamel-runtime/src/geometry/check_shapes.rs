//! The geometry of a model must be one a body can have: a shape of positive size about a
//! real axle, orientations and surface frames that are rotations (not scaled, not
//! reflected, with a normal), spheres and bowls of positive radius, a ball that fits in its
//! bowl, and contact points that exist. Checked with the bodies' mass and inertia
//! ([`super::check_bodies`]) when a state is built, when a run starts and when a model is
//! linearized, so that a ball of negative radius is an error naming the body instead of a
//! run with its centre below the bowl, and a plane whose frame is scaled by 2 an error naming
//! the plane instead of a ball floating a radius above it.

use super::{Body, Contact, Rotation3, Shape, Surface, Vector3};
use crate::error::{Error, Num};

/// The advice for a size or a frame made of the parameters.
const PARAMETERS: &str = "check the parameters it is made of";

/// How far a rotation's matrix may be from orthogonal (max |RᵀR − I|): rotations built from
/// angles, axes or quaternions are orthogonal to a few units of rounding.
const ORTHOGONAL: f64 = 1e-9;

/// Why `r` is not a rotation, if it is not: an entry that is not finite (the rotation of a
/// zero axis or a zero quaternion), axes that are not unit vectors at right angles, or a
/// determinant of −1 (a reflection).
pub(super) fn not_a_rotation(r: &Rotation3) -> Option<String> {
    let m = r.matrix();
    if m.iter().flatten().any(|v| !v.is_finite()) {
        return Some(
            "its matrix has entries that are not finite numbers (the rotation about a zero \
             axis, or of a zero quaternion: check the parameters and coordinates it is made \
             of)"
            .into(),
        );
    }
    let column = |j: usize| Vector3::new(m[0][j], m[1][j], m[2][j]);
    let axes = [column(0), column(1), column(2)];
    let lengths = axes.map(|a| a.norm());
    let det = axes[0].dot(&axes[1].cross(&axes[2]));
    let mut defect: f64 = 0.0;
    for i in 0..3 {
        for j in 0..3 {
            let identity = if i == j { 1.0 } else { 0.0 };
            defect = defect.max((axes[i].dot(&axes[j]) - identity).abs());
        }
    }
    if defect <= ORTHOGONAL && det > 0.0 {
        return None;
    }
    let [x, y, z] = lengths.map(Num);
    if lengths[2] == 0.0 {
        return Some(format!(
            "its z axis is the zero vector (its axes have lengths {x}, {y} and {z}), so it has \
             no normal; a frame is a rotation, its axes unit vectors at right angles"
        ));
    }
    if defect <= ORTHOGONAL {
        return Some(format!(
            "its determinant is {}: it is a reflection, which turns the side bodies roll on \
             inside out; a frame is a rotation, determinant 1",
            Num(det)
        ));
    }
    Some(format!(
        "it is not a rotation: its axes have lengths {x}, {y} and {z} and its determinant is {} \
         (|RᵀR − I| = {}); a frame is a rotation, its axes unit vectors at right angles \
         (`Rotation3::from_matrix_unchecked` takes the matrix as it is)",
        Num(det),
        Num(defect)
    ))
}

/// Why `shape` is no shape a body can have, if it is not.
pub(super) fn impossible_shape(shape: &Shape) -> Option<String> {
    let positive = |what: &str, v: f64| {
        (!(v.is_finite() && v > 0.0)).then(|| {
            format!(
                "its {what} is {}; it must be positive ({PARAMETERS})",
                Num(v)
            )
        })
    };
    let centre = shape.centre();
    if !centre.to_array().iter().all(|v| v.is_finite()) {
        return Some(format!(
            "its centre ({}, {}, {}) is not finite",
            Num(centre.x),
            Num(centre.y),
            Num(centre.z)
        ));
    }
    match *shape {
        Shape::Disk { axle, radius, .. } => positive("radius", radius)
            .map(|r| format!("a disk: {r}"))
            .or_else(|| impossible_axle(axle)),
        Shape::Torus {
            axle, radius, tube, ..
        } => positive("radius", radius)
            .or_else(|| {
                (!(tube.is_finite() && tube >= 0.0)).then(|| {
                    format!(
                        "its tube's radius is {}; it must not be negative ({PARAMETERS})",
                        Num(tube)
                    )
                })
            })
            .map(|r| format!("a torus: {r}"))
            .or_else(|| impossible_axle(axle)),
        Shape::Sphere { radius, .. } => {
            positive("radius", radius).map(|r| format!("a sphere: {r}"))
        }
        Shape::Ellipsoid { semi_axes: s, .. } => [("x", s.x), ("y", s.y), ("z", s.z)]
            .iter()
            .find_map(|&(axis, v)| positive(&format!("semi-axis along {axis}"), v))
            .map(|r| format!("an ellipsoid: {r}")),
    }
}

/// Why a wheel's axle is not one, if it is not: `Shape::disk` normalizes it, so the zero
/// vector comes out NaN.
fn impossible_axle(axle: Vector3) -> Option<String> {
    not_a_unit_vector("its axle", axle)
}

/// Why `v`, called `what`, is not a unit vector, if it is not.
pub(super) fn not_a_unit_vector(what: &str, v: Vector3) -> Option<String> {
    let length = v.norm();
    if length.is_finite() && (length - 1.0).abs() <= ORTHOGONAL {
        return None;
    }
    Some(if length.is_nan() || length == 0.0 {
        format!("{what} is the zero vector (or not finite), which has no direction")
    } else {
        format!(
            "{what} has length {}; it must be a unit vector (`Shape::disk` and \
             `Shape::torus` normalize their axles, `v.normalize()` any vector)",
            Num(length)
        )
    })
}

/// Check each contact's surface, and that its body can touch it: a plane's frame must be a
/// rotation, a sphere's or a bowl's radius positive, a ball smaller than its bowl and not at
/// its sphere's centre. (A point that does not exist at one configuration, a disk lying flat,
/// is a singularity, which a run names with its time and state.) `bodies` and `names` (the
/// model's bodies, in order) name the body of each contact.
///
/// ```
/// use hamel_runtime::geometry::{Body, Contact, Inertia, Rotation3, Shape, Surface, Vector3, check_contacts};
/// let ball = Body::new(1.0, Inertia::principal(0.004, 0.004, 0.004), Vector3::new(0.0, 0.0, 0.1),
///     Rotation3::identity()).with_shape(Shape::sphere(0.1));
/// let bowl = Surface::bowl(Vector3::new(0.0, 0.0, 1.0), 1.0);
/// assert!(check_contacts(&[Contact::rolling(ball, bowl)], &[ball], &["ball"]).is_ok());
/// let small = Surface::bowl(Vector3::new(0.0, 0.0, 0.05), 0.05);
/// let e = check_contacts(&[Contact::rolling(ball, small)], &[ball], &["ball"]).unwrap_err();
/// assert!(e.to_string().contains("body `ball`"), "{e}");
/// assert!(e.to_string().contains("not smaller than the bowl's"), "{e}");
/// ```
pub fn check_contacts(contacts: &[Contact], bodies: &[Body], names: &[&str]) -> Result<(), Error> {
    for (i, contact) in contacts.iter().enumerate() {
        let body = body_name(&contact.body, bodies, names);
        let what = format!(
            "contact {i} (body {body} on {})",
            surface_name(&contact.surface)
        );
        if let Some(reason) = impossible_surface(&contact.surface) {
            return Err(Error::ImpossibleGeometry { what, reason });
        }
        if let Some(reason) = impossible_contact(contact, false) {
            return Err(Error::ImpossibleGeometry { what, reason });
        }
    }
    Ok(())
}

/// [`check_contacts`] of one contact, and also a point that does not exist at this
/// configuration (a disk lying flat), which a model's run reports with the time and state
/// instead: for [`Contact::try_rolling`].
pub(super) fn check_contact(contact: &Contact) -> Result<(), Error> {
    let what = || format!("the contact on {}", surface_name(&contact.surface));
    if let Some(reason) = impossible_surface(&contact.surface) {
        return Err(Error::ImpossibleGeometry {
            what: what(),
            reason,
        });
    }
    match impossible_contact(contact, true) {
        Some(reason) => Err(Error::ImpossibleGeometry {
            what: what(),
            reason,
        }),
        None => Ok(()),
    }
}

/// `body `name``, or `contact's body` for a body that is not among `bodies`.
fn body_name(body: &Body, bodies: &[Body], names: &[&str]) -> String {
    let same = |b: &Body| {
        b.mass == body.mass
            && b.inertia == body.inertia
            && b.centre == body.centre
            && b.orientation == body.orientation
    };
    match bodies.iter().position(same) {
        Some(j) => names
            .get(j)
            .map_or_else(|| format!("`body{j}`"), |n| format!("`{n}`")),
        None => "(not among the model's bodies)".into(),
    }
}

fn surface_name(surface: &Surface) -> &'static str {
    match surface {
        Surface::Plane { .. } => "a plane",
        Surface::Sphere { .. } => "a sphere",
        Surface::Bowl { .. } => "a bowl",
    }
}

/// Why `surface` is no surface, if it is not.
fn impossible_surface(surface: &Surface) -> Option<String> {
    let finite = |v: &Vector3| v.to_array().iter().all(|x| x.is_finite());
    match surface {
        Surface::Plane {
            origin,
            orientation,
        } => {
            if !finite(origin) {
                return Some("the plane's origin is not finite".into());
            }
            not_a_rotation(orientation).map(|why| format!("the plane's frame: {why}"))
        }
        Surface::Sphere { centre, radius } | Surface::Bowl { centre, radius } => {
            if !finite(centre) {
                return Some("its centre is not finite".into());
            }
            (!(radius.is_finite() && *radius > 0.0)).then(|| {
                format!(
                    "the {}'s radius is {}; it must be positive ({PARAMETERS})",
                    surface_name(surface).trim_start_matches("a "),
                    Num(*radius)
                )
            })
        }
    }
}

/// Why the body of `contact` cannot touch its surface as written, if it cannot: a ball no
/// smaller than its bowl, a body at its sphere's centre; with `every`, also any other point
/// that is not finite (a disk lying flat: a singular configuration, which a run names with
/// its time and state).
fn impossible_contact(contact: &Contact, every: bool) -> Option<String> {
    let body = &contact.body;
    let shape = body.shape.as_ref();
    if let (Surface::Bowl { radius: bowl, .. }, Some(Shape::Sphere { radius, .. })) =
        (contact.surface, shape)
    {
        if *radius >= bowl {
            return Some(format!(
                "the ball's radius {} is not smaller than the bowl's, {}: a ball rolls inside a \
                 bowl only when the bowl is larger than the ball ({PARAMETERS})",
                Num(*radius),
                Num(bowl)
            ));
        }
    }
    let p = contact.point;
    if p.to_array().iter().all(|v| v.is_finite()) {
        return None;
    }
    let centre = shape.map_or(body.centre, |s| body.point(s.centre()));
    Some(match (contact.surface, shape) {
        (Surface::Sphere { centre: c, .. } | Surface::Bowl { centre: c, .. }, _)
            if (centre - c).norm() == 0.0 =>
        {
            format!(
                "the body's centre is at the {}'s centre, ({}, {}, {}), where no direction \
                 points to the surface: place it on the surface",
                surface_name(&contact.surface).trim_start_matches("a "),
                Num(c.x),
                Num(c.y),
                Num(c.z)
            )
        }
        _ if !every => return None,
        (Surface::Plane { .. }, Some(Shape::Disk { .. } | Shape::Torus { .. })) => {
            "the wheel lies flat on the plane (its axle along the plane's normal), where its \
             rim has no lowest point"
                .into()
        }
        _ => format!(
            "the point where it touches the surface is not a finite number ({}, {}, {})",
            Num(p.x),
            Num(p.y),
            Num(p.z)
        ),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Inertia;

    fn ball(radius: f64, centre: Vector3) -> Body {
        Body::new(
            1.0,
            Inertia::principal(0.004, 0.004, 0.004),
            centre,
            Rotation3::identity(),
        )
        .with_shape(Shape::sphere(radius))
    }

    fn message(contact: Contact, body: Body) -> String {
        check_contacts(&[contact], &[body], &["ball"])
            .unwrap_err()
            .to_string()
    }

    #[test]
    fn rotations_pass_and_scaled_reflected_or_flat_frames_are_named() {
        let turn = Rotation3::about_z(0.3) * Rotation3::from_quaternion(1.0, 2.0, -0.5, 0.2);
        assert_eq!(not_a_rotation(&turn), None);
        let m = |s: f64, t: f64| {
            Rotation3::from_matrix_unchecked([[s, 0.0, 0.0], [0.0, s, 0.0], [0.0, 0.0, t]])
        };
        let cases = [
            (m(2.0, 2.0), "lengths 2, 2 and 2"),
            (m(1.0, -1.0), "reflection"),
            (m(1.0, 0.0), "z axis is the zero vector"),
            (
                Rotation3::from_axis_angle(&Vector3::zeros(), 0.3),
                "zero axis",
            ),
        ];
        for (r, reason) in cases {
            let why = not_a_rotation(&r).expect("not a rotation");
            assert!(why.contains(reason), "{why}");
        }
    }

    #[test]
    fn shapes_of_no_size_or_without_an_axle_are_named() {
        assert_eq!(
            impossible_shape(&Shape::torus(0.3, 0.0, Vector3::y())),
            None
        );
        let cases = [
            (Shape::sphere(-0.05), "radius is -0.05"),
            (Shape::sphere(0.0), "radius is 0"),
            (
                Shape::disk(-0.3, Vector3::y()),
                "a disk: its radius is -0.3",
            ),
            (
                Shape::disk(0.3, Vector3::zeros()),
                "axle is the zero vector",
            ),
            (
                Shape::torus(0.3, -0.01, Vector3::y()),
                "tube's radius is -0.01",
            ),
            (Shape::ellipsoid(0.1, 0.0, 0.2), "semi-axis along y is 0"),
        ];
        for (shape, reason) in cases {
            let why = impossible_shape(&shape).expect("impossible");
            assert!(why.contains(reason), "{why}");
        }
    }

    #[test]
    fn contacts_that_cannot_be_are_named_with_their_body_and_surface() {
        let b = ball(0.1, Vector3::new(0.0, 0.0, 0.5));
        let fits = Surface::bowl(Vector3::new(0.0, 0.0, 1.0), 1.0);
        assert!(check_contacts(&[Contact::rolling(b, fits)], &[b], &["ball"]).is_ok());
        let tight = Surface::bowl(Vector3::new(0.0, 0.0, 1.0), 0.1);
        let e = message(Contact::rolling(b, tight), b);
        assert!(e.contains("contact 0 (body `ball` on a bowl)"), "{e}");
        assert!(e.contains("not smaller than the bowl's"), "{e}");
        let centred = ball(0.1, Vector3::zeros());
        let sphere = Surface::sphere(Vector3::zeros(), 1.0);
        let e = message(Contact::rolling(centred, sphere), centred);
        assert!(e.contains("at the sphere's centre"), "{e}");
        let scaled =
            Rotation3::from_matrix_unchecked([[2.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 2.0]]);
        let plane = Surface::plane(Vector3::zeros(), scaled);
        let e = message(Contact::rolling(b, plane), b);
        assert!(e.contains("the plane's frame: it is not a rotation"), "{e}");
        let e = message(
            Contact::rolling(b, Surface::bowl(Vector3::zeros(), -1.0)),
            b,
        );
        assert!(e.contains("the bowl's radius is -1"), "{e}");
    }
}
