//! Regression test for a fixed engine bug, compiled into the `engine` test binary and checked
//! by `engine_corpus.rs`: the test binary is built with the dev profile's full debuginfo, the configuration that crashed,
//! so a regression fails the build of the suite itself.
//!
//! Every intermediate value is used twice, so the emitted code is ~3000 sequential `let`s in
//! one function. Each `let` opens a lexical scope nested in the previous one, and with full
//! debuginfo (the default of `cargo build`/`cargo test`) rustc 1.95 overflows its stack in
//! LLVM's `DwarfCompileUnit::createAndAddScopeChildren` (SIGSEGV) from about 2500 of them.
//! The 20-link chain's `f_hessian` (13843 operations) hits the same limit.

pub struct Model;

#[hamel::differentiate]
impl Model {
    pub fn f(&self, x: f64) -> f64 {
        let mut s = x;
        for _ in 0..3000 {
            s = 0.5 * s * s + x;
        }
        s
    }
}
