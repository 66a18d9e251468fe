//! Emitted code at scale, compiled into the test binary (`engine_corpus.rs` checks the values):
//! each file reproduces an engine bug that once crashed rustc.

pub mod deep_expression;
pub mod long_let_sequence;
