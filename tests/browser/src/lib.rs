//! hamel's scenes in a real browser: headless Chromium driven over the DevTools protocol
//! ([`chromium`]), a scene page opened at a time with the camera it drew with ([`page`]),
//! and the catalogue's models with bodies in short runs ([`catalogue`]).
//!
//! `tests/scenes.rs` checks each catalogue scene (no console error; the checked body drawn
//! where its trajectory puts it, at two times; the picture moves); `benches/frame_time.rs`
//! measures the bicycle's frame time; `src/bin/screenshot.rs` takes the README's screenshot.
//! Without Chromium the test says how to install it and passes as skipped.

pub mod catalogue;
pub mod chromium;
pub mod page;
