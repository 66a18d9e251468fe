//! The checks of an adaptive method's settings, one set for every method: the same setting
//! is accepted or refused, with the same words, whichever method it is given to.

use crate::error::Error;

/// The largest absolute tolerance accepted: an error of 10¹⁰⁰ in any component of a
/// physical state is no control at all (at 10³⁰⁰ Radau5 crossed its span in one step and
/// returned that step's value).
pub(crate) const ATOL_CEILING: f64 = 1e100;

/// An adaptive method's tolerances and step limits, as the user set them.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Adaptive {
    pub rtol: f64,
    pub atol: f64,
    pub initial_step: Option<f64>,
    pub max_step: f64,
    pub max_steps: usize,
    pub min_step: f64,
}

/// The smallest relative tolerance a method accepts, and why.
#[derive(Clone, Copy, Debug)]
pub(crate) struct RtolFloor {
    /// rtol must be ≥ this (`inclusive`) or above it.
    pub value: f64,
    pub inclusive: bool,
    pub reason: &'static str,
}

fn invalid(name: &'static str, value: f64, reason: &'static str) -> Result<(), Error> {
    Err(Error::InvalidSetting {
        name,
        value,
        reason,
    })
}

/// Refuses a setting no integration can honour: a tolerance that is not a number, a relative
/// tolerance of 1 or more (it controls nothing: every step would pass), a step limit that is
/// 0, a floor on the step that is not below the span or |t| it is relative to.
pub(crate) fn check(s: &Adaptive, floor: RtolFloor) -> Result<(), Error> {
    let positive = |v: f64| v.is_finite() && v > 0.0;
    let above_floor = if floor.inclusive {
        s.rtol >= floor.value
    } else {
        s.rtol > floor.value
    };
    if !(s.rtol.is_finite() && above_floor) {
        return invalid("rtol", s.rtol, floor.reason);
    }
    if s.rtol >= 1.0 {
        return invalid(
            "rtol",
            s.rtol,
            "a relative tolerance of 1 or more controls nothing (every step passes); use one \
             below 1, such as 1e-6",
        );
    }
    // A positive atol keeps every scale positive, so an error norm is never 0/0.
    if !positive(s.atol) {
        return invalid(
            "atol",
            s.atol,
            "the absolute tolerance must be a positive finite number",
        );
    }
    if s.atol > ATOL_CEILING {
        return invalid(
            "atol",
            s.atol,
            "an absolute tolerance above 1e100 controls nothing (every step of any state \
             passes, and the run returns whatever one step gives); use one of the size of the \
             smallest change that matters, such as 1e-9",
        );
    }
    if let Some(h) = s.initial_step.filter(|h| !positive(*h)) {
        return invalid(
            "initial step",
            h,
            "the initial step must be a positive finite number",
        );
    }
    if s.max_step.is_nan() || s.max_step <= 0.0 {
        return invalid(
            "max step",
            s.max_step,
            "the largest step must be positive (infinite for no limit)",
        );
    }
    if s.max_steps == 0 {
        return invalid("max steps", 0.0, "the integration needs at least one step");
    }
    if !(s.min_step.is_finite() && (0.0..1.0).contains(&s.min_step)) {
        return invalid(
            "min step",
            s.min_step,
            "the relative floor on the step must be in [0, 1)",
        );
    }
    Ok(())
}

/// Refuses steps that cannot be taken from the start, for a method whose smallest step is
/// `min_step` of |t| (at least 16 ulps of t) where it is taken: a first step below that floor
/// at t0 (it would be a step-size underflow before any step), and a largest step below it
/// somewhere in the span (every step there would be).
pub(crate) fn check_relative_floor(s: &Adaptive, t0: f64, t_end: f64) -> Result<(), Error> {
    let floor = |t: f64| (s.min_step * t.abs()).max(16.0 * f64::EPSILON * t.abs());
    check_floor(s, floor(t0), floor(t0).max(floor(t_end)))
}

/// [`check_relative_floor`] for a method whose smallest step is `min_step` of the span.
pub(crate) fn check_span_floor(s: &Adaptive, t0: f64, t_end: f64) -> Result<(), Error> {
    let floor = |t: f64| (s.min_step * (t_end - t0)).max(16.0 * f64::EPSILON * t.abs());
    check_floor(s, floor(t0), floor(t0).max(floor(t_end)))
}

/// The checks of [`check_relative_floor`] with the floor at the start and the largest floor
/// in the span.
fn check_floor(s: &Adaptive, at_start: f64, largest: f64) -> Result<(), Error> {
    if let Some(h) = s.initial_step.filter(|h| *h < at_start.max(1e-300)) {
        return invalid(
            "initial step",
            h,
            "the initial step is below the smallest step the integration may take at the \
             start time (`min_step` of |t| or of the span, and 16 ulps of t): no step could \
             be taken; give a larger one, or none to have it estimated",
        );
    }
    if s.max_step < largest {
        return invalid(
            "max step",
            s.max_step,
            "the largest step is below the smallest step the integration may take in the span \
             (`min_step` of |t| or of the span, and 16 ulps of t): no step could be taken \
             there; raise the largest step or lower `min_step`",
        );
    }
    Ok(())
}
