//! Machinery of the engine corpus test (`tests/engine_corpus.rs`): an independent AD to
//! compare against, flattening of argument and result types, and the comparison itself.
//! `repro/` holds minimal reproductions of engine bugs, compiled by trybuild from the test.

pub mod dual;
pub mod harness;
pub mod shapes;
