//! hamel's compile-fail suite lives in `tests/`: every file of `tests/ui/` is a malformed
//! model and its `.stderr` the errors a user sees.
