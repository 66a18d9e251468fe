//! hamel: nonholonomic mechanical systems compiled into fast simulators.
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

pub use hamel_macros::{differentiate, hamel_system};
pub use hamel_runtime::*;
