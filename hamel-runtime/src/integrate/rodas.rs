//! Rosenbrock methods for stiff systems: Rodas5P (Steinebach 2023) and Rodas4 (Hairer &
//! Wanner's RODAS), with error control, dense output and events, on the exact Jacobian.
//!
//! A Rosenbrock step solves no nonlinear equations: each of its stages is one linear solve
//! with W = I/(hγ) − J, a single LU factorization per step. Where an implicit Runge–Kutta
//! method (Radau5) iterates to convergence, a Rosenbrock method needs the Jacobian to be the
//! right-hand side's own, evaluated at every step (and ∂f/∂t for a time-dependent system):
//! exactly what a generated model has at compile time (`Ode::jacobian`, by dual numbers). On
//! the standard stiff test set SciMLBenchmarks find Rodas4 and Rodas5P the fastest solvers at
//! rtol 10⁻³…10⁻⁷, where Radau catches up only near 10⁻⁹.
//!
//! The step-size control is RODAS's: the local error estimate is the last stage's increment
//! (the difference to the embedded solution), measured as √(mean((eᵢ/scᵢ)²)) with
//! scᵢ = atol + rtol·max(|y₀ᵢ|, |y₁ᵢ|), the step changed by a factor in [1/5, 6], with
//! Gustafsson's predictive controller after the first accepted step. Unlike Radau5's, the
//! tolerances are used as given. A singular W halves the step, five times in a row at most
//! (RODAS); a stage whose right-hand side is not finite rejects the step.

use super::dense::SquareLu;
use super::differences::Jacobian;
use super::initial_step::{Target, initial_step};
use super::observer::{Control, Interpolant, Observer, SampleTimes, StepView};
use super::rosenbrock_tableau::RosenbrockTableau;
use super::sampling::Samples;
use super::settings::{self, Adaptive, RtolFloor};
use super::singular::{SUSPICIOUS_PIVOT, growing_mode, relative_pivot};
use super::{
    Integrator, MAX_STEPS, NonFinite, Ode, Stats, Watched, check_problem, check_span, check_state,
    is_finite, too_many_steps,
};
use crate::error::Error;
use crate::vector::Vector;
use nalgebra::Complex;

/// RODAS's constants: the safety factor and the bounds of a step's change (h/5 … 6h).
const SAFE: f64 = 0.9;
const FAC1: f64 = 5.0;
const FAC2: f64 = 1.0 / 6.0;

/// Singular matrices W in a row, each followed by a step half as long, after which the run
/// ends with [`Error::SingularIterationMatrix`] (RODAS gives up after 5 too).
const SINGULAR_IN_A_ROW: usize = 5;

/// The settings every Rodas method shares.
macro_rules! rodas_method {
    ($(#[$doc:meta])* $name:ident, $tableau:expr, $label:literal) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, PartialEq)]
        pub struct $name {
            /// Relative tolerance (> 10 ε).
            pub rtol: f64,
            /// Absolute tolerance (> 0).
            pub atol: f64,
            /// The first step size; `None` estimates it from the problem (Hairer's HINIT).
            pub initial_step: Option<f64>,
            /// The largest step allowed.
            pub max_step: f64,
            /// The most steps (accepted and rejected) an integration may take.
            pub max_steps: usize,
            /// The smallest step allowed, relative to |t| where it is taken (in [0, 1); and
            /// never below 16 ulps of t), as [`super::Radau5::min_step`].
            pub min_step: f64,
        }

        impl $name {
            /// Adaptive steps with these tolerances.
            pub fn new(rtol: f64, atol: f64) -> Self {
                $name {
                    rtol,
                    atol,
                    initial_step: None,
                    max_step: f64::INFINITY,
                    max_steps: MAX_STEPS,
                    min_step: Self::MIN_STEP,
                }
            }

            /// The default floor on a step, relative to |t|: 10⁻¹⁴ of it.
            pub const MIN_STEP: f64 = 1e-14;

            pub fn with_initial_step(mut self, h: f64) -> Self {
                self.initial_step = Some(h);
                self
            }

            pub fn with_max_step(mut self, h: f64) -> Self {
                self.max_step = h;
                self
            }

            /// Limits an integration to `n` steps, rejected ones included.
            pub fn with_max_steps(mut self, n: usize) -> Self {
                self.max_steps = n;
                self
            }

            /// The floor on a step, relative to |t| (in [0, 1)).
            pub fn with_min_step(mut self, relative: f64) -> Self {
                self.min_step = relative;
                self
            }

            fn settings(&self) -> Adaptive {
                Adaptive {
                    rtol: self.rtol,
                    atol: self.atol,
                    initial_step: self.initial_step,
                    max_step: self.max_step,
                    max_steps: self.max_steps,
                    min_step: self.min_step,
                }
            }
        }

        impl Integrator for $name {
            fn integrate_observed<O: Ode, T: SampleTimes + ?Sized>(
                &self,
                ode: &mut O,
                t0: f64,
                x0: &O::State,
                samples: &T,
                observer: &mut dyn Observer<O::State>,
            ) -> Result<Stats, Error> {
                integrate(&$tableau, &self.settings(), ode, (t0, x0), samples, observer)
            }
        }
    };
}

rodas_method!(
    /// Rodas5P (Steinebach 2023): a Rosenbrock method of order 5 (embedded order 4), L-stable
    /// and stiffly accurate, with a dense output of order 4; eight right-hand sides, one
    /// Jacobian (with ∂f/∂t for a time-dependent system) and one LU factorization per step,
    /// no iteration. For stiff systems at moderate tolerances (rtol 10⁻³…10⁻⁷): with a
    /// generated model's exact Jacobian it is the fastest of hamel's stiff methods there,
    /// where [`super::Radau5`] wins at tighter tolerances (`hamel::docs::running`, "Stiff
    /// models", measured per problem).
    ///
    /// It needs the Jacobian to be the right-hand side's (a Rosenbrock method loses its order
    /// with an approximate one): a simulation's is exact; a hand-written `Ode` without
    /// [`Ode::jacobian`] gets differences (`num_jac`'s steps), and without
    /// [`Ode::time_derivative`] f is differenced in t (one more evaluation per step; an
    /// autonomous system saves it by writing zeros).
    ///
    /// Settings, statistics, samples (from the dense output, projected), events and
    /// constraint projection are those of [`super::Radau5`], except the tolerances, used as
    /// given (the local error per step is held to rtol·|y| + atol). A singular iteration
    /// matrix halves the step, and five in a row are an [`Error::SingularIterationMatrix`]
    /// naming the growing motion; a step below the floor an [`Error::StepSizeUnderflow`] (or,
    /// when the right-hand side was not finite on the way, an [`Error::NonFiniteRate`]
    /// naming it). Every error names t, h and the state.
    ///
    /// ```
    /// use hamel_runtime::{Error, Integrator, Ode, Rodas5P};
    ///
    /// /// y′ = −10⁶ (y − cos t): y ≈ cos t + 10⁻⁶ sin t after a microsecond.
    /// struct Stiff;
    /// impl Ode for Stiff {
    ///     type State = [f64; 1];
    ///     fn rhs(&mut self, t: f64, y: &[f64; 1], dy: &mut [f64; 1]) -> Result<(), Error> {
    ///         dy[0] = -1e6 * (y[0] - t.cos());
    ///         Ok(())
    ///     }
    ///     fn jacobian(&mut self, _: f64, _: &[f64; 1], j: &mut [f64]) -> Result<bool, Error> {
    ///         j[0] = -1e6;
    ///         Ok(true)
    ///     }
    ///     fn time_derivative(&mut self, t: f64, _: &[f64; 1], d: &mut [f64; 1]) -> Result<bool, Error> {
    ///         d[0] = -1e6 * t.sin();
    ///         Ok(true)
    ///     }
    /// }
    ///
    /// let mut end = 0.0;
    /// let stats = Rodas5P::new(1e-8, 1e-8).integrate(&mut Stiff, 0.0, &[1.0], &[10.0], &mut |_, y| {
    ///     end = y[0];
    ///     Ok(())
    /// })?;
    /// assert!((end - (10f64.cos() + 1e-6 * 10f64.sin())).abs() < 1e-8);
    /// // Eight evaluations a step, one LU.
    /// assert!(stats.evaluations < 8 * (stats.steps + stats.rejected) + 10, "{stats:?}");
    /// # Ok::<(), hamel_runtime::Error>(())
    /// ```
    Rodas5P,
    RosenbrockTableau::rodas5p(),
    "Rodas5P"
);

rodas_method!(
    /// Rodas4 (Hairer & Wanner's RODAS): a Rosenbrock method of order 4 (embedded order 3),
    /// L-stable and stiffly accurate, with a dense output of order 3; six right-hand sides,
    /// one Jacobian and one LU factorization per step. Everything else as [`Rodas5P`], which
    /// is as cheap per step for one order more; Rodas4 is here for comparison and for
    /// problems where its coarser steps at loose tolerances pay.
    Rodas4,
    RosenbrockTableau::rodas4(),
    "Rodas4"
);

/// One integration with the Rosenbrock method `tableau`.
fn integrate<O: Ode, T: SampleTimes + ?Sized, const S: usize, const K: usize>(
    tableau: &RosenbrockTableau<S, K>,
    method: &Adaptive,
    ode: &mut O,
    (t0, x0): (f64, &O::State),
    samples: &T,
    observer: &mut dyn Observer<O::State>,
) -> Result<Stats, Error> {
    let floor = RtolFloor {
        value: 10.0 * f64::EPSILON,
        inclusive: false,
        reason: "the relative tolerance of a Rosenbrock method must be a finite number above \
                 10 ε ≈ 2.2e-15 (below it the error estimate is rounding)",
    };
    settings::check(method, floor)?;
    check_problem(ode, t0, x0, samples)?;
    let mut samples = Samples {
        times: samples,
        next: 0,
        observer,
    };
    if let Some(s) = samples.report_start(t0, x0)? {
        return Ok(Stats {
            stopped: Some(s),
            ..Stats::default()
        });
    }
    let Some(t_end) = samples.upcoming().map(|_| samples.times.last()) else {
        return Ok(Stats::default());
    };
    check_span(ode, t0, t_end, x0)?;
    settings::check_relative_floor(method, t0, t_end)?;
    let mut run = Run::new(tableau, method, ode, (t0, x0), t_end)?;
    run.integrate(&mut samples)?;
    Ok(run.stats)
}

/// The dense output of an accepted step: (1 − θ) y₀ + θ (y₁ + (1 − θ)(K₁ + θ(K₂ + θK₃))).
pub(crate) struct RosenbrockDense<V, const K: usize> {
    t: f64,
    h: f64,
    y0: V,
    y1: V,
    k: [V; K],
}

impl<V: Vector, const K: usize> Interpolant<V> for RosenbrockDense<V, K> {
    fn at(&self, t: f64) -> V {
        let theta = (t - self.t) / self.h;
        let theta1 = 1.0 - theta;
        let mut out = V::zeros();
        for (i, o) in out.as_mut().iter_mut().enumerate() {
            // Horner from the highest coefficient.
            let mut inner = 0.0;
            for km in self.k.iter().rev() {
                inner = km.as_ref()[i] + theta * inner;
            }
            let y0 = self.y0.as_ref()[i];
            let y1 = self.y1.as_ref()[i];
            *o = theta1 * y0 + theta * (y1 + theta1 * inner);
        }
        out
    }
}

/// How an attempted step ended.
enum Attempt<V, const S: usize> {
    /// The increments kᵢ, the new value and its error estimate.
    Done { k: [V; S], y1: V, err: f64 },
    /// W was singular (the growing eigenvalue of J, if one was found).
    Singular(Option<(f64, f64)>),
}

/// One Rosenbrock integration.
struct Run<'a, 't, O: Ode, const S: usize, const K: usize> {
    tableau: &'t RosenbrockTableau<S, K>,
    method: &'a Adaptive,
    /// The ODE, its right-hand side's values watched for NaN (named when the run ends).
    ode: Watched<'a, O>,
    stats: Stats,
    jacobian: Jacobian,
    /// ∂f/∂t at the point the Jacobian is for.
    dfdt: O::State,
    /// The LU of W = I/(hγ) − J, for the h and Jacobian (by its count) in `formed`.
    lu: <O::State as Vector>::Lu,
    formed: Option<(f64, usize)>,
    t: f64,
    y: O::State,
    /// f(t, y).
    f0: O::State,
    /// Whether the Jacobian (and ∂f/∂t) are for (t, y).
    current: bool,
    t_end: f64,
    h: f64,
    hmax: f64,
    /// Gustafsson's controller: the last accepted step and its error.
    accepted: Option<(f64, f64)>,
    reject: bool,
    singular_in_a_row: usize,
}

impl<'a, 't, O: Ode, const S: usize, const K: usize> Run<'a, 't, O, S, K> {
    fn new(
        tableau: &'t RosenbrockTableau<S, K>,
        method: &'a Adaptive,
        ode: &'a mut O,
        (t0, x0): (f64, &O::State),
        t_end: f64,
    ) -> Result<Self, Error> {
        let span = t_end - t0;
        let hmax = method.max_step.min(span);
        if span / method.max_step > method.max_steps as f64 {
            return Err(super::too_many_steps_planned(
                ode,
                t0,
                method.max_step,
                x0,
                (span / method.max_step).ceil(),
            ));
        }
        let mut stats = Stats::default();
        let mut ode = Watched::new(ode);
        let mut f0 = O::State::zeros();
        ode.rhs(t0, x0, &mut f0)?;
        stats.evaluations += 1;
        if let Some(found) = NonFinite::check(t0, x0, &f0) {
            return Err(found.error(&ode));
        }
        let h = match method.initial_step {
            Some(h) => h.min(hmax),
            None => {
                let target = Target {
                    rtol: method.rtol,
                    atol: method.atol,
                    order: tableau.estimate_order,
                    hmax,
                };
                initial_step(&mut ode, (t0, x0, &f0), target, &mut stats)?
            }
        };
        Ok(Run {
            tableau,
            method,
            ode,
            stats,
            jacobian: Jacobian::new(O::State::LEN, method.atol),
            dfdt: O::State::zeros(),
            lu: <O::State as Vector>::Lu::new(),
            formed: None,
            t: t0,
            y: *x0,
            f0,
            current: false,
            t_end,
            h,
            hmax,
            accepted: None,
            reject: false,
            singular_in_a_row: 0,
        })
    }

    /// The smallest step allowed at t: `min_step` of |t|, at least 16 ulps of t.
    fn floor(&self, t: f64) -> f64 {
        (self.method.min_step * t.abs())
            .max(16.0 * f64::EPSILON * t.abs())
            .max(1e-300)
    }

    /// The steps from the start to the end (or the observer's stop).
    fn integrate<T: SampleTimes + ?Sized>(
        &mut self,
        samples: &mut Samples<'_, T, O::State>,
    ) -> Result<(), Error> {
        loop {
            let (t, y) = (self.t, self.y);
            // RODAS: a step that nearly reaches the end is stretched to it.
            let last = t + self.h * 1.0001 >= self.t_end;
            if last {
                self.h = self.t_end - t;
            }
            let h = self.h;
            let tried = self.stats.steps + self.stats.rejected;
            if tried >= self.method.max_steps {
                return Err(too_many_steps(&self.ode, t, h, &y, tried));
            }
            if h < self.floor(t) {
                return Err(self.ode.explain(Error::StepSizeUnderflow {
                    t,
                    h,
                    state: self.ode.describe(&y),
                }));
            }
            if !self.current {
                self.evaluate_jacobian()?;
            }
            let (k, y1, err) = match self.attempt()? {
                Attempt::Done { k, y1, err } => (k, y1, err),
                Attempt::Singular(mode) => {
                    self.singular(mode)?;
                    continue;
                }
            };
            self.singular_in_a_row = 0;
            let exponent = 1.0 / (self.tableau.estimate_order + 1.0);
            let mut fac = FAC2.max(FAC1.min(err.powf(exponent) / SAFE));
            if err <= 1.0 {
                // Gustafsson's predictive controller, from the second accepted step on.
                if let Some((h_acc, err_acc)) = self.accepted {
                    let gus = (h_acc / h) * (err * err / err_acc).powf(exponent) / SAFE;
                    fac = fac.max(gus.clamp(FAC2, FAC1));
                }
                self.accepted = Some((h, err.max(1e-2)));
                let t1 = if last { self.t_end } else { t + h };
                let dense = self.dense(&k, y1);
                if self.accept(dense, t1, last, samples)? {
                    return Ok(());
                }
                let mut h_new = (h / fac).min(self.hmax);
                if self.reject {
                    h_new = h_new.min(h);
                }
                self.reject = false;
                self.h = h_new;
            } else {
                self.stats.rejected += 1;
                self.reject = true;
                // A rejected first step is retried ten times shorter (RADAU5's rule): its
                // error estimate, inside the initial transient, need not shrink as h⁵ does.
                // Measured on POLLU at rtol 10⁻⁸ (`benches/work_precision`, `at POLLU "hamel
                // Rodas5P" 1e-8`): the estimate grew from 1.2 to 5.0 while h/fac took the step
                // from 6.5·10⁻⁵ to 5.7·10⁻⁶ over 14 rejections; now 2, and 1103 evaluations
                // instead of 1179 for the same error (7.9·10⁻¹⁰ against 7.2·10⁻¹⁰).
                self.h = if self.stats.steps == 0 {
                    0.1 * h
                } else {
                    h / fac
                };
            }
        }
    }

    /// Evaluates J and ∂f/∂t at the current point: the ODE's own, or by differences (f in t
    /// over √ε·max(|t|, 1), FiniteDiff.jl's default step).
    fn evaluate_jacobian(&mut self) -> Result<(), Error> {
        let (t, y, f0) = (self.t, self.y, self.f0);
        self.jacobian
            .evaluate(&mut self.ode, t, &y, Some(&f0), &mut self.stats)?;
        if !self.ode.time_derivative(t, &y, &mut self.dfdt)? {
            let delta = f64::EPSILON.sqrt() * t.abs().max(1.0);
            let shifted = t + delta;
            let mut f1 = O::State::zeros();
            self.ode.rhs(shifted, &y, &mut f1)?;
            self.stats.evaluations += 1;
            if let Some(found) = NonFinite::check(shifted, &y, &f1) {
                return Err(found.error(&self.ode));
            }
            let step = shifted - t;
            for (d, (a, b)) in self
                .dfdt
                .as_mut()
                .iter_mut()
                .zip(f1.as_ref().iter().zip(f0.as_ref()))
            {
                *d = (a - b) / step;
            }
        }
        if let Some(i) = self.dfdt.as_ref().iter().position(|v| !v.is_finite()) {
            let state = self.ode.describe(&y);
            let name = state
                .0
                .get(i)
                .map_or_else(|| format!("x{i}"), |(n, _)| n.clone());
            return Err(Error::NonFiniteDerivative {
                of: format!("the rate of `{name}`"),
                by: "t".into(),
                value: self.dfdt.as_ref()[i],
                at: format!("at t = {}, in the state {state}", crate::error::Num(t)),
            });
        }
        self.current = true;
        Ok(())
    }

    /// Factors W = I/(hγ) − J for the current h and Jacobian (unless done already): whether
    /// it is singular, with the growing eigenvalue of J that makes it so if one does.
    fn factor(&mut self) -> Option<Option<(f64, f64)>> {
        let id = (self.h, self.jacobian.count());
        if self.formed == Some(id) {
            return None;
        }
        self.formed = None;
        let diagonal = 1.0 / (self.h * self.tableau.gamma);
        let jacobian = self.jacobian.matrix();
        let n = jacobian.nrows();
        let mut largest = 0.0f64;
        let smallest = self.lu.factor(|m| {
            let columns = m
                .chunks_exact_mut(n.max(1))
                .zip(jacobian.as_slice().chunks_exact(n.max(1)));
            for (c, (column, js)) in columns.enumerate() {
                for (r, (v, &j)) in column.iter_mut().zip(js).enumerate() {
                    // As `0.0 - j` (not −j: the sign of a zero).
                    *v = if r == c { diagonal - j } else { 0.0 - j };
                    largest = largest.max(v.abs());
                }
            }
        });
        self.stats.factorizations += 1;
        if relative_pivot(smallest, largest) <= SUSPICIOUS_PIVOT {
            let mu = [Complex::new(self.tableau.gamma, 0.0)];
            let mode = growing_mode(jacobian, self.h, &mu);
            if mode.is_some() || smallest == 0.0 {
                return Some(mode);
            }
        }
        self.formed = Some(id);
        None
    }

    /// The stages of the step h from (t, y).
    fn attempt(&mut self) -> Result<Attempt<O::State, S>, Error> {
        if let Some(mode) = self.factor() {
            return Ok(Attempt::Singular(mode));
        }
        let (t, y, h) = (self.t, self.y, self.h);
        let tab = self.tableau;
        let coupling: [[f64; S]; S] = tab.coupling.map(|row| row.map(|c| c / h));
        let mut k = [O::State::zeros(); S];
        for i in 0..S {
            let mut rhs = if i == 0 {
                self.f0
            } else {
                let mut u = y;
                for (j, kj) in k.iter().enumerate().take(i) {
                    let a = tab.a[i][j];
                    if a != 0.0 {
                        for (v, kv) in u.as_mut().iter_mut().zip(kj.as_ref()) {
                            *v += a * kv;
                        }
                    }
                }
                let mut f = O::State::zeros();
                self.ode.rhs(t + tab.c[i] * h, &u, &mut f)?;
                self.stats.evaluations += 1;
                if !is_finite(&f) {
                    // A value that is not a number rejects the step (the watch notes it).
                    return Ok(Attempt::Done {
                        k,
                        y1: y,
                        err: f64::INFINITY,
                    });
                }
                f
            };
            let hd = h * tab.d[i];
            for (p, r) in rhs.as_mut().iter_mut().enumerate() {
                let mut sum = hd * self.dfdt.as_ref()[p];
                for (c, kj) in coupling[i].iter().zip(&k).take(i) {
                    sum += c * kj.as_ref()[p];
                }
                *r += sum;
            }
            if !self.lu.solve(rhs.as_mut()) {
                return Ok(Attempt::Singular(None));
            }
            k[i] = rhs;
        }
        let mut y1 = y;
        for (j, kj) in k.iter().enumerate() {
            let b = tab.b[j];
            for (v, kv) in y1.as_mut().iter_mut().zip(kj.as_ref()) {
                *v += b * kv;
            }
        }
        let err = self.error_norm(&y, &y1, &k[S - 1]);
        Ok(Attempt::Done { k, y1, err })
    }

    /// RODAS's error norm: √(mean((eᵢ/scᵢ)²)) over the controlled components, with
    /// scᵢ = atol + rtol·max(|y₀ᵢ|, |y₁ᵢ|); not a number becomes infinite (rejected).
    fn error_norm(&self, y0: &O::State, y1: &O::State, e: &O::State) -> f64 {
        let len = self.ode.controlled_components().min(O::State::LEN).max(1);
        let (rtol, atol) = (self.method.rtol, self.method.atol);
        let sum: f64 = (0..len)
            .map(|i| {
                let sc = atol + rtol * y0.as_ref()[i].abs().max(y1.as_ref()[i].abs());
                (e.as_ref()[i] / sc).powi(2)
            })
            .sum();
        let err = (sum / len as f64).sqrt();
        if err.is_nan() { f64::INFINITY } else { err }
    }

    /// The dense output of the step whose increments are `k`, ending at `y1`.
    fn dense(&self, k: &[O::State; S], y1: O::State) -> RosenbrockDense<O::State, K> {
        let mut out = [O::State::zeros(); K];
        for (m, km) in out.iter_mut().enumerate() {
            for (j, kj) in k.iter().enumerate() {
                let hmj = self.tableau.dense[m][j];
                for (v, kv) in km.as_mut().iter_mut().zip(kj.as_ref()) {
                    *v += hmj * kv;
                }
            }
        }
        RosenbrockDense {
            t: self.t,
            h: self.h,
            y0: self.y,
            y1,
            k: out,
        }
    }

    /// A singular W at the current step: RODAS halves the step, and gives up after
    /// [`SINGULAR_IN_A_ROW`] in a row.
    fn singular(&mut self, mode: Option<(f64, f64)>) -> Result<(), Error> {
        self.singular_in_a_row += 1;
        if self.singular_in_a_row >= SINGULAR_IN_A_ROW {
            let (growth, frequency) = mode.unwrap_or((f64::NAN, 0.0));
            return Err(self.ode.explain(Error::SingularIterationMatrix {
                t: self.t,
                h: self.h,
                growth,
                frequency,
                state: self.ode.describe(&self.y),
            }));
        }
        self.stats.rejected += 1;
        self.reject = true;
        self.h *= 0.5;
        Ok(())
    }

    /// Completes an accepted step to t1: checks, projects and reports it and the samples it
    /// covers, and moves on from it. Whether the integration is done.
    fn accept<T: SampleTimes + ?Sized>(
        &mut self,
        dense: RosenbrockDense<O::State, K>,
        t1: f64,
        last: bool,
        samples: &mut Samples<'_, T, O::State>,
    ) -> Result<bool, Error> {
        let (t, y) = (self.t, self.y);
        check_state(&self.ode, t1, &dense.y1)?;
        self.stats.steps += 1;
        // A value that was not finite at a rejected attempt is no longer a cause.
        self.ode.non_finite = None;
        let mut y1 = dense.y1;
        self.ode.project(t1, &mut y1)?;
        let control = if samples.observer.watches_steps() {
            let view = StepView {
                t,
                x: &y,
                t1,
                x1: &y1,
                dense: &dense,
            };
            samples.observer.step(&view)?
        } else {
            Control::Continue
        };
        let stop = match control {
            Control::Continue => None,
            Control::Stop(ts) => Some(ts.clamp(t, t1)),
        };
        let stop = samples.report(&mut self.ode, (t1, &y1), |s| dense.at(s), stop)?;
        if stop.is_some() {
            self.stats.stopped = stop;
            return Ok(true);
        }
        (self.t, self.y) = (t1, y1);
        self.current = false;
        if last {
            return Ok(true);
        }
        self.ode.rhs(t1, &y1, &mut self.f0)?;
        self.stats.evaluations += 1;
        if let Some(found) = NonFinite::check(t1, &y1, &self.f0) {
            // Every step from here would start from it.
            return Err(found.error(&self.ode));
        }
        Ok(false)
    }
}
