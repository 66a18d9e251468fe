//! hamel: nonholonomic mechanical systems compiled into fast simulators.

pub use hamel_macros::differentiate;
pub use hamel_runtime::{OpCounts, Scalar};
