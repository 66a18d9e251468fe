//! The classical fourth-order Runge–Kutta method with a fixed step: no error control, four
//! evaluations per step, and the same steps on every run — useful as a reference and for
//! real-time loops with a fixed budget.

use super::observer::{Control, Interpolant, Observer, SampleTimes, StepView};
use super::{
    Integrator, MAX_STEPS, Ode, Stats, check_problem, check_state, combine, equal_steps,
    too_many_steps, too_many_steps_planned,
};
use crate::error::Error;
use crate::vector::Vector;

/// Classical RK4 with step size at most `step`. It steps exactly onto every sample time: an
/// interval of length Δ between samples is cut into ⌈Δ/step⌉ equal sub-steps, so output times
/// never need interpolation and the order is the same at every sample. Between steps (for an
/// observer that watches them, to locate events) the solution is the cubic Hermite
/// interpolant of the step's ends and slopes, third-order accurate; the slope at a step's end
/// is the next step's first stage, so it costs one evaluation at the very end only.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rk4 {
    pub step: f64,
    /// The most steps an integration may take; more is refused before the first step.
    /// Default [`super::MAX_STEPS`].
    pub max_steps: usize,
}

impl Rk4 {
    pub fn new(step: f64) -> Self {
        Rk4 {
            step,
            max_steps: MAX_STEPS,
        }
    }

    /// Limits an integration to `n` steps.
    pub fn with_max_steps(mut self, n: usize) -> Self {
        self.max_steps = n;
        self
    }
}

impl Integrator for Rk4 {
    fn integrate_observed<O: Ode, T: SampleTimes + ?Sized>(
        &self,
        ode: &mut O,
        t0: f64,
        x0: &O::State,
        samples: &T,
        observer: &mut dyn Observer<O::State>,
    ) -> Result<Stats, Error> {
        if !(self.step.is_finite() && self.step > 0.0) {
            return Err(Error::InvalidSetting {
                name: "step",
                value: self.step,
                reason: "the RK4 step must be a positive finite number",
            });
        }
        check_problem(ode, t0, x0, samples)?;
        // Each sample interval adds at most one step to span/step.
        let span = samples.last() - t0;
        if samples.count() > 0 && span / self.step > self.max_steps as f64 {
            return Err(too_many_steps_planned(
                ode,
                t0,
                self.step,
                x0,
                span / self.step,
            ));
        }
        let mut run = Run {
            ode,
            observer,
            stats: Stats::default(),
            watch: false,
            slope: None,
        };
        run.watch = run.observer.watches_steps();
        let (mut t, mut x) = (t0, *x0);
        for i in 0..samples.count() {
            let sample = samples.time(i);
            if sample > t {
                match run.interval((t, x), sample, self.step, self.max_steps)? {
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
}

/// One integration's state: the ODE, the observer, the cost, and the slope at the current
/// point when it is known already (the last step's end, evaluated for its dense output).
struct Run<'a, O: Ode> {
    ode: &'a mut O,
    observer: &'a mut dyn Observer<O::State>,
    stats: Stats,
    watch: bool,
    slope: Option<O::State>,
}

impl<O: Ode> Run<'_, O> {
    /// The equal sub-steps from (t, x) to the sample time `to`; the state there, or `None`
    /// when the observer stopped the integration (its last sample reported).
    fn interval(
        &mut self,
        (t, x): (f64, O::State),
        to: f64,
        step: f64,
        max_steps: usize,
    ) -> Result<Option<O::State>, Error> {
        let (n, h) = equal_steps(to - t, step);
        let mut x = x;
        // Times are computed from the interval's start, not accumulated, and the last
        // sub-step ends exactly on the sample.
        for i in 0..n {
            if self.stats.steps >= max_steps {
                return Err(too_many_steps(&*self.ode, t, h, &x, self.stats.steps));
            }
            let start = t + i as f64 * h;
            let end = if i + 1 < n {
                t + (i + 1) as f64 * h
            } else {
                to
            };
            let k1 = match self.slope.take() {
                Some(k1) => k1,
                None => {
                    let mut k1 = O::State::zeros();
                    self.ode.rhs(start, &x, &mut k1)?;
                    self.stats.evaluations += 1;
                    k1
                }
            };
            let mut next = rk4_step(self.ode, start, &x, &k1, h)?;
            self.stats.steps += 1;
            self.stats.evaluations += 3;
            check_state(&*self.ode, end, &next)?;
            self.ode.project(end, &mut next)?;
            if self.watch {
                if let Some(ts) = self.watch_step((start, &x, &k1), (end, &next))? {
                    self.stats.stopped = Some(ts);
                    return Ok(None);
                }
            }
            x = next;
        }
        Ok(Some(x))
    }

    /// Reports a step to the observer with its Hermite interpolant; on a stop, the state
    /// there as the last sample, and the stop's time.
    fn watch_step(
        &mut self,
        (t, x, k1): (f64, &O::State, &O::State),
        (t1, x1): (f64, &O::State),
    ) -> Result<Option<f64>, Error> {
        let mut k_end = O::State::zeros();
        self.ode.rhs(t1, x1, &mut k_end)?;
        self.stats.evaluations += 1;
        let dense = Hermite {
            t,
            h: t1 - t,
            x: *x,
            x1: *x1,
            k: *k1,
            k1: k_end,
        };
        let view = StepView {
            t,
            x,
            t1,
            x1,
            dense: &dense,
        };
        match self.observer.step(&view)? {
            Control::Continue => {
                // The slope at the (projected) end is the next step's first stage.
                self.slope = Some(k_end);
                Ok(None)
            }
            Control::Stop(ts) => {
                let ts = ts.clamp(t, t1);
                let mut value = if ts == t1 { *x1 } else { dense.at(ts) };
                self.ode.project(ts, &mut value)?;
                // The run ends here whatever the observer answers.
                let _ = self.observer.sample(ts, &value)?;
                Ok(Some(ts))
            }
        }
    }
}

/// The cubic Hermite interpolant of a step from (t, x) with slope k to (t + h, x1) with slope
/// k1.
struct Hermite<V> {
    t: f64,
    h: f64,
    x: V,
    x1: V,
    k: V,
    k1: V,
}

impl<V: Vector> Interpolant<V> for Hermite<V> {
    fn at(&self, s: f64) -> V {
        let theta = (s - self.t) / self.h;
        let (t2, t3) = (theta * theta, theta * theta * theta);
        let h00 = 2.0 * t3 - 3.0 * t2 + 1.0;
        let h10 = t3 - 2.0 * t2 + theta;
        let h01 = -2.0 * t3 + 3.0 * t2;
        let h11 = t3 - t2;
        let mut out = V::zeros();
        for (i, o) in out.as_mut().iter_mut().enumerate() {
            *o = h00 * self.x.as_ref()[i]
                + h10 * self.h * self.k.as_ref()[i]
                + h01 * self.x1.as_ref()[i]
                + h11 * self.h * self.k1.as_ref()[i];
        }
        out
    }
}

/// One classical RK4 step of size `h` from (t, x), whose slope is `k1`.
fn rk4_step<O: Ode>(
    ode: &mut O,
    t: f64,
    x: &O::State,
    k1: &O::State,
    h: f64,
) -> Result<O::State, Error> {
    let mut k2 = O::State::zeros();
    let mut k3 = O::State::zeros();
    let mut k4 = O::State::zeros();
    ode.rhs(t + 0.5 * h, &combine(x, 0.5 * h, &[(1.0, k1)]), &mut k2)?;
    ode.rhs(t + 0.5 * h, &combine(x, 0.5 * h, &[(1.0, &k2)]), &mut k3)?;
    ode.rhs(t + h, &combine(x, h, &[(1.0, &k3)]), &mut k4)?;
    Ok(combine(
        x,
        h / 6.0,
        &[(1.0, k1), (2.0, &k2), (2.0, &k3), (1.0, &k4)],
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ẋ = 1: every method is exact, so only the stepping logic is tested.
    struct Clock(Vec<f64>);

    impl Ode for Clock {
        type State = [f64; 1];

        fn rhs(&mut self, t: f64, _x: &[f64; 1], dx: &mut [f64; 1]) -> Result<(), Error> {
            self.0.push(t);
            dx[0] = 1.0;
            Ok(())
        }
    }

    #[test]
    fn steps_land_on_every_sample() {
        let mut ode = Clock(Vec::new());
        let mut seen = Vec::new();
        let stats = Rk4::new(0.1)
            .integrate(
                &mut ode,
                0.0,
                &[0.0],
                &[0.0, 0.7, 0.7, 1.1, 1.15],
                &mut |t, x| {
                    seen.push((t, x[0]));
                    Ok(())
                },
            )
            .unwrap();
        // 0 → 0.7 in 7 sub-steps, 0.7 → 1.1 in 4 (the slack keeps (1.1 − 0.7)/0.1 =
        // 4.000000000000001 from adding a fifth), 1.1 → 1.15 in 1.
        assert_eq!(
            stats,
            Stats {
                steps: 12,
                rejected: 0,
                evaluations: 48,
                stopped: None,
                ..Stats::default()
            }
        );
        assert_eq!(
            seen.iter().map(|s| s.0).collect::<Vec<_>>(),
            [0.0, 0.7, 0.7, 1.1, 1.15]
        );
        for (t, x) in seen {
            assert!((x - t).abs() < 1e-15, "x({t}) = {x}");
        }
        // The first stage of each step is evaluated at the step's start.
        assert_eq!(ode.0[0], 0.0);
        assert!((ode.0[4] - 0.1).abs() < 1e-16);
    }

    #[test]
    fn invalid_steps_are_errors() {
        for step in [0.0, -0.1, f64::NAN, f64::INFINITY] {
            let result = Rk4::new(step).integrate(
                &mut Clock(Vec::new()),
                0.0,
                &[0.0],
                &[1.0],
                &mut |_, _| Ok(()),
            );
            match result {
                Err(Error::InvalidSetting {
                    name: "step",
                    value,
                    ..
                }) => {
                    assert!(value.is_nan() || value == step);
                }
                other => panic!("expected an invalid step error for {step}, got {other:?}"),
            }
        }
    }
}
