//! Machinery of the engine corpus (`engine_corpus.rs`): an independent AD to compare against,
//! flattening of argument and result types, and the comparison itself; and the nested dual
//! numbers `control.rs` computes Lie derivatives with. `at_scale/` holds reproductions of
//! engine bugs that once crashed rustc, compiled into the test binary.

pub mod at_scale;
pub mod dual;
pub mod harness;
pub mod nested;
pub mod shapes;
