//! The runtime's integration tests, one test binary (`cargo test -p hamel-runtime --test
//! runtime`): each module below was a test binary of its own and keeps its name in the
//! tests' names (`cargo test -p hamel-runtime --test runtime -- simulation::ensembles`). One
//! binary links the runtime and monomorphizes its generic code once instead of once per file.
//!
//! The tests run in parallel threads of one process: none may change process-wide state
//! (environment, working directory, the global thread pool), and a file one writes is named
//! after the test as well as the process.

mod common;

mod holonomic;
mod integrators;
mod linearization;
mod messages;
mod simulation;
