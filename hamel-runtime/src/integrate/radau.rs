//! Radau IIA of order 5 with step-size control, for stiff systems (stiff springs and
//! dampers, tyre and motor models): after Hairer's RADAU5 (Hairer & Wanner, *Solving Ordinary
//! Differential Equations II*, IV.8) — the same error estimate, Newton stopping test (its
//! test for an iteration that will not converge as Hairer & Wanner state it, as scipy's does),
//! predictive (Gustafsson) step-size controller, Jacobian reuse and tolerance convention,
//! and the same transformed stage equations: one real and one complex system of n equations
//! ([`super::radau_stages`]). An earlier version solved one real system of 3n equations, the
//! same iterates in exact arithmetic; at n = 8 (HIRES) and n = 20 (the pollution model) it was
//! 8 to 11 times slower than diffsol's BDF at equal error (`benches/work_precision.rs`).
//!
//! Why not a crate: diffsol (0.18, BDF and SDIRK methods) was measured
//! (`benches/diffsol_build_cost.sh`): with only its nalgebra backend it still brings 83 more
//! crates (faer among them) and added 79 s of CPU time to a fresh debug build and 110 s to a
//! release one, beside 16 s and 19 s for nalgebra and num-dual alone; and it fits badly: its
//! right-hand side cannot return an error (a singular configuration would have to become NaN),
//! it has no projection hook, and it takes the Jacobian as a Jacobian-vector product that it
//! colours into a matrix by repeated calls, each of which would cost a whole dual-number
//! Jacobian here. The scheme is written on nalgebra's LU instead.

use super::collocation::{Collocation, Tableau, extrapolate};
use super::differences::Jacobian;
use super::initial_step::{Target, initial_step};
use super::newton::{Criterion, Outcome};
use super::observer::{Control, Interpolant, Observer, SampleTimes, StepView};
use super::radau_stages::TransformedStages;
use super::sampling::Samples;
use super::settings::{self, Adaptive, RtolFloor};
use super::{
    Integrator, MAX_STEPS, Ode, Stats, Watched, check_problem, check_span, check_state,
    too_many_steps,
};
use crate::error::Error;
use crate::vector::Vector;

/// Radau IIA (3 stages, order 5, L-stable, stiffly accurate) with error control: for systems
/// whose fast, strongly damped motions force an explicit method into tiny steps whatever the
/// tolerance. Its steps follow the slow motion; each solves 3n implicit equations by
/// simplified Newton on the Jacobian ([`Ode::jacobian`]: for a simulation, the system's exact
/// one), which it evaluates afresh only when the iteration slows down (contracts by more than
/// 0.001 per iteration; a Jacobian by differences, which costs n evaluations, only when the
/// iteration also took more than two, and by more than 0.1 for ten or more components), and
/// keeps its step size, and so its LU factorizations, unless the Jacobian is renewed or the
/// step would grow by more than 1.2. At tolerances looser than about 10⁻⁶,
/// [`super::Rodas5P`] is usually faster on the exact Jacobian (`hamel::docs::running`,
/// "Which stiff method").
///
/// The tolerances are RADAU5's: rtol and atol are mapped to 0.1·rtol^(2/3) and
/// 0.1·rtol^(2/3)·atol/rtol before the local error is held to them. The global error is then
/// not rtol: on the standard stiff test set it came out between 0.06 and 13 times rtol, on
/// stiff mechanical models up to 900 times (measured per problem in
/// `hamel::docs::running`). Samples
/// inside a step come from the collocation polynomial (third order, as RADAU5's CONTR5),
/// projected; the integrator never shortens a step to hit a sample.
///
/// The first step is estimated from the problem, and the smallest step is relative to |t|
/// (`min_step`), so a run over 10¹¹ s starts with the microsecond steps its transient needs.
/// A step whose Newton iteration fails (diverges, or by Hairer & Wanner's prediction will not
/// converge in the iterations left) is retried half as long on a fresh Jacobian, and with a
/// fresh Jacobian and RADAU5's reduction on an old one; ten failures in a
/// row with a fresh Jacobian, or more such failures than accepted steps (the iteration, not
/// the tolerance, setting the step), end the run with an [`Error::NewtonNotConverged`]. A
/// singular iteration matrix halves the step, and five in a row are an
/// [`Error::SingularIterationMatrix`] naming the growing motion that makes it singular (a
/// stable system never does, however large the step). A step below the floor is an
/// [`Error::StepSizeUnderflow`]. Every error names t, h and the state.
///
/// ```
/// use hamel_runtime::{Integrator, Ode, Error, Radau5};
///
/// /// y′ = −10⁶ (y − cos t): after a transient of a microsecond y follows cos t closely,
/// /// y ≈ cos t + 10⁻⁶ sin t; an explicit method would need millions of steps for 10 s.
/// struct Stiff;
/// impl Ode for Stiff {
///     type State = [f64; 1];
///     fn rhs(&mut self, t: f64, y: &[f64; 1], dy: &mut [f64; 1]) -> Result<(), Error> {
///         dy[0] = -1e6 * (y[0] - t.cos());
///         Ok(())
///     }
/// }
///
/// let mut end = 0.0;
/// let stats = Radau5::new(1e-10, 1e-10).integrate(&mut Stiff, 0.0, &[1.0], &[10.0], &mut |_, y| {
///     end = y[0];
///     Ok(())
/// })?;
/// // RADAU5's tolerance convention holds the local error to 0.1·rtol^(2/3) ≈ 2·10⁻⁸; on a
/// // problem this stiff the global error stays at that level (3·10⁻⁸ here) instead of
/// // accumulating, so it is not near rtol: the guide lists the factor measured per problem.
/// assert!((end - (10f64.cos() + 1e-6 * 10f64.sin())).abs() < 1e-7);
/// // 14 steps, about a hundred evaluations.
/// assert!(stats.evaluations < 200, "{stats:?}");
/// # Ok::<(), hamel_runtime::Error>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Radau5 {
    /// Relative tolerance (> 10 ε).
    pub rtol: f64,
    /// Absolute tolerance (> 0).
    pub atol: f64,
    /// The first step size; `None` estimates it from the problem (Hairer's HINIT, as
    /// scipy's `Radau` does): a fixed first step fits no problem whose time scale is far from
    /// it (Robertson's problem over 4·10¹⁰ s).
    pub initial_step: Option<f64>,
    /// The largest step allowed.
    pub max_step: f64,
    /// The most steps (accepted and rejected) an integration may take.
    pub max_steps: usize,
    /// The smallest step allowed, relative to |t| where it is taken (in [0, 1); and never
    /// below 16 ulps of t). Relative to |t| and not to the span: a stiff transient at the
    /// start of a long span needs steps far below any fixed fraction of the span (RADAU5 and
    /// scipy bound the step by |t| alone).
    pub min_step: f64,
    /// The most Newton iterations per step (RADAU5's NIT, 7).
    pub max_iterations: usize,
}

/// RADAU5's constants: the safety factor, the bounds of a step's change (h/5 … 8h), the
/// contraction below which the Jacobian is kept, and the band of step ratios that keep the
/// step (and so the factorization) unchanged.
const SAFE: f64 = 0.9;
const FACL: f64 = 5.0;
const FACR: f64 = 0.125;
const THET: f64 = 0.001;
/// The same for a Jacobian by differences of a system of [`COSTLY_DIFFERENCES`] components
/// or more: RADAU5's advice (its WORK(3): 0.001 for small systems, "increase to 0.1, say,
/// when Jacobian evaluations are costly"). Such a Jacobian costs n evaluations, an iteration
/// three: the iteration then converges a little more slowly on an older Jacobian instead of
/// paying n evaluations after nearly every step. Measured (`benches/work_precision`): on
/// POLLU (n = 20) 0.1 takes the evaluations from 1.48 to 0.90 times scipy's `Radau` by
/// differences at equal error; on ROBER (n = 3) from 1.01 to 1.29, and Robertson's y₁ at
/// 4·10¹⁰ from 1.5·10⁻⁵ to 1.8·10⁻⁴ of its value; HIRES (n = 8) about even.
const THET_DIFFERENCED: f64 = 0.1;

/// The size from which a Jacobian by differences counts as costly ([`THET_DIFFERENCED`]).
const COSTLY_DIFFERENCES: usize = 10;
/// RADAU5's stretch of a step that nearly reaches the end (its QUOT1).
const QUOT1: f64 = 1.0;
/// The largest growth of the step that still keeps it, and so its factorization, after a
/// step on which the Jacobian is kept (RADAU5's QUOT2). Below it the step is kept whatever
/// the controller proposes, shrinking included, as scipy's `Radau` does (RADAU5 keeps it only
/// for ratios in [1, 1.2] and factors afresh for a step 1 % smaller). An accepted step's
/// proposal to shrink comes from an error estimate near the tolerance (or the predictive
/// controller's caution), and the same step again mostly passes: measured
/// (`benches/work_precision`, `once PROBLEM "hamel Radau5"`, rtol 10⁻³…10⁻¹⁰), the
/// factorizations fall by up to 59 % (VDPOL at 10⁻¹⁰, 3434 to 1412), 38 % (OREGO), 10 %
/// (HIRES), with the evaluations within ±4 % and the worst error per rtol the same or
/// smaller on all five test-set problems; the rejections rise (VDPOL 4 to 19 at 10⁻¹⁰).
const QUOT2: f64 = 1.2;

impl Radau5 {
    /// Adaptive steps with these tolerances.
    pub fn new(rtol: f64, atol: f64) -> Self {
        Radau5 {
            rtol,
            atol,
            initial_step: None,
            max_step: f64::INFINITY,
            max_steps: MAX_STEPS,
            min_step: Self::MIN_STEP,
            max_iterations: 7,
        }
    }

    /// The default floor on a step, relative to |t|: 10⁻¹⁴ of it, about 45 ulps.
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

    fn check_settings(&self) -> Result<(), Error> {
        let floor = RtolFloor {
            value: 10.0 * f64::EPSILON,
            inclusive: false,
            reason: "the relative tolerance of Radau5 must be a finite number above 10 ε ≈ \
                     2.2e-15 (its error control works with rtol^(2/3))",
        };
        settings::check(&self.settings(), floor)?;
        if self.max_iterations < 2 {
            return Err(Error::InvalidSetting {
                name: "max iterations",
                value: self.max_iterations as f64,
                reason: "the Newton iteration needs at least 2 iterations to measure its \
                         convergence",
            });
        }
        Ok(())
    }
}

impl Integrator for Radau5 {
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
        settings::check_relative_floor(&self.settings(), t0, t_end)?;
        let tableau = Tableau::radau_iia();
        let mut run = Run::new(self, &tableau, ode, (t0, x0), t_end)?;
        run.integrate(&mut samples)?;
        Ok(run.stats)
    }
}

/// The constants of RADAU5's error estimate: the weights of the stage increments in the
/// embedded formula (its DD1…DD3); its matrix (u₁/h) I − J, u₁ the real eigenvalue of A⁻¹, is
/// the transformed iteration's real one ([`TransformedStages::solve_real`]).
struct Estimate {
    dd: [f64; 3],
}

impl Estimate {
    fn new() -> Self {
        let r = 6f64.sqrt();
        Estimate {
            dd: [-(13.0 + 7.0 * r) / 3.0, (-13.0 + 7.0 * r) / 3.0, -1.0 / 3.0],
        }
    }
}

/// RADAU5's step quotient h/h_new after a step of error `err`: its standard controller,
/// err^(1/4)/fac, and, after an accepted step that follows another, Gustafsson's predictive
/// one, (h_acc/h)·(err²/err_acc)^(1/4)/SAFE, each clamped to [FACR, FACL] and the larger
/// taken. Each costs a `powf` (some 125 instructions, a few per cent of a small system's
/// step), taken only where the result needs it: which controller gives the larger quotient,
/// and whether it surely keeps the step ([`Run::next_step`]), are read off their fourth
/// powers, err/fac⁴ and (h_acc/h/SAFE)⁴·err²/err_acc, wherever those differ by more than
/// any rounding of either side (a relative [`FOURTH_POWER_MARGIN`] against a few units of
/// 10⁻¹⁶). What is computed is then what computing both gives, to the bit.
struct Quotient {
    err: f64,
    fac: f64,
    /// Gustafsson's h_acc/h and err²/err_acc, where his controller applies.
    predictive: Option<(f64, f64)>,
}

/// The relative difference between fourth powers beyond which [`Quotient`] orders the
/// quotients they stand for without computing them.
const FOURTH_POWER_MARGIN: f64 = 1e-9;

impl Quotient {
    fn standard(&self) -> f64 {
        FACR.max(FACL.min(self.err.powf(0.25) / self.fac))
    }

    /// The fourth power of the standard quotient before its clamps.
    fn standard_fourth(&self) -> f64 {
        self.err / self.fac.powi(4)
    }

    /// The quotient: the larger of the two controllers' (the standard one's alone without
    /// Gustafsson's).
    fn value(&self) -> f64 {
        let Some((ratio, squared)) = self.predictive else {
            return self.standard();
        };
        let predictive = || (ratio * squared.powf(0.25) / SAFE).clamp(FACR, FACL);
        let (standard, gustafsson) = (self.standard_fourth(), (ratio / SAFE).powi(4) * squared);
        // Both finite and normal numbers: their relative roundings are a few ulps.
        let ordered = |a: f64, b: f64| a.is_finite() && b.is_finite() && a.min(b) > 1e-290;
        if ordered(standard, gustafsson) {
            // The clamps keep the order: the larger one before them is the larger after.
            if standard > gustafsson * (1.0 + FOURTH_POWER_MARGIN) {
                return self.standard();
            }
            if gustafsson > standard * (1.0 + FOURTH_POWER_MARGIN) {
                return predictive();
            }
        }
        self.standard().max(predictive())
    }

    /// Whether the quotient is surely above `q` (in (FACR, FACL)), whatever the rounding of
    /// its `powf`s; `false` where that is not clear.
    fn surely_above(&self, q: f64) -> bool {
        let bound = q.powi(4) * (1.0 + FOURTH_POWER_MARGIN);
        let above = |fourth: f64| fourth.is_finite() && fourth > bound;
        above(self.standard_fourth())
            || self
                .predictive
                .is_some_and(|(ratio, squared)| above((ratio / SAFE).powi(4) * squared))
    }
}

/// One Radau5 integration.
struct Run<'a, 't, O: Ode> {
    method: &'a Radau5,
    tableau: &'t Tableau<3>,
    /// The ODE, its right-hand side's values watched for NaN (named when the run ends).
    ode: Watched<'a, O>,
    stats: Stats,
    /// The Jacobian, evaluated afresh when the iteration slows down.
    jacobian: Jacobian,
    /// The factored matrices of RADAU5's transformed iteration (the real one is the error
    /// estimate's too).
    stages: TransformedStages<O::State>,
    estimate: Estimate,
    /// The tolerances as RADAU5 transforms them, and its Newton tolerance.
    rtol: f64,
    atol: f64,
    fnewt: f64,
    t: f64,
    y: O::State,
    /// RADAU5's scale at y, atol + rtol·|yᵢ|: formed once for each y, for every attempt
    /// at the step and its error estimate.
    scale: O::State,
    /// f(t, y).
    f0: O::State,
    t_end: f64,
    h: f64,
    hmax: f64,
    /// The last accepted step, for the starting values of the next.
    last: Option<Collocation<'t, O::State, 3>>,
    /// Gustafsson's controller: the last accepted step and its error.
    accepted: Option<(f64, f64)>,
    first: bool,
    reject: bool,
    /// The last Newton contraction rate, which decides whether the Jacobian is kept.
    theta: f64,
    /// What has failed so far, for the errors that end the run.
    failures: Failures,
}

/// The failures that step reduction answers, counted: past their limits, step reduction
/// has not rescued the integration and the run ends with the failure named.
#[derive(Default)]
struct Failures {
    /// Newton iterations that failed with a Jacobian evaluated at the step's start, since
    /// the last accepted step, and in all.
    newton_in_a_row: usize,
    newton: usize,
    /// Singular iteration matrices since the last accepted step (RADAU5's NSING).
    singular_in_a_row: usize,
}

/// Newton failures with a fresh Jacobian in a row, each followed by a smaller step (by at
/// least half), after which the run ends with [`Error::NewtonNotConverged`]: the step has
/// shrunk by 2¹⁰ or more and the stages still do not converge.
const NEWTON_FAILURES_IN_A_ROW: usize = 10;

/// Newton failures with a fresh Jacobian in all, once they outnumber the accepted steps,
/// after which the run ends with [`Error::NewtonNotConverged`]: every few steps the
/// iteration fails again at a step the error estimate allows, so the iteration, not the
/// tolerance, sets the step. With a correct Jacobian simplified Newton fails on a few per
/// cent of the steps; with a wrong one the run would crawl to the step limit.
const NEWTON_FAILURES_SUSTAINED: usize = 50;

/// Singular iteration matrices in a row, each followed by a step half as long, after which
/// the run ends with [`Error::SingularIterationMatrix`] (RADAU5 gives up after 5 too).
const SINGULAR_IN_A_ROW: usize = 5;

/// RADAU5's scale of each component of y: atol + rtol·|yᵢ| (transformed tolerances).
fn scale<V: Vector>(rtol: f64, atol: f64, y: &V) -> V {
    let mut scale = V::zeros();
    for (s, v) in scale.as_mut().iter_mut().zip(y.as_ref()) {
        *s = atol + rtol * v.abs();
    }
    scale
}

/// A step's stage increments and the Newton iterations they took.
type Solved<V> = ([V; 3], usize);

/// What the step size does after an accepted step.
enum Next {
    Done,
    Continue,
}

impl<'a, 't, O: Ode> Run<'a, 't, O> {
    fn new(
        method: &'a Radau5,
        tableau: &'t Tableau<3>,
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
        let rtol = 0.1 * method.rtol.powf(2.0 / 3.0);
        let atol = rtol * method.atol / method.rtol;
        let fnewt = (10.0 * f64::EPSILON / rtol).max(0.03f64.min(rtol.sqrt()));
        let mut stats = Stats::default();
        let mut f0 = O::State::zeros();
        ode.rhs(t0, x0, &mut f0)?;
        stats.evaluations += 1;
        let h = match method.initial_step {
            Some(h) => h.min(hmax),
            None => {
                // Radau5's error estimate is of order 3 (scipy's choice for its Radau).
                let target = Target {
                    rtol: method.rtol,
                    atol: method.atol,
                    order: 3.0,
                    hmax,
                };
                initial_step(ode, (t0, x0, &f0), target, &mut stats)?
            }
        };
        let controlled = ode.controlled_components();
        let scale = scale(rtol, atol, x0);
        Ok(Run {
            method,
            tableau,
            ode: Watched::new(ode),
            stats,
            jacobian: Jacobian::new(O::State::LEN, method.atol),
            stages: TransformedStages::new(controlled, tableau),
            estimate: Estimate::new(),
            rtol,
            atol,
            fnewt,
            t: t0,
            y: *x0,
            scale,
            f0,
            t_end,
            h,
            hmax,
            last: None,
            accepted: None,
            first: true,
            reject: false,
            theta: 0.0,
            failures: Failures::default(),
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
        self.evaluate_jacobian()?;
        // Stretch a first step that nearly reaches the end (RADAU5's rule).
        let mut last = self.t + self.h * QUOT1 >= self.t_end;
        if last {
            self.h = self.t_end - self.t;
        }
        loop {
            let (t, y, h) = (self.t, self.y, self.h);
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
            let Some((z, iterations)) = self.attempt()? else {
                last = false;
                continue;
            };
            let err = match self.error(&z) {
                Ok(err) => err,
                Err(e @ Error::SingularIterationMatrix { .. }) => {
                    self.singular(e)?;
                    last = false;
                    continue;
                }
                Err(e) => return Err(e),
            };
            // RADAU5: a step that needed many iterations may not grow much.
            let nit = self.method.max_iterations as f64;
            let fac = SAFE.min(SAFE * (1.0 + 2.0 * nit) / (iterations as f64 + 2.0 * nit));
            let quotient = Quotient {
                err,
                fac,
                // Gustafsson's predictive controller, from the second accepted step on.
                predictive: match self.accepted {
                    Some((h_acc, err_acc)) if err < 1.0 => Some((h_acc / h, err * err / err_acc)),
                    _ => None,
                },
            };
            if err < 1.0 {
                self.accepted = Some((h, err.max(1e-2)));
                self.failures.newton_in_a_row = 0;
                self.failures.singular_in_a_row = 0;
                let t1 = if last { self.t_end } else { t + h };
                match self.accept(z, t1, last, samples)? {
                    Next::Done => return Ok(()),
                    Next::Continue => {}
                }
                let refresh = self.renew_jacobian(iterations);
                last = self.next_step(&quotient, refresh);
                self.jacobian.fresh = false;
                if refresh {
                    self.evaluate_jacobian()?;
                }
            } else {
                self.stats.rejected += 1;
                self.reject = true;
                last = false;
                self.h = if self.first {
                    0.1 * h
                } else {
                    h / quotient.value()
                };
                self.refresh_unless_fresh()?;
            }
        }
    }

    /// Sets the step after an accepted one, RADAU5's proposal being h / `quotient`; whether
    /// it is the last.
    fn next_step(&mut self, quotient: &Quotient, refresh: bool) -> bool {
        let h = self.h;
        // The step stays whatever the proposal when the Jacobian does, the quotient surely
        // keeps h_new/h below QUOT2 (h_new ≤ h/quotient, its clamps only lower it) and a step
        // of QUOT2·h would not reach the end: the branches below would keep it too.
        if !refresh
            && quotient.surely_above(1.0 / QUOT2)
            && self.t + h * QUOT2 * (1.0 + FOURTH_POWER_MARGIN) < self.t_end
        {
            self.reject = false;
            self.first = false;
            return false;
        }
        let mut h_new = (h / quotient.value()).min(self.hmax);
        if self.reject {
            h_new = h_new.min(h);
        }
        self.reject = false;
        self.first = false;
        if self.t + h_new * QUOT1 >= self.t_end {
            self.h = self.t_end - self.t;
            return true;
        }
        // Below a growth of QUOT2 the step, and so the factorization, is kept when the
        // Jacobian is.
        if refresh || h_new / h > QUOT2 {
            self.h = h_new;
        } else if self.t + h >= self.t_end {
            // The kept step, longer than the proposal, would pass the end.
            self.h = self.t_end - self.t;
            return true;
        }
        false
    }

    /// One attempt at the stages of the step h from (t, y), with the singular iteration
    /// matrices and failed iterations that step reduction answers answered: `None` after
    /// such a failure (the step reduced).
    fn attempt(&mut self) -> Result<Option<Solved<O::State>>, Error> {
        match self.solve_stages() {
            Err(e @ Error::SingularIterationMatrix { .. }) => {
                self.singular(e)?;
                Ok(None)
            }
            other => other,
        }
    }

    /// A singular iteration matrix at the current step: RADAU5 halves the step, and gives up
    /// (returning `e`) after [`SINGULAR_IN_A_ROW`] in a row.
    fn singular(&mut self, e: Error) -> Result<(), Error> {
        self.failures.singular_in_a_row += 1;
        if self.failures.singular_in_a_row >= SINGULAR_IN_A_ROW {
            return Err(self.ode.explain(e));
        }
        self.stats.rejected += 1;
        self.reject = true;
        self.h *= 0.5;
        self.refresh_unless_fresh()
    }

    /// Evaluates the Jacobian at the current point unless it was evaluated there.
    fn refresh_unless_fresh(&mut self) -> Result<(), Error> {
        if !self.jacobian.fresh {
            self.evaluate_jacobian()?;
        }
        Ok(())
    }

    /// Whether the Jacobian is evaluated afresh after an accepted step whose iteration took
    /// `iterations`: when the iteration contracted by more than [`Self::thet`] (RADAU5), and,
    /// for a Jacobian by differences, which costs n evaluations, only if it also needed more
    /// than two iterations (scipy's `Radau`, whose rule this is for every Jacobian). Measured
    /// on the test set by differences (`benches/work_precision`, `once PROBLEM "hamel Radau5
    /// (differences)"`, against scipy's `Radau` by differences at equal error, rtol
    /// 10⁻³…10⁻¹⁰): the largest ratio of evaluations falls on ROBER from 1.32 to 1.17, stays
    /// 1.40 on HIRES (one point; 0.96 since the first Jacobian's columns lost in rounding are
    /// differenced again, `differences.rs`), and 1.06–1.09 on VDPOL and OREGO; the
    /// factorizations fall by 10–40 %; Robertson's y₁ at 4·10¹⁰ comes out 1.2·10⁻⁵ off (was
    /// 1.5·10⁻⁵) in 1916 evaluations (was 2105; 2.2·10⁻⁵ in 1888 since a failed iteration on
    /// a fresh Jacobian halves the step, in 1890 since the first Jacobian's fix). With the
    /// exact Jacobian RADAU5's rule stays: there a Jacobian costs no evaluation, and scipy's
    /// rule took ROBER at 10⁻¹⁰ from 0.60 to 0.99 of scipy's evaluations at equal error.
    fn renew_jacobian(&self, iterations: usize) -> bool {
        self.theta > self.thet() && (!self.jacobian.differenced() || iterations > 2)
    }

    /// The contraction below which the Jacobian is kept after a step (RADAU5's THET).
    fn thet(&self) -> f64 {
        if self.jacobian.differenced() && O::State::LEN >= COSTLY_DIFFERENCES {
            THET_DIFFERENCED
        } else {
            THET
        }
    }

    /// Evaluates the Jacobian at the current point (t, y), where f is `f0`.
    fn evaluate_jacobian(&mut self) -> Result<(), Error> {
        let (t, y, f0) = (self.t, self.y, self.f0);
        self.jacobian
            .evaluate(&mut self.ode, t, &y, Some(&f0), &mut self.stats)
    }

    /// The stage increments of a step of size h from (t, y) and the iterations they took, or
    /// `None` after a failed iteration (the step size reduced, the Jacobian refreshed where
    /// it was old, and the attempt counted as rejected).
    fn solve_stages(&mut self) -> Result<Option<Solved<O::State>>, Error> {
        let (t, y, h) = (self.t, self.y, self.h);
        self.factor()?;
        let mut z = match &self.last {
            Some(last) if !self.first && last.t + last.h == t => extrapolate(last, &y, h),
            _ => [O::State::zeros(); 3],
        };
        let criterion = Criterion::Predicted {
            tolerance: self.fnewt,
            max_iterations: self.method.max_iterations,
        };
        let fresh = self.jacobian.fresh;
        let outcome = self.stages.iterate(
            &mut self.ode,
            self.tableau,
            (t, &y, h),
            &mut z,
            criterion,
            &self.scale,
            &mut self.stats,
        )?;
        match outcome {
            Outcome::Converged { iterations, rate } => {
                self.theta = rate;
                Ok(Some((z, iterations)))
            }
            Outcome::Failed {
                shrink,
                iterations,
                rate,
                increment,
            } => {
                if fresh {
                    self.newton_failed()?;
                    // Step reduction has not rescued it: the failure is the iteration's.
                    if self.failures.newton_in_a_row >= NEWTON_FAILURES_IN_A_ROW
                        || (self.failures.newton >= NEWTON_FAILURES_SUSTAINED
                            && self.failures.newton > self.stats.steps)
                    {
                        return Err(self.ode.explain(Error::NewtonNotConverged {
                            t,
                            h,
                            iterations,
                            increment,
                            rate,
                            state: self.ode.describe(&y),
                        }));
                    }
                }
                self.stats.rejected += 1;
                self.reject = true;
                // On a fresh Jacobian the step is too long for the iteration: halved (Hairer
                // & Wanner IV.8, scipy's `Radau`), so that the retry converges fast; on an old
                // one the Jacobian may be at fault, and it is renewed with RADAU5's milder
                // reduction. RADAU5's reduction after both took HIRES's retries to six or
                // seven iterations each; halving after both costs evaluations by differences
                // (OREGO's largest ratio to scipy's by differences 1.14 to 1.28).
                self.h *= if fresh { 0.5 } else { shrink };
                self.refresh_unless_fresh()?;
                Ok(None)
            }
        }
    }

    /// Counts a Newton failure with a Jacobian evaluated at the step's start.
    fn newton_failed(&mut self) -> Result<(), Error> {
        self.failures.newton_in_a_row += 1;
        self.failures.newton += 1;
        Ok(())
    }

    /// RADAU5's error estimate (ESTRAD): ((u₁/h) I − J)⁻¹ (f(y) + Σ eᵢ Zᵢ / h), measured
    /// in the controlled components; after a rejection or at the first step, when it is ≥ 1,
    /// once more through an evaluation at y + the estimate, which filters the stiff
    /// components.
    fn error(&mut self, z: &[O::State; 3]) -> Result<f64, Error> {
        let (t, y, h) = (self.t, self.y, self.h);
        let stages = &self.stages;
        // On the stack, solved in place: the estimate allocates nothing.
        let solve = |v: &mut O::State| stages.solve_real(v);
        let mut f2 = O::State::zeros();
        for (i, zi) in z.iter().enumerate() {
            for (f, v) in f2.as_mut().iter_mut().zip(zi.as_ref()) {
                *f += self.estimate.dd[i] / h * v;
            }
        }
        let mut cont = f2;
        for (c, v) in cont.as_mut().iter_mut().zip(self.f0.as_ref()) {
            *c += v;
        }
        solve(&mut cont);
        let mut err = self.error_norm(&cont);
        if err >= 1.0 && (self.first || self.reject) {
            let mut shifted = y;
            for (v, c) in shifted.as_mut().iter_mut().zip(cont.as_ref()) {
                *v += c;
            }
            let mut f1 = O::State::zeros();
            self.ode.rhs(t, &shifted, &mut f1)?;
            self.stats.evaluations += 1;
            for ((c, v), f) in cont.as_mut().iter_mut().zip(f1.as_ref()).zip(f2.as_ref()) {
                *c = v + f;
            }
            solve(&mut cont);
            err = self.error_norm(&cont);
        }
        // A NaN estimate (a stage where f overflowed) rejects the step.
        Ok(if err.is_nan() { f64::INFINITY } else { err })
    }

    /// √(mean((eᵢ/scᵢ)²)) over the controlled components, at least 10⁻¹⁰ (RADAU5).
    fn error_norm(&self, e: &O::State) -> f64 {
        let len = self.ode.controlled_components().min(O::State::LEN).max(1);
        // Slices of the controlled length zipped: no index checks in the loop.
        let sum: f64 = e.as_ref()[..len]
            .iter()
            .zip(&self.scale.as_ref()[..len])
            .map(|(e, s)| (e / s).powi(2))
            .sum();
        (sum / len as f64).sqrt().max(1e-10)
    }

    /// Factors the transformed iteration's matrices for the current h and Jacobian (unless
    /// done already); a singular one is an error naming the growing mode that makes it so.
    fn factor(&mut self) -> Result<(), Error> {
        let id = (self.h, self.jacobian.count());
        let singular =
            self.stages
                .factor(self.jacobian.matrix(), id, self.tableau, &mut self.stats);
        match singular {
            None => Ok(()),
            Some((growth, frequency)) => Err(Error::SingularIterationMatrix {
                t: self.t,
                h: self.h,
                growth,
                frequency,
                state: self.ode.describe(&self.y),
            }),
        }
    }

    /// Completes an accepted step to t1: checks, projects and reports it and the samples it
    /// covers, and moves on from it (with f there, unless it is the last).
    fn accept<T: SampleTimes + ?Sized>(
        &mut self,
        z: [O::State; 3],
        t1: f64,
        last: bool,
        samples: &mut Samples<'_, T, O::State>,
    ) -> Result<Next, Error> {
        let (t, y, h) = (self.t, self.y, self.h);
        let step = Collocation {
            tableau: self.tableau,
            t,
            h,
            y0: y,
            z,
        };
        let raw = self.tableau.end(&y, &z);
        check_state(&self.ode, t1, &raw)?;
        self.stats.steps += 1;
        // A value that was not finite at a rejected attempt is no longer a cause.
        self.ode.non_finite = None;
        let mut y1 = raw;
        self.ode.project(t1, &mut y1)?;
        let control = if samples.observer.watches_steps() {
            let view = StepView {
                t,
                x: &y,
                t1,
                x1: &y1,
                dense: &step,
            };
            samples.observer.step(&view)?
        } else {
            Control::Continue
        };
        let stop = match control {
            Control::Continue => None,
            Control::Stop(ts) => Some(ts.clamp(t, t1)),
        };
        let stop = samples.report(&mut self.ode, (t1, &y1), |s| step.at(s), stop)?;
        if stop.is_some() {
            self.stats.stopped = stop;
            return Ok(Next::Done);
        }
        self.last = Some(step);
        (self.t, self.y) = (t1, y1);
        self.scale = scale(self.rtol, self.atol, &y1);
        if last {
            return Ok(Next::Done);
        }
        self.ode.rhs(t1, &y1, &mut self.f0)?;
        self.stats.evaluations += 1;
        Ok(Next::Continue)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The quotient with its `powf`s taken only where needed is RADAU5's to the bit, and a
    /// quotient said to be surely above a bound is.
    #[test]
    fn the_step_quotient_is_radau5s() {
        let eager = |q: &Quotient| {
            let mut quot = FACR.max(FACL.min(q.err.powf(0.25) / q.fac));
            if let Some((ratio, squared)) = q.predictive {
                quot = quot.max((ratio * squared.powf(0.25) / SAFE).clamp(FACR, FACL));
            }
            quot
        };
        let mut checked = 0;
        for err in [1e-10f64, 3.7e-6, 0.004, 0.2, 0.5, 0.97, 1.0, 1.3, 40.0, 1e6] {
            for fac in [0.9f64, 0.9 * 15.0 / 17.0, 0.9 * 15.0 / 22.0] {
                // Ratios that put Gustafsson's quotient near the standard one, to a few ulps.
                let tie = SAFE * (err / fac.powi(4) / (err * err / 0.01)).powf(0.25);
                let mut ratios = vec![0.01, 0.3, 1.0, 2.5, 8.0, tie];
                for k in 1..4 {
                    ratios.push(tie * (1.0 + k as f64 * f64::EPSILON));
                    ratios.push(tie * (1.0 - k as f64 * f64::EPSILON));
                }
                for ratio in ratios {
                    for predictive in [None, Some((ratio, err * err / 0.01))] {
                        let q = Quotient {
                            err,
                            fac,
                            predictive,
                        };
                        assert_eq!(q.value().to_bits(), eager(&q).to_bits(), "{err} {ratio}");
                        for bound in [1.0 / QUOT2, 1.0, 0.3] {
                            if q.surely_above(bound) {
                                assert!(eager(&q) > bound, "{err} {fac} {ratio} {bound}");
                                checked += 1;
                            }
                        }
                    }
                }
            }
        }
        assert!(checked > 100, "{checked}");
    }

    #[test]
    fn the_estimate_constants_are_radau5s() {
        // RADAU5: U1 = 1/((6 + 81^(1/3) − 9^(1/3))/30), the real eigenvalue of A⁻¹.
        let u1 = super::super::radau_stages::Transformation::new(&Tableau::radau_iia()).gamma;
        assert!((u1 - 3.637_834_252_744_496).abs() < 1e-12);
        // The eigenvalue: det(A⁻¹ − u₁ I) = 0, i.e. det(I − u₁ A) = 0.
        let a = Tableau::radau_iia().a;
        let m = nalgebra::DMatrix::from_fn(3, 3, |i, j| {
            (if i == j { 1.0 } else { 0.0 }) - u1 * a[i][j]
        });
        assert!(m.determinant().abs() < 1e-12);
        // RADAU5's DD1…DD3.
        let dd = Estimate::new().dd;
        assert!((dd[0] + (13.0 + 7.0 * 6f64.sqrt()) / 3.0).abs() < 1e-15);
    }
}
