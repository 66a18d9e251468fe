//! The compile-time differentiation engine: Rust function bodies → expression graph →
//! derivative graphs → straight-line Rust.
//!
//! * `graph` — the hash-consed DAG with its simplifications;
//! * `lower` — Rust syntax of the supported subset into graph values;
//! * `diff` — tangent (forward) and adjoint (reverse) sweeps, and their compositions;
//! * `emit` — the graph back to Rust;
//! * `factor` — a last pass taking common factors out of finished sums;
//! * `ops` — operation counts of what is emitted.

pub mod diff;
pub mod emit;
mod factor;
pub mod graph;
pub mod hash;
pub mod lower;
mod normal;
pub mod ops;

#[cfg(test)]
mod tests;
