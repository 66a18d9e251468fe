//! Machinery of the engine corpus test (`tests/engine_corpus.rs`): an independent AD to
//! compare against, flattening of argument and result types, and the comparison itself.
//! `at_scale/` holds reproductions of engine bugs that once crashed rustc, compiled into the test.

pub mod dual;
pub mod harness;
pub mod shapes;
