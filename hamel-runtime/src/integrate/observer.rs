//! What an integrator reports, and to whom: the sample times it must report the solution at,
//! and an [`Observer`] that receives those samples and, if it asks, every accepted step with
//! the solution in between (for events), and may end the integration early.

use crate::error::Error;

/// The times an integrator reports the solution at: ascending, none before the start. A
/// slice or vector of times, or a [`Grid`] that computes them on demand (so that a run of
/// 10⁸ samples does not hold 10⁸ times).
pub trait SampleTimes {
    /// How many times there are.
    fn count(&self) -> usize;
    /// Time number `i` (< `count()`).
    fn time(&self, i: usize) -> f64;
    /// Whether the times are ascending by construction, so that they need no check.
    fn ascending(&self) -> bool {
        false
    }
    /// The last time, where the integration ends (NaN when there is none).
    fn last(&self) -> f64 {
        match self.count() {
            0 => f64::NAN,
            n => self.time(n - 1),
        }
    }
}

impl SampleTimes for [f64] {
    fn count(&self) -> usize {
        self.len()
    }
    fn time(&self, i: usize) -> f64 {
        self[i]
    }
}

impl<const N: usize> SampleTimes for [f64; N] {
    fn count(&self) -> usize {
        N
    }
    fn time(&self, i: usize) -> f64 {
        self[i]
    }
}

impl SampleTimes for Vec<f64> {
    fn count(&self) -> usize {
        self.len()
    }
    fn time(&self, i: usize) -> f64 {
        self[i]
    }
}

/// The uniform sample times t₀, t₀ + Δ, …, computed from the index (i·Δ from the start
/// rather than an accumulated sum, so that t₀ + 100·0.01 is 1 and not 1.0000000000000007),
/// and t_end last; a grid time closer to t_end than a billionth of Δ gives way to t_end
/// rather than leaving a sliver of an interval.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grid {
    t0: f64,
    dt: f64,
    t_end: f64,
    /// Grid times before t_end.
    before_end: usize,
}

impl Grid {
    /// The grid from t0 to t_end > t0 by dt > 0 (all finite; the caller checks).
    pub fn new(t0: f64, t_end: f64, dt: f64) -> Grid {
        // The count, then corrected for rounding in either direction.
        let mut before_end = ((t_end - t0) / dt).ceil().max(1.0) as usize;
        let at = |i: usize| t0 + i as f64 * dt;
        while before_end > 1 && at(before_end - 1) >= t_end - 1e-9 * dt {
            before_end -= 1;
        }
        while at(before_end) < t_end - 1e-9 * dt {
            before_end += 1;
        }
        Grid {
            t0,
            dt,
            t_end,
            before_end,
        }
    }
}

impl SampleTimes for Grid {
    fn count(&self) -> usize {
        self.before_end + 1
    }
    fn ascending(&self) -> bool {
        true
    }
    fn time(&self, i: usize) -> f64 {
        if i < self.before_end {
            self.t0 + i as f64 * self.dt
        } else {
            self.t_end
        }
    }
}

/// The solution between the ends of an accepted step: the method's continuous extension.
pub trait Interpolant<V> {
    /// The solution at t, within the step.
    fn at(&self, t: f64) -> V;
}

/// A continuous extension formed when first evaluated: a step with no sample inside it,
/// watched by an observer that does not look inside it (a progress callback), forms none.
pub(super) struct LazyInterpolant<D, F> {
    made: std::cell::OnceCell<D>,
    make: F,
}

impl<D, F: Fn() -> D> LazyInterpolant<D, F> {
    pub fn new(make: F) -> Self {
        LazyInterpolant {
            made: std::cell::OnceCell::new(),
            make,
        }
    }
}

impl<V, D: Interpolant<V>, F: Fn() -> D> Interpolant<V> for LazyInterpolant<D, F> {
    fn at(&self, t: f64) -> V {
        self.made.get_or_init(&self.make).at(t)
    }
}

/// An accepted step from (t, x) to (t1, x1) — x1 as the integrator continues from it,
/// projected — with the solution in between.
pub struct StepView<'a, V> {
    pub t: f64,
    pub x: &'a V,
    pub t1: f64,
    pub x1: &'a V,
    pub dense: &'a dyn Interpolant<V>,
}

/// What the observer of a step or a sample wants next.
#[derive(Clone, Copy, Debug, PartialEq)]
#[must_use = "an observer may ask to stop the integration"]
pub enum Control {
    Continue,
    /// From [`Observer::step`]: end the integration at this time, within the step just
    /// reported (a terminal event, a cancelled run): the integrator reports the samples
    /// before it, then the solution at this time as the last sample. From
    /// [`Observer::sample`]: end it at that sample (a run cancelled while a step holds many
    /// samples); the time given is not read.
    Stop(f64),
}

/// Where an integrator reports the solution: at every sample time, and — if
/// [`Observer::watches_steps`] — after every accepted step. An `Err` stops the integration
/// and is returned as is. ([`super::Integrator::integrate`] takes a closure that observes the
/// samples only.)
pub trait Observer<V> {
    /// The solution x at sample time t; [`Control::Stop`] ends the integration there, the
    /// integrator reporting that it stopped at t ([`super::Stats::stopped`]).
    fn sample(&mut self, t: f64, x: &V) -> Result<Control, Error>;

    /// Whether [`Observer::step`] is to be called; integrators ask once, before the first
    /// step. Dense output can cost: a method without a natural continuous extension (RK4)
    /// forms one with an extra evaluation per step.
    fn watches_steps(&self) -> bool {
        false
    }

    /// Whether [`Observer::step`] reads the solution inside the step ([`StepView::dense`]);
    /// asked with [`Observer::watches_steps`]. An observer that only looks at the step's ends
    /// (a progress callback) says no, and a method then forms its continuous extension only
    /// where a sample needs it (it still forms it if read).
    fn reads_inside_steps(&self) -> bool {
        true
    }

    /// An accepted step, before the samples within it are reported.
    fn step(&mut self, _step: &StepView<'_, V>) -> Result<Control, Error> {
        Ok(Control::Continue)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grids_end_exactly_at_the_end() {
        let grid = Grid::new(0.0, 2.0, 0.1);
        assert_eq!(grid.count(), 21);
        assert_eq!(grid.time(10), 1.0);
        assert_eq!(grid.last(), 2.0);
        // An interval that does not divide the span: the last one is shorter.
        let uneven = Grid::new(-1.0, 0.5, 0.4);
        assert_eq!(uneven.count(), 5);
        assert_eq!((uneven.time(0), uneven.time(4)), (-1.0, 0.5));
        // No sliver: an end a hair beyond a multiple of the interval replaces that sample.
        let hair = Grid::new(0.0, 1.0 + 1e-12, 0.25);
        let times: Vec<f64> = (0..hair.count()).map(|i| hair.time(i)).collect();
        assert_eq!(times, [0.0, 0.25, 0.5, 0.75, 1.0 + 1e-12]);
        // A huge grid costs nothing until asked.
        let huge = Grid::new(0.0, 1e5, 1e-3);
        assert_eq!(huge.count(), 100_000_001);
    }
}
