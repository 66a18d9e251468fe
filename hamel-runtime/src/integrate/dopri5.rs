//! The Dormand–Prince 5(4) method with step-size control and dense output, after Hairer's
//! DOPRI5 (Hairer, Nørsett & Wanner, *Solving Ordinary Differential Equations I*, II.4–II.6):
//! the same tableau, error norm, PI controller, initial-step heuristic and continuous
//! extension, so its step counts can be checked against the Fortran code's. (The controller
//! is computed in logarithms, which gives the same step sizes up to rounding: [`Controller`].)

use super::initial_step::{Target, initial_step};
use super::observer::{Control, Interpolant, LazyInterpolant, Observer, SampleTimes, StepView};
use super::sampling::Samples;
use super::settings::{self, Adaptive, RtolFloor};
use super::{
    Integrator, MAX_STEPS, NonFinite, Ode, Stats, UNDERFLOW_ULPS, Watched, check_problem,
    check_span, check_state, combine, equal_steps, fresh, fresh_component, too_many_steps,
    too_many_steps_planned,
};
use crate::error::Error;
use crate::vector::Vector;

/// Dormand–Prince 5(4): an explicit Runge–Kutta pair of orders 5 and 4, continued with the
/// fifth-order solution (local extrapolation). The last stage of a step is the first of the
/// next (FSAL), so an accepted step costs six right-hand-side evaluations.
///
/// Steps are chosen so that the local error estimate e satisfies
/// √(mean((eᵢ/scᵢ)²)) ≤ 1 with scᵢ = atol + rtol·max(|y₀ᵢ|, |y₁ᵢ|). Sample times inside a step
/// are observed through the method's fourth-order continuous extension; the integrator never
/// shortens a step to hit a sample, only the last one to end exactly on the final sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DormandPrince {
    /// Relative tolerance (≥ 0).
    pub rtol: f64,
    /// Absolute tolerance (> 0).
    pub atol: f64,
    /// The first step size; `None` lets Hairer's heuristic choose it from the problem.
    pub initial_step: Option<f64>,
    /// The largest step allowed (`f64::INFINITY`: only the integration span limits it).
    pub max_step: f64,
    /// `Some(h)`: no error control; equal steps of at most h that end exactly on the final
    /// sample, every one accepted. For convergence studies and reproducible cost.
    pub fixed_step: Option<f64>,
    /// The most steps (accepted and rejected) an integration may take (Hairer's NMAX): near
    /// a singularity of the solution the steps can shrink to where they still advance, but by
    /// so little that the run would not end; a fixed or largest step too small for the span
    /// is refused before the first step. Default [`super::MAX_STEPS`].
    pub max_steps: usize,
    /// The smallest step an adaptive integration may take, relative to the span integrated
    /// (default [`Self::MIN_STEP`]): a step below it means the solution (or the tolerance)
    /// asks for more than the method can give, and is an error rather than a crawl.
    pub min_step: f64,
}

impl DormandPrince {
    /// Adaptive steps with these tolerances, the automatic initial step and no step limit.
    pub fn new(rtol: f64, atol: f64) -> Self {
        DormandPrince {
            rtol,
            atol,
            initial_step: None,
            max_step: f64::INFINITY,
            fixed_step: None,
            max_steps: MAX_STEPS,
            min_step: Self::MIN_STEP,
        }
    }

    /// The default floor on an adaptive step, relative to the span: 10⁻¹² of it, far below
    /// what a non-stiff solution at any sensible tolerance needs, far above what would make
    /// a run crawl for hours.
    pub const MIN_STEP: f64 = 1e-12;

    /// Limits an integration to `n` steps, rejected ones included.
    pub fn with_max_steps(mut self, n: usize) -> Self {
        self.max_steps = n;
        self
    }

    /// The floor on an adaptive step, relative to the span integrated (≥ 0; 0 leaves only
    /// the limit of `f64` itself).
    pub fn with_min_step(mut self, relative: f64) -> Self {
        self.min_step = relative;
        self
    }

    pub fn with_initial_step(mut self, h: f64) -> Self {
        self.initial_step = Some(h);
        self
    }

    pub fn with_max_step(mut self, h: f64) -> Self {
        self.max_step = h;
        self
    }

    pub fn with_fixed_step(mut self, h: f64) -> Self {
        self.fixed_step = Some(h);
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

    fn check_settings(&self) -> Result<(), Error> {
        let floor = RtolFloor {
            value: 0.0,
            inclusive: true,
            reason: "the relative tolerance must be a finite number ≥ 0",
        };
        settings::check(&self.settings(), floor)?;
        if let Some(h) = self.fixed_step.filter(|h| !(h.is_finite() && *h > 0.0)) {
            return Err(Error::InvalidSetting {
                name: "fixed step",
                value: h,
                reason: "the fixed step must be a positive finite number",
            });
        }
        Ok(())
    }
}

// The Butcher tableau (Dormand & Prince 1980), as in Hairer's DOPRI5.
const C2: f64 = 0.2;
const C3: f64 = 0.3;
const C4: f64 = 0.8;
const C5: f64 = 8.0 / 9.0;
const A21: f64 = 0.2;
const A31: f64 = 3.0 / 40.0;
const A32: f64 = 9.0 / 40.0;
const A41: f64 = 44.0 / 45.0;
const A42: f64 = -56.0 / 15.0;
const A43: f64 = 32.0 / 9.0;
const A51: f64 = 19372.0 / 6561.0;
const A52: f64 = -25360.0 / 2187.0;
const A53: f64 = 64448.0 / 6561.0;
const A54: f64 = -212.0 / 729.0;
const A61: f64 = 9017.0 / 3168.0;
const A62: f64 = -355.0 / 33.0;
const A63: f64 = 46732.0 / 5247.0;
const A64: f64 = 49.0 / 176.0;
const A65: f64 = -5103.0 / 18656.0;
// The fifth-order weights (stage 2's weight is zero), which are also the seventh stage's row.
const A71: f64 = 35.0 / 384.0;
const A73: f64 = 500.0 / 1113.0;
const A74: f64 = 125.0 / 192.0;
const A75: f64 = -2187.0 / 6784.0;
const A76: f64 = 11.0 / 84.0;
// The fifth- minus the fourth-order weights: the local error estimate.
const E1: f64 = 71.0 / 57600.0;
const E3: f64 = -71.0 / 16695.0;
const E4: f64 = 71.0 / 1920.0;
const E5: f64 = -17253.0 / 339200.0;
const E6: f64 = 22.0 / 525.0;
const E7: f64 = -1.0 / 40.0;
// The continuous extension of Shampine (1986), Hairer's CONTD5.
const D1: f64 = -12715105075.0 / 11282082432.0;
const D3: f64 = 87487479700.0 / 32700410799.0;
const D4: f64 = -10690763975.0 / 1880347072.0;
const D5: f64 = 701980252875.0 / 199316789632.0;
const D6: f64 = -1453857185.0 / 822651844.0;
const D7: f64 = 69997945.0 / 29380423.0;

// Hairer's step-size control constants (DOPRI5's defaults).
const SAFETY: f64 = 0.9;
/// Bounds on h_new/h: FAC1 ≤ h_new/h ≤ FAC2.
const FAC1: f64 = 0.2;
const FAC2: f64 = 10.0;
/// Weight of the previous error in the PI controller (Lund stabilization).
const BETA: f64 = 0.04;
const EXPO1: f64 = 0.2 - BETA * 0.75;
/// The floor of the controller's memory of the last error, Hairer's 1e-4, as a logarithm.
const LN_FACOLD_MIN: f64 = -9.210340371976182;

/// The seven stages of a step from (t, y) with size h: `k[0]` = f(t, y) (the last stage of
/// the step before, FSAL), …, `k[6]` = f(t + h, y1). One set lives through an integration and
/// every attempt overwrites stages 2 to 7: no copies, no allocation.
type Stages<V> = [V; 7];

/// One attempted step from (t, y) with size h, `k[0]` given: its stages into `k`, and its
/// fifth-order result.
#[inline(always)]
fn attempt<O: Ode>(
    ode: &mut O,
    t: f64,
    y: &O::State,
    k: &mut Stages<O::State>,
    h: f64,
    stats: &mut Stats,
) -> Result<O::State, Error> {
    stats.evaluations += 6;
    let [k1, k2, k3, k4, k5, k6, k7] = k;
    ode.rhs(t + C2 * h, &combine(y, h, &[(A21, k1)]), k2)?;
    ode.rhs(t + C3 * h, &combine(y, h, &[(A31, k1), (A32, k2)]), k3)?;
    ode.rhs(
        t + C4 * h,
        &combine(y, h, &[(A41, k1), (A42, k2), (A43, k3)]),
        k4,
    )?;
    ode.rhs(
        t + C5 * h,
        &combine(y, h, &[(A51, k1), (A52, k2), (A53, k3), (A54, k4)]),
        k5,
    )?;
    let t1 = t + h;
    let stage6 = combine(
        y,
        h,
        &[(A61, k1), (A62, k2), (A63, k3), (A64, k4), (A65, k5)],
    );
    ode.rhs(t1, &stage6, k6)?;
    let y1 = combine(
        y,
        h,
        &[(A71, k1), (A73, k3), (A74, k4), (A75, k5), (A76, k6)],
    );
    ode.rhs(t1, &y1, k7)?;
    Ok(y1)
}

/// The square of Hairer's error norm: the mean of (eᵢ/scᵢ)², scᵢ = atol + rtol·max(|y₀ᵢ|,
/// |y₁ᵢ|), over the first `len` components (`Ode::controlled_components`); the step is
/// accepted when it is ≤ 1. NaN if the step produced a non-finite value there (and then the
/// step is rejected). Squared because the controller needs only its logarithm: the square
/// root Hairer takes would sit on the path to the next step size for nothing.
#[inline(always)]
fn error_norm_squared<V: Vector>(
    (y, y1): (&V, &V),
    k: &Stages<V>,
    h: f64,
    (rtol, atol): (f64, f64),
    len: usize,
) -> f64 {
    let len = len.min(V::LEN);
    if len == 0 {
        return 0.0;
    }
    let [k1, _, k3, k4, k5, k6, _] = k.each_ref().map(|v| v.as_ref());
    // The last stage is the right-hand side's value of a moment ago.
    let k7 = &k[6];
    let (y, y1) = (y.as_ref(), y1.as_ref());
    // Two partial sums (even and odd components, a pair of lanes of the vector arithmetic):
    // the next step waits for the sum, and two chains of additions end sooner than one.
    let mut sums = [0.0; 2];
    for i in 0..len {
        // All but the last stage's share, and the weight h/scᵢ, are known before the last
        // stage is: only a multiplication and an addition wait for it.
        let (a, b) = (y[i].abs(), y1[i].abs());
        // A NaN in y1 makes scᵢ, and so the error, NaN: the step is rejected.
        let weight = h / (atol + rtol * if a > b { a } else { b });
        let known = E1 * k1[i] + E3 * k3[i] + E4 * k4[i] + E5 * k5[i] + E6 * k6[i];
        let scaled = (known + E7 * fresh_component(k7, i)) * weight;
        sums[i % 2] += scaled * scaled;
    }
    let sum = sums[0] + sums[1];
    // The mean: by a power of two (as 8 states are) a multiplication, the same bits as the
    // division and a few cycles sooner on the path to the next step size.
    if len.is_power_of_two() {
        sum * (1.0 / len as f64)
    } else {
        sum / len as f64
    }
}

/// The continuous extension of an accepted step from (t, y): a polynomial of degree 4 in
/// θ = (s − t)/h that interpolates y and y1 with the slopes k1 and k7 and is fourth-order
/// accurate in between.
struct Dense<V> {
    t: f64,
    h: f64,
    r: [V; 5],
}

/// Component i of the extension's five coefficients (Hairer's RCONT).
#[inline(always)]
fn coefficients<V: Vector>(h: f64, (y, y1): (&V, &V), k: &Stages<V>, i: usize) -> [f64; 5] {
    let [k1, _, k3, k4, k5, k6, k7] = k.each_ref().map(|v| v.as_ref());
    let (y, y1) = (y.as_ref()[i], y1.as_ref()[i]);
    let ydiff = y1 - y;
    let bspl = h * k1[i] - ydiff;
    [
        y,
        ydiff,
        bspl,
        ydiff - h * k7[i] - bspl,
        h * (D1 * k1[i] + D3 * k3[i] + D4 * k4[i] + D5 * k5[i] + D6 * k6[i] + D7 * k7[i]),
    ]
}

/// The extension's value from its coefficients at θ (θ1 = 1 − θ), Hairer's CONTD5.
#[inline(always)]
fn horner([r1, r2, r3, r4, r5]: [f64; 5], theta: f64, theta1: f64) -> f64 {
    r1 + theta * (r2 + theta1 * (r3 + theta * (r4 + theta1 * r5)))
}

impl<V: Vector> Dense<V> {
    fn new(t: f64, h: f64, y: (&V, &V), k: &Stages<V>) -> Self {
        let mut r = [V::zeros(); 5];
        for i in 0..V::LEN {
            for (rj, c) in r.iter_mut().zip(coefficients(h, y, k, i)) {
                rj.as_mut()[i] = c;
            }
        }
        Dense { t, h, r }
    }

    fn at(&self, s: f64) -> V {
        let theta = (s - self.t) / self.h;
        let theta1 = 1.0 - theta;
        let mut out = V::zeros();
        let [r1, r2, r3, r4, r5] = self.r.each_ref().map(|v| v.as_ref());
        for (i, o) in out.as_mut().iter_mut().enumerate() {
            *o = horner([r1[i], r2[i], r3[i], r4[i], r5[i]], theta, theta1);
        }
        out
    }

    /// [`Dense::at`] without forming the extension: its coefficients computed and used at
    /// once, the same arithmetic and so the same bits. For a sample inside a step, where the
    /// extension is read once or twice: forming it stores five vectors and loads them back.
    fn value(t: f64, h: f64, y: (&V, &V), k: &Stages<V>, s: f64) -> V {
        let theta = (s - t) / h;
        let theta1 = 1.0 - theta;
        let mut out = V::zeros();
        for (i, o) in out.as_mut().iter_mut().enumerate() {
            *o = horner(coefficients(h, y, k, i), theta, theta1);
        }
        out
    }
}

/// Hairer's PI step-size controller with Lund stabilization: after an accepted step of size
/// h with error err, h_new = h·SAFETY·facoldᵝ/err^EXPO1, the ratio h_new/h kept within
/// [FAC1, FAC2], facold the last accepted error (at least 1e-4).
///
/// Computed in logarithms, from the squared error: ln(err²) once, then one exponential,
/// h_new = h·SAFETY·exp(β·ln facold − EXPO1·ln err), with ln facold kept from the last
/// accepted step. The next step waits for this value, so its latency is the run's: Hairer's
/// form (a square root, a power, three divisions) took about twice as long as a logarithm,
/// an exponential and a multiplication. The step sizes differ from it in the last bits.
struct Controller {
    /// The logarithm of the error of the last accepted step (at least LN_FACOLD_MIN).
    ln_facold: f64,
    /// After a rejection the next accepted step may not grow: the rejection just showed that
    /// a larger step fails.
    after_rejection: bool,
}

impl Controller {
    fn new() -> Self {
        Controller {
            ln_facold: LN_FACOLD_MIN,
            after_rejection: false,
        }
    }

    /// The next step size after a step of size h with squared error err2 ≤ 1 was accepted.
    #[inline]
    fn accepted(&mut self, h: f64, err2: f64, hmax: f64) -> f64 {
        // What does not depend on this step's error first, computed while it is still being
        // summed.
        let old = BETA * self.ln_facold;
        let (hs, lo, hi) = (h * SAFETY, h * FAC1, h * FAC2);
        let ln_err = 0.5 * err2.ln();
        // Compared rather than `max`/`min`: no NaN can arise (err2 ≤ 1), and the comparisons
        // are one instruction each.
        let h_new = hs * (old - EXPO1 * ln_err).exp();
        let h_new = if h_new < lo { lo } else { h_new };
        let h_new = if h_new > hi { hi } else { h_new };
        let mut h_new = if h_new > hmax { hmax } else { h_new };
        self.ln_facold = ln_err.max(LN_FACOLD_MIN);
        if self.after_rejection {
            h_new = h_new.min(h);
        }
        self.after_rejection = false;
        h_new
    }

    /// The retry step size after a step of size h was rejected with squared error err2 > 1
    /// (or NaN: a non-finite stage, which the largest reduction answers):
    /// h·max(SAFETY/err^EXPO1, FAC1).
    fn rejected(&mut self, h: f64, err2: f64) -> f64 {
        self.after_rejection = true;
        let shrink = SAFETY * (-0.5 * EXPO1 * err2.ln()).exp();
        // `max` takes FAC1 over a NaN.
        h * shrink.max(FAC1)
    }
}

impl<V: Vector> Interpolant<V> for Dense<V> {
    fn at(&self, t: f64) -> V {
        Dense::at(self, t)
    }
}

impl Integrator for DormandPrince {
    fn integrate_observed<O: Ode, T: SampleTimes + ?Sized>(
        &self,
        ode: &mut O,
        t0: f64,
        x0: &O::State,
        samples: &T,
        observer: &mut dyn Observer<O::State>,
    ) -> Result<Stats, Error> {
        self.check_settings()?;
        check_problem(ode, t0, x0, samples)?;
        let mut stats = Stats::default();
        let mut samples = Samples {
            times: samples,
            next: 0,
            observer,
        };
        if let Some(s) = samples.report_start(t0, x0)? {
            stats.stopped = Some(s);
            return Ok(stats);
        }
        let Some(t_end) = samples.upcoming().map(|_| samples.times.last()) else {
            return Ok(stats);
        };
        // A step too small for the span is an error now, not after the steps it allows.
        let smallest = self.fixed_step.unwrap_or(self.max_step);
        let needed = ((t_end - t0) / smallest).ceil();
        if needed > self.max_steps as f64 {
            return Err(too_many_steps_planned(ode, t0, smallest, x0, needed));
        }
        if self.fixed_step.is_none() {
            check_span(ode, t0, t_end, x0)?;
            settings::check_span_floor(&self.settings(), t0, t_end)?;
        }

        let mut k: Stages<O::State> = [O::State::zeros(); 7];
        ode.rhs(t0, x0, &mut k[0])?;
        stats.evaluations += 1;
        let watching = samples.observer.watches_steps();
        let reads_inside = watching && samples.observer.reads_inside_steps();
        let mut run = Run {
            ode,
            samples,
            stats,
            k,
            watching,
            reads_inside,
        };
        match self.fixed_step {
            Some(h) => self.fixed(&mut run, (t0, *x0), (h, t_end))?,
            None => self.adaptive(&mut run, (t0, *x0), t_end)?,
        }
        Ok(run.stats)
    }
}

/// One integration: the ODE, the samples and their observer, the cost so far and the stages
/// of the current step.
struct Run<'a, O: Ode, T: ?Sized> {
    ode: &'a mut O,
    samples: Samples<'a, T, O::State>,
    stats: Stats,
    k: Stages<O::State>,
    /// Whether the observer watches steps: asked once, before the first step (as RK4 does).
    watching: bool,
    /// Whether it reads the solution inside them.
    reads_inside: bool,
}

impl<O: Ode, T: SampleTimes + ?Sized> Run<'_, O, T> {
    /// Completes an accepted step from (t, y) to t1 whose result is `y1`: checks it, projects
    /// it (`Ode::project`), reports it (if the observer watches steps) and the samples it
    /// covers, and makes `k[0]` the slope the next step starts from: the step's last stage
    /// (FSAL), or, if the projection moved the state, a new evaluation there, counted (none
    /// after the `last` step). Makes `y` the state the next step starts from and returns
    /// true, or returns false when the observer stopped the integration. (The state is
    /// written in place: returned, it was copied twice a step.)
    fn complete(
        &mut self,
        (t, y): (f64, &mut O::State),
        (t1, last): (f64, bool),
        y1: &O::State,
        h: f64,
    ) -> Result<bool, Error> {
        check_state(&*self.ode, t1, y1)?;
        self.stats.steps += 1;
        let mut y1_projected = *y1;
        let moved = self.ode.project(t1, &mut y1_projected)?;
        let (k, y_start) = (&self.k, &*y);
        // The continuous extension interpolates the step's own result, before projection.
        let extension = || Dense::new(t, h, (y_start, y1), k);
        // Formed at once for an observer that reads inside the step (events), and read in
        // place for the samples too (moving it, 5n values, cost a copy a step).
        let watched = self.reads_inside.then(extension);
        let stop = if self.watching {
            // For an observer that does not read inside the step, formed only if read.
            let lazy;
            let dense: &dyn Interpolant<O::State> = match &watched {
                Some(dense) => dense,
                None => {
                    lazy = LazyInterpolant::new(extension);
                    &lazy
                }
            };
            let view = StepView {
                t,
                x: y_start,
                t1,
                x1: &y1_projected,
                dense,
            };
            match self.samples.observer.step(&view)? {
                Control::Continue => None,
                Control::Stop(ts) => Some(ts.clamp(t, t1)),
            }
        } else {
            None
        };
        // Otherwise evaluated where a sample falls inside the step, without forming it.
        let at = |s| match &watched {
            Some(dense) => dense.at(s),
            None => Dense::value(t, h, (y_start, y1), k, s),
        };
        let stopped = self
            .samples
            .report(&mut *self.ode, (t1, &y1_projected), at, stop)?;
        if stopped.is_some() {
            self.stats.stopped = stopped;
            return Ok(false);
        }
        if moved && !last {
            self.ode.rhs(t1, &y1_projected, &mut self.k[0])?;
            self.stats.evaluations += 1;
        } else {
            self.k[0] = fresh(&self.k[6]);
        }
        *y = y1_projected;
        Ok(true)
    }
}

/// The error for a run that gave up after a step of size `h` from (t, y) met a right-hand
/// side value that is not a number: that step taken again, its stages watched, and the value
/// named (or `otherwise`, if the stages are all finite this time). Cold: only a failing run
/// gets here, so the stages of every other step are not watched.
#[cold]
fn non_finite_cause<O: Ode>(
    ode: &mut O,
    (t, y): (f64, &O::State),
    k: &Stages<O::State>,
    h: f64,
    otherwise: Error,
) -> Error {
    if let Some(found) = NonFinite::check(t, y, &k[0]) {
        return found.error(ode);
    }
    let mut watched = Watched::new(ode);
    let mut stages = *k;
    let _ = attempt(&mut watched, t, y, &mut stages, h, &mut Stats::default());
    watched.explain(otherwise)
}

impl DormandPrince {
    fn adaptive<O: Ode, T: SampleTimes + ?Sized>(
        &self,
        run: &mut Run<'_, O, T>,
        (t0, y0): (f64, O::State),
        t_end: f64,
    ) -> Result<(), Error> {
        let hmax = self.max_step.min(t_end - t0);
        let floor = self.min_step * (t_end - t0);
        let mut h = match self.initial_step {
            Some(h) => h.min(hmax),
            None => {
                let target = Target {
                    rtol: self.rtol,
                    atol: self.atol,
                    order: 4.0,
                    hmax,
                };
                initial_step(run.ode, (t0, &y0, &run.k[0]), target, &mut run.stats)?
            }
        };
        let mut controller = Controller::new();
        let (mut t, mut y) = (t0, y0);
        let len = run.ode.controlled_components();
        // The last step rejected for an error estimate that was not a number since the last
        // accepted one: if the step then underflows, the right-hand side's NaN is the cause.
        let mut nan_step = None;
        loop {
            let tried = run.stats.steps + run.stats.rejected;
            if tried >= self.max_steps {
                return Err(too_many_steps(&*run.ode, t, h, &y, tried));
            }
            // Below a few ulps of t the steps no longer advance; below the floor the run
            // would crawl: the solution (or the tolerance) asks for more than the method
            // can give.
            if h < UNDERFLOW_ULPS * f64::EPSILON * t.abs() || h < floor || h < 1e-300 {
                let underflow = Error::StepSizeUnderflow {
                    t,
                    h,
                    state: run.ode.describe(&y),
                };
                return Err(match nan_step {
                    Some(h_nan) => non_finite_cause(run.ode, (t, &y), &run.k, h_nan, underflow),
                    None => underflow,
                });
            }
            // Stretch the last step by up to 1% rather than leave a sliver (Hairer's rule).
            let last = t + 1.01 * h - t_end > 0.0;
            if last {
                h = t_end - t;
            }
            let y1 = attempt(run.ode, t, &y, &mut run.k, h, &mut run.stats)?;
            let err2 = error_norm_squared((&y, &y1), &run.k, h, (self.rtol, self.atol), len);
            if err2 <= 1.0 {
                let t1 = if last { t_end } else { t + h };
                // The next step size first: its logarithm and exponential, on which the next
                // step waits, then overlap the bookkeeping of this one (samples, dense output).
                let h_new = controller.accepted(h, err2, hmax);
                if !run.complete((t, &mut y), (t1, last), &y1, h)? {
                    return Ok(());
                }
                nan_step = None;
                t = t1;
                if last {
                    return Ok(());
                }
                h = h_new;
            } else {
                run.stats.rejected += 1;
                if err2.is_nan() {
                    nan_step = Some(h);
                }
                h = controller.rejected(h, err2);
            }
        }
    }

    fn fixed<O: Ode, T: SampleTimes + ?Sized>(
        &self,
        run: &mut Run<'_, O, T>,
        (t0, y0): (f64, O::State),
        (h_max, t_end): (f64, f64),
    ) -> Result<(), Error> {
        let mut y = y0;
        let (n, h) = equal_steps(t_end - t0, h_max);
        for i in 0..n {
            // Times from the start, not accumulated; the last step ends exactly on t_end.
            let t = t0 + i as f64 * h;
            let t1 = if i + 1 < n {
                t0 + (i + 1) as f64 * h
            } else {
                t_end
            };
            let y1 = attempt(run.ode, t, &y, &mut run.k, h, &mut run.stats)?;
            if !run.complete((t, &mut y), (t1, i + 1 == n), &y1, h)? {
                return Ok(());
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ẏ = (cos t, −sin t) with y(0) = (0, 1): y = (sin t, cos t).
    struct Circle;

    impl Ode for Circle {
        type State = [f64; 2];

        fn rhs(&mut self, t: f64, _y: &[f64; 2], dy: &mut [f64; 2]) -> Result<(), Error> {
            *dy = [t.cos(), -t.sin()];
            Ok(())
        }
    }

    #[test]
    fn tableau_rows_sum_to_their_nodes() {
        let rows: [(&[f64], f64); 6] = [
            (&[A21], C2),
            (&[A31, A32], C3),
            (&[A41, A42, A43], C4),
            (&[A51, A52, A53, A54], C5),
            (&[A61, A62, A63, A64, A65], 1.0),
            (&[A71, A73, A74, A75, A76], 1.0),
        ];
        for (row, c) in rows {
            assert!(
                (row.iter().sum::<f64>() - c).abs() < 1e-14,
                "row {row:?} should sum to {c}"
            );
        }
        // Both orders are consistent, so the error weights sum to zero; so do the dense
        // coefficients (the θ⁴ term must vanish for y' = const).
        assert!((E1 + E3 + E4 + E5 + E6 + E7).abs() < 1e-15);
        assert!((D1 + D3 + D4 + D5 + D6 + D7).abs() < 1e-12);
    }

    #[test]
    fn continuous_extension_interpolates_the_step() {
        let mut stats = Stats::default();
        let (t, y, h) = (0.3, [0.3f64.sin(), 0.3f64.cos()], 0.25);
        let mut k = [[0.0; 2]; 7];
        Circle.rhs(t, &y, &mut k[0]).unwrap();
        let y1 = attempt(&mut Circle, t, &y, &mut k, h, &mut stats).unwrap();
        let dense = Dense::new(t, h, (&y, &y1), &k);
        assert_eq!(dense.at(t), y);
        for (a, b) in dense.at(t + h).iter().zip(&y1) {
            // y + (y1 − y): equal up to the rounding of the difference.
            assert!((a - b).abs() <= 2.0 * f64::EPSILON);
        }
        // Inside the step: fourth order, local error O(h⁵) ≈ 1e-3 · small constant.
        for theta in [0.1, 0.37, 0.5, 0.81] {
            let s = t + theta * h;
            let v = dense.at(s);
            assert!(
                (v[0] - s.sin()).abs() < 1e-7 && (v[1] - s.cos()).abs() < 1e-7,
                "θ = {theta}: {v:?}"
            );
        }
    }

    #[test]
    fn controller_bounds_and_memory() {
        assert_eq!(LN_FACOLD_MIN, 1e-4f64.ln());
        let mut c = Controller::new();
        // A tiny error lets the step grow by at most FAC2.
        assert_eq!(c.accepted(1.0, 0.0, f64::INFINITY), FAC2);
        // A huge error shrinks it by at most FAC1 ...
        assert_eq!(c.rejected(1.0, 1e30), FAC1);
        assert_eq!(c.rejected(1.0, f64::NAN), FAC1);
        // ... and the next accepted step may not grow beyond the rejected one.
        assert_eq!(c.accepted(0.5, 1e-8, f64::INFINITY), 0.5);
        assert!(c.accepted(0.5, 1e-8, f64::INFINITY) > 0.5);
        assert_eq!(c.accepted(0.5, 1e-8, 0.25), 0.25);
    }

    /// The logarithmic form gives Hairer's step sizes (DOPRI5: fac = err^EXPO1/facold^β,
    /// bounded to [1/FAC2, 1/FAC1] after division by SAFETY, h_new = h/fac) to rounding.
    #[test]
    fn controller_gives_hairers_step_sizes() {
        let close = |ours: f64, hairer: f64| (ours - hairer).abs() <= 1e-14 * hairer;
        let mut c = Controller::new();
        let mut facold: f64 = 1e-4;
        for err in [1e-12_f64, 3e-7, 0.01, 0.2, 0.5, 0.93, 1.0, 1e-3, 0.7, 1e-9] {
            let fac = (err.powf(EXPO1) / facold.powf(BETA) / SAFETY).clamp(1.0 / FAC2, 1.0 / FAC1);
            let ours = c.accepted(0.1, err * err, f64::INFINITY);
            assert!(
                close(ours, 0.1 / fac),
                "err {err}: {ours} against {}",
                0.1 / fac
            );
            facold = err.max(1e-4);
        }
        for err in [1.0001_f64, 2.0, 30.0, 1e4] {
            let hairer = 0.1 / (err.powf(EXPO1) / SAFETY).min(1.0 / FAC1);
            let ours = c.rejected(0.1, err * err);
            assert!(close(ours, hairer), "err {err}: {ours} against {hairer}");
        }
    }

    #[test]
    fn all_samples_at_the_start_cost_nothing() {
        let mut seen = 0;
        let stats = DormandPrince::new(1e-6, 1e-6)
            .integrate(&mut Circle, 1.0, &[0.0, 0.0], &[1.0, 1.0], &mut |_, _| {
                seen += 1;
                Ok(())
            })
            .unwrap();
        assert_eq!((seen, stats), (2, Stats::default()));
    }
}
