//! Compile-fail suite: every file in `tests/ui/` is a small model with one kind of mistake (or,
//! in `several_independent_mistakes.rs`, several), and its `.stderr` is what a user sees. The
//! messages must point at the user's own code and say what is wrong and what is expected, and
//! one mistake gives one error: the `uses_model_*` cases use the broken model as a program
//! would, and rustc must add nothing to the macro's error. (Role attributes outside the impl
//! block with `#[hamel_system]` run one by one, so each reports itself.) Two cases record the
//! exception: when the impl block or the struct lacks `#[hamel_system]`, no expansion sees both
//! the model's type and its roles, nothing stands in for `impl HamelSystem` or `Parameters`,
//! and rustc reports each use of the model too (`uses_model_missing_hamel_system_on_impl`,
//! `uses_model_struct_without_hamel_system`); the first error still names the mistake.
//!
//! Each case is checked by rustc against the hamel cargo built for this test (`harness/`).
//! After changing a message: `HAMEL_UI=overwrite cargo test -p hamel-ui`, then read the diff.

mod harness;

#[test]
fn malformed_models_fail_to_build_with_messages_that_point_at_the_mistake() {
    harness::check_compile_fail("tests/ui");
}
