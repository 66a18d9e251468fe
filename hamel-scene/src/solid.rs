//! What a body can be drawn as in place of what the model says: [`Solid`], one of the
//! model's own shapes ([`geometry::Shape`](hamel_runtime::geometry::Shape)) or a solid that only
//! drawing needs (a box, a cylinder, the uniform solids of the body's inertia).

use hamel_runtime::geometry::{Shape, Vector3};

/// A solid to draw a body as, in the body's own axes, centred on its centre of mass unless
/// moved with [`Solid::at`]. Give one to a body by name with
/// [`Scene::shape`](super::Scene::shape) or [`Picture::shape`](super::Picture::shape);
/// bodies without one are drawn from what the model says (see [`hamel::scene`](crate)).
///
/// Disks, wheels with tyres, spheres and ellipsoids are the model's own
/// [`Shape`](hamel_runtime::geometry::Shape)s (a `Shape` converts into a `Solid`); this type adds
/// what a body that rolls on nothing may look like: a box, a cylinder, or the uniform box or
/// ellipsoid of its mass and inertia. Sizes are in the model's length unit; a size that is
/// not finite and positive is an error when the scene or picture is made.
///
/// ```
/// use hamel::geometry::{Shape, Vector3};
/// use hamel::scene::Solid;
///
/// // A crate on a frame, its centre 0.2 above the frame's centre of mass, drawn in red.
/// let crate_ = Solid::box_(0.4, 0.3, 0.2).at(Vector3::new(0.0, 0.0, 0.2)).color(0xd62728);
/// let axle = Solid::cylinder(0.02, 0.5, Vector3::y());
/// let ball: Solid = Shape::sphere(0.1).into();
/// assert_ne!(crate_, Solid::inertia_box());
/// # let _ = (axle, ball);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Solid {
    pub(crate) form: Form,
    /// The solid's centre from the body's centre of mass, in the body's axes.
    pub(crate) centre: Vector3,
    pub(crate) color: Option<u32>,
}

/// What a [`Solid`] is, before it is placed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Form {
    /// One of the model's shapes (its own centre is [`Solid::centre`]).
    Shape(Shape),
    /// Edge lengths along the body's x, y and z axes.
    Box([f64; 3]),
    /// Radius, length, and the unit vector it lies along.
    Cylinder(f64, f64, Vector3),
    /// The uniform box with the body's mass and principal moments.
    InertiaBox,
    /// The uniform ellipsoid with the body's mass and principal moments.
    InertiaEllipsoid,
}

impl From<Shape> for Solid {
    fn from(shape: Shape) -> Self {
        Solid {
            form: Form::Shape(shape),
            centre: shape.centre(),
            color: None,
        }
    }
}

impl Solid {
    fn of(form: Form) -> Self {
        Solid {
            form,
            centre: Vector3::zeros(),
            color: None,
        }
    }

    /// A box with edges `x`, `y` and `z` long along the body's axes.
    pub fn box_(x: f64, y: f64, z: f64) -> Self {
        Solid::of(Form::Box([x, y, z]))
    }

    /// A solid cylinder of radius `radius` and length `length` along `axis`, a direction in
    /// the body's axes (normalized; a zero or non-finite one is an error when drawn).
    pub fn cylinder(radius: f64, length: f64, axis: Vector3) -> Self {
        Solid::of(Form::Cylinder(radius, length, axis))
    }

    /// The uniform solid box with the body's mass and principal moments of inertia, along
    /// its principal axes (the default for a body without a shape is the ellipsoid).
    pub fn inertia_box() -> Self {
        Solid::of(Form::InertiaBox)
    }

    /// The uniform solid ellipsoid with the body's mass and principal moments of inertia,
    /// along its principal axes: what a body without a shape that touches nothing is drawn as.
    pub fn inertia_ellipsoid() -> Self {
        Solid::of(Form::InertiaEllipsoid)
    }

    /// The same solid centred `centre` from the body's centre of mass, in the body's axes.
    pub fn at(mut self, centre: Vector3) -> Self {
        self.centre = centre;
        if let Form::Shape(shape) = self.form {
            self.form = Form::Shape(shape.at(centre));
        }
        self
    }

    /// Drawn in this colour, `0xRRGGBB`, instead of the body's colour from the palette.
    pub fn color(mut self, rgb: u32) -> Self {
        self.color = Some(rgb & 0xff_ff_ff);
        self
    }

    /// Why the solid cannot be drawn, if it cannot: a size that is not finite and positive,
    /// an axis that is zero or not finite, or a centre that is not finite.
    pub(crate) fn problem(&self) -> Option<String> {
        let mut axis = None;
        let sizes: Vec<f64> = match self.form {
            Form::Shape(Shape::Disk { radius, axle, .. }) => {
                axis = Some(axle);
                vec![radius]
            }
            Form::Shape(Shape::Torus {
                radius, tube, axle, ..
            }) => {
                axis = Some(axle);
                vec![radius, tube]
            }
            Form::Shape(Shape::Sphere { radius, .. }) => vec![radius],
            Form::Shape(Shape::Ellipsoid { semi_axes, .. }) => semi_axes.to_array().to_vec(),
            Form::Box(edges) => edges.to_vec(),
            Form::Cylinder(radius, length, along) => {
                axis = Some(along);
                vec![radius, length]
            }
            Form::InertiaBox | Form::InertiaEllipsoid => Vec::new(),
        };
        if let Some(bad) = sizes.iter().find(|s| !(s.is_finite() && **s > 0.0)) {
            return Some(format!(
                "has the size {bad}: every size must be finite and positive"
            ));
        }
        if let Some(axis) = axis.filter(|a| !(a.norm() > 0.0 && a.norm().is_finite())) {
            return Some(format!(
                "has the axis {axis}: it must be finite and not zero"
            ));
        }
        let centre = self.centre.to_array();
        (!centre.iter().all(|v| v.is_finite()))
            .then(|| format!("has the centre {}: it must be finite", self.centre))
    }
}
