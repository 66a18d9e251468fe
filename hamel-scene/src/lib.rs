//! See the motion: a model stated from its bodies, animated in 3D in the browser
//! ([`Scene`]), or drawn at one configuration in front, side and top views ([`Picture`],
//! feature `plot`).
//!
//! Both draw what the model says, as the macro read it (through
//! [`Mechanism`](hamel_runtime::geometry::Mechanism), which `#[hamel_system]` implements for models
//! with `#[bodies]`):
//!
//! * a body given a [`Shape`](hamel_runtime::geometry::Shape) in the model (`Body::with_shape`) is
//!   drawn as that shape (a wheel with a tyre as the disk of its outer radius);
//! * a body without one that rolls on a contact is the shape its contact runs round: the contact point,
//!   read in the body's own axes at the configuration and at perturbations of every
//!   coordinate, stays at one distance from the centre; in a plane through the centre the
//!   body is a **disk** of that radius (a wheel, drawn in coloured sectors round a dark hub
//!   so that its spin shows), otherwise a **sphere** (drawn in coloured lunes);
//! * any other body is the **uniform ellipsoid** with its mass and principal moments of
//!   inertia, along its principal axes (nalgebra's eigen-decomposition): semi-axes
//!   aᵢ² = 5 (Iⱼ + Iₖ − Iᵢ) / (2m). An inertia in the wrong axes, or off by a factor, looks
//!   wrong. A body with no inertia is a point mass, drawn as a small sphere; one whose
//!   inertia no rigid body has (not positive definite, or moments that violate the triangle
//!   inequality) is drawn as a red marker, and the page, the picture's legend and
//!   [`Scene::warnings`] say why;
//! * every body's axes are a triad: x red, y green, z blue;
//! * [`Solid`] gives a body a solid of your own, by name: any of the model's shapes, a box,
//!   a cylinder, or the equivalent box instead of the ellipsoid.
//!
//! Up is against gravity (`#[gravity]`), or +z for a model without. Each surface the
//! contacts touch is drawn where the model puts it (as at the first sample): a plane of any
//! pose as a grid in its own plane, a sphere (or a bowl) as a sphere; a model without
//! contacts gets the ground z = 0. Each contact leaves its trace. A contact point that is not
//! on its surface — a tilted plane taken as flat, a sphere of the wrong radius — is a
//! warning, and the picture shows the gap. So is a body drawn through a surface the contacts
//! touch, at any sample: a solid that is not the body's shape where it rolls (the
//! rattleback's inertia ellipsoid is drawn 5.8 mm into its floor), or a body with no contact
//! that the motion takes through it.
//!
//! The page is one HTML file of about 0.8 MB plus the samples (three.js 0.185.1 is embedded,
//! with its MIT licence; nothing is fetched), which opens from `file://` in any current
//! browser. It plays in real time or faster or slower, pauses, has a time slider and an
//! orbit camera (drag, scroll, right-drag), follows the mechanism, and shows the time and
//! the chosen columns with their units beside the scene. Its frames are the trajectory's
//! samples as computed: nothing is interpolated or smoothed, so sample at the rate you want
//! to watch. A trajectory of more than [`MAX_SCENE_SAMPLES`] samples (a quarter of a
//! million) is drawn at one sample in k, and the last, with a warning. The fragment `#t=1.5&pause` opens it at a time. In a browser that draws without
//! a graphics processor (SwiftShader), the page lowers the resolution it plays at, to as
//! little as half, when frames come slower than 50 per second, and says so; paused, it draws
//! at full resolution.
//!
//! A scene or a picture is written whole or not at all, and every bad input is a
//! [`SceneError`] naming it: a trajectory without the model's coordinates (the missing
//! column), an empty trajectory, times that are not finite or do not increase, two columns
//! of one name, an unknown column or body name (to show, or given a unit), a shape or value
//! that is not finite, a path that cannot be written. A model without bodies does not compile.
//!
//! ```
//! use hamel::models::ChaplyginBall;
//! use hamel::prelude::*;
//! use hamel::scene::Scene;
//!
//! let ball = ChaplyginBall::default();
//! let x0 = ball.state_builder().set("beta", 1.0).set("alpha_rate", 3.0).build()?;
//! let run = Simulation::new(&ball, x0)
//!     .end_time(2.0)
//!     .sample_interval(1.0 / 60.0)
//!     .run_constant(&DormandPrince::new(1e-8, 1e-10), [])?;
//! // The ball is drawn as the sphere its contact makes it.
//! let html = Scene::new(&ball, &run)?.show(["x", "y"]).to_html()?;
//! assert!(html.contains(r#""kind":"sphere","radius":0.1"#));
//! // A trajectory without the model's coordinates is refused, naming the one missing.
//! let disk = hamel::models::RollingDisk::default();
//! let Err(err) = Scene::new(&disk, &run) else { panic!("the ball's run has no psi") };
//! assert!(err.to_string().contains("no column `psi`"));
//! # Ok::<(), hamel::Error>(())
//! ```

mod data;
mod equivalent;
mod error;
#[cfg(feature = "plot")]
mod ground;
mod html;
mod infer;
mod json;
mod look;
mod motion;
#[cfg(feature = "plot")]
mod outline;
mod penetration;
#[cfg(feature = "plot")]
mod picture;
#[allow(clippy::module_inception)]
mod scene;
mod snapshot;
mod solid;
mod view;
mod write;

pub use error::{ErrorKind, SceneError};
#[cfg(feature = "plot")]
pub use picture::{PICTURE_SIZE, Picture};
pub use scene::{MAX_SCENE_SAMPLES, Scene};
pub use solid::Solid;

#[cfg(test)]
mod tests;
