//! Integrators for the reduced ODE: the [`Ode`] they integrate, the [`Integrator`] interface
//! and the checks and vector arithmetic every method shares.
//!
//! An integrator reports the solution at the sample times the caller asks for, and, when the
//! observer watches steps, every accepted step with its dense output, through an observer
//! ([`observer`]). That keeps the solution on the stack (no per-step allocation), lets the
//! caller monitor energy and constraints at exactly the times it records, and locate events
//! between steps.
//!
//! Every integration is bounded: a limit on the number of steps, and for the adaptive method
//! a floor on the step size; reaching either is an error that names the time, the step and
//! the state, never a run that does not end.

mod collocation;
#[doc(hidden)]
pub mod dense;
mod differences;
mod dopri5;
mod fixed_step;
mod gauss;
mod initial_step;
mod midpoint;
mod newton;
pub mod observer;
mod radau;
mod radau_stages;
mod rk4;
mod rodas;
mod rosenbrock_tableau;
mod sampling;
mod settings;
mod singular;

pub use dopri5::DormandPrince;
pub use gauss::GaussLegendre;
pub use midpoint::ImplicitMidpoint;
pub use newton::NEWTON_MAX_ITERATIONS;
pub use observer::{Control, Grid, Interpolant, Observer, SampleTimes, StepView};
pub use radau::Radau5;
pub use rk4::Rk4;
pub use rodas::{Rodas4, Rodas5P};

use crate::error::Error;
use crate::named::NamedValues;
use crate::vector::Vector;

/// A first-order ODE ẋ = f(t, x) with a fixed-size state.
pub trait Ode {
    type State: Vector;

    /// Writes f(t, x) into `dx`. An error stops the integration and is returned unchanged.
    fn rhs(&mut self, t: f64, x: &Self::State, dx: &mut Self::State) -> Result<(), Error>;

    /// How many leading components of the state an adaptive method's error estimate covers
    /// (default: all). The others are integrated along but never shorten a step: quantities
    /// monitored alongside the solution, such as the work done on a mechanical system, leave
    /// the steps exactly those of the solution alone.
    fn controlled_components(&self) -> usize {
        Self::State::LEN
    }

    /// Moves a state computed by the integrator back onto a manifold the exact solution
    /// stays on (for a mechanical system: re-solves the holonomic constraints), and says
    /// whether it changed anything. Integrators call it with the end time and result of
    /// every accepted step, before continuing from it, and with every sample they
    /// interpolate; the initial state is the caller's. An error stops the integration and is
    /// returned unchanged. The default changes nothing.
    fn project(&mut self, _t: f64, _x: &mut Self::State) -> Result<bool, Error> {
        Ok(false)
    }

    /// Writes the Jacobian ∂f/∂x at (t, x) into `jacobian`, row by row (`LEN × LEN` entries:
    /// entry `i·LEN + j` is ∂fᵢ/∂xⱼ), and returns `Ok(true)`. The implicit and Rosenbrock
    /// methods solve their stage equations with it. The default writes nothing and returns
    /// `Ok(false)`: they then form it by forward differences of [`Ode::rhs`] (LEN
    /// evaluations, counted, more where a column's difference must be refined), each column's
    /// step chosen from the state's scale, the tolerance and the function's scale as scipy's
    /// `num_jac` chooses it (`integrate::differences`). An error stops the integration and is
    /// returned unchanged.
    fn jacobian(
        &mut self,
        _t: f64,
        _x: &Self::State,
        _jacobian: &mut [f64],
    ) -> Result<bool, Error> {
        Ok(false)
    }

    /// Writes ∂f/∂t at (t, x) into `dfdt` and returns `Ok(true)`: the Rosenbrock methods
    /// ([`Rodas5P`], [`Rodas4`]) need it with the Jacobian at every step. The default writes
    /// nothing and returns `Ok(false)`: they then difference f in t (one evaluation, counted).
    /// An autonomous system (f independent of t) saves that evaluation by writing zeros. An
    /// error stops the integration and is returned unchanged.
    fn time_derivative(
        &mut self,
        _t: f64,
        _x: &Self::State,
        _dfdt: &mut Self::State,
    ) -> Result<bool, Error> {
        Ok(false)
    }

    /// The state with its component names, for error messages. The default names the
    /// components `x0`, `x1`, …; a mechanical system names them after its coordinates.
    fn describe(&self, x: &Self::State) -> NamedValues {
        NamedValues(
            x.as_ref()
                .iter()
                .enumerate()
                .map(|(i, v)| (format!("x{i}"), *v))
                .collect(),
        )
    }
}

/// What an integration cost, and whether it ended before the last sample time.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stats {
    /// Accepted steps.
    pub steps: usize,
    /// Steps computed and thrown away because their error estimate was too large.
    pub rejected: usize,
    /// Right-hand-side evaluations, including those spent choosing the initial step (and
    /// those of Jacobians formed by differences).
    pub evaluations: usize,
    /// Jacobians ∂f/∂x evaluated (implicit methods only).
    pub jacobians: usize,
    /// LU factorizations of an implicit or Rosenbrock method's iteration matrices (implicit
    /// methods only): Radau5's real and complex matrices of a step count as two, as scipy's
    /// `Radau` counts them.
    pub factorizations: usize,
    /// The time the observer stopped the integration at ([`Control::Stop`]), if it did.
    pub stopped: Option<f64>,
}

/// The default limit on the steps of one integration (accepted and rejected): far more than a
/// run over many of its natural time scales takes at any tolerance (hundreds to a few
/// hundred thousand), and seconds to minutes of computing, so that a run that could not end
/// is an error instead.
pub const MAX_STEPS: usize = 10_000_000;

/// Where [`Integrator::integrate`] reports the solution: called with (t, x(t)) at every sample
/// time; an `Err` stops the integration and is returned as is.
pub type SampleObserver<'a, S> = dyn FnMut(f64, &S) -> Result<(), Error> + 'a;

/// A method that integrates an [`Ode`] and reports the solution at given times.
pub trait Integrator {
    /// Integrates from (`t0`, `x0`) to the last sample time and reports exactly one
    /// `observer.sample` for every sample time (ascending, none before `t0`), in order; a
    /// sample equal to `t0` reports `x0`. When the observer watches steps, every accepted
    /// step is reported before its samples, and [`Control::Stop`] ends the integration there
    /// (the samples before the stop, then the stop itself, are reported). An error from the
    /// observer or the right-hand side stops the integration and is returned unchanged. No
    /// samples: nothing is integrated.
    fn integrate_observed<O: Ode, T: SampleTimes + ?Sized>(
        &self,
        ode: &mut O,
        t0: f64,
        x0: &O::State,
        samples: &T,
        observer: &mut dyn Observer<O::State>,
    ) -> Result<Stats, Error>;

    /// Whether the method is symmetric — its step with −h undoes its step with h — as the
    /// Gauss–Legendre methods are: on a [`crate::HamelSystem::REVERSIBLE`] model such a method
    /// keeps the energy error bounded over long runs, on any other it does not, and a
    /// `Simulation`'s summary says so. Default `false`.
    fn symmetric(&self) -> bool {
        false
    }

    /// [`Integrator::integrate_observed`] with a closure that observes the samples only.
    fn integrate<O: Ode, T: SampleTimes + ?Sized>(
        &self,
        ode: &mut O,
        t0: f64,
        x0: &O::State,
        samples: &T,
        observe: &mut SampleObserver<'_, O::State>,
    ) -> Result<Stats, Error> {
        self.integrate_observed(ode, t0, x0, samples, &mut Samples(observe))
    }
}

/// A closure of samples as an [`Observer`].
struct Samples<'o, 'a, V>(&'o mut SampleObserver<'a, V>);

impl<V> Observer<V> for Samples<'_, '_, V> {
    fn sample(&mut self, t: f64, x: &V) -> Result<Control, Error> {
        (self.0)(t, x).map(|()| Control::Continue)
    }
}

/// The error for an integration that would need more than `limit` steps: known before the
/// first step for fixed steps (`needed` of them), reached during it for adaptive ones.
pub(crate) fn too_many_steps<O: Ode>(ode: &O, t: f64, h: f64, x: &O::State, steps: usize) -> Error {
    Error::TooManySteps {
        t,
        steps,
        h,
        planned: false,
        state: ode.describe(x),
    }
}

/// A fixed or largest step that would need `needed` steps for the span, beyond the limit:
/// refused before the first step.
pub(crate) fn too_many_steps_planned<O: Ode>(
    ode: &O,
    t0: f64,
    h: f64,
    x0: &O::State,
    needed: f64,
) -> Error {
    Error::TooManySteps {
        t: t0,
        steps: needed.min(usize::MAX as f64) as usize,
        h,
        planned: true,
        state: ode.describe(x0),
    }
}

/// The checks every integrator makes before its first step: a finite start, a finite initial
/// state (the error names the component), and sample times that are finite, ascending and
/// not before the start.
pub(crate) fn check_problem<O: Ode, T: SampleTimes + ?Sized>(
    ode: &O,
    t0: f64,
    x0: &O::State,
    samples: &T,
) -> Result<(), Error> {
    if !t0.is_finite() {
        return Err(Error::InvalidSetting {
            name: "start time",
            value: t0,
            reason: "it must be a finite number",
        });
    }
    if let Some(i) = x0.as_ref().iter().position(|v| !v.is_finite()) {
        let named = ode.describe(x0);
        let name = named
            .0
            .get(i)
            .map_or_else(|| format!("x{i}"), |(n, _)| n.clone());
        return Err(Error::NonFiniteInitialValue {
            name,
            value: x0.as_ref()[i],
        });
    }
    // A grid is ascending by construction (only its start is checked); given times are
    // checked, each once.
    let checked = if samples.ascending() {
        samples.count().min(1)
    } else {
        samples.count()
    };
    let mut previous = t0;
    for i in 0..checked {
        let s = samples.time(i);
        // Written so that NaN fails too.
        if !(s.is_finite() && s >= previous) {
            return Err(Error::InvalidSetting {
                name: "sample time",
                value: s,
                reason: "sample times must be finite, ascending and not before the start time",
            });
        }
        previous = s;
    }
    Ok(())
}

/// Below this many ulps of t, t + h no longer differs from t by more than a few roundings.
pub(crate) const UNDERFLOW_ULPS: f64 = 16.0;

/// Refuses an adaptive integration whose span is shorter than a step can resolve at its
/// start time (a few ulps of t0): no step could be taken, and that is not a step that shrank.
pub(crate) fn check_span<O: Ode>(ode: &O, t0: f64, t_end: f64, x0: &O::State) -> Result<(), Error> {
    if t_end - t0 < UNDERFLOW_ULPS * f64::EPSILON * t0.abs() {
        return Err(Error::SpanTooShort {
            t0,
            t_end,
            state: ode.describe(x0),
        });
    }
    Ok(())
}

/// A right-hand side value that is not a number (NaN), returned at a finite state: no step
/// size makes it one, so it is named as the cause of a failing run. An infinite value is not
/// one of these: it is what a solution that blows up gives as it overflows (y′ = y² near its
/// pole), and the step-size underflow there says what happened.
#[derive(Clone, Copy, Debug)]
pub(crate) struct NonFinite<V> {
    pub t: f64,
    pub x: V,
    pub rate: V,
}

impl<V: Vector> NonFinite<V> {
    /// The right-hand side's value `rate` at (t, x) if it has a NaN where x is finite.
    pub fn check(t: f64, x: &V, rate: &V) -> Option<Self> {
        (rate.as_ref().iter().any(|v| v.is_nan()) && is_finite(x) && t.is_finite()).then_some(
            NonFinite {
                t,
                x: *x,
                rate: *rate,
            },
        )
    }

    /// The error naming the first component whose rate is NaN.
    pub fn error<O: Ode<State = V>>(&self, ode: &O) -> Error {
        let i = self
            .rate
            .as_ref()
            .iter()
            .position(|v| v.is_nan())
            .unwrap_or(0);
        let state = ode.describe(&self.x);
        let rate = state
            .0
            .get(i)
            .map_or_else(|| format!("x{i}"), |(name, _)| name.clone());
        Error::NonFiniteRate {
            t: self.t,
            rate,
            value: self.rate.as_ref().get(i).copied().unwrap_or(f64::NAN),
            state,
        }
    }
}

/// An [`Ode`] whose right-hand side values are watched: the last that had a NaN at a finite
/// state is kept (`non_finite`), so that an integration that gives up after
/// failed steps can name it as the cause instead of the step size or the iteration. The
/// caller clears it when a step succeeds (a value that a smaller step avoided is no cause).
/// Its price, a finiteness check of each value, matters to no implicit method (each
/// evaluation is followed by linear solves); an explicit one watches only when it fails.
pub(crate) struct Watched<'o, O: Ode> {
    pub ode: &'o mut O,
    pub non_finite: Option<NonFinite<O::State>>,
}

impl<'o, O: Ode> Watched<'o, O> {
    pub fn new(ode: &'o mut O) -> Self {
        Watched {
            ode,
            non_finite: None,
        }
    }

    /// `error`, unless a right-hand side value that was not finite explains it: then the
    /// error naming that value.
    pub fn explain(&self, error: Error) -> Error {
        match &self.non_finite {
            Some(found) => found.error(&*self.ode),
            None => error,
        }
    }
}

impl<O: Ode> Ode for Watched<'_, O> {
    type State = O::State;

    #[inline]
    fn rhs(&mut self, t: f64, x: &O::State, dx: &mut O::State) -> Result<(), Error> {
        self.ode.rhs(t, x, dx)?;
        if let Some(found) = NonFinite::check(t, x, dx) {
            self.non_finite = Some(found);
        }
        Ok(())
    }

    fn controlled_components(&self) -> usize {
        self.ode.controlled_components()
    }

    fn project(&mut self, t: f64, x: &mut O::State) -> Result<bool, Error> {
        self.ode.project(t, x)
    }

    fn jacobian(&mut self, t: f64, x: &O::State, jacobian: &mut [f64]) -> Result<bool, Error> {
        self.ode.jacobian(t, x, jacobian)
    }

    fn time_derivative(
        &mut self,
        t: f64,
        x: &O::State,
        dfdt: &mut O::State,
    ) -> Result<bool, Error> {
        self.ode.time_derivative(t, x, dfdt)
    }

    fn describe(&self, x: &O::State) -> NamedValues {
        self.ode.describe(x)
    }
}

/// The error for a step that produced a non-finite state.
pub(crate) fn check_state<O: Ode>(ode: &O, t: f64, x: &O::State) -> Result<(), Error> {
    if is_finite(x) {
        Ok(())
    } else {
        Err(Error::NonFiniteState {
            t,
            state: ode.describe(x),
        })
    }
}

pub(crate) fn is_finite<V: Vector>(x: &V) -> bool {
    // Every component tested, without a branch each: the compiler tests them in pairs.
    x.as_ref().iter().fold(true, |all, v| all & v.is_finite())
}

/// Relative slack in ⌈span/step⌉: a span computed in floating point can exceed a whole number
/// of steps by an ulp ((1.1 − 0.7)/0.1 = 4.000000000000001), and without the slack such a span
/// would take one needless extra step.
const STEP_COUNT_SLACK: f64 = 1e-9;

/// The number n of equal steps, none longer than `max_step` (up to the slack), that cover
/// `span` > 0, and their length span/n.
pub(crate) fn equal_steps(span: f64, max_step: f64) -> (u64, f64) {
    let n = (span / max_step * (1.0 - STEP_COUNT_SLACK)).ceil().max(1.0);
    // `as` saturates: an absurd count only means an integration that takes long.
    (n as u64, span / n)
}

/// x + h·Σ aⱼ kⱼ: the one vector operation Runge–Kutta methods need. Component-wise with the
/// sum formed before the multiplication by h, as in Hairer's codes. Always inlined: with the
/// terms a literal of known length the sums unroll (called out of line it took a quarter of
/// a whole Dormand–Prince run of the robot).
///
/// The last term is the slope the right-hand side has just written: it is read one
/// component at a time ([`fresh_component`]).
#[inline(always)]
pub(crate) fn combine<V: Vector>(x: &V, h: f64, terms: &[(f64, &V)]) -> V {
    let mut out = *x;
    let Some(((a_last, k_last), older)) = terms.split_last() else {
        return out;
    };
    for (i, o) in out.as_mut().iter_mut().enumerate() {
        let sum = older.iter().map(|(a, k)| a * k.as_ref()[i]).sum::<f64>()
            + a_last * fresh_component(*k_last, i);
        *o += h * sum;
    }
    out
}

/// Component `i` of a vector the right-hand side has only just written, read on its own.
///
/// A right-hand side stores its result one component at a time, or in pairs that need not
/// line up with the pairs the integrator's vectorized arithmetic loads (generated code
/// stores whatever the compiler paired). A load of two components that spans two such
/// stores cannot take its value from the stores still in flight and waits until they reach
/// the cache: a failed store-to-load forwarding, about a dozen cycles. An explicit method
/// reads the slope just computed at once, so that wait lay on the critical path of every
/// stage (on the robot's run, about a tenth of Dormand–Prince's time, `benches/run.rs`).
/// A volatile read is one load of one component, which the compiler may neither widen nor
/// merge with its neighbour's. Its price is paid by a right-hand side so small that it is
/// inlined into the stage: its values could have stayed in registers and now pass through
/// memory, a few cycles a stage (a hand-written oscillator: 3 % slower under Dormand–Prince,
/// 44 % under RK4; every catalogue model is as fast or faster: `benches/workloads.rs`).
#[inline(always)]
pub(crate) fn fresh_component<V: Vector>(v: &V, i: usize) -> f64 {
    let component: &f64 = &v.as_ref()[i];
    // SAFETY: `component` is a reference, so valid, aligned and initialized for a read.
    unsafe { core::ptr::read_volatile(component) }
}

/// A copy of a vector the right-hand side has only just written, read component by
/// component ([`fresh_component`]).
#[inline(always)]
pub(crate) fn fresh<V: Vector>(v: &V) -> V {
    let mut out = V::zeros();
    for (i, o) in out.as_mut().iter_mut().enumerate() {
        *o = fresh_component(v, i);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Decay;

    impl Ode for Decay {
        type State = [f64; 2];

        fn rhs(&mut self, _t: f64, x: &[f64; 2], dx: &mut [f64; 2]) -> Result<(), Error> {
            *dx = [-x[0], -x[1]];
            Ok(())
        }
    }

    #[test]
    fn default_description_numbers_the_components() {
        assert_eq!(Decay.describe(&[1.0, 2.5]).to_string(), "x0 = 1, x1 = 2.5");
    }

    #[test]
    fn problem_checks_name_the_offending_value() {
        let ok = [1.0, 2.0];
        assert_eq!(check_problem(&Decay, 0.0, &ok, &[0.0, 0.0, 1.0]), Ok(()));
        assert!(matches!(
            check_problem(&Decay, f64::INFINITY, &ok, &[] as &[f64]),
            Err(Error::InvalidSetting {
                name: "start time",
                ..
            })
        ));
        match check_problem(&Decay, 0.0, &[1.0, f64::NAN], &[1.0]) {
            Err(Error::NonFiniteInitialValue { name, value }) => {
                assert_eq!(name, "x1");
                assert!(value.is_nan());
            }
            other => panic!("expected a non-finite initial value, got {other:?}"),
        }
        for bad in [[0.5, 0.25], [-1.0, 1.0], [0.5, f64::NAN]] {
            match check_problem(&Decay, 0.0, &ok, &bad) {
                Err(Error::InvalidSetting {
                    name: "sample time",
                    value,
                    ..
                }) => {
                    assert!(value.is_nan() || value == bad[0] || value == bad[1]);
                }
                other => panic!("expected an invalid sample time for {bad:?}, got {other:?}"),
            }
        }
    }

    #[test]
    fn combine_forms_the_stage_sum() {
        let x = [1.0, 2.0];
        let y = combine(&x, 0.5, &[(2.0, &[1.0, 0.0]), (-1.0, &[0.0, 4.0])]);
        assert_eq!(y, [2.0, 0.0]);
    }
}
