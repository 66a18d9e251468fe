//! Guides, with runnable examples.
//!
//! * [`model`] — writing a model: every role and its signature, the names, the state layout,
//!   inputs and forces, the errors, and a worked example of each input form.
//! * [`geometry`] — models from geometry: rigid bodies, rolling contacts and `rate!`, the
//!   velocities derived by the macro; orientation parametrizations and where each is
//!   singular; shared helpers; the rolling disk, Chaplygin's ball and the bicycle.
//! * [`running`] — running a simulation: the recorded columns, events, streaming, progress
//!   and cancelling, the limits that end every run, and what the summary flags.
//! * [`studies`] — studies of any model: a study's command line in a few lines (grids,
//!   shards, merge, resume, job arrays), honest tables, and stability along a parameter
//!   (modes tracked, crossings, stable ranges); the bicycle's and the rattleback's studies.
//! * [`control`] — control from the model: the control-affine form, outputs and their Lie
//!   derivatives, Lie brackets and the accessibility rank, exact input–output linearization,
//!   LQR with its Riccati equation, and controllers as a run's input function.
//! * [`export`] — a model as a C library and header: CasADi's external functions with exact
//!   first and second derivatives (NMPC with IPOPT), plain C functions, a model of your own.
//! * [`python`] — hamel from Python: the package, runs, ensembles, studies, errors, `compile`.
//! * [`subset`] — the part of Rust a role function's body may use.
//! * [`design`] — the design notes: the mathematics the generated code computes, and how it
//!   obtains each derivative.

#[doc = include_str!("model.md")]
pub mod model {}

#[doc = include_str!("geometry.md")]
pub mod geometry {}

#[doc = include_str!("running.md")]
// Ensembles and their tables come with the feature `ensemble` (`study` includes it), and so
// does their section, with its runnable example.
#[cfg_attr(feature = "ensemble", doc = include_str!("running_ensembles.md"))]
#[cfg_attr(
    not(feature = "ensemble"),
    doc = "\n## Studies: many runs on every core\n\n`hamel::Ensemble`, one computation run for \
           many cases on every core, and `hamel::Table`, their rows, come with hamel's feature \
           `ensemble` (or `study`, which includes it); these docs were built without it."
)]
pub mod running {}

#[cfg(feature = "study")]
#[doc = include_str!("studies.md")]
#[doc = "```no_run"]
#[doc = include_str!("../../examples/rattleback_study.rs")]
#[doc = "```"]
pub mod studies {}

/// Studies of any model (`hamel::study`): this guide, and the module, come with hamel's
/// feature `study` (`--features study`, or `features = ["study"]` where hamel is a
/// dependency), which these docs were built without.
#[cfg(not(feature = "study"))]
pub mod studies {}

#[doc = include_str!("control.md")]
pub mod control {}

#[doc = include_str!("export.md")]
pub mod export {}

#[doc = include_str!("subset.md")]
pub mod subset {}

#[doc = include_str!("python.md")]
pub mod python {}

#[doc = include_str!("design.md")]
pub mod design {}
