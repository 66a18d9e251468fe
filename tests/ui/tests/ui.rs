//! Compile-fail suite: every file in `tests/ui/` is a small model with one kind of mistake (or,
//! in `several_independent_mistakes.rs`, several), and its `.stderr` is what a user sees. The
//! messages must point at the user's own code and say what is wrong and what is expected, and
//! one mistake gives one error: the `uses_model_*` cases use the broken model as a program
//! would, and rustc must add nothing to the macro's error. (Role attributes outside the impl
//! block with `#[hamel_system]` run one by one, so each reports itself.) Two cases record the
//! exception: when the impl block or the struct lacks `#[hamel_system]`, no expansion sees both
//! the model's type and its roles, nothing stands in for `impl HamelSystem` or `Parameters`,
//! and rustc reports each use of the model too (`uses_model_missing_hamel_system_on_impl`,
//! `uses_model_struct_without_hamel_system`); the first error still names the mistake. (A
//! model whose `helpers(..)` names a set without `#[hamel::helpers]` does see both: rustc's
//! "cannot find macro" at the name is its one error, `uses_model_helpers_not_marked`.)
//!
//! Each case is checked by rustc against the hamel cargo built for this test (`harness/`).
//! After changing a message: `HAMEL_UI=overwrite cargo test -p hamel-ui`, then read the diff.
//!
//! The same harness compiles and runs the programs of `tests/at_scale/`: emitted code at a
//! scale that once crashed rustc, in the configuration that crashed it (an ignored test, run
//! by `.ci/run`).

mod harness;

#[test]
fn malformed_models_fail_to_build_with_messages_that_point_at_the_mistake() {
    harness::check_compile_fail("tests/ui");
}

/// Each file of `tests/at_scale/` is a model whose emitted code once crashed rustc 1.95 (a
/// stack overflow: in LLVM's debuginfo for ~3000 sequential `let`s, in the parser for an
/// expression 1000 deep), and a `main` that checks the emitted `f_generic::<f64>` against `f`
/// bit for bit. rustc compiles each with full debuginfo at opt-level 0, the configuration
/// that crashed (line tables only, or no debuginfo as in the dev profile, do not overflow
/// on the `let`s), generates its code and links it; the program must then run. `link-dead-code`
/// sends the derivative methods `main` does not call (`f_hessian`, …, the longest emitted
/// functions) through code generation too: about a quarter more CPU time.
#[test]
#[ignore = "heavy (22–28 s of CPU: full debuginfo for ~85,000 lines of emitted code); \
            .ci/run runs it: cargo test -p hamel-ui -- --ignored"]
fn emitted_code_at_scale_compiles_with_full_debuginfo_and_computes_its_function() {
    let flags = ["-Cdebuginfo=2", "-Copt-level=0", "-Clink-dead-code"];
    harness::check_run_pass("tests/at_scale", &flags);
}
