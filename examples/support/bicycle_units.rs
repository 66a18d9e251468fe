//! The units of the bicycle examples' figures, as far as `hamel::models::WhippleBicycle`
//! states them: its quantities' and parameters' (the trail `c` in m, the rear frame's mass
//! `m_b` in kg), the forward speed `v` in the wheels' length unit per the time unit, and the
//! eigenvalues `λ` per the time unit. A unit the model does not state stays off the labels.

use hamel::HamelSystem;
use hamel::Parameters;
use hamel::models::WhippleBicycle;
use hamel::plot::Units;

/// The units of the bicycle's quantities and parameters, with `v` and `λ`.
pub fn units() -> Units {
    let mut units = Units::of::<WhippleBicycle>();
    let (length, time) = (
        WhippleBicycle::parameter_unit("r_r"),
        WhippleBicycle::unit("t"),
    );
    if let (Some(length), Some(time)) = (length, time) {
        units = units.with("v", &format!("{length}/{time}"));
    }
    if let Some(time) = time {
        units = units.with("λ", &format!("1/{time}"));
    }
    units
}
