//! A catalogue of models: the paper's robot and the classic nonholonomic systems the test
//! suite validates against. Each is an ordinary `#[hamel_system]` model; read its source.
//! The N-trailer is written once for every N, as a `macro_rules!` ([`crate::n_trailer!`])
//! that the catalogue instantiates for a few N.
//!
//! Use it through `hamel`, as `hamel::models` (and `hamel::n_trailer!`): the examples are
//! there. It is a crate of its own only so that a build compiles it once.

/// The attribute the catalogue's models are written with, and that `n_trailer!` expands to
/// (as `$crate::hamel_system`, since the crate it is used in may not name `hamel_macros`).
#[doc(hidden)]
pub use hamel_macros::hamel_system;

pub mod ball_on_turntable;
pub mod chaplygin_ball;
pub mod chaplygin_sleigh;
pub mod contact_oscillator;
pub mod knife_edge;
pub mod mobile_robot;
pub mod n_trailer;
pub mod rattleback;
pub mod rolling_disk;
pub mod vertical_disk;
pub mod whipple_bicycle;

pub use ball_on_turntable::BallOnTurntable;
pub use chaplygin_ball::ChaplyginBall;
pub use chaplygin_sleigh::ChaplyginSleigh;
pub use contact_oscillator::ContactOscillator;
pub use knife_edge::KnifeEdge;
pub use mobile_robot::{MobileRobot, MobileRobotPaper};
pub use n_trailer::{NTrailer1, NTrailer2, NTrailer8, NTrailer24};
pub use rattleback::Rattleback;
pub use rolling_disk::RollingDisk;
pub use vertical_disk::VerticalDisk;
pub use whipple_bicycle::WhippleBicycle;
