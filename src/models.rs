//! A catalogue of models: the paper's robot and the classic nonholonomic systems the test
//! suite validates against. Each is an ordinary `#[hamel_system]` model; read its source
//! (the `hamel-models` crate, which this module re-exports).
//!
//! The N-trailer is written once for every N, as a `macro_rules!` ([`crate::n_trailer!`])
//! that the catalogue instantiates for N = 1, 2, 8 and 24:
//!
//! ```
//! use hamel::models::NTrailer2;
//! use hamel::prelude::*;
//!
//! // Turning, with the trailers not yet in line: x, y, θ₀, θ₁, θ₂; v, ω.
//! let train = NTrailer2::default();
//! let x0 = train.state_from_speeds(0.0, &[0.0, 0.0, 0.3, 0.1, -0.2], &[1.0, 0.4])?;
//! let run = Simulation::new(&train, x0)
//!     .end_time(3.0)
//!     .run_constant(&DormandPrince::new(1e-10, 1e-12), [0.0, 0.0])?;
//! assert_eq!(NTrailer2::STATE[2..5], ["theta0", "theta1", "theta2"]);
//! assert_eq!(run.column("theta2").unwrap().len(), run.len());
//! // No input acts: the energy is conserved, and every axle keeps rolling.
//! assert!(run.summary().relative_energy_drift < 1e-8);
//! assert!(run.summary().max_constraint_residual < 1e-12);
//! # Ok::<(), hamel::Error>(())
//! ```

// Named one by one, not by a glob: a glob would also list the catalogue crate's hidden
// `hamel_system` re-export in these docs. A model added to the catalogue is added here too.
#[doc(inline)]
pub use hamel_models::{
    BallOnTurntable, ChaplyginBall, ChaplyginSleigh, ContactOscillator, KnifeEdge, MobileRobot,
    MobileRobotPaper, NTrailer1, NTrailer2, NTrailer8, NTrailer24, Rattleback, RollingDisk,
    VerticalDisk, WhippleBicycle,
};
#[doc(inline)]
pub use hamel_models::{
    ball_on_turntable, chaplygin_ball, chaplygin_sleigh, contact_oscillator, knife_edge,
    mobile_robot, n_trailer, rattleback, rolling_disk, vertical_disk, whipple_bicycle,
};
