//! The Whipple bicycle falling over, for the bicycle example's `--animate` and the README's
//! screenshot (`tests/browser`): from upright at 3 m/s, below the weave speed (4.29 m/s),
//! with a lean of 0.01 rad. The growing mode at this speed is the weave, an oscillation of
//! lean and steer (the capsize mode is stable below the capsize speed, 6.02 m/s): it grows
//! while the lean changes side twice (at t = 1.20 s and 2.68 s), then the bicycle falls
//! over. Sampled at 60 per second, the animation's frame rate.
//!
//! The run ends at the first of two events. `fallen`: the roll angle reaches 60°. `across`:
//! the front wheel has turned square across the rear frame (a steer of 90°, beyond any
//! handlebar's stop). Falling, the bicycle meets `across` first, at t = 3.268 s, leaning
//! 0.81 rad: from t = 3.18 s the front frame flops from 0.41 to 1.57 rad of steer, the rear
//! frame pitches up by 0.18 rad, and the rear wheel, spinning relative to it, reads 6.3 m/s
//! (`speed`, r times its rate; the rear contact moves over the ground at 5.2 m/s), the
//! energy kept to 2.7·10⁻⁹ of itself. Just past it, at a steer of 1.596 rad, the rolling
//! constraints and the speeds become dependent (the transformation A(q) is singular) and
//! the model no longer determines the motion: run on through it to a roll of 60°, the steer
//! reached 5.03 rad and the energy changed by 2.5·10⁻⁴, no longer a motion of this bicycle.

use hamel::models::WhippleBicycle;
use hamel::prelude::*;

/// The forward speed, below the weave speed.
pub const SPEED: f64 = 3.0;
/// The lean it starts from (rad).
pub const LEAN: f64 = 0.01;
/// The roll angle at which it has fallen (rad): 60°.
pub const FALLEN: f64 = std::f64::consts::FRAC_PI_3;

/// The steer angle at which the front wheel is square across the rear frame (rad): 90°.
pub const ACROSS: f64 = std::f64::consts::FRAC_PI_2;

/// The columns shown beside the scene.
pub const SHOWN: [&str; 4] = ["phi", "delta", "psi", "speed"];

/// The ride, until the roll angle reaches ±60° or the steer ±90° (or 30 s pass).
pub fn ride(bike: &WhippleBicycle) -> Result<Trajectory, Error> {
    let x0 = bike
        .state_builder()
        .set("phi", LEAN)
        .set("rear_wheel_rate", -SPEED / bike.r_r)
        .build()?;
    let column = |name: &str| WhippleBicycle::STATE.iter().position(|n| *n == name);
    let (Some(phi), Some(steer), Some(rate)) =
        (column("phi"), column("delta"), column("rear_wheel_rate"))
    else {
        return Err(Error::Io {
            path: "the bicycle".into(),
            message: "the model has no phi, delta or rear_wheel_rate".into(),
        });
    };
    let r = bike.r_r;
    Simulation::new(bike, x0)
        .end_time(30.0)
        .sample_interval(1.0 / 60.0)
        .project_holonomic(true)
        .output("speed", move |_t, x| -r * x[rate])
        .event(Event::on(bike, "fallen", move |_t, x| x[phi].abs() - FALLEN).terminal())
        .event(Event::on(bike, "across", move |_t, x| x[steer].abs() - ACROSS).terminal())
        .run_constant(&DormandPrince::new(1e-9, 1e-12), [0.0, 0.0])
}
