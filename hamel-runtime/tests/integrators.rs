//! The integrators against problems with known solutions: convergence orders, tolerance
//! proportionality on the Arenstorf orbit, Hairer's DOPRI5 step counts, dense output, and the
//! errors a user can run into.
//!
//! Run with `--nocapture` to see the measured figures.

use hamel_runtime::{
    DormandPrince, Error, GaussLegendre, ImplicitMidpoint, Integrator, Ode, Radau5, Rk4, Stats,
};

// The implicit methods' own tests (orders, symmetry, stiffness, their errors), sharing the
// problems below.
mod implicit;
// The Rosenbrock methods' (Rodas5P, Rodas4).
mod rosenbrock;

/// y' = −2ty², y(0) = 1: y = 1/(1 + t²). Non-autonomous and nonlinear.
struct Riccati;

impl Ode for Riccati {
    type State = [f64; 1];

    fn rhs(&mut self, t: f64, y: &[f64; 1], dy: &mut [f64; 1]) -> Result<(), Error> {
        dy[0] = -2.0 * t * y[0] * y[0];
        Ok(())
    }
}

fn riccati_exact(t: f64) -> f64 {
    1.0 / (1.0 + t * t)
}

/// y'' = −y, y(0) = 1, y'(0) = 0: y = cos t.
struct Oscillator;

impl Ode for Oscillator {
    type State = [f64; 2];

    fn rhs(&mut self, _t: f64, y: &[f64; 2], dy: &mut [f64; 2]) -> Result<(), Error> {
        *dy = [y[1], -y[0]];
        Ok(())
    }
}

/// The restricted three-body problem (Hairer, Nørsett & Wanner I, II.0): a satellite in the
/// rotating frame of earth and moon. With these initial values the orbit is periodic.
struct Arenstorf;

const MU: f64 = 0.012277471;
// The initial value and period as published (Hairer, Nørsett & Wanner), digit for digit.
#[allow(clippy::excessive_precision)]
const ARENSTORF_X0: [f64; 4] = [0.994, 0.0, 0.0, -2.00158510637908252240537862224];
#[allow(clippy::excessive_precision)]
const ARENSTORF_PERIOD: f64 = 17.0652165601579625588917206249;

impl Ode for Arenstorf {
    type State = [f64; 4];

    fn rhs(&mut self, _t: f64, y: &[f64; 4], dy: &mut [f64; 4]) -> Result<(), Error> {
        let mu1 = 1.0 - MU;
        let d1 = ((y[0] + MU).powi(2) + y[1].powi(2)).powf(1.5);
        let d2 = ((y[0] - mu1).powi(2) + y[1].powi(2)).powf(1.5);
        dy[0] = y[2];
        dy[1] = y[3];
        dy[2] = y[0] + 2.0 * y[3] - mu1 * (y[0] + MU) / d1 - MU * (y[0] - mu1) / d2;
        dy[3] = y[1] - 2.0 * y[2] - mu1 * y[1] / d1 - MU * y[1] / d2;
        Ok(())
    }
}

/// Integrates and returns the states at the sample times, with the statistics.
fn solve<O: Ode, I: Integrator>(
    method: &I,
    ode: &mut O,
    t0: f64,
    x0: O::State,
    samples: &[f64],
) -> Result<(Vec<O::State>, Stats), Error> {
    let mut states = Vec::new();
    let stats = method.integrate(ode, t0, &x0, samples, &mut |_, x| {
        states.push(*x);
        Ok(())
    })?;
    assert_eq!(states.len(), samples.len(), "one observation per sample");
    Ok((states, stats))
}

/// The least-squares slope of ln(error) against ln(h).
fn observed_order(h: &[f64], err: &[f64]) -> f64 {
    let xs: Vec<f64> = h.iter().map(|v| v.ln()).collect();
    let ys: Vec<f64> = err.iter().map(|v| v.ln()).collect();
    let n = xs.len() as f64;
    let (mx, my) = (xs.iter().sum::<f64>() / n, ys.iter().sum::<f64>() / n);
    let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx).powi(2)).sum();
    sxy / sxx
}

/// Global errors at the end time for a sequence of halved steps, and the fitted order.
fn convergence<I: Integrator, O: Ode>(
    label: &str,
    method: impl Fn(f64) -> I,
    mut ode: O,
    x0: O::State,
    t_end: f64,
    h0: f64,
    error: impl Fn(&O::State) -> f64,
) -> f64 {
    let hs: Vec<f64> = (0..5).map(|k| h0 / f64::powi(2.0, k)).collect();
    let errors: Vec<f64> = hs
        .iter()
        .map(|&h| {
            let (states, stats) = solve(&method(h), &mut ode, 0.0, x0, &[t_end]).unwrap();
            assert_eq!(
                stats.steps as f64,
                (t_end / h).round(),
                "{label}: fixed steps of {h}"
            );
            error(&states[0])
        })
        .collect();
    let order = observed_order(&hs, &errors);
    let shown: Vec<String> = errors.iter().map(|e| format!("{e:.3e}")).collect();
    println!("{label}: h = {hs:?}\n  errors = {shown:?}\n  observed order {order:.3}");
    order
}

#[test]
fn rk4_converges_with_order_four() {
    let riccati = convergence("RK4, Riccati", Rk4::new, Riccati, [1.0], 2.0, 0.2, |y| {
        (y[0] - riccati_exact(2.0)).abs()
    });
    let oscillator = convergence(
        "RK4, oscillator",
        Rk4::new,
        Oscillator,
        [1.0, 0.0],
        10.0,
        0.5,
        |y| (y[0] - 10f64.cos()).abs().max((y[1] + 10f64.sin()).abs()),
    );
    for order in [riccati, oscillator] {
        assert!((order - 4.0).abs() <= 0.3, "RK4 order {order}");
    }
}

#[test]
fn dormand_prince_with_fixed_steps_converges_with_order_five() {
    let fixed = |h| DormandPrince::new(1e-6, 1e-6).with_fixed_step(h);
    let riccati = convergence("DP5 fixed, Riccati", fixed, Riccati, [1.0], 1.0, 0.2, |y| {
        (y[0] - riccati_exact(1.0)).abs()
    });
    let oscillator = convergence(
        "DP5 fixed, oscillator",
        fixed,
        Oscillator,
        [1.0, 0.0],
        10.0,
        1.0,
        |y| (y[0] - 10f64.cos()).abs().max((y[1] + 10f64.sin()).abs()),
    );
    for order in [riccati, oscillator] {
        assert!((order - 5.0).abs() <= 0.3, "Dormand–Prince order {order}");
    }
}

/// Hairer's DOPRI5 driver `dr_dopri5.f` on the Arenstorf orbit, rtol = atol = 1e-7, automatic
/// initial step: (t, y1, y2) from its dense output, as printed (10 significant digits), and
/// its statistics line `tol=0.10D-06 fcn= 1442 step= 240 accpt= 216 rejct= 22`.
const HAIRER_ARENSTORF: [(f64, f64, f64); 9] = [
    (2.0, -0.5798781411E+00, 0.6090775251E+00),
    (4.0, -0.1983335270E+00, 0.1137638086E+01),
    (6.0, -0.4735743943E+00, 0.2239068118E+00),
    (8.0, -0.1174553350E+01, -0.2759466982E+00),
    (10.0, -0.8398073466E+00, 0.4468302268E+00),
    (12.0, 0.1314712468E-01, -0.8385751499E+00),
    (14.0, -0.6031129504E+00, -0.9912598031E+00),
    (16.0, 0.2427110999E+00, -0.3899948833E+00),
    (ARENSTORF_PERIOD, 0.9940021016E+00, 0.8911185692E-05),
];

#[test]
fn dormand_prince_reproduces_hairers_dopri5() {
    let times: Vec<f64> = HAIRER_ARENSTORF.iter().map(|r| r.0).collect();
    let (states, stats) = solve(
        &DormandPrince::new(1e-7, 1e-7),
        &mut Arenstorf,
        0.0,
        ARENSTORF_X0,
        &times,
    )
    .unwrap();
    println!("Arenstorf, tol 1e-7: {stats:?}");
    // Hairer's `rejct` leaves out rejections before the first accepted step; his `step`
    // (all attempts) = 240 = 216 accepted + 24 rejected. fcn = 2 (f(x0) and the initial-step
    // probe) + 6 per attempt.
    assert_eq!(
        stats,
        Stats {
            steps: 216,
            rejected: 24,
            evaluations: 1442,
            stopped: None,
            ..Stats::default()
        }
    );
    for ((t, y1, y2), y) in HAIRER_ARENSTORF.iter().zip(&states) {
        // The printed values are rounded to 10 digits: half a unit of the last one is at most
        // 5e-10 here; what remains is rounding in the two codes, far smaller.
        for (mine, his) in [(y[0], *y1), (y[1], *y2)] {
            assert!(
                (mine - his).abs() <= 5e-10,
                "t = {t}: {mine} vs DOPRI5's {his}"
            );
        }
    }

    // A given first step instead of the heuristic: no probe evaluation, and the step
    // sequence of dopri5.f with h = 1e-4 (217 accepted, 21 rejected, as russell_ode's
    // comparison with it records).
    let given = DormandPrince::new(1e-7, 1e-7).with_initial_step(1e-4);
    let (_, stats) = solve(
        &given,
        &mut Arenstorf,
        0.0,
        ARENSTORF_X0,
        &[ARENSTORF_PERIOD],
    )
    .unwrap();
    assert_eq!(
        stats,
        Stats {
            steps: 217,
            rejected: 21,
            evaluations: 1 + 6 * 238,
            stopped: None,
            ..Stats::default()
        }
    );
}

/// The distance of the state after one period from the initial state: (positions, full state).
fn arenstorf_closure(tol: f64) -> (f64, f64, Stats) {
    let method = DormandPrince::new(tol, tol);
    let (states, stats) = solve(
        &method,
        &mut Arenstorf,
        0.0,
        ARENSTORF_X0,
        &[ARENSTORF_PERIOD],
    )
    .unwrap();
    let diff: Vec<f64> = states[0]
        .iter()
        .zip(&ARENSTORF_X0)
        .map(|(a, b)| (a - b).abs())
        .collect();
    let position = diff[0].max(diff[1]);
    let state = diff.iter().copied().fold(0.0, f64::max);
    println!(
        "Arenstorf, rtol = atol = {tol:e}: closure error {position:.3e} (position), {state:.3e} (state), {stats:?}"
    );
    (position, state, stats)
}

/// The orbit passes close to the moon (it starts 0.006 from it), and there the flow is
/// violently sensitive: finite differences with rtol = 1e-14 give ∂y(T)/∂y(0) entries up to
/// 1.4e4 for the position and 2.2e6 for the velocity. Local error control keeps each step's
/// error near the tolerance, but the global error after a period is that of the whole
/// history, amplified by this sensitivity; "closes to the tolerance" can therefore only
/// mean a small multiple of those factors: we assert the position within 1e3·tol and the
/// full state within 1e5·tol (Hairer's DOPRI5 at tol 1e-7 misses the start position by
/// 8.9e-6 = 89·tol). What proves that the misses are integration error, not bad constants:
/// they fall in proportion to the tolerance.
#[test]
fn arenstorf_orbit_closes_in_proportion_to_the_tolerance() {
    let (position, state, stats) = arenstorf_closure(1e-10);
    assert!(position <= 1e-7, "position closure {position:e}");
    assert!(state <= 1e-5, "state closure {state:e}");
    assert_eq!(stats.evaluations, 2 + 6 * (stats.steps + stats.rejected));

    // Error ∝ tolerance would give a factor 100; the step-size rule makes it a little less
    // than proportional in general, so ask for 30.
    let (position_12, state_12, _) = arenstorf_closure(1e-12);
    assert!(position / position_12 >= 30.0 && state / state_12 >= 30.0);

    // Cost: Hairer's 240 attempts at 1e-7 scale like tol^(-1/5) to ~150 at 1e-6.
    let (_, _, stats) = arenstorf_closure(1e-6);
    assert!(
        (100..=250).contains(&(stats.steps + stats.rejected)),
        "{stats:?}"
    );
}

/// y'' = −y sampled every 0.01 over three periods: most samples fall inside steps and come
/// from the continuous extension. Its error there must be the integration's own: at most
/// twice the global error at the end (which it carries) plus the tolerance. A cubic Hermite
/// interpolant from the end slopes alone would miss by ~h⁴/384 ≈ 4e-8 at tol = 1e-9 and fail.
#[test]
fn dense_output_is_as_accurate_as_the_steps() {
    let exact_error = |t: f64, y: &[f64; 2]| (y[0] - t.cos()).abs().max((y[1] + t.sin()).abs());
    for tol in [1e-6, 1e-9] {
        let method = DormandPrince::new(tol, tol);
        let times: Vec<f64> = (0..=2000).map(|i| i as f64 * 0.01).collect();
        let (states, stats) = solve(&method, &mut Oscillator, 0.0, [1.0, 0.0], &times).unwrap();
        let dense = times
            .iter()
            .zip(&states)
            .map(|(t, y)| exact_error(*t, y))
            .fold(0.0, f64::max);
        let (end_state, end_stats) =
            solve(&method, &mut Oscillator, 0.0, [1.0, 0.0], &[20.0]).unwrap();
        let end = exact_error(20.0, &end_state[0]);
        println!(
            "dense output, tol {tol:e}: max error {dense:.3e} at 2001 samples, {end:.3e} at the end; {stats:?}"
        );
        // Samples do not change the steps: the integrator never shortens one to hit them.
        assert_eq!(stats, end_stats);
        assert!(
            stats.steps < 400,
            "most samples must be interpolated: {stats:?}"
        );
        assert!(
            dense <= 2.0 * end + tol,
            "dense output error {dense:e} vs {end:e} at the end"
        );
    }
}

/// y' = y², y(0) = 1: y = 1/(1 − t) blows up at t = 1.
struct BlowUp;

impl Ode for BlowUp {
    type State = [f64; 1];

    fn rhs(&mut self, _t: f64, y: &[f64; 1], dy: &mut [f64; 1]) -> Result<(), Error> {
        dy[0] = y[0] * y[0];
        Ok(())
    }
}

#[test]
fn blow_up_is_a_step_size_underflow() {
    // With the default floor (10⁻¹² of the span) the run stops there; with no floor, at the
    // limit of f64 itself (16 ulps of t). Either way an error naming t, h and the state.
    let span = 2.0;
    for (min_step, tol) in [
        (DormandPrince::MIN_STEP, 1e-6),
        (DormandPrince::MIN_STEP, 1e-10),
        (0.0, 1e-6),
        (0.0, 1e-10),
    ] {
        let mut observed = Vec::new();
        let result = DormandPrince::new(tol, tol)
            .with_min_step(min_step)
            .integrate(&mut BlowUp, 0.0, &[1.0], &[0.5, span], &mut |t, y| {
                observed.push((t, y[0]));
                Ok(())
            });
        println!("blow-up, floor {min_step:e}, tol {tol:e}: {result:?}");
        match result {
            Err(Error::StepSizeUnderflow { t, h, state }) => {
                // y = 1/(t* − t): a relative error δ in y shifts the singularity t* by
                // δ·(t* − t) ≤ δ, and δ is of the order of the tolerance.
                assert!((t - 1.0).abs() < 10.0 * tol, "t = {t}");
                let limit = (min_step * span).max(16.0 * f64::EPSILON * t.abs());
                assert!(h > 0.0 && h < limit, "h = {h:e}, limit {limit:e}");
                let y = state.get("x0").unwrap();
                assert!(y.is_finite() && y > 1e5, "state {state}");
            }
            other => panic!("expected a step size underflow, got {other:?}"),
        }
        // The sample before the singularity was observed, the one after it was not.
        assert_eq!(observed.len(), 1);
        assert!((observed[0].1 - 2.0).abs() < 10.0 * tol);
    }
}

/// Every setting an integrator takes, wrong in every way: an error naming the setting and the
/// value, before any evaluation.
#[test]
fn invalid_settings_are_errors_naming_the_value() {
    fn expect_invalid<I: Integrator>(method: &I, setting: &str, value: f64) {
        let result = method.integrate(&mut BlowUp, 0.0, &[1.0], &[0.5], &mut |_, _| Ok(()));
        match result {
            Err(Error::InvalidSetting { name, value: v, .. }) => {
                assert_eq!(name, setting);
                assert!(
                    v == value || (v.is_nan() && value.is_nan()),
                    "{v} vs {value}"
                );
            }
            other => panic!("expected {setting} = {value} to be invalid, got {other:?}"),
        }
    }
    for bad in [0.0, -1e-3, f64::NAN, f64::INFINITY] {
        expect_invalid(&Rk4::new(bad), "step", bad);
        expect_invalid(&DormandPrince::new(1e-6, bad), "atol", bad);
        expect_invalid(
            &DormandPrince::new(1e-6, 1e-6).with_initial_step(bad),
            "initial step",
            bad,
        );
        expect_invalid(
            &DormandPrince::new(1e-6, 1e-6).with_fixed_step(bad),
            "fixed step",
            bad,
        );
    }
    for bad in [-1e-3, f64::NAN, f64::INFINITY] {
        expect_invalid(&DormandPrince::new(bad, 1e-6), "rtol", bad);
    }
    for bad in [0.0, -1.0, f64::NAN] {
        expect_invalid(
            &DormandPrince::new(1e-6, 1e-6).with_max_step(bad),
            "max step",
            bad,
        );
    }
    expect_invalid(
        &DormandPrince::new(1e-6, 1e-6).with_max_steps(0),
        "max steps",
        0.0,
    );
    // Pure absolute control and an unlimited step are fine.
    let ok = DormandPrince::new(0.0, 1e-6).with_max_step(f64::INFINITY);
    assert!(
        ok.integrate(&mut BlowUp, 0.0, &[1.0], &[0.5], &mut |_, _| Ok(()))
            .is_ok()
    );
}

/// Settings no run can honour, refused by every adaptive method with the setting named: an
/// absolute tolerance of 10³⁰⁰ (Radau5 took it, crossed the span in one step and returned that
/// step's value), a largest step below the floor on the step (only ever an underflow before),
/// a first step below that floor (it had lost its message: "step size underflow at t = 0").
#[test]
fn absurd_tolerances_and_step_limits_are_refused_by_name() {
    let refused =
        |label: &str, result: Result<Stats, Error>, setting: &str, words: &str| match result {
            Err(e @ Error::InvalidSetting { .. }) => {
                let Error::InvalidSetting { name, .. } = &e else {
                    unreachable!()
                };
                assert_eq!(*name, setting, "{label}: {e}");
                assert!(e.to_string().contains(words), "{label}: {e}");
            }
            other => panic!("{label}: expected `{setting}` refused, got {other:?}"),
        };
    let quiet = &mut |_: f64, _: &[f64; 2]| Ok(());
    let x0 = [1.0, 0.0];
    let atol = "controls nothing";
    refused(
        "DP5",
        DormandPrince::new(1e-6, 1e300).integrate(&mut Oscillator, 0.0, &x0, &[1.0], quiet),
        "atol",
        atol,
    );
    refused(
        "Radau5",
        Radau5::new(1e-6, 1e300).integrate(&mut Oscillator, 0.0, &x0, &[1.0], quiet),
        "atol",
        atol,
    );
    refused(
        "Rodas5P",
        hamel_runtime::Rodas5P::new(1e-6, 1e300).integrate(
            &mut Oscillator,
            0.0,
            &x0,
            &[1.0],
            quiet,
        ),
        "atol",
        atol,
    );
    refused(
        "Rodas5P",
        hamel_runtime::Rodas5P::new(1.0, 1e-6).integrate(&mut Oscillator, 0.0, &x0, &[1.0], quiet),
        "rtol",
        "controls nothing",
    );
    // A floor of half the span (Dormand–Prince's floor is relative to the span) above the
    // largest step; and for Radau5, whose floor is relative to |t|, at t = 1000.
    refused(
        "DP5",
        DormandPrince::new(1e-6, 1e-6)
            .with_min_step(0.5)
            .with_max_step(0.1)
            .integrate(&mut Oscillator, 0.0, &x0, &[1.0], quiet),
        "max step",
        "below the smallest step",
    );
    refused(
        "Radau5",
        Radau5::new(1e-6, 1e-6)
            .with_min_step(1e-3)
            .with_max_step(0.1)
            .integrate(&mut Oscillator, 1000.0, &x0, &[1001.0], quiet),
        "max step",
        "below the smallest step",
    );
    refused(
        "DP5",
        DormandPrince::new(1e-6, 1e-6)
            .with_initial_step(1e-300)
            .integrate(&mut Oscillator, 0.0, &x0, &[1.0], quiet),
        "initial step",
        "below the smallest step the integration may take at the start",
    );
    refused(
        "Rodas5P",
        hamel_runtime::Rodas5P::new(1e-6, 1e-6)
            .with_initial_step(1e-300)
            .integrate(&mut Oscillator, 1.0, &x0, &[2.0], quiet),
        "initial step",
        "below the smallest step the integration may take at the start",
    );
}

#[test]
fn bad_start_and_sample_times_are_errors() {
    let methods: (Rk4, DormandPrince) = (Rk4::new(0.1), DormandPrince::new(1e-6, 1e-6));
    fn check<I: Integrator>(method: &I) {
        let run = |t0: f64, x0: [f64; 2], samples: &[f64]| {
            method.integrate(&mut Oscillator, t0, &x0, samples, &mut |_, _| {
                panic!("nothing may be observed")
            })
        };
        match run(0.0, [1.0, f64::NAN], &[1.0]) {
            Err(Error::NonFiniteInitialValue { name, value }) => {
                assert!(name == "x1" && value.is_nan())
            }
            other => panic!("{other:?}"),
        }
        match run(0.0, [f64::NEG_INFINITY, 0.0], &[1.0]) {
            Err(Error::NonFiniteInitialValue { name, value }) => {
                assert!(name == "x0" && value == f64::NEG_INFINITY)
            }
            other => panic!("{other:?}"),
        }
        assert!(matches!(
            run(f64::NAN, [1.0, 0.0], &[1.0]),
            Err(Error::InvalidSetting {
                name: "start time",
                ..
            })
        ));
        for (samples, culprit) in [
            (&[1.0, 0.5][..], 0.5),
            (&[-0.1][..], -0.1),
            (&[0.5, f64::INFINITY][..], f64::INFINITY),
        ] {
            match run(0.0, [1.0, 0.0], samples) {
                Err(Error::InvalidSetting {
                    name: "sample time",
                    value,
                    ..
                }) => assert_eq!(value, culprit),
                other => panic!("{samples:?}: {other:?}"),
            }
        }
        match run(0.0, [1.0, 0.0], &[0.5, f64::NAN]) {
            Err(Error::InvalidSetting {
                name: "sample time",
                value,
                ..
            }) => assert!(value.is_nan()),
            other => panic!("{other:?}"),
        }
        // No samples: nothing to do, and nothing evaluated.
        assert_eq!(run(0.0, [1.0, 0.0], &[]), Ok(Stats::default()));
    }
    check(&methods.0);
    check(&methods.1);
    check(&ImplicitMidpoint::new(0.1));
    check(&GaussLegendre::new(2, 0.1));
    check(&Radau5::new(1e-6, 1e-6));
    check(&hamel_runtime::Rodas5P::new(1e-6, 1e-6));
}

#[test]
fn every_sample_is_observed_once_in_order() {
    fn check<I: Integrator>(method: &I) {
        let samples = [0.0, 0.0, 0.25, 1.0, 1.0, 3.0, std::f64::consts::PI];
        let mut seen = Vec::new();
        method
            .integrate(&mut Oscillator, 0.0, &[1.0, 0.0], &samples, &mut |t, y| {
                seen.push((t, *y));
                Ok(())
            })
            .unwrap();
        assert_eq!(seen.iter().map(|s| s.0).collect::<Vec<_>>(), samples);
        // The start is observed exactly, and so is a repeated sample.
        assert_eq!(seen[0].1, [1.0, 0.0]);
        assert_eq!(seen[1].1, [1.0, 0.0]);
        assert_eq!(seen[3].1, seen[4].1);
        for (t, y) in seen {
            assert!(
                (y[0] - t.cos()).abs() < 1e-5 && (y[1] + t.sin()).abs() < 1e-5,
                "t = {t}: {y:?}"
            );
        }
    }
    check(&Rk4::new(0.05));
    check(&DormandPrince::new(1e-8, 1e-8));
    check(&DormandPrince::new(1e-8, 1e-8).with_fixed_step(0.05));
    check(&ImplicitMidpoint::new(0.002));
    check(&GaussLegendre::new(2, 0.05));
    check(&GaussLegendre::new(3, 0.1));
    check(&Radau5::new(1e-8, 1e-8));
}

/// ẏ = 1 until `t_fail`; then the right-hand side fails (`Err`) or returns NaN.
struct Failing {
    t_fail: f64,
    nan: bool,
}

impl Ode for Failing {
    type State = [f64; 1];

    fn rhs(&mut self, t: f64, _y: &[f64; 1], dy: &mut [f64; 1]) -> Result<(), Error> {
        if t < self.t_fail {
            dy[0] = 1.0;
        } else if self.nan {
            dy[0] = f64::NAN;
        } else {
            return Err(Error::InvalidParameter {
                name: "marker".into(),
                value: t,
            });
        }
        Ok(())
    }
}

#[test]
fn errors_from_the_right_hand_side_and_the_observer_propagate_unchanged() {
    fn check<I: Integrator>(method: &I) {
        let mut ode = Failing {
            t_fail: 1.0,
            nan: false,
        };
        match method.integrate(&mut ode, 0.0, &[0.0], &[0.5, 2.0], &mut |_, _| Ok(())) {
            Err(Error::InvalidParameter { name, value }) => {
                assert!(name == "marker" && value >= 1.0)
            }
            other => panic!("{other:?}"),
        }
        let mut calls = 0;
        let stop = Error::Io {
            path: "observer".into(),
            message: "full".into(),
        };
        let result = method.integrate(
            &mut Oscillator,
            0.0,
            &[1.0, 0.0],
            &[0.5, 1.0, 2.0],
            &mut |_, _| {
                calls += 1;
                if calls == 2 {
                    Err(stop.clone())
                } else {
                    Ok(())
                }
            },
        );
        assert_eq!(result, Err(stop.clone()));
        assert_eq!(calls, 2, "integration stops at the observer's error");
    }
    check(&Rk4::new(0.1));
    check(&DormandPrince::new(1e-6, 1e-6));
    check(&DormandPrince::new(1e-6, 1e-6).with_fixed_step(0.1));
    check(&GaussLegendre::new(2, 0.1));
    check(&Radau5::new(1e-6, 1e-6));
    check(&hamel_runtime::Rodas5P::new(1e-6, 1e-6));
}

#[test]
fn a_non_finite_state_is_an_error_not_a_result() {
    // Fixed steps accept whatever the step produces, so the NaN is caught after the step.
    for (label, result) in [
        (
            "RK4",
            Rk4::new(0.1).integrate(
                &mut Failing {
                    t_fail: 1.0,
                    nan: true,
                },
                0.0,
                &[0.0],
                &[3.0],
                &mut |_, _| Ok(()),
            ),
        ),
        (
            "DP5 fixed",
            DormandPrince::new(1e-6, 1e-6)
                .with_fixed_step(0.1)
                .integrate(
                    &mut Failing {
                        t_fail: 1.0,
                        nan: true,
                    },
                    0.0,
                    &[0.0],
                    &[3.0],
                    &mut |_, _| Ok(()),
                ),
        ),
    ] {
        match result {
            Err(Error::NonFiniteState { t, state }) => {
                assert!((t - 1.0).abs() < 0.11, "{label}: t = {t}");
                assert!(state.get("x0").unwrap().is_nan());
            }
            other => panic!("{label}: {other:?}"),
        }
    }
    // Adaptive steps reject a NaN error estimate and shrink until the step underflows at the
    // start of the trouble: an error, not a hang and not a NaN trajectory; and the error names
    // the NaN, the rate it is in and its time (it blamed the step size, "the solution may have
    // a singularity"). Likewise for every adaptive and implicit method.
    let failing = || Failing {
        t_fail: 1.0,
        nan: true,
    };
    let quiet = &mut |_: f64, _: &[f64; 1]| Ok(());
    for (label, result) in [
        (
            "DP5",
            DormandPrince::new(1e-6, 1e-6).integrate(&mut failing(), 0.0, &[0.0], &[3.0], quiet),
        ),
        (
            "Radau5",
            Radau5::new(1e-6, 1e-6).integrate(&mut failing(), 0.0, &[0.0], &[3.0], quiet),
        ),
        (
            "Rodas5P",
            hamel_runtime::Rodas5P::new(1e-6, 1e-6).integrate(
                &mut failing(),
                0.0,
                &[0.0],
                &[3.0],
                quiet,
            ),
        ),
        (
            "Gauss 2",
            GaussLegendre::new(2, 0.1).integrate(&mut failing(), 0.0, &[0.0], &[3.0], quiet),
        ),
    ] {
        match result {
            Err(e @ Error::NonFiniteRate { .. }) => {
                println!("{label}: {e}");
                let Error::NonFiniteRate { t, rate, state, .. } = &e else {
                    unreachable!()
                };
                // At the trouble (within a step of the method, for the fixed-step one).
                assert!((t - 1.0).abs() < 0.1, "{label}: t = {t}");
                assert_eq!(rate, "x0", "{label}");
                assert!(state.get("x0").unwrap().is_finite(), "{label}");
                assert!(
                    e.to_string().contains("returned NaN for the rate of `x0`"),
                    "{e}"
                );
            }
            other => panic!("{label}: {other:?}"),
        }
    }
}

/// The oscillator with a third component ẏ₂ = 50 cos(50t) carried along, inside the step-size
/// control or outside it.
struct Monitored {
    controlled: usize,
}

impl Ode for Monitored {
    type State = [f64; 3];

    fn rhs(&mut self, t: f64, y: &[f64; 3], dy: &mut [f64; 3]) -> Result<(), Error> {
        *dy = [y[1], -y[0], 50.0 * (50.0 * t).cos()];
        Ok(())
    }

    fn controlled_components(&self) -> usize {
        self.controlled
    }
}

#[test]
fn components_outside_the_error_control_leave_the_steps_alone() {
    let samples = [1.0, 2.5, 10.0];
    let dp = DormandPrince::new(1e-8, 1e-8);
    let (plain, plain_stats) = solve(&dp, &mut Oscillator, 0.0, [1.0, 0.0], &samples).unwrap();
    let mut carried = Monitored { controlled: 2 };
    let (states, stats) = solve(&dp, &mut carried, 0.0, [1.0, 0.0, 0.0], &samples).unwrap();
    println!("oscillator {plain_stats:?}; with a fast component outside the control {stats:?}");
    assert_eq!(stats, plain_stats);
    for (a, b) in plain.iter().zip(&states) {
        assert_eq!(a[..], b[..2], "the same steps give the same numbers");
    }
    // Inside the control, the fast component sets the steps.
    let mut controlled = Monitored { controlled: 3 };
    let (_, more) = solve(&dp, &mut controlled, 0.0, [1.0, 0.0, 0.0], &samples).unwrap();
    println!("... inside the control {more:?}");
    assert!(more.steps > 2 * stats.steps, "{more:?}");
}

/// Uniform motion on the unit circle, ẏ = (−y₁, y₀), optionally projected back onto |y| = 1
/// (where the exact solution stays and the integrator's does not, quite); the projection
/// fails from `t_fail` on.
struct Circle {
    project: bool,
    moved: usize,
    t_fail: f64,
}

impl Circle {
    fn new(project: bool) -> Self {
        Circle {
            project,
            moved: 0,
            t_fail: f64::INFINITY,
        }
    }
}

impl Ode for Circle {
    type State = [f64; 2];

    fn rhs(&mut self, _t: f64, y: &[f64; 2], dy: &mut [f64; 2]) -> Result<(), Error> {
        *dy = [-y[1], y[0]];
        Ok(())
    }

    fn project(&mut self, t: f64, y: &mut [f64; 2]) -> Result<bool, Error> {
        if t >= self.t_fail {
            return Err(Error::InvalidSetting {
                name: "projection",
                value: t,
                reason: "marker",
            });
        }
        let r = y[0].hypot(y[1]);
        if !self.project || r == 1.0 {
            return Ok(false);
        }
        *y = [y[0] / r, y[1] / r];
        self.moved += 1;
        Ok(true)
    }
}

/// The largest ||y| − 1| over the states.
fn off_circle(states: &[[f64; 2]]) -> f64 {
    states
        .iter()
        .map(|y| (y[0].hypot(y[1]) - 1.0).abs())
        .fold(0.0, f64::max)
}

#[test]
fn projected_steps_and_samples_stay_on_the_manifold() {
    let samples: Vec<f64> = (1..=100).map(|i| 0.5 * i as f64).collect();
    let dp = DormandPrince::new(1e-6, 1e-6);
    let (free, free_stats) =
        solve(&dp, &mut Circle::new(false), 0.0, [1.0, 0.0], &samples).unwrap();
    let mut projected = Circle::new(true);
    let (on, stats) = solve(&dp, &mut projected, 0.0, [1.0, 0.0], &samples).unwrap();
    let (drift, kept) = (off_circle(&free), off_circle(&on));
    println!(
        "DP5 on the circle: ||y| − 1| ≤ {drift:.3e} free ({free_stats:?}), {kept:.3e} projected ({stats:?})"
    );
    assert!(drift > 1e-8 && drift < 1e-4, "{drift:e}");
    assert!(kept <= 2.0 * f64::EPSILON, "{kept:e}");

    // Only the end: every projection is after a step, and each but the last step's costs
    // one evaluation of the derivative the next step starts from.
    let mut end_only = Circle::new(true);
    let (_, stats) = solve(&dp, &mut end_only, 0.0, [1.0, 0.0], &[50.0]).unwrap();
    assert!(
        end_only.moved > stats.steps / 2,
        "{} of {stats:?}",
        end_only.moved
    );
    assert_eq!(
        stats.evaluations,
        2 + 6 * (stats.steps + stats.rejected) + end_only.moved - 1
    );

    // RK4 carries no derivative over: projections cost nothing.
    let rk4 = Rk4::new(0.05);
    let (free, _) = solve(&rk4, &mut Circle::new(false), 0.0, [1.0, 0.0], &samples).unwrap();
    let (on, stats) = solve(&rk4, &mut Circle::new(true), 0.0, [1.0, 0.0], &samples).unwrap();
    assert!(off_circle(&free) > 1e-8, "{:e}", off_circle(&free));
    assert!(off_circle(&on) <= 2.0 * f64::EPSILON);
    assert_eq!(stats.evaluations, 4 * stats.steps);
}

#[test]
fn a_failing_projection_stops_the_integration() {
    fn check<I: Integrator>(method: &I) {
        let mut ode = Circle {
            t_fail: 1.0,
            ..Circle::new(true)
        };
        match method.integrate(&mut ode, 0.0, &[1.0, 0.0], &[0.5, 2.0], &mut |_, _| Ok(())) {
            Err(Error::InvalidSetting {
                name: "projection",
                value,
                ..
            }) => assert!((1.0..2.0).contains(&value), "{value}"),
            other => panic!("{other:?}"),
        }
    }
    check(&Rk4::new(0.1));
    check(&DormandPrince::new(1e-6, 1e-6));
    check(&DormandPrince::new(1e-6, 1e-6).with_fixed_step(0.1));
    check(&GaussLegendre::new(2, 0.1));
    check(&Radau5::new(1e-6, 1e-6));
    check(&hamel_runtime::Rodas5P::new(1e-6, 1e-6));
}

/// y' = −10⁶ (y − cos t): stiff, so an explicit method's steps stay near its stability limit,
/// 3·10⁻⁶, whatever the tolerance; 10 time units would take millions of steps.
struct Stiff;

impl Ode for Stiff {
    type State = [f64; 1];

    fn rhs(&mut self, t: f64, y: &[f64; 1], dy: &mut [f64; 1]) -> Result<(), Error> {
        dy[0] = -1e6 * (y[0] - t.cos());
        Ok(())
    }
}

#[test]
fn an_integration_that_would_not_end_runs_out_of_steps() {
    let method = DormandPrince::new(1e-6, 1e-6).with_max_steps(1000);
    match method.integrate(&mut Stiff, 0.0, &[1.0], &[10.0], &mut |_, _| Ok(())) {
        Err(e @ Error::TooManySteps { .. }) => {
            let message = e.to_string();
            println!("{message}");
            let Error::TooManySteps {
                t, steps, h, state, ..
            } = e
            else {
                unreachable!()
            };
            assert_eq!(steps, 1000);
            assert!(t > 0.0 && t < 0.01, "{t}");
            assert!(h < 1e-5, "{h}");
            assert!((state.get("x0").unwrap() - t.cos()).abs() < 1e-5);
            assert!(message.contains("`with_max_steps`"), "{message}");
        }
        other => panic!("{other:?}"),
    }
    assert_eq!(
        DormandPrince::new(1e-6, 1e-6).max_steps,
        hamel_runtime::integrate::MAX_STEPS
    );
}
