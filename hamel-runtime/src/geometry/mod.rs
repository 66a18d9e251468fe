//! The geometry vocabulary of models: vectors, rotations, rigid bodies and rolling contacts.
//!
//! These are ordinary Rust types, usable anywhere at run time. Inside the role functions of a
//! `#[hamel_system]` model the macro knows them by name, as it knows `f64::sin`: it
//! differentiates through them at compile time, so they cost nothing at run time. The names
//! follow nalgebra's (`Vector3::new`, `a.cross(&b)`, `Rotation3::from_axis_angle`, `r * v`,
//! `r.transpose()`) and SymPy mechanics' (`Body`, `Inertia` with its products of inertia in
//! `inertia(frame, ixx, iyy, izz, ixy, iyz, izx)` order).
//!
//! A model states its rigid bodies with `#[bodies]` (mass, inertia, centre of mass and
//! orientation as functions of q, and optionally a [`Shape`]), and the macro derives their
//! velocities, the kinetic energy and gravity's potential; `#[contacts]` states where bodies
//! roll without slipping on a [`Surface`], and the macro derives the constraint rows from the
//! velocity of the material point at the contact. `hamel::docs::geometry` is the guide.
//!
//! ```
//! use hamel_runtime::geometry::{Rotation3, Vector3};
//! use std::f64::consts::FRAC_PI_2;
//!
//! // A quarter turn about z takes x to y.
//! let r = Rotation3::about_z(FRAC_PI_2);
//! let y = r * Vector3::x();
//! assert!((y - Vector3::y()).norm() < 1e-15);
//! // Composition applies the right factor first; the transpose undoes the rotation.
//! let turn = Rotation3::about_x(0.3) * Rotation3::about_y(-0.2);
//! let v = Vector3::new(1.0, 2.0, 3.0);
//! assert!((turn.transpose() * (turn * v) - v).norm() < 1e-15);
//! ```

mod body;
mod check;
mod check_shapes;
mod mechanism;
mod rotation;
mod shape;
mod surface;
mod turns;
mod vector;

pub use body::{Body, Contact, Inertia, disk_contact, try_disk_contact};
pub use check::check_bodies;
pub use check_shapes::check_contacts;
pub use mechanism::Mechanism;
pub use rotation::Rotation3;
pub use shape::Shape;
pub use surface::Surface;
pub use turns::{ThreeTurns, at_singular_orientation};
pub use vector::Vector3;
