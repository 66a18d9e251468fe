//! hamel's validation suite, second of its two test binaries: the catalogue's models and
//! their runs against closed forms from the literature, independent formulations (Lagrange's
//! equations with multipliers, models written by hand), published benchmarks and
//! conservation laws; bad input, long runs, events, control. `engine.rs` is the other binary:
//! the macro and its engine.
//!
//! Each module below was a test binary of its own, and keeps its name in the tests' names:
//! `cargo test -p hamel-validation --test models -- rolling::a_free_top`. (Why two binaries:
//! `engine.rs`.)
//!
//! The tests of a binary run in parallel threads of one process: none may change
//! process-wide state (environment, working directory, the global thread pool), and a file
//! one writes is named after the test as well as the process.

/// References shared by several modules and with `engine.rs` (each binary declares the ones
/// its tests use): closed forms, models written by hand, independent formulations, the seeded
/// random generator. The benchmarks include some of these files on their own (`#[path]`).
mod common {
    pub mod affine_multipliers;
    pub mod disk_closed_forms;
    pub mod planar_closed_forms;
    pub mod robot_by_hand;
    pub mod robot_closed_form;
    pub mod robot_projected_lagrange;
    pub mod stiff_problems;
    pub mod whipple_by_hand;
    pub mod xorshift;
}

/// Nested dual numbers behind `hamel::Scalar`, for the Lie derivatives of `control.rs`.
mod support {
    pub mod nested;
}

mod affine_multipliers;
mod bad_input;
mod bicycle;
mod classic_models;
mod constraint_forces;
mod control;
mod events;
mod geometry;
mod long_runs;
mod mechanism;
mod n_trailer;
mod readme_dask;
mod riccati;
mod robot;
mod rolling;
mod turntable;
