//! The driver of the fixed-step methods ([`super::Rk4`], [`super::GaussLegendre`]): they step
//! exactly onto every sample time, an interval of length Δ between samples cut into
//! ⌈Δ/step⌉ equal sub-steps, so samples never need interpolation and have the method's full
//! order. What differs between the methods is one step and the continuous extension shown to
//! an observer that watches steps; the rest — checks, step budget, sample loop, projection —
//! is here once.

use super::observer::{Control, Observer, SampleTimes};
use super::{
    Ode, Stats, check_problem, check_state, equal_steps, too_many_steps, too_many_steps_planned,
};
use crate::error::Error;

/// A fixed-step method as the driver sees it.
pub(super) trait FixedStep<O: Ode> {
    /// One step from `start` = (t, x) by `step` = (h, t1): the state at t1, before it is
    /// checked and projected. h is the interval's equal step; t1 is t + h up to rounding,
    /// and exactly the sample time on an interval's last step. Counts its evaluations in
    /// `stats` (the driver counts the step).
    fn step(
        &mut self,
        ode: &mut O,
        start: (f64, &O::State),
        step: (f64, f64),
        stats: &mut Stats,
    ) -> Result<O::State, Error>;

    /// Shows the step just taken, from `start` = (t, x) to `end` = (t1, x1) (checked and
    /// projected), to an observer that watches steps. When the observer stops the run within
    /// it, reports the state there as the last sample ([`super::sampling::final_sample`]) and
    /// returns the time.
    fn watch(
        &mut self,
        ode: &mut O,
        observer: &mut dyn Observer<O::State>,
        start: (f64, &O::State),
        end: (f64, &O::State),
        stats: &mut Stats,
    ) -> Result<Option<f64>, Error>;
}

/// The step of a fixed-step integration and the most steps it may take.
pub(super) struct Budget {
    pub step: f64,
    pub max_steps: usize,
    /// Why a step that is not a positive finite number is refused, in the method's words.
    pub invalid_step: &'static str,
}

/// Integrates from (t0, x0) through every sample time with `method`'s steps.
pub(super) fn integrate<O: Ode, T: SampleTimes + ?Sized, M: FixedStep<O>>(
    method: &mut M,
    budget: &Budget,
    ode: &mut O,
    (t0, x0): (f64, &O::State),
    samples: &T,
    observer: &mut dyn Observer<O::State>,
) -> Result<Stats, Error> {
    let step = budget.step;
    if !(step.is_finite() && step > 0.0) {
        return Err(Error::InvalidSetting {
            name: "step",
            value: step,
            reason: budget.invalid_step,
        });
    }
    check_problem(ode, t0, x0, samples)?;
    // Each sample interval adds at most one step to span/step.
    let span = samples.last() - t0;
    if samples.count() > 0 && span / step > budget.max_steps as f64 {
        return Err(too_many_steps_planned(ode, t0, step, x0, span / step));
    }
    let mut run = Run {
        watch: observer.watches_steps(),
        method,
        ode,
        observer,
        stats: Stats::default(),
        max_steps: budget.max_steps,
    };
    let (mut t, mut x) = (t0, *x0);
    for i in 0..samples.count() {
        let sample = samples.time(i);
        if sample > t {
            match run.interval((t, x), sample, step)? {
                Some(end) => x = end,
                None => break,
            }
            t = sample;
        }
        if let Control::Stop(_) = run.observer.sample(sample, &x)? {
            run.stats.stopped = Some(sample);
            break;
        }
    }
    Ok(run.stats)
}

/// One fixed-step integration: the method, the ODE, the observer and the cost.
struct Run<'a, O: Ode, M> {
    method: &'a mut M,
    ode: &'a mut O,
    observer: &'a mut dyn Observer<O::State>,
    stats: Stats,
    max_steps: usize,
    watch: bool,
}

impl<O: Ode, M: FixedStep<O>> Run<'_, O, M> {
    /// The equal sub-steps from (t, x) to the sample time `to`; the state there, or `None`
    /// when the observer stopped the integration (its last sample reported).
    fn interval(
        &mut self,
        (t, x): (f64, O::State),
        to: f64,
        step: f64,
    ) -> Result<Option<O::State>, Error> {
        let (n, h) = equal_steps(to - t, step);
        let mut x = x;
        for i in 0..n {
            if self.stats.steps >= self.max_steps {
                return Err(too_many_steps(&*self.ode, t, h, &x, self.stats.steps));
            }
            // Times are computed from the interval's start, not accumulated, and the last
            // sub-step ends exactly on the sample.
            let start = t + i as f64 * h;
            let end = if i + 1 < n {
                t + (i + 1) as f64 * h
            } else {
                to
            };
            let mut next = self
                .method
                .step(self.ode, (start, &x), (h, end), &mut self.stats)?;
            self.stats.steps += 1;
            check_state(&*self.ode, end, &next)?;
            self.ode.project(end, &mut next)?;
            if self.watch {
                let watched = self.method.watch(
                    self.ode,
                    &mut *self.observer,
                    (start, &x),
                    (end, &next),
                    &mut self.stats,
                )?;
                if let Some(ts) = watched {
                    self.stats.stopped = Some(ts);
                    return Ok(None);
                }
            }
            x = next;
        }
        Ok(Some(x))
    }
}
