//! Guides, with runnable examples.

#[doc = include_str!("subset.md")]
pub mod subset {}
