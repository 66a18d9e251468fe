//! The shapes a body can be given by name, in place of the one drawn from what the model
//! says: [`Shape`].

use crate::geometry::Vector3;

/// One of a body's own axes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Axis {
    X,
    Y,
    Z,
}

impl Axis {
    /// The unit vector along the axis.
    pub fn unit(self) -> Vector3 {
        match self {
            Axis::X => Vector3::x(),
            Axis::Y => Vector3::y(),
            Axis::Z => Vector3::z(),
        }
    }
}

/// A shape to draw a body as, in the body's own axes, centred on its centre of mass unless
/// moved with [`Shape::offset`]. Give one to a body by name with
/// [`Scene::shape`](super::Scene::shape) or [`Picture::shape`](super::Picture::shape);
/// bodies without one are drawn from what the model says (see [`crate::scene`]).
///
/// Sizes are in the model's length unit. A size that is not finite and positive is an error
/// when the scene or picture is made.
///
/// ```
/// use hamel::geometry::Vector3;
/// use hamel::scene::{Axis, Shape};
///
/// // A crate on a frame, its centre 0.2 above the frame's centre of mass, drawn in red.
/// let crate_ = Shape::box_(0.4, 0.3, 0.2).offset(Vector3::new(0.0, 0.0, 0.2)).color(0xd62728);
/// let axle = Shape::cylinder(0.02, 0.5, Axis::Y);
/// let ball = Shape::sphere(0.1);
/// assert_ne!(crate_, Shape::inertia_box());
/// # let _ = (axle, ball);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shape {
    pub(crate) form: Form,
    pub(crate) offset: Vector3,
    pub(crate) color: Option<u32>,
}

/// What a [`Shape`] is, before it is placed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Form {
    /// Edge lengths along the body's x, y and z axes.
    Box([f64; 3]),
    /// Radius, length, and the axis it lies along.
    Cylinder(f64, f64, Axis),
    /// A thin disk: radius and the axis normal to it.
    Disk(f64, Axis),
    Sphere(f64),
    /// Semi-axes along the body's x, y and z axes.
    Ellipsoid([f64; 3]),
    /// The uniform box with the body's mass and principal moments.
    InertiaBox,
    /// The uniform ellipsoid with the body's mass and principal moments.
    InertiaEllipsoid,
}

impl Shape {
    fn of(form: Form) -> Self {
        Shape {
            form,
            offset: Vector3::zeros(),
            color: None,
        }
    }

    /// A box with edges `x`, `y` and `z` long along the body's axes.
    pub fn box_(x: f64, y: f64, z: f64) -> Self {
        Shape::of(Form::Box([x, y, z]))
    }

    /// A solid cylinder of radius `radius` and length `length` along the body's `axis`.
    pub fn cylinder(radius: f64, length: f64, axis: Axis) -> Self {
        Shape::of(Form::Cylinder(radius, length, axis))
    }

    /// A thin disk (a wheel) of radius `radius` normal to the body's `axis` (its axle), drawn
    /// with coloured sectors so that its spin shows.
    pub fn disk(radius: f64, axis: Axis) -> Self {
        Shape::of(Form::Disk(radius, axis))
    }

    /// A sphere of radius `radius`, drawn in coloured lunes so that its rotation shows.
    pub fn sphere(radius: f64) -> Self {
        Shape::of(Form::Sphere(radius))
    }

    /// An ellipsoid with semi-axes `a`, `b` and `c` along the body's x, y and z axes.
    pub fn ellipsoid(a: f64, b: f64, c: f64) -> Self {
        Shape::of(Form::Ellipsoid([a, b, c]))
    }

    /// The uniform solid box with the body's mass and principal moments of inertia, along
    /// its principal axes (the default for a body that touches nothing is the ellipsoid).
    pub fn inertia_box() -> Self {
        Shape::of(Form::InertiaBox)
    }

    /// The uniform solid ellipsoid with the body's mass and principal moments of inertia,
    /// along its principal axes: what a body that touches nothing is drawn as by default.
    pub fn inertia_ellipsoid() -> Self {
        Shape::of(Form::InertiaEllipsoid)
    }

    /// The shape's centre is at `offset` from the body's centre of mass, in the body's axes.
    pub fn offset(mut self, offset: Vector3) -> Self {
        self.offset = offset;
        self
    }

    /// Drawn in this colour, `0xRRGGBB`, instead of the body's colour from the palette.
    pub fn color(mut self, rgb: u32) -> Self {
        self.color = Some(rgb & 0xff_ff_ff);
        self
    }

    /// Why the shape cannot be drawn, if it cannot: a size that is not finite and positive,
    /// or an offset that is not finite.
    pub(crate) fn problem(&self) -> Option<String> {
        let sizes: &[f64] = match &self.form {
            Form::Box(edges) | Form::Ellipsoid(edges) => edges,
            Form::Cylinder(r, l, _) => &[*r, *l],
            Form::Disk(r, _) | Form::Sphere(r) => &[*r],
            Form::InertiaBox | Form::InertiaEllipsoid => &[],
        };
        if let Some(bad) = sizes.iter().find(|s| !(s.is_finite() && **s > 0.0)) {
            return Some(format!(
                "has the size {bad}: every size must be finite and positive"
            ));
        }
        let offset = self.offset.to_array();
        (!offset.iter().all(|v| v.is_finite()))
            .then(|| format!("has the offset {}: it must be finite", self.offset))
    }
}
