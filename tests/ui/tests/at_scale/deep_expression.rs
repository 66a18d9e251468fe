//! Regression test for a fixed engine bug: emitted code with a chain of 1000 single-use values.
//! Compiled and run by `tests/ui.rs` (an ignored test that `.ci/run` runs) with rustc's full
//! debuginfo (`-C debuginfo=2`, opt-level 0), the configuration of its sibling
//! `long_let_sequence.rs`; `main` checks the emitted `f_generic::<f64>` against `f` itself,
//! bit for bit.
//!
//! Every intermediate value is used once, so a naive emitter inlines it into its user and the
//! emitted value is a single expression nested 1000 deep: `((… (x + x).sin() …) + x).sin()`.
//! rustc 1.95's parser overflows its stack on it (SIGSEGV in `parse_expr_assoc_with`), with
//! or without debuginfo. The emitter now binds a single-use value to a `let` past a nesting
//! depth of 24 (`MAX_INLINE_DEPTH` in hamel-macros' `engine/emit.rs`). With that turned off
//! (`usize::MAX`), this file crashes rustc 1.95's parser; with the `let` blocks of
//! `long_let_sequence.rs` turned off, its derivative methods (which the check also sends
//! through code generation) crash LLVM's debuginfo as that file does.

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

fn main() {
    let x = 0.1;
    let (emitted, plain) = (Model.f_generic::<f64>(x), Model.f(x));
    assert_eq!(
        emitted.to_bits(),
        plain.to_bits(),
        "the emitted f_generic::<f64>({x}) = {emitted:e} differs from f({x}) = {plain:e}"
    );
}
