//! The classical fourth-order Runge–Kutta method with a fixed step: no error control, four
//! evaluations per step, and the same steps on every run — useful as a reference and for
//! real-time loops with a fixed budget.

use super::{Integrator, Observer, Ode, Stats, check_problem, check_state, combine, equal_steps};
use crate::error::Error;
use crate::vector::Vector;

/// Classical RK4 with step size at most `step`. It steps exactly onto every sample time: an
/// interval of length Δ between samples is cut into ⌈Δ/step⌉ equal sub-steps, so output times
/// never need interpolation and the order is the same at every sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rk4 {
    pub step: f64,
}

impl Rk4 {
    pub fn new(step: f64) -> Self {
        Rk4 { step }
    }
}

impl Integrator for Rk4 {
    fn integrate<O: Ode>(
        &self,
        ode: &mut O,
        t0: f64,
        x0: &O::State,
        samples: &[f64],
        observe: &mut Observer<'_, O::State>,
    ) -> Result<Stats, Error> {
        if !(self.step.is_finite() && self.step > 0.0) {
            return Err(Error::InvalidSetting {
                name: "step",
                value: self.step,
                reason: "the RK4 step must be a positive finite number",
            });
        }
        check_problem(ode, t0, x0, samples)?;

        let mut stats = Stats::default();
        let (mut t, mut x) = (t0, *x0);
        for &sample in samples {
            let span = sample - t;
            if span > 0.0 {
                let (n, h) = equal_steps(span, self.step);
                // Times are computed from the interval's start, not accumulated, and the last
                // sub-step ends exactly on the sample.
                for i in 0..n {
                    x = rk4_step(ode, t + i as f64 * h, &x, h)?;
                    stats.steps += 1;
                    stats.evaluations += 4;
                    let t_end = if i + 1 < n {
                        t + (i + 1) as f64 * h
                    } else {
                        sample
                    };
                    check_state(ode, t_end, &x)?;
                    // No derivative is carried from step to step, so a projected state
                    // costs no evaluation.
                    ode.project(t_end, &mut x)?;
                }
                t = sample;
            }
            observe(sample, &x)?;
        }
        Ok(stats)
    }
}

/// One classical RK4 step of size `h` from (t, x).
fn rk4_step<O: Ode>(ode: &mut O, t: f64, x: &O::State, h: f64) -> Result<O::State, Error> {
    let mut k1 = O::State::zeros();
    let mut k2 = O::State::zeros();
    let mut k3 = O::State::zeros();
    let mut k4 = O::State::zeros();
    ode.rhs(t, x, &mut k1)?;
    ode.rhs(t + 0.5 * h, &combine(x, 0.5 * h, &[(1.0, &k1)]), &mut k2)?;
    ode.rhs(t + 0.5 * h, &combine(x, 0.5 * h, &[(1.0, &k2)]), &mut k3)?;
    ode.rhs(t + h, &combine(x, h, &[(1.0, &k3)]), &mut k4)?;
    Ok(combine(
        x,
        h / 6.0,
        &[(1.0, &k1), (2.0, &k2), (2.0, &k3), (1.0, &k4)],
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
                evaluations: 48
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
