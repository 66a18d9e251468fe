//! The implicit methods on problems with known solutions: the convergence orders of the
//! Gauss–Legendre methods (2, 4, 6), their symmetry (steps forward then backward retrace
//! themselves to rounding) and exact conservation of quadratic invariants, Radau5's
//! tolerance proportionality and its cost on a stiff problem beside Dormand–Prince's, the
//! projection hook, and every error they report.

use super::{
    BlowUp, Circle, Oscillator, Riccati, Stiff, convergence, off_circle, riccati_exact, solve,
};
use hamel_runtime::{
    DormandPrince, Error, GaussLegendre, ImplicitMidpoint, Integrator, Ode, Radau5, Stats,
};

/// The pendulum θ̈ = −sin θ as (θ, θ̇), with its exact Jacobian.
struct Pendulum;

impl Ode for Pendulum {
    type State = [f64; 2];

    fn rhs(&mut self, _t: f64, y: &[f64; 2], dy: &mut [f64; 2]) -> Result<(), Error> {
        *dy = [y[1], -y[0].sin()];
        Ok(())
    }

    fn jacobian(&mut self, _t: f64, y: &[f64; 2], j: &mut [f64]) -> Result<bool, Error> {
        j.copy_from_slice(&[0.0, 1.0, -y[0].cos(), 0.0]);
        Ok(true)
    }
}

fn pendulum_energy(y: &[f64; 2]) -> f64 {
    0.5 * y[1] * y[1] - y[0].cos()
}

#[test]
fn gauss_legendre_methods_converge_with_orders_two_four_and_six() {
    // (stages, h₀ for the oscillator over 10, for the Riccati equation over 2)
    for (stages, h_osc, h_ric) in [(1, 0.1, 0.1), (2, 0.5, 0.2), (3, 1.0, 0.5)] {
        let order = 2.0 * stages as f64;
        let method = |h| GaussLegendre::new(stages, h);
        let oscillator = convergence(
            &format!("Gauss {stages}, oscillator"),
            method,
            Oscillator,
            [1.0, 0.0],
            10.0,
            h_osc,
            |y| (y[0] - 10f64.cos()).abs().max((y[1] + 10f64.sin()).abs()),
        );
        let riccati = convergence(
            &format!("Gauss {stages}, Riccati"),
            method,
            Riccati,
            [1.0],
            2.0,
            h_ric,
            |y| (y[0] - riccati_exact(2.0)).abs(),
        );
        for observed in [oscillator, riccati] {
            assert!(
                (observed - order).abs() <= 0.1,
                "{stages} stages: order {observed}, expected {order}"
            );
        }
    }
    // The midpoint rule is Gauss with one stage, step for step.
    let (a, _) = solve(
        &ImplicitMidpoint::new(0.1),
        &mut Riccati,
        0.0,
        [1.0],
        &[2.0],
    )
    .unwrap();
    let (b, _) = solve(
        &GaussLegendre::new(1, 0.1),
        &mut Riccati,
        0.0,
        [1.0],
        &[2.0],
    )
    .unwrap();
    assert_eq!(a, b);
}

#[test]
fn steps_forward_then_backward_retrace_themselves() {
    // The pendulum swinging through large angles, 200 steps and back: a symmetric method's
    // map satisfies Φ₋ₕ ∘ Φₕ = id, so what remains is rounding (and the Newton iterations'
    // convergence to it).
    let x0 = [2.0, 0.3];
    for stages in 1..=3 {
        let method = GaussLegendre::new(stages, 0.1);
        let (x1, forward) = method.advance(&mut Pendulum, 0.0, &x0, 0.1, 200).unwrap();
        let (back, _) = method.advance(&mut Pendulum, 20.0, &x1, -0.1, 200).unwrap();
        let miss = (back[0] - x0[0]).abs().max((back[1] - x0[1]).abs());
        println!("Gauss {stages}: back to the start within {miss:.2e}; forward {forward:?}");
        assert!(miss <= 1e-12, "{stages} stages: {miss:e}");
        // The energy error of a symmetric method oscillates; over these 20 s it is small.
        let drift = (pendulum_energy(&x1) - pendulum_energy(&x0)).abs();
        assert!(drift < 1e-2, "{drift:e}");
    }
    // The midpoint rule's own entry point is the same map.
    let (m, _) = ImplicitMidpoint::new(0.1)
        .advance(&mut Pendulum, 0.0, &x0, 0.1, 10)
        .unwrap();
    let (g, _) = GaussLegendre::new(1, 0.1)
        .advance(&mut Pendulum, 0.0, &x0, 0.1, 10)
        .unwrap();
    assert_eq!(m, g);
    // A step of 0 or not finite is refused.
    for h in [0.0, f64::NAN] {
        assert!(matches!(
            GaussLegendre::new(2, 0.1).advance(&mut Pendulum, 0.0, &x0, h, 1),
            Err(Error::InvalidSetting { name: "step", .. })
        ));
    }
}

#[test]
fn gauss_methods_keep_quadratic_invariants_and_reuse_the_jacobian() {
    // ½(x² + v²) of the oscillator is a quadratic invariant, which every Gauss method keeps
    // exactly (Cooper's theorem; Hairer, Lubich & Wanner, IV.2): over 10⁴ steps only
    // rounding remains.
    for stages in 1..=3 {
        let (end, stats) = solve(
            &GaussLegendre::new(stages, 0.5),
            &mut Oscillator,
            0.0,
            [1.0, 0.0],
            &[5000.0],
        )
        .unwrap();
        let end = end[0];
        let energy = 0.5 * (end[0] * end[0] + end[1] * end[1]);
        println!("Gauss {stages}, oscillator to t = 5000: energy {energy:.17}, {stats:?}");
        assert!((energy - 0.5).abs() < 1e-12, "{energy}");
        // A linear problem: one Jacobian (by differences: 3 evaluations) for the whole run,
        // one factorization.
        assert_eq!((stats.jacobians, stats.factorizations), (1, 1), "{stats:?}");
    }
}

#[test]
fn radau5_error_falls_with_the_tolerance() {
    // The Riccati equation over [0, 2]: RADAU5's tolerances are meant for the global error.
    let mut previous = f64::INFINITY;
    for tol in [1e-4, 1e-6, 1e-8, 1e-10] {
        let (y, stats) = solve(&Radau5::new(tol, tol), &mut Riccati, 0.0, [1.0], &[2.0]).unwrap();
        let error = (y[0][0] - riccati_exact(2.0)).abs();
        println!("Radau5, Riccati, tol {tol:e}: error {error:.3e}, {stats:?}");
        assert!(error < 10.0 * tol, "tol {tol:e}: error {error:e}");
        assert!(error < previous);
        previous = error;
    }
}

#[test]
fn radau5_takes_few_steps_where_dormand_prince_takes_millions() {
    // y′ = −10⁶ (y − cos t) over 1 s: the smooth solution is y ≈ cos t + 10⁻⁶ sin t −
    // 10⁻¹² cos t + O(e^(−10⁶ t)) (the asymptotic series, each term 10⁻⁶ of the last).
    let exact = |t: f64| t.cos() + 1e-6 * t.sin() - 1e-12 * t.cos();
    let t_end = 1.0;
    let (dp, dp_stats) = solve(
        &DormandPrince::new(1e-8, 1e-8),
        &mut Stiff,
        0.0,
        [1.0],
        &[t_end],
    )
    .unwrap();
    let (rd, rd_stats) = solve(&Radau5::new(1e-8, 1e-8), &mut Stiff, 0.0, [1.0], &[t_end]).unwrap();
    let (dp_error, rd_error) = (
        (dp[0][0] - exact(t_end)).abs(),
        (rd[0][0] - exact(t_end)).abs(),
    );
    println!(
        "stiff scalar: DP5 error {dp_error:.2e} {dp_stats:?}; Radau5 {rd_error:.2e} {rd_stats:?}"
    );
    assert!(rd_error <= 1e-8, "{rd_error:e}");
    // DP5 is held at its stability limit, ~3.3/10⁶: 3·10⁵ steps whatever the tolerance.
    assert!(dp_stats.evaluations > 1_000_000, "{dp_stats:?}");
    assert!(
        rd_stats.evaluations * 100 < dp_stats.evaluations,
        "{rd_stats:?} vs {dp_stats:?}"
    );
}

/// The states at 40 samples over 20 s on the circle, free or projected, and the number of
/// projections that moved the state.
fn on_circle<I: Integrator>(method: &I, project: bool) -> (Vec<[f64; 2]>, usize) {
    let samples: Vec<f64> = (1..=40).map(|i| 0.5 * i as f64).collect();
    let mut circle = Circle::new(project);
    let (states, _) = solve(method, &mut circle, 0.0, [1.0, 0.0], &samples).unwrap();
    (states, circle.moved)
}

#[test]
fn implicit_methods_project_steps_and_samples() {
    for (label, (free, _), (on, moved)) in [
        (
            "Gauss 2",
            on_circle(&GaussLegendre::new(2, 0.25), false),
            on_circle(&GaussLegendre::new(2, 0.25), true),
        ),
        (
            "Radau5",
            on_circle(&Radau5::new(1e-5, 1e-5), false),
            on_circle(&Radau5::new(1e-5, 1e-5), true),
        ),
    ] {
        println!(
            "{label}: ||y| − 1| ≤ {:.2e} free, {:.2e} projected ({moved} projections)",
            off_circle(&free),
            off_circle(&on),
        );
        assert!(off_circle(&on) <= 2.0 * f64::EPSILON, "{label}");
        assert!(moved > 0, "{label}");
    }
}

/// ẏ = y with its exact Jacobian: I − h·½·J vanishes for the midpoint rule at h = 2.
struct Growth;

impl Ode for Growth {
    type State = [f64; 1];

    fn rhs(&mut self, _t: f64, y: &[f64; 1], dy: &mut [f64; 1]) -> Result<(), Error> {
        dy[0] = y[0];
        Ok(())
    }

    fn jacobian(&mut self, _t: f64, _y: &[f64; 1], j: &mut [f64]) -> Result<bool, Error> {
        j[0] = 1.0;
        Ok(true)
    }
}

#[test]
fn failures_of_the_implicit_stages_are_errors_naming_t_h_and_the_state() {
    // y′ = y² from 1 with the midpoint rule and h = 0.9: y₁ = 1 + 0.9·((1 + y₁)/2)² has no
    // real root, so no iteration converges, however fresh the Jacobian.
    match ImplicitMidpoint::new(0.9).integrate(&mut BlowUp, 0.0, &[1.0], &[5.0], &mut |_, _| Ok(()))
    {
        Err(e @ Error::NewtonNotConverged { .. }) => {
            println!("{e}");
            let Error::NewtonNotConverged { t, h, state, .. } = &e else {
                unreachable!()
            };
            assert_eq!((*t, *h), (0.0, 5.0 / 6.0));
            assert_eq!(state.get("x0"), Some(1.0));
            assert!(e.to_string().contains("smaller step"));
        }
        other => panic!("{other:?}"),
    }
    // A singular iteration matrix: I − (h/2)·1 = 0 at h = 2.
    match ImplicitMidpoint::new(2.0).integrate(&mut Growth, 1.0, &[3.0], &[3.0], &mut |_, _| Ok(()))
    {
        Err(e @ Error::SingularIterationMatrix { .. }) => {
            println!("{e}");
            let Error::SingularIterationMatrix { t, h, state, .. } = &e else {
                unreachable!()
            };
            assert_eq!((*t, *h, state.get("x0")), (1.0, 2.0, Some(3.0)));
        }
        other => panic!("{other:?}"),
    }
    // Radau5 reduces the step where the stages do not converge; up to the blow-up at t = 1
    // it ends in a step size underflow there.
    match Radau5::new(1e-6, 1e-6).integrate(&mut BlowUp, 0.0, &[1.0], &[2.0], &mut |_, _| Ok(())) {
        Err(Error::StepSizeUnderflow { t, state, .. }) => {
            assert!((t - 1.0).abs() < 1e-3, "t = {t}");
            assert!(state.get("x0").unwrap() > 1e3);
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn step_limits_and_settings_are_checked() {
    let quiet = |_: f64, _: &[f64; 2]| Ok(());
    // Planned: 10 s in steps of 1e-9 is 1e10 steps, beyond the default limit.
    for method in [GaussLegendre::new(2, 1e-9)] {
        match method.integrate(
            &mut Oscillator,
            0.0,
            &[1.0, 0.0],
            &[10.0],
            &mut quiet.clone(),
        ) {
            Err(Error::TooManySteps { planned, h, .. }) => assert!(planned && h == 1e-9),
            other => panic!("{other:?}"),
        }
    }
    match ImplicitMidpoint::new(0.01).with_max_steps(100).integrate(
        &mut Oscillator,
        0.0,
        &[1.0, 0.0],
        &[10.0],
        &mut quiet.clone(),
    ) {
        Err(Error::TooManySteps { planned, .. }) => assert!(planned),
        other => panic!("{other:?}"),
    }
    // Exhausted during the run.
    match Radau5::new(1e-10, 1e-10).with_max_steps(20).integrate(
        &mut Oscillator,
        0.0,
        &[1.0, 0.0],
        &[100.0],
        &mut quiet.clone(),
    ) {
        Err(Error::TooManySteps {
            planned, steps, t, ..
        }) => {
            assert!(!planned && steps == 20 && t > 0.0 && t < 100.0);
        }
        other => panic!("{other:?}"),
    }
    let expect_invalid = |result: Result<Stats, Error>, setting: &str| match result {
        Err(Error::InvalidSetting { name, .. }) => assert_eq!(name, setting),
        other => panic!("expected {setting} to be invalid: {other:?}"),
    };
    let run = |method: &dyn Fn(&mut Oscillator) -> Result<Stats, Error>| method(&mut Oscillator);
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        expect_invalid(
            run(&|o| {
                ImplicitMidpoint::new(bad).integrate(
                    o,
                    0.0,
                    &[1.0, 0.0],
                    &[1.0],
                    &mut quiet.clone(),
                )
            }),
            "step",
        );
        expect_invalid(
            run(&|o| {
                Radau5::new(1e-6, bad).integrate(o, 0.0, &[1.0, 0.0], &[1.0], &mut quiet.clone())
            }),
            "atol",
        );
        expect_invalid(
            run(&|o| {
                Radau5::new(1e-6, 1e-6).with_initial_step(bad).integrate(
                    o,
                    0.0,
                    &[1.0, 0.0],
                    &[1.0],
                    &mut quiet.clone(),
                )
            }),
            "initial step",
        );
    }
    for bad in [-0.1, f64::NAN, f64::INFINITY] {
        expect_invalid(
            run(&|o| {
                GaussLegendre::new(2, 0.1).with_refresh_rate(bad).integrate(
                    o,
                    0.0,
                    &[1.0, 0.0],
                    &[1.0],
                    &mut quiet.clone(),
                )
            }),
            "refresh rate",
        );
    }
    for bad in [0.0, 1e-16, f64::NAN] {
        expect_invalid(
            run(&|o| {
                Radau5::new(bad, 1e-6).integrate(o, 0.0, &[1.0, 0.0], &[1.0], &mut quiet.clone())
            }),
            "rtol",
        );
    }
}
