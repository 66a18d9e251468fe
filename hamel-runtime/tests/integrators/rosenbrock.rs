//! The Rosenbrock methods (Rodas5P, Rodas4) on problems with known solutions: their orders (5
//! and 4) with ∂f/∂t given and differenced, their dense output's order, a stiff problem where
//! the explicit method takes millions of steps, projection, and their errors (a singular
//! iteration matrix five times in a row, a NaN of the right-hand side).

use super::{Circle, Stiff, off_circle, solve};
use hamel_runtime::{Error, Integrator, Ode, Rodas4, Rodas5P, Stats};

/// y′ = −2ty², y(0) = 1: y = 1/(1 + t²), non-autonomous, with its Jacobian and (when
/// `given`) its ∂f/∂t = −2y².
struct Riccati {
    given: bool,
}

impl Ode for Riccati {
    type State = [f64; 1];

    fn rhs(&mut self, t: f64, y: &[f64; 1], dy: &mut [f64; 1]) -> Result<(), Error> {
        dy[0] = -2.0 * t * y[0] * y[0];
        Ok(())
    }

    fn jacobian(&mut self, t: f64, y: &[f64; 1], j: &mut [f64]) -> Result<bool, Error> {
        j[0] = -4.0 * t * y[0];
        Ok(true)
    }

    fn time_derivative(&mut self, _t: f64, y: &[f64; 1], d: &mut [f64; 1]) -> Result<bool, Error> {
        d[0] = -2.0 * y[0] * y[0];
        Ok(self.given)
    }
}

/// Steps of exactly h (a tolerance so loose that no step is refused, the largest step h).
fn fixed<I: Integrator>(
    method: &I,
    ode: &mut Riccati,
    t_end: f64,
    samples: &[f64],
) -> (Vec<f64>, Stats) {
    let mut values = Vec::new();
    let stats = method
        .integrate(ode, 0.0, &[1.0], samples, &mut |t, y| {
            values.push(y[0] - 1.0 / (1.0 + t * t));
            Ok(())
        })
        .unwrap();
    assert!(
        samples.last() == Some(&t_end) && stats.rejected == 0,
        "{stats:?}"
    );
    (values, stats)
}

/// The observed order of the end error and of the dense output's error at the same point
/// inside a step (37 % into the step from t = 1), from steps h and h/2.
fn orders(
    h: f64,
    new: impl Fn(f64) -> Box<dyn Fn(&mut Riccati, &[f64]) -> (Vec<f64>, Stats)>,
) -> (f64, f64) {
    let t_end = 2.0;
    let mut errors = Vec::new();
    for step in [h, h / 2.0] {
        let samples = [1.0 + 0.37 * step, t_end];
        let (e, stats) = new(step)(&mut Riccati { given: true }, &samples);
        assert_eq!(stats.steps, (t_end / step).round() as usize, "{stats:?}");
        errors.push(e);
    }
    let order = |i: usize| (errors[0][i] / errors[1][i]).abs().log2();
    (order(1), order(0))
}

#[test]
fn rosenbrock_methods_converge_with_their_orders() {
    // Rodas5P: order 5 at the end; its dense output of order 4 has a local error O(h⁵), as
    // the steps' global error is.
    let (end, dense) = orders(0.1, |h| {
        let method = Rodas5P::new(0.5, 1e10)
            .with_initial_step(h)
            .with_max_step(h);
        Box::new(move |ode, samples| fixed(&method, ode, 2.0, samples))
    });
    println!("Rodas5P: order {end:.2} at the end, {dense:.2} inside a step");
    assert!((end - 5.0).abs() < 0.3, "{end}");
    assert!(dense > 4.7, "{dense}");
    let (end, dense) = orders(0.025, |h| {
        let method = Rodas4::new(0.5, 1e10).with_initial_step(h).with_max_step(h);
        Box::new(move |ode, samples| fixed(&method, ode, 2.0, samples))
    });
    // Rodas4: order 4; its dense output of order 3 has a local error O(h⁴), which this
    // non-autonomous problem shows only from steps of 0.025 on (from 0.1 and 0.05 the ratio
    // is 6.5, then 12, 14, 15, 15.5 as h halves).
    println!("Rodas4: order {end:.2} at the end, {dense:.2} inside a step");
    assert!((end - 4.0).abs() < 0.3, "{end}");
    assert!(dense > 3.7, "{dense}");
}

/// Without ∂f/∂t the method differences f in t: one evaluation more per step, and the same
/// answer to about √ε of the step's contribution.
#[test]
fn a_differenced_time_derivative_costs_one_evaluation_a_step() {
    let run = |given: bool| {
        let mut end = 0.0;
        let stats = Rodas5P::new(1e-8, 1e-8)
            .integrate(&mut Riccati { given }, 0.0, &[1.0], &[3.0], &mut |_, y| {
                end = y[0];
                Ok(())
            })
            .unwrap();
        (end, stats)
    };
    let ((exact, s1), (differenced, s2)) = (run(true), run(false));
    println!("given: {s1:?}\ndifferenced: {s2:?}");
    assert!((exact - 0.1).abs() < 1e-8, "{exact}");
    assert!(
        (differenced - exact).abs() < 1e-8,
        "{differenced} against {exact}"
    );
    assert_eq!(s2.evaluations - s1.evaluations, s2.jacobians);
}

#[test]
fn rodas5p_takes_few_steps_where_an_explicit_method_takes_millions() {
    // `Stiff`: y′ = −10⁶ (y − cos t), differenced Jacobian and ∂f/∂t.
    let mut end = 0.0;
    let stats = Rodas5P::new(1e-8, 1e-8)
        .integrate(&mut Stiff, 0.0, &[1.0], &[10.0], &mut |_, y| {
            end = y[0];
            Ok(())
        })
        .unwrap();
    let exact = 10f64.cos() + 1e-6 * 10f64.sin();
    println!(
        "Rodas5P on the stiff decay: {stats:?}, error {:.1e}",
        end - exact
    );
    assert!((end - exact).abs() < 1e-8);
    assert!(stats.steps < 200, "{stats:?}");
}

#[test]
fn rodas5p_projects_steps_and_samples() {
    let samples: Vec<f64> = (1..=40).map(|i| 0.5 * i as f64).collect();
    let mut free = Circle::new(false);
    let (off, _) = solve(
        &Rodas5P::new(1e-5, 1e-5),
        &mut free,
        0.0,
        [1.0, 0.0],
        &samples,
    )
    .unwrap();
    let mut projected = Circle::new(true);
    let (on, _) = solve(
        &Rodas5P::new(1e-5, 1e-5),
        &mut projected,
        0.0,
        [1.0, 0.0],
        &samples,
    )
    .unwrap();
    println!(
        "Rodas5P: ||y| − 1| ≤ {:.2e} free, {:.2e} projected ({} projections)",
        off_circle(&off),
        off_circle(&on),
        projected.moved
    );
    assert!(off_circle(&on) <= 2.0 * f64::EPSILON);
    assert!(projected.moved > 0);
}

/// ẋ = diag(λ₁…λ₅) x with λₖ = 2ᵏ/(γ h₀): the matrix I/(hγ) − J is singular at h₀, and again
/// at each halving of it, five times in a row.
struct Growing;

const H0: f64 = 0.01;
const GAMMA: f64 = 0.21193756319429014;

fn lambda(k: usize) -> f64 {
    (1u32 << k) as f64 / (GAMMA * H0)
}

impl Ode for Growing {
    type State = [f64; 5];

    fn rhs(&mut self, _t: f64, x: &[f64; 5], dx: &mut [f64; 5]) -> Result<(), Error> {
        for k in 0..5 {
            dx[k] = lambda(k) * x[k];
        }
        Ok(())
    }

    fn jacobian(&mut self, _t: f64, _x: &[f64; 5], j: &mut [f64]) -> Result<bool, Error> {
        j.fill(0.0);
        for k in 0..5 {
            j[k * 5 + k] = lambda(k);
        }
        Ok(true)
    }

    fn time_derivative(&mut self, _: f64, _: &[f64; 5], d: &mut [f64; 5]) -> Result<bool, Error> {
        d.fill(0.0);
        Ok(true)
    }
}

#[test]
fn a_singular_iteration_matrix_five_times_in_a_row_is_an_error_naming_the_growth() {
    let result = Rodas5P::new(1e-6, 1e-6).with_initial_step(H0).integrate(
        &mut Growing,
        0.0,
        &[1e-3; 5],
        &[1.0],
        &mut |_, _| Ok(()),
    );
    match result {
        Err(e @ Error::SingularIterationMatrix { .. }) => {
            println!("{e}");
            let Error::SingularIterationMatrix { t, h, growth, .. } = &e else {
                unreachable!()
            };
            assert_eq!((*t, *h), (0.0, H0 / 16.0));
            // The mode that met the last step: λ₄ = 16/(γh₀).
            assert!((growth - lambda(4)).abs() < 1e-6 * lambda(4), "{growth}");
            assert!(e.to_string().contains("grows by a factor e every"), "{e}");
        }
        other => panic!("{other:?}"),
    }
}
