//! Regression test for a fixed engine bug (compiled by trybuild from `tests/engine_corpus.rs`).
//!
//! Every intermediate value is used once, so the emitter inlines it into its user and the
//! emitted value is a single expression nested 1000 deep: `((… (x + x).sin() …) + x).sin()`.
//! rustc 1.95's parser overflows its stack on it (SIGSEGV in `parse_expr_assoc_with`), with
//! or without debuginfo.

struct Model;

#[hamel::differentiate]
impl Model {
    fn f(&self, x: f64) -> f64 {
        let mut s = x;
        for _ in 0..1000 {
            s = (s + x).sin();
        }
        s
    }
}

fn main() {
    let x = 0.1;
    assert_eq!(Model.f_generic::<f64>(x), Model.f(x));
}
