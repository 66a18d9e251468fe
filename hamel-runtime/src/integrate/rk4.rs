//! The classical fourth-order Runge–Kutta method with a fixed step: no error control, four
//! evaluations per step, and the same steps on every run — useful as a reference and for
//! real-time loops with a fixed budget.

use super::fixed_step::{self, Budget, FixedStep};
use super::observer::{Control, Interpolant, Observer, SampleTimes, StepView};
use super::sampling::final_sample;
use super::{Integrator, MAX_STEPS, Ode, Stats, combine};
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
        let budget = Budget {
            step: self.step,
            max_steps: self.max_steps,
            invalid_step: "the RK4 step must be a positive finite number",
        };
        let mut steps = Steps {
            k1: O::State::zeros(),
            slope: None,
        };
        fixed_step::integrate(&mut steps, &budget, ode, (t0, x0), samples, observer)
    }
}

/// RK4's steps: the last step's first stage, and the slope at the current point when it is
/// known already (the last step's end, evaluated for its dense output).
struct Steps<V> {
    k1: V,
    slope: Option<V>,
}

impl<O: Ode> FixedStep<O> for Steps<O::State> {
    fn step(
        &mut self,
        ode: &mut O,
        (t, x): (f64, &O::State),
        (h, _): (f64, f64),
        stats: &mut Stats,
    ) -> Result<O::State, Error> {
        self.k1 = match self.slope.take() {
            Some(k1) => k1,
            None => {
                let mut k1 = O::State::zeros();
                ode.rhs(t, x, &mut k1)?;
                stats.evaluations += 1;
                k1
            }
        };
        let next = rk4_step(ode, t, x, &self.k1, h)?;
        stats.evaluations += 3;
        Ok(next)
    }

    /// Shows the step with its Hermite interpolant, which needs the slope at the end: that
    /// slope is the next step's first stage.
    fn watch(
        &mut self,
        ode: &mut O,
        observer: &mut dyn Observer<O::State>,
        (t, x): (f64, &O::State),
        (t1, x1): (f64, &O::State),
        stats: &mut Stats,
    ) -> Result<Option<f64>, Error> {
        let mut k_end = O::State::zeros();
        ode.rhs(t1, x1, &mut k_end)?;
        stats.evaluations += 1;
        let dense = Hermite {
            t,
            h: t1 - t,
            x: *x,
            x1: *x1,
            k: self.k1,
            k1: k_end,
        };
        let view = StepView {
            t,
            x,
            t1,
            x1,
            dense: &dense,
        };
        match observer.step(&view)? {
            Control::Continue => {
                self.slope = Some(k_end);
                Ok(None)
            }
            Control::Stop(ts) => {
                let ts = ts.clamp(t, t1);
                final_sample(ode, observer, ts, (t1, x1), |s| dense.at(s))?;
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
