//! hamel's validation suite, first of its two test binaries: the macro and its engine —
//! every form of the language, the generated functions and derivatives against rustc and
//! num-dual, and what the generated code derives (prepared values, B = A⁻¹, linearizations,
//! named constraints). `models.rs` is the other binary: the catalogue's models and their runs.
//!
//! Each module below was a test binary of its own, and keeps its name in the tests' names:
//! `cargo test -p hamel-validation --test engine -- syntax_forms::if_else_statements`. Two
//! binaries rather than one per file: each links hamel and monomorphizes its generic code
//! again; two rather than one: rustc type-checks a crate on one thread, so two halves of
//! similar size build side by side on two cores (the package's `Cargo.toml` has the figures).
//!
//! The tests of a binary run in parallel threads of one process: none may change
//! process-wide state (environment, working directory, the global thread pool), and a file
//! one writes is named after the test as well as the process.

/// References shared with `models.rs`. Each binary declares the ones its tests use: a file
/// declared and unused is still expanded and type-checked (all of `support/` in both
/// binaries cost 25 s more CPU time).
mod common {
    pub mod robot_closed_form;
    pub mod same_system;
    pub mod xorshift;
}

/// Machinery of the engine corpus (`engine_corpus.rs`): an independent AD to compare
/// against, flattening of argument and result types, and the comparison itself. (Emitted code
/// at a scale that once crashed rustc is not compiled into this binary: the compile-fail
/// package compiles it with full debuginfo, `tests/ui/tests/at_scale/`.)
mod support {
    pub mod dual;
    pub mod harness;
    pub mod shapes;
}

mod constraint_names;
mod engine_corpus;
mod holonomic;
mod linearization;
mod prepared;
mod singular_crossing;
mod syntax_forms;
mod transformation;
