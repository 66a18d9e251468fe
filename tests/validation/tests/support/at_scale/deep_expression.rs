//! Regression test for a fixed engine bug, compiled into the `engine` test binary and checked
//! by `engine_corpus.rs`: the test binary is built with the dev profile's full debuginfo, the configuration that crashed,
//! so a regression fails the build of the suite itself.
//!
//! Every intermediate value is used once, so the emitter inlines it into its user and the
//! emitted value is a single expression nested 1000 deep: `((… (x + x).sin() …) + x).sin()`.
//! rustc 1.95's parser overflows its stack on it (SIGSEGV in `parse_expr_assoc_with`), with
//! or without debuginfo.

pub struct Model;

#[hamel::differentiate]
impl Model {
    pub fn f(&self, x: f64) -> f64 {
        let mut s = x;
        for _ in 0..1000 {
            s = (s + x).sin();
        }
        s
    }
}
