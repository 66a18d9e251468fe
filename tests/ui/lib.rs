//! hamel's compile-fail suite lives in `tests/`: every file of `tests/ui/` is a malformed
//! model and its `.stderr` the errors a user sees. Beside it, `tests/at_scale/` holds models
//! whose emitted code once crashed rustc, compiled with full debuginfo and run by an ignored
//! test (`cargo test -p hamel-ui -- --ignored`, which `.ci/run` runs).
