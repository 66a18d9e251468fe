//! hamel's validation suite, one test binary (`cargo test -p hamel-validation --test
//! validation`): each module below was a test binary of its own, and is still run by its
//! name (`cargo test -p hamel-validation --test validation -- rolling::free_top`). One binary
//! links hamel and monomorphizes its generic code once instead of once per file.
//!
//! The shared references (`common`) and machinery (`support`) are modules of their own, used
//! by path (`crate::common::xorshift`). The tests run in parallel threads of one process: none
//! of them may change process-wide state (environment, working directory, global thread
//! pool), and files they write are named after the test as well as the process.

mod common;
mod support;

mod affine_multipliers;
mod bad_input;
mod bicycle;
mod classic_models;
mod constraint_forces;
mod constraint_names;
mod control;
mod engine_corpus;
mod events;
mod geometry;
mod holonomic;
mod linearization;
mod long_runs;
mod mechanism;
mod n_trailer;
mod prepared;
mod readme_dask;
mod riccati;
mod robot;
mod rolling;
mod singular_crossing;
mod syntax_forms;
mod transformation;
mod turntable;
