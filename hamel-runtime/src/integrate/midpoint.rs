//! The implicit midpoint rule, x₁ = x₀ + h f(t₀ + h/2, (x₀ + x₁)/2): the simplest symmetric
//! method (Gauss–Legendre with one stage, order 2), with fixed steps.

use super::gauss::GaussLegendre;
use super::observer::{Observer, SampleTimes};
use super::{Integrator, MAX_STEPS, Ode, Stats};
use crate::error::Error;

/// The implicit midpoint rule with a fixed step of at most `step`: order 2, one stage, the
/// cheapest symmetric method — [`GaussLegendre`] with one stage, which documents the
/// stepping, the dense output (here the straight line between a step's ends), the Newton
/// iteration and the errors.
///
/// ```
/// use hamel_runtime::{ImplicitMidpoint, Integrator, Ode, Error};
///
/// /// ẋ = −x (a decay): the midpoint rule gives x₁ = x₀ (1 − h/2)/(1 + h/2) per step.
/// struct Decay;
/// impl Ode for Decay {
///     type State = [f64; 1];
///     fn rhs(&mut self, _t: f64, x: &[f64; 1], dx: &mut [f64; 1]) -> Result<(), Error> {
///         dx[0] = -x[0];
///         Ok(())
///     }
/// }
///
/// let mut end = 0.0;
/// ImplicitMidpoint::new(0.1).integrate(&mut Decay, 0.0, &[1.0], &[1.0], &mut |_, x| {
///     end = x[0];
///     Ok(())
/// })?;
/// assert!((end - (0.95f64 / 1.05).powi(10)).abs() < 1e-15);
/// # Ok::<(), hamel_runtime::Error>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImplicitMidpoint {
    pub step: f64,
    /// The most steps an integration may take; more is refused before the first step.
    /// Default [`super::MAX_STEPS`].
    pub max_steps: usize,
    /// As [`GaussLegendre::refresh_rate`].
    pub refresh_rate: f64,
}

impl ImplicitMidpoint {
    pub fn new(step: f64) -> Self {
        ImplicitMidpoint {
            step,
            max_steps: MAX_STEPS,
            refresh_rate: GaussLegendre::REFRESH_RATE,
        }
    }

    /// Limits an integration to `n` steps.
    pub fn with_max_steps(mut self, n: usize) -> Self {
        self.max_steps = n;
        self
    }

    /// `n` steps of size `h` (negative to step backwards), as [`GaussLegendre::advance`].
    pub fn advance<O: Ode>(
        &self,
        ode: &mut O,
        t0: f64,
        x0: &O::State,
        h: f64,
        n: usize,
    ) -> Result<(O::State, Stats), Error> {
        GaussLegendre::from(self).advance(ode, t0, x0, h, n)
    }
}

impl Integrator for ImplicitMidpoint {
    /// Gauss–Legendre methods are symmetric.
    fn symmetric(&self) -> bool {
        true
    }

    fn integrate_observed<O: Ode, T: SampleTimes + ?Sized>(
        &self,
        ode: &mut O,
        t0: f64,
        x0: &O::State,
        samples: &T,
        observer: &mut dyn Observer<O::State>,
    ) -> Result<Stats, Error> {
        GaussLegendre::from(self).integrate_observed(ode, t0, x0, samples, observer)
    }
}
