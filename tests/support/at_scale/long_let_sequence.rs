//! Regression test for a fixed engine bug (compiled by trybuild from `tests/engine_corpus.rs`).
//!
//! Every intermediate value is used twice, so the emitted code is ~3000 sequential `let`s in
//! one function. Each `let` opens a lexical scope nested in the previous one, and with full
//! debuginfo (the default of `cargo build`/`cargo test`) rustc 1.95 overflows its stack in
//! LLVM's `DwarfCompileUnit::createAndAddScopeChildren` (SIGSEGV) from about 2500 of them.
//! The 20-link chain's `f_hessian` (13843 operations) hits the same limit.

struct Model;

#[hamel::differentiate]
impl Model {
    fn f(&self, x: f64) -> f64 {
        let mut s = x;
        for _ in 0..3000 {
            s = 0.5 * s * s + x;
        }
        s
    }
}

fn main() {
    let x = 0.1;
    assert_eq!(Model.f_generic::<f64>(x), Model.f(x));
}
