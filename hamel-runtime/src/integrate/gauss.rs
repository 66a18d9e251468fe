//! Gauss–Legendre collocation with fixed steps: the symmetric implicit Runge–Kutta methods of
//! order 2s (s = 1, the implicit midpoint rule; 2, order 4; 3, order 6), their stages solved
//! by simplified Newton on the ODE's Jacobian ([`super::newton`]).
//!
//! Why symmetric: a symmetric method applied to a system that is reversible under a linear
//! map ρ (for a mechanical system without forces, with a kinetic energy quadratic in the
//! velocities and homogeneous, time-independent constraints: ρ(q, ω) = (q, −ω)) is itself
//! ρ-reversible, and for such integrable-like problems reversibility — not symplecticity, which
//! a nonholonomic flow does not have — keeps the energy error bounded over long times instead
//! of drifting (McLachlan & Perlmutter, *J. Nonlinear Sci.* 16 (2006); Modin & Verdier,
//! *Numer. Math.* 144 (2020); Hairer, Lubich & Wanner, *Geometric Numerical Integration*,
//! XI). [`crate::HamelSystem::REVERSIBLE`] says whether a model is reversible in this sense.

use super::collocation::{Collocation, Tableau, extrapolate};
use super::fixed_step::{self, Budget, FixedStep};
use super::midpoint::ImplicitMidpoint;
use super::newton::{Criterion, Newton, Outcome};
use super::observer::{Control, Interpolant, Observer, SampleTimes, StepView};
use super::sampling::final_sample;
use super::{Integrator, MAX_STEPS, Ode, Stats, Watched, check_problem, check_state};
use crate::error::Error;
use crate::vector::Vector;

/// Gauss–Legendre collocation with `stages` = 1, 2 or 3 stages (order 2, 4 or 6) and a fixed
/// step of at most `step`: symmetric, A-stable, and for a reversible system reversible, so
/// that over long runs its energy error stays bounded where an explicit method's drifts.
///
/// Like [`super::Rk4`] it steps exactly onto every sample time (an interval between samples is
/// cut into equal sub-steps no longer than `step`), so samples have the method's full order;
/// sample at a multiple of the step to keep every step the same. Between steps (events) the
/// solution is the step's collocation polynomial, of degree s (error O(hˢ⁺¹)).
///
/// Each step solves its stage equations to rounding by simplified Newton on the Jacobian
/// ([`Ode::jacobian`]: for a simulation, the system's exact one), which it keeps over many
/// steps and evaluates afresh only when the iteration contracts by less than the factor
/// [`GaussLegendre::refresh_rate`] per iteration. A step whose iteration does not converge
/// even with a fresh Jacobian is an [`Error::NewtonNotConverged`], a singular iteration
/// matrix an [`Error::SingularIterationMatrix`], both naming t, h and the state.
///
/// ```
/// use hamel_runtime::{GaussLegendre, Integrator, Ode, Error};
///
/// /// The harmonic oscillator: its energy ½(x² + v²) is a quadratic invariant, which Gauss
/// /// methods conserve exactly (to rounding).
/// struct Oscillator;
/// impl Ode for Oscillator {
///     type State = [f64; 2];
///     fn rhs(&mut self, _t: f64, x: &[f64; 2], dx: &mut [f64; 2]) -> Result<(), Error> {
///         *dx = [x[1], -x[0]];
///         Ok(())
///     }
/// }
///
/// let mut end = [0.0; 2];
/// GaussLegendre::new(2, 0.5).integrate(&mut Oscillator, 0.0, &[1.0, 0.0], &[1000.0], &mut |_, x| {
///     end = *x;
///     Ok(())
/// })?;
/// assert!((0.5 * (end[0] * end[0] + end[1] * end[1]) - 0.5).abs() < 1e-12);
/// # Ok::<(), hamel_runtime::Error>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GaussLegendre {
    /// 1 (the implicit midpoint rule, order 2), 2 (order 4) or 3 (order 6).
    pub stages: usize,
    pub step: f64,
    /// The most steps an integration may take; more is refused before the first step.
    /// Default [`super::MAX_STEPS`].
    pub max_steps: usize,
    /// The contraction factor per Newton iteration above which the next step evaluates the
    /// Jacobian afresh; below it the old one is kept (default [`Self::REFRESH_RATE`]).
    pub refresh_rate: f64,
}

impl GaussLegendre {
    /// The method with `stages` stages (order 2·`stages`) and steps of at most `step`.
    pub fn new(stages: usize, step: f64) -> Self {
        GaussLegendre {
            stages,
            step,
            max_steps: MAX_STEPS,
            refresh_rate: Self::REFRESH_RATE,
        }
    }

    /// Limits an integration to `n` steps.
    pub fn with_max_steps(mut self, n: usize) -> Self {
        self.max_steps = n;
        self
    }

    /// Evaluates the Jacobian afresh when the Newton iteration contracts by less than `rate`
    /// per iteration (0: at every step).
    pub fn with_refresh_rate(mut self, rate: f64) -> Self {
        self.refresh_rate = rate;
        self
    }

    /// The default of [`GaussLegendre::refresh_rate`]. A Jacobian costs about one
    /// right-hand side per state component, an iteration one per stage; from the
    /// extrapolated start an iteration contracting by 0.05 needs twice as many iterations to
    /// reach rounding as one contracting by 0.001.
    pub const REFRESH_RATE: f64 = 0.05;

    /// `n` steps of size `h` from (t0, x0) — `h` may be negative, to step backwards — with
    /// neither samples nor projection: the method's one-step map applied `n` times. What a
    /// symmetric method is about: `advance(h, n)` then `advance(−h, n)` from where it ended
    /// comes back to x0 up to rounding.
    pub fn advance<O: Ode>(
        &self,
        ode: &mut O,
        t0: f64,
        x0: &O::State,
        h: f64,
        n: usize,
    ) -> Result<(O::State, Stats), Error> {
        check_settings(self)?;
        if !(h.is_finite() && h != 0.0) {
            return Err(Error::InvalidSetting {
                name: "step",
                value: h,
                reason: "the step must be a finite number other than 0",
            });
        }
        check_problem(ode, t0, x0, &[] as &[f64])?;
        let rate = self.refresh_rate;
        match self.stages {
            1 => advance(&Tableau::gauss1(), rate, ode, (t0, x0), h, n),
            2 => advance(&Tableau::gauss2(), rate, ode, (t0, x0), h, n),
            _ => advance(&Tableau::gauss3(), rate, ode, (t0, x0), h, n),
        }
    }
}

impl From<&ImplicitMidpoint> for GaussLegendre {
    fn from(m: &ImplicitMidpoint) -> Self {
        GaussLegendre {
            stages: 1,
            step: m.step,
            max_steps: m.max_steps,
            refresh_rate: m.refresh_rate,
        }
    }
}

/// The checks of the settings every entry point makes (the step is checked where its sign
/// matters).
fn check_settings(method: &GaussLegendre) -> Result<(), Error> {
    if !(1..=3).contains(&method.stages) {
        return Err(Error::InvalidSetting {
            name: "stages",
            value: method.stages as f64,
            reason: "Gauss–Legendre methods are offered with 1, 2 or 3 stages (orders 2, 4, 6)",
        });
    }
    if !(method.refresh_rate.is_finite() && method.refresh_rate >= 0.0) {
        return Err(Error::InvalidSetting {
            name: "refresh rate",
            value: method.refresh_rate,
            reason: "the contraction factor that refreshes the Jacobian must be a finite number ≥ 0",
        });
    }
    Ok(())
}

impl Integrator for GaussLegendre {
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
        check_settings(self)?;
        match self.stages {
            1 => integrate_fixed(&Tableau::gauss1(), self, ode, (t0, x0), samples, observer),
            2 => integrate_fixed(&Tableau::gauss2(), self, ode, (t0, x0), samples, observer),
            _ => integrate_fixed(&Tableau::gauss3(), self, ode, (t0, x0), samples, observer),
        }
    }
}

/// The steps of a fixed-step collocation integration: the Newton machinery, and the last
/// step's polynomial for the next one's starting values.
struct Stepper<'t, V, const S: usize> {
    tableau: &'t Tableau<S>,
    newton: Newton,
    last: Option<Collocation<'t, V, S>>,
    /// Evaluate the Jacobian at the next step's start.
    refresh: bool,
    /// [`GaussLegendre::refresh_rate`].
    refresh_rate: f64,
}

/// The largest relative change of the step for which a factorization is kept: equal steps of
/// different sample intervals differ in their last bits, and a change of 1 % adds at most
/// about 0.01 to the contraction of an iteration that converges to rounding anyway.
const LU_REUSE: f64 = 0.01;

impl<'t, V: Vector, const S: usize> Stepper<'t, V, S> {
    /// The steps for an ODE whose leading `controlled` components the convergence test
    /// measures ([`Ode::controlled_components`]).
    fn new(tableau: &'t Tableau<S>, refresh_rate: f64, controlled: usize) -> Self {
        Stepper {
            tableau,
            newton: Newton::new(V::LEN, controlled, S).with_reuse(LU_REUSE),
            last: None,
            refresh: true,
            refresh_rate,
        }
    }

    /// One step of size h from (t, y): its collocation polynomial (whose end is the result).
    fn collocate<O: Ode<State = V>>(
        &mut self,
        ode: &mut O,
        (t, y): (f64, &V),
        h: f64,
        stats: &mut Stats,
    ) -> Result<&Collocation<'t, V, S>, Error> {
        // Watched, so that an iteration that fails on a value that is not finite names it.
        let ode = &mut Watched::new(ode);
        if self.refresh || !self.newton.has_jacobian() {
            self.newton.evaluate(ode, t, y, stats)?;
            self.refresh = false;
        }
        self.newton.factor(ode, self.tableau, (t, y, h), stats)?;
        let start = match &self.last {
            // Continuing from the last step's end (projected or not).
            Some(last) if last.t + last.h == t => extrapolate(last, y, h),
            _ => [V::zeros(); S],
        };
        // Increments relative to each component's size, absolute below 1.
        let mut scale = V::zeros();
        for (s, v) in scale.as_mut().iter_mut().zip(y.as_ref()) {
            *s = v.abs().max(1.0);
        }
        let mut z = start;
        let mut outcome = self.newton.iterate(
            ode,
            self.tableau,
            (t, y, h),
            &mut z,
            Criterion::Rounding,
            scale.as_ref(),
            stats,
        )?;
        if matches!(outcome, Outcome::Failed { .. }) && !self.newton.jacobian.fresh {
            // An old Jacobian may be to blame: once more with a fresh one.
            self.newton.evaluate(ode, t, y, stats)?;
            self.newton.factor(ode, self.tableau, (t, y, h), stats)?;
            z = start;
            outcome = self.newton.iterate(
                ode,
                self.tableau,
                (t, y, h),
                &mut z,
                Criterion::Rounding,
                scale.as_ref(),
                stats,
            )?;
        }
        match outcome {
            Outcome::Converged { rate, .. } => self.refresh = rate > self.refresh_rate,
            Outcome::Failed {
                iterations,
                rate,
                increment,
                ..
            } => {
                return Err(ode.explain(Error::NewtonNotConverged {
                    t,
                    h,
                    iterations,
                    increment,
                    rate,
                    state: ode.describe(y),
                }));
            }
        }
        self.newton.jacobian.fresh = false;
        Ok(self.last.insert(Collocation {
            tableau: self.tableau,
            t,
            h,
            y0: *y,
            z,
        }))
    }
}

/// `n` steps of size h from (t0, x0), nothing observed or projected.
fn advance<O: Ode, const S: usize>(
    tableau: &Tableau<S>,
    refresh_rate: f64,
    ode: &mut O,
    (t0, x0): (f64, &O::State),
    h: f64,
    n: usize,
) -> Result<(O::State, Stats), Error> {
    let mut stepper = Stepper::new(tableau, refresh_rate, ode.controlled_components());
    let mut stats = Stats::default();
    let mut x = *x0;
    for i in 0..n {
        let t = t0 + i as f64 * h;
        let step = stepper.collocate(ode, (t, &x), h, &mut stats)?;
        x = tableau.end(&step.y0, &step.z);
        stats.steps += 1;
        check_state(ode, t + h, &x)?;
    }
    Ok((x, stats))
}

/// A fixed-step integration with the collocation method `tableau` and the settings of
/// `method` (its stages are `tableau`'s).
fn integrate_fixed<O: Ode, T: SampleTimes + ?Sized, const S: usize>(
    tableau: &Tableau<S>,
    method: &GaussLegendre,
    ode: &mut O,
    (t0, x0): (f64, &O::State),
    samples: &T,
    observer: &mut dyn Observer<O::State>,
) -> Result<Stats, Error> {
    let budget = Budget {
        step: method.step,
        max_steps: method.max_steps,
        invalid_step: "the step of an implicit fixed-step method must be a positive finite number",
    };
    let mut stepper = Stepper::new(tableau, method.refresh_rate, ode.controlled_components());
    fixed_step::integrate(&mut stepper, &budget, ode, (t0, x0), samples, observer)
}

impl<'t, O: Ode, const S: usize> FixedStep<O> for Stepper<'t, O::State, S> {
    fn step(
        &mut self,
        ode: &mut O,
        (t, x): (f64, &O::State),
        (_, t1): (f64, f64),
        stats: &mut Stats,
    ) -> Result<O::State, Error> {
        let collocation = self.collocate(ode, (t, x), t1 - t, stats)?;
        Ok(collocation.tableau.end(&collocation.y0, &collocation.z))
    }

    /// Shows the step with its collocation polynomial.
    fn watch(
        &mut self,
        ode: &mut O,
        observer: &mut dyn Observer<O::State>,
        (t, x): (f64, &O::State),
        (t1, x1): (f64, &O::State),
        _: &mut Stats,
    ) -> Result<Option<f64>, Error> {
        let Some(collocation) = &self.last else {
            // `step` keeps every step's polynomial: there is one after a step.
            return Ok(None);
        };
        let view = StepView {
            t,
            x,
            t1,
            x1,
            dense: collocation,
        };
        match observer.step(&view)? {
            Control::Continue => Ok(None),
            Control::Stop(ts) => {
                let ts = ts.clamp(t, t1);
                final_sample(ode, observer, ts, (t1, x1), |s| collocation.at(s))?;
                Ok(Some(ts))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ẋ = 1: every method is exact, so only the stepping logic is tested.
    struct Clock;

    impl Ode for Clock {
        type State = [f64; 1];

        fn rhs(&mut self, _t: f64, _x: &[f64; 1], dx: &mut [f64; 1]) -> Result<(), Error> {
            dx[0] = 1.0;
            Ok(())
        }
    }

    #[test]
    fn steps_land_on_every_sample() {
        for stages in 1..=3 {
            let mut seen = Vec::new();
            let stats = GaussLegendre::new(stages, 0.1)
                .integrate(
                    &mut Clock,
                    0.0,
                    &[0.0],
                    &[0.0, 0.7, 1.1, 1.15],
                    &mut |t, x| {
                        seen.push((t, x[0]));
                        Ok(())
                    },
                )
                .unwrap();
            // 7 + 4 + 1 steps; one Jacobian (by differences: 2 evaluations), never refreshed
            // (the iteration is exact at once), one factorization per step size.
            assert_eq!(stats.steps, 12);
            assert_eq!(stats.jacobians, 1);
            for (t, x) in seen {
                assert!((x - t).abs() < 1e-14, "{stages} stages: x({t}) = {x}");
            }
        }
    }

    #[test]
    fn stages_other_than_one_to_three_are_refused() {
        for stages in [0, 4] {
            match GaussLegendre::new(stages, 0.1).integrate(
                &mut Clock,
                0.0,
                &[0.0],
                &[1.0],
                &mut |_, _| Ok(()),
            ) {
                Err(Error::InvalidSetting {
                    name: "stages",
                    value,
                    ..
                }) => assert_eq!(value, stages as f64),
                other => panic!("{other:?}"),
            }
        }
    }
}
