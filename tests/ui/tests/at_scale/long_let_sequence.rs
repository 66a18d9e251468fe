//! Regression test for a fixed engine bug: emitted code with ~3000 sequential shared values.
//! Compiled and run by `tests/ui.rs` (an ignored test that `.ci/run` runs) with rustc's full
//! debuginfo (`-C debuginfo=2`, opt-level 0), the configuration that crashed; `main` checks
//! the emitted `f_generic::<f64>` against `f` itself, bit for bit.
//!
//! Every intermediate value is used twice, so a naive emitter writes ~3000 sequential `let`s
//! in one function. Each `let` opens a lexical scope nested in the previous one, and with full
//! debuginfo rustc 1.95 overflows its stack in LLVM's
//! `DwarfCompileUnit::createAndAddScopeChildren` (SIGSEGV). The emitter now binds more than
//! 512 `let`s in a row in blocks of 64, which keeps the nesting of scopes shallow
//! (`MAX_FLAT_LETS` in hamel-macros' `engine/emit.rs`). The 20-link chain's `f_hessian`
//! (13843 operations) hit the same limit.
//!
//! Only full (or limited) debuginfo overflows, not `line-tables-only` nor none, so the check
//! sets its own flags rather than take the dev profile's. With that blocking turned off
//! (`MAX_FLAT_LETS = usize::MAX`), this file crashes rustc 1.95 with `-C debuginfo=2` and
//! compiles with `-C debuginfo=line-tables-only`; a hand-written function of 3000 such `let`s
//! does the same (2900 of them do not crash it).

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

fn main() {
    let x = 0.1;
    let (emitted, plain) = (Model.f_generic::<f64>(x), Model.f(x));
    assert_eq!(
        emitted.to_bits(),
        plain.to_bits(),
        "the emitted f_generic::<f64>({x}) = {emitted:e} differs from f({x}) = {plain:e}"
    );
}
