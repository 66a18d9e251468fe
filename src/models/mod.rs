//! A catalogue of models: the paper's robot and the classic nonholonomic systems the test
//! suite validates against. Each is an ordinary `#[hamel_system]` model; read its source.
//! The N-trailer is written once for every N, as a `macro_rules!` ([`crate::n_trailer!`])
//! that the catalogue instantiates for a few N.

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
