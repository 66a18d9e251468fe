//! The Whipple bicycle capsizing, for the bicycle example's `--animate` and the README's
//! screenshot (`tests/browser`): from upright at 3 m/s, below the weave speed (4.29 m/s),
//! with a lean of 0.01 rad, the weave grows until the bicycle falls; the run ends when the
//! roll angle reaches 60°. Sampled at 60 per second, the animation's frame rate.

use hamel::models::WhippleBicycle;
use hamel::prelude::*;

/// The forward speed, below the weave speed.
pub const SPEED: f64 = 3.0;
/// The lean it starts from (rad).
pub const LEAN: f64 = 0.01;
/// The roll angle at which it has fallen (rad): 60°.
pub const FALLEN: f64 = std::f64::consts::FRAC_PI_3;

/// The columns shown beside the scene.
pub const SHOWN: [&str; 4] = ["phi", "delta", "psi", "speed"];

/// The ride, until the roll angle reaches ±60° (or 30 s pass).
pub fn ride(bike: &WhippleBicycle) -> Result<Trajectory, Error> {
    let x0 = bike
        .state_builder()
        .set("phi", LEAN)
        .set("rear_wheel_rate", -SPEED / bike.r_r)
        .build()?;
    let phi = WhippleBicycle::STATE.iter().position(|n| *n == "phi");
    let rate = WhippleBicycle::STATE
        .iter()
        .position(|n| *n == "rear_wheel_rate");
    let (Some(phi), Some(rate)) = (phi, rate) else {
        return Err(Error::Io {
            path: "the bicycle".into(),
            message: "the model has no phi or rear_wheel_rate".into(),
        });
    };
    let r = bike.r_r;
    Simulation::new(bike, x0)
        .end_time(30.0)
        .sample_interval(1.0 / 60.0)
        .project_holonomic(true)
        .output("speed", move |_t, x| -r * x[rate])
        .event(Event::on(bike, "fallen", move |_t, x| x[phi].abs() - FALLEN).terminal())
        .run_constant(&DormandPrince::new(1e-9, 1e-12), [0.0, 0.0])
}
