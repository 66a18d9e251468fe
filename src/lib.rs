#![doc = include_str!("../README.md")]
//!
//! # Guides
//!
//! * [`docs::model`] — how to write a model: every role with its exact signature, the names
//!   and the state layout, inputs and forces, the errors, and a worked example of each input
//!   form.
//! * [`docs::running`] — running a simulation: events, extra columns, streaming, progress,
//!   the limits that end every run, and what the summary flags.
//! * [`docs::subset`] — the part of Rust a role function's body may use.
//! * [`docs::design`] — the design notes: the mathematics the generated code computes.
//!
//! [`plot`] (feature `plot`, on by default) draws trajectories and analyses as SVG or PNG.
//!
//! # How a model becomes a simulator
//!
//! `#[hamel_system]` lowers the role functions' bodies into one expression graph and builds
//! Hamel's equations on it ([`docs::design`] restates the mathematics): the
//! gradient of L̃(q, ω) by a reverse sweep, the reduced mass matrix and (∂²L̃/∂ω∂q)·q̇ by
//! tangent sweeps over it, and the γ terms as two bidirectional second derivatives of
//! Φ(q, v) = pᵀA(q)v per free direction, never the n³ tensor. With a closed-form inverse B the
//! Lagrangian in quasi-velocities is composed as L̃ = L(q, B(q)ω); without one, B is derived
//! from A(q) after a block-triangular permutation found from A's sparsity pattern — small
//! diagonal blocks inverted in closed form by their adjugates, larger ones by an LU
//! factorization with partial pivoting unrolled into the generated code — and Lagrange's
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
#[cfg(feature = "plot")]
pub mod plot;
pub mod prelude;

pub use hamel_macros::{differentiate, hamel_system};
// The role attributes: `#[hamel_system]` reads them, so these run only when one is misplaced,
// to say where it belongs.
pub use hamel_macros::{
    constraints, forces, holonomic, kinetic_energy, lagrangian, potential_energy, quasi_lagrangian,
    quasi_velocities, velocities,
};
pub use hamel_runtime::*;
