//! The first step of an adaptive method, from the problem rather than a constant: Hairer's
//! HINIT (Hairer, Nørsett & Wanner, *Solving ODEs I*, II.4), as DOPRI5 and scipy's
//! `select_initial_step` choose it. A step whose explicit-Euler increment is 1 % of the
//! solution's scale, refined by a difference estimate of the second derivative so that the
//! local error of the first step, of order `order`, is near the tolerance. One evaluation.
//! Like the error norms it looks only at the components the step-size control covers.

use super::{Ode, Stats, combine};
use crate::error::Error;
use crate::vector::Vector;

/// The tolerances and the step limit the first step is chosen for.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Target {
    pub rtol: f64,
    pub atol: f64,
    /// The order of the local error estimate: the step scales as its (order + 1)-th root.
    pub order: f64,
    pub hmax: f64,
}

/// The first step from (t, y) with slope `f0`.
pub(crate) fn initial_step<O: Ode>(
    ode: &mut O,
    (t, y, f0): (f64, &O::State, &O::State),
    target: Target,
    stats: &mut Stats,
) -> Result<f64, Error> {
    let scale = |i: usize| target.atol + target.rtol * y.as_ref()[i].abs();
    let n = ode.controlled_components().min(O::State::LEN);
    let dnf: f64 = (0..n).map(|i| (f0.as_ref()[i] / scale(i)).powi(2)).sum();
    let dny: f64 = (0..n).map(|i| (y.as_ref()[i] / scale(i)).powi(2)).sum();
    let mut h = if dnf <= 1e-10 || dny <= 1e-10 {
        1e-6
    } else {
        (dny / dnf).sqrt() * 0.01
    };
    // A non-finite derivative makes h NaN; start small and let step rejection deal with it.
    if !(h > 0.0 && h.is_finite()) {
        h = 1e-6;
    }
    h = h.min(target.hmax);

    let mut f1 = O::State::zeros();
    ode.rhs(t + h, &combine(y, h, &[(1.0, f0)]), &mut f1)?;
    stats.evaluations += 1;
    let der2 = (0..n)
        .map(|i| ((f1.as_ref()[i] - f0.as_ref()[i]) / scale(i)).powi(2))
        .sum::<f64>()
        .sqrt()
        / h;
    let der12 = der2.abs().max(dnf.sqrt());
    let h1 = if der12 <= 1e-15 {
        (h * 1e-3).max(1e-6)
    } else {
        (0.01 / der12).powf(1.0 / (target.order + 1.0))
    };
    // f64::min ignores a NaN h1, leaving a finite step.
    Ok((100.0 * h).min(h1).min(target.hmax))
}
