#![doc = include_str!("../README.md")]
//!
//! # Guides
//!
//! * [`docs::model`] — how to write a model: every role with its exact signature, the names
//!   and the state layout, inputs and forces, the errors, and a worked example of each input
//!   form.
//! * [`docs::geometry`] — three-dimensional models stated from their bodies and rolling
//!   contacts, the velocities derived by the macro.
//! * [`docs::running`] — running a simulation: events, extra columns, streaming, progress,
//!   the limits that end every run, and what the summary flags.
//! * [`docs::studies`] — studies of any model (`hamel::study`): the command line of a batch
//!   engine's task in a few lines, and stability along a parameter ([`ModeSweep`]).
//! * [`docs::subset`] — the part of Rust a role function's body may use.
//! * [`docs::design`] — the design notes: the mathematics the generated code computes.
//!
//! [`plot`] (feature `plot`, on by default) draws trajectories and analyses as SVG, and as PNG
//! with the feature `png`. Studies (`hamel::study`, [`docs::studies`]) come with the feature
//! `study`. Both are off by default, so that a program that simulates and draws SVG builds
//! neither.
//! [`scene`] animates a model's bodies in 3D in the browser, and draws them at one
//! configuration in front, side and top views.
//!
//! # How a model becomes a simulator
//!
//! `#[hamel_system]` lowers the role functions' bodies into one expression graph and builds
//! Hamel's equations on it ([`docs::design`] restates the mathematics): the
//! gradient of L̃(q, ω) by a reverse sweep, the reduced mass matrix and (∂²L̃/∂ω∂q)·q̇ by
//! tangent sweeps over it, and the γ terms as two bidirectional second derivatives of
//! Φ(q, v) = pᵀA(q)v per free direction, never the n³ tensor. With a closed-form inverse B the
//! Lagrangian in quasi-velocities is composed as L̃ = L(q, B(q)ω); without one, B is derived
//! from A(q) after a block-triangular permutation found from A's sparsity pattern — its
//! diagonal blocks inverted in closed form by their adjugates when the largest has two or
//! three rows, and otherwise A solved by an LU factorization with partial pivoting unrolled
//! into the generated code — and Lagrange's
//! equations are projected on the admissible directions instead. The reduced mass matrix is
//! factored by an unrolled LDLᵀ; its pivots, and B's determinants or pivots, are checked
//! before any result is used.
//!
//! The constraint rows may be affine in the velocities and depend on the time,
//! A(q, t) q̇ + a(q, t) = 0 (a ball on a turntable, a wheel on a moving belt): the macro reads
//! A and a off the same function and adds the terms they bring to Hamel's equations.
//! Holonomic constraints f(t, q) = 0 are written as such and differentiated by the macro;
//! the runtime keeps them by Newton's method. [`docs::design`] derives the equations,
//! [`docs::model`] says how to write each form.
//!
//! # The differentiation engine
//!
//! Everything rests on a compile-time differentiation engine: it reads ordinary Rust
//! function bodies over `f64`, builds a hash-consed expression graph, differentiates it by
//! source transformation (tangent and adjoint sweeps and their compositions) and emits
//! straight-line Rust. [`docs::subset`] lists what a body may contain, with an example of
//! each form; [`differentiate`] is the engine's direct interface.
//!
//! # Why the emitted code is generic over [`Scalar`]
//!
//! Linearizing a simulator about an operating point (control design; the Whipple bicycle
//! benchmark) needs the Jacobian of its right-hand side, a third derivative of the
//! Lagrangian. Rather than emitting that, the engine can emit any function generic over
//! [`Scalar`] (`f_generic` for `#[differentiate]`): dual numbers then flow through the
//! generated code, including its numeric linear solves, while the `f64` instantiation is
//! exactly the plain code. This keeps the emitted code small (no third-order blocks growing
//! with n³) and reuses a well-tested operator-overloading AD where speed does not matter.

// Generated code names this crate `::hamel`; inside the crate itself too.
extern crate self as hamel;

pub mod docs;
pub mod models;
#[cfg(feature = "parquet")]
pub mod parquet;
// `plot` and `scene` are crates of their own (`hamel-plot`, `hamel-scene`), so that a build
// compiles them beside the catalogue once the runtime's metadata is ready.
#[cfg(feature = "plot")]
#[doc(inline)]
pub use hamel_plot as plot;
pub mod prelude;
#[doc(inline)]
pub use hamel_scene as scene;
#[cfg(feature = "study")]
pub mod study;

#[doc(hidden)]
pub use hamel_macros::__hamel_with_helpers;
pub use hamel_macros::{differentiate, hamel_system, helpers};
// The role attributes: `#[hamel_system]` reads them, so these run only when one is misplaced,
// to say where it belongs.
pub use hamel_macros::{
    bodies, constraints, contacts, forces, gravity, holonomic, kinetic_energy, lagrangian, outputs,
    potential_energy, quasi_lagrangian, quasi_velocities, velocities,
};
pub use hamel_runtime::*;

/// A tractor with three trailers:
///
/// ```
/// hamel::n_trailer!(
///     /// A tractor with three trailers.
///     pub Train3, trailers = 3, axles = 4
/// );
///
/// use hamel::prelude::*;
/// assert_eq!((Train3::N, Train3::P, Train3::TRAILERS), (6, 4, 3));
/// assert_eq!(Train3::COORDINATES, ["x", "y", "theta0", "theta1", "theta2", "theta3"]);
/// assert_eq!(Train3::SPEEDS, ["v", "omega"]);
/// assert_eq!(Train3::INPUTS, ["drive", "steer"]);
/// assert_eq!(Train3::THETA + 3, Train3::THETA3);
/// assert_eq!(&Train3::NAMES[..4], ["m0", "m1", "m2", "m3"]);
/// let mut train = Train3::default();
/// train.set("d2", 1.5)?;
/// assert_eq!(train.d[2], 1.5);
/// # Ok::<(), hamel::Error>(())
/// ```
///
/// Numbers that do not match are one compile error:
///
/// ```compile_fail,E0080
/// // error: evaluation panicked: n_trailer!: `axles` must be `trailers + 1`
/// hamel::n_trailer!(pub Train3, trailers = 3, axles = 3);
/// ```
#[doc(inline)]
pub use hamel_models::n_trailer;

/// The time derivative along the motion of an expression of the coordinates (and the time),
/// d/dt = Σ q̇ⱼ ∂/∂qⱼ + ∂/∂t: `rate!(contact.x)`. The macro computes it, in the body of a
/// role of a `#[hamel_system]` model that is read with the velocities `qd` (`#[constraints]`,
/// `#[quasi_velocities]`, `#[kinetic_energy]`, `#[lagrangian]`, `#[forces]`); anywhere else it
/// is a compile error. `hamel::docs::geometry` shows it at work.
///
/// ```
/// use hamel::prelude::*;
///
/// #[hamel_system]
/// pub struct Sleigh { pub m: f64, pub inertia: f64, pub a: f64 }
///
/// #[hamel_system(coordinates(x, y, theta), speeds(v, omega))]
/// impl Sleigh {
///     #[kinetic_energy]
///     fn kinetic_energy(&self, _q: &[f64; 3], qd: &[f64; 3]) -> f64 {
///         0.5 * self.m * (qd[0] * qd[0] + qd[1] * qd[1]) + 0.5 * self.inertia * qd[2] * qd[2]
///     }
///
///     /// The blade, a behind the centre of mass, does not move sideways.
///     #[constraints]
///     fn blade(&self, q: &[f64; 3], _qd: &[f64; 3]) -> [f64; 1] {
///         let (s, c) = q[2].sin_cos();
///         let contact = Vector3::new(q[0] - self.a * c, q[1] - self.a * s, 0.0);
///         [rate!(contact).dot(&Vector3::new(-s, c, 0.0))]
///     }
///
///     #[quasi_velocities]
///     fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
///         [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[2]]
///     }
/// }
///
/// // The generated body computes the rate, so the role can be called at run time.
/// let sleigh = Sleigh { m: 2.0, inertia: 0.5, a: 0.4 };
/// let sideways = sleigh.blade(&[0.0, 0.0, 0.0], &[0.0, 1.0, 0.0]);
/// assert_eq!(sideways, [1.0]);
/// ```
#[macro_export]
macro_rules! rate {
    ($($expression:tt)*) => {
        ::core::compile_error!(
            "`rate!` is the time derivative along the motion: it can be used only in the body \
             of a role of a `#[hamel_system]` model that is read with the velocities `qd` \
             (`#[constraints]`, `#[quasi_velocities]`, `#[kinetic_energy]`, `#[lagrangian]`, \
             `#[forces]`), where the macro computes it"
        )
    };
}

/// The angular velocity ω of a rotation along the motion, in the ground's axes:
/// `angular_velocity!(body.orientation)`, a `Vector3` (`body_rates!` gives it in the body's
/// own axes). The macro computes it, from the turns the rotation is a product of, in the body
/// of a role of a `#[hamel_system]` model that is read with the velocities `qd`, as `rate!`;
/// anywhere else it is a compile error.
#[macro_export]
macro_rules! angular_velocity {
    ($($expression:tt)*) => {
        ::core::compile_error!(
            "`angular_velocity!` is the angular velocity of a rotation along the motion: it can \
             be used only in the body of a role of a `#[hamel_system]` model that is read with \
             the velocities `qd` (`#[constraints]`, `#[quasi_velocities]`, `#[kinetic_energy]`, \
             `#[lagrangian]`, `#[forces]`), where the macro computes it"
        )
    };
}

/// The body rates Ω = Rᵀ ω of a rotation R along the motion — its angular velocity in the
/// rotated body's own axes, the classic quasi-velocities of Hamel's equations:
/// `body_rates!(ball.orientation).to_array()` as the speeds of a ball. The macro computes it
/// in the body of a role of a `#[hamel_system]` model that is read with the velocities `qd`,
/// as `rate!`; anywhere else it is a compile error. `hamel::docs::geometry` uses it for
/// Chaplygin's ball.
///
/// ```
/// use hamel::prelude::*;
///
/// #[hamel_system]
/// pub struct Top { pub i1: f64, pub i2: f64, pub i3: f64 }
///
/// #[hamel_system(coordinates(w, x, y, z), speeds(w1, w2, w3), constraints(unit))]
/// impl Top {
///     #[bodies]
///     fn bodies(&self, q: &[f64; 4]) -> [Body; 1] {
///         let orientation = Rotation3::from_quaternion(q[0], q[1], q[2], q[3]);
///         let inertia = Inertia::principal(self.i1, self.i2, self.i3);
///         [Body::new(1.0, inertia, Vector3::zeros(), orientation)]
///     }
///
///     /// The quaternion's length does not change (the orientation does not depend on it).
///     #[constraints]
///     fn unit(&self, q: &[f64; 4], qd: &[f64; 4]) -> [f64; 1] {
///         [q[0] * qd[0] + q[1] * qd[1] + q[2] * qd[2] + q[3] * qd[3]]
///     }
///
///     #[quasi_velocities]
///     fn rates(&self, q: &[f64; 4], _qd: &[f64; 4]) -> [f64; 3] {
///         let [top] = self.bodies(q);
///         body_rates!(top.orientation).to_array()
///     }
/// }
///
/// let top = Top { i1: 1.0, i2: 2.0, i3: 3.0 };
/// // Turning about the body's z axis at 2 rad/s: q̇ = ½ q ⊗ (0, 0, 0, 2) at q = 1.
/// assert_eq!(top.rates(&[1.0, 0.0, 0.0, 0.0], &[0.0, 0.0, 0.0, 1.0]), [0.0, 0.0, 2.0]);
/// ```
#[macro_export]
macro_rules! body_rates {
    ($($expression:tt)*) => {
        ::core::compile_error!(
            "`body_rates!` is the angular velocity of a rotation along the motion in the body's \
             own axes: it can be used only in the body of a role of a `#[hamel_system]` model \
             that is read with the velocities `qd` (`#[constraints]`, `#[quasi_velocities]`, \
             `#[kinetic_energy]`, `#[lagrangian]`, `#[forces]`), where the macro computes it"
        )
    };
}
