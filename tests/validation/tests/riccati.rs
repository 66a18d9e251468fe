//! The Riccati solver of `hamel::control` (`solve_care`, and `Lqr` on a model's
//! linearization) against scipy's `solve_continuous_are`: the gains to 1e-9 relative.
//!
//! scipy's answers come from `scripts/care_reference.py`, run on the cases built here when
//! `python3` with scipy is on the machine; otherwise from `tests/data/care_reference.txt`,
//! which that script wrote (rerun with `HAMEL_WRITE_CARE_REFERENCE=1 cargo test -p
//! hamel-validation --test models -- riccati::` to renew it), after checking that its cases
//! are these.

use std::io::Write as _;
use std::process::{Command, Stdio};

use crate::common::xorshift::XorShift;
use hamel::control::{Lqr, solve_care};
use hamel::models::{MobileRobot, WhippleBicycle};
use hamel::{Error, HamelSystem};
use nalgebra::DMatrix;

/// The gains agree with scipy's to this, relative to the largest gain of the case.
const GAIN_TOLERANCE: f64 = 1e-9;
/// The stored cases are the cases built here to rounding (the linearizations are computed
/// on each machine).
const CASE_TOLERANCE: f64 = 1e-12;

struct Case {
    name: &'static str,
    a: DMatrix<f64>,
    b: DMatrix<f64>,
    q: DMatrix<f64>,
    r: DMatrix<f64>,
}

/// The benchmark bicycle's lateral linearization at 2 m/s (below its weave speed, unstable)
/// with the steer torque alone.
fn bicycle_at_2ms() -> hamel::Linearization {
    let bike = WhippleBicycle::default();
    let x = bike
        .state_builder()
        .set("rear_wheel_rate", -2.0 / bike.r_r)
        .build()
        .unwrap();
    bike.linearize(0.0, &x, &[0.0, 0.0])
        .unwrap()
        .reduce(&["phi", "delta", "roll_rate", "steer_rate"])
        .unwrap()
        .with_inputs(&["steer_torque"])
        .unwrap()
}

/// The robot upright at rest: its pitch is an inverted pendulum.
fn robot_upright() -> hamel::Linearization {
    MobileRobot::default()
        .linearize(0.0, &[0.0; 8], &[0.0, 0.0])
        .unwrap()
        .reduce(&["alpha", "w3", "w4"])
        .unwrap()
}

fn cases() -> Vec<Case> {
    let bicycle = bicycle_at_2ms();
    let robot = robot_upright();
    let mut rng = XorShift::new(1980);
    let random = DMatrix::from_fn(6, 6, |_, _| rng.uniform(-1.0, 1.0));
    let random_b = DMatrix::from_fn(6, 2, |_, _| rng.uniform(-1.0, 1.0));
    vec![
        Case {
            name: "double_integrator",
            a: DMatrix::from_row_slice(2, 2, &[0.0, 1.0, 0.0, 0.0]),
            b: DMatrix::from_row_slice(2, 1, &[0.0, 1.0]),
            q: DMatrix::identity(2, 2),
            r: DMatrix::identity(1, 1),
        },
        Case {
            name: "bicycle_2ms_steer",
            a: bicycle.a_matrix().clone(),
            b: bicycle.b_matrix().clone(),
            q: DMatrix::from_diagonal(&nalgebra::DVector::from_row_slice(&[10.0, 1.0, 1.0, 0.1])),
            r: DMatrix::identity(1, 1),
        },
        Case {
            name: "robot_upright",
            a: robot.a_matrix().clone(),
            b: robot.b_matrix().clone(),
            q: DMatrix::from_diagonal(&nalgebra::DVector::from_row_slice(&[100.0, 1.0, 10.0])),
            r: DMatrix::from_row_slice(2, 2, &[1.0, 0.2, 0.2, 2.0]),
        },
        Case {
            name: "random_6x6",
            a: random,
            b: random_b,
            q: DMatrix::identity(6, 6),
            r: DMatrix::from_row_slice(2, 2, &[1.0, 0.0, 0.0, 0.5]),
        },
    ]
}

/// The cases as `care_reference.py` reads them: `{:?}` prints the shortest decimal that
/// reads back to the same double.
fn as_text(cases: &[Case]) -> String {
    let mut text = String::new();
    for c in cases {
        text += &format!("case {} {} {}\n", c.name, c.a.nrows(), c.b.ncols());
        for m in [&c.a, &c.b, &c.q, &c.r] {
            for row in m.row_iter() {
                let values: Vec<String> = row.iter().map(|v| format!("{v:?}")).collect();
                text += &values.join(" ");
                text.push('\n');
            }
        }
    }
    text
}

/// `case NAME N M` blocks of numbers: (name, rows of numbers).
fn blocks(text: &str) -> Vec<(String, Vec<f64>)> {
    let mut out: Vec<(String, Vec<f64>)> = Vec::new();
    for line in text.lines() {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("case") => out.push((words.next().unwrap().to_string(), Vec::new())),
            Some(first) => {
                let last = out.last_mut().expect("numbers before the first case");
                last.1.extend(
                    core::iter::once(first)
                        .chain(words)
                        .map(|w| w.parse::<f64>().unwrap()),
                );
            }
            None => {}
        }
    }
    out
}

/// scipy's output for the cases, by running the script, or `None` without python3 and scipy.
fn run_scipy(input: &str) -> Option<String> {
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/scripts/care_reference.py");
    let mut child = Command::new("python3")
        .arg(script)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .ok()?;
    child.stdin.take()?.write_all(input.as_bytes()).ok()?;
    let output = child.wait_with_output().ok()?;
    output
        .status
        .success()
        .then(|| String::from_utf8(output.stdout).unwrap())
}

const STORED: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/care_reference.txt");
const SEPARATOR: &str = "--- scipy.linalg.solve_continuous_are:\n";

fn relative(computed: &[f64], reference: &[f64]) -> f64 {
    let scale = reference.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let worst = computed
        .iter()
        .zip(reference)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    assert_eq!(computed.len(), reference.len());
    worst / scale
}

/// scipy's K and P for each case: live, or stored for these same cases.
fn reference(cases: &[Case]) -> (Vec<(String, Vec<f64>)>, &'static str) {
    let input = as_text(cases);
    if let Some(live) = run_scipy(&input) {
        if std::env::var_os("HAMEL_WRITE_CARE_REFERENCE").is_some() {
            std::fs::write(STORED, format!("{input}{SEPARATOR}{live}")).unwrap();
        }
        return (blocks(&live), "scipy, run now");
    }
    let stored = std::fs::read_to_string(STORED).unwrap();
    let (stored_input, output) = stored.split_once(SEPARATOR).unwrap();
    for ((name, then), (_, now)) in blocks(stored_input).iter().zip(blocks(&input)) {
        let drift = relative(&now, then);
        assert!(
            drift <= CASE_TOLERANCE,
            "the stored case {name} is not this one: {drift:e}"
        );
    }
    (blocks(output), "scipy, stored by scripts/care_reference.py")
}

#[test]
fn gains_equal_scipys() {
    let cases = cases();
    let (reference, source) = reference(&cases);
    assert_eq!(reference.len(), cases.len());
    for (case, (name, values)) in cases.iter().zip(&reference) {
        assert_eq!(case.name, name);
        let riccati = solve_care(&case.a, &case.b, &case.q, &case.r).unwrap();
        let (n, m) = (case.a.nrows(), case.b.ncols());
        let k: Vec<f64> = riccati.gain.transpose().iter().copied().collect();
        let p: Vec<f64> = riccati.solution.transpose().iter().copied().collect();
        let (gain_error, solution_error) = (
            relative(&k, &values[..m * n]),
            relative(&p, &values[m * n..]),
        );
        println!(
            "{name}: gain {gain_error:.1e}, solution {solution_error:.1e} relative to {source} \
             (residual {:.1e}, steps {:?})",
            riccati.residual, riccati.steps
        );
        assert!(gain_error <= GAIN_TOLERANCE, "{name}: {gain_error:e}");
    }
}

#[test]
fn double_integrator_has_its_closed_form() {
    // P = [[√3, 1], [1, √3]], K = [1, √3] (Anderson and Moore, Optimal Control, §3.3).
    let a = DMatrix::from_row_slice(2, 2, &[0.0, 1.0, 0.0, 0.0]);
    let b = DMatrix::from_row_slice(2, 1, &[0.0, 1.0]);
    let riccati = solve_care(&a, &b, &DMatrix::identity(2, 2), &DMatrix::identity(1, 1)).unwrap();
    let s3 = 3f64.sqrt();
    let expected = [s3, 1.0, 1.0, s3];
    assert!(relative(riccati.solution.as_slice(), &expected) < 1e-14);
}

#[test]
fn lqr_stabilizes_the_bicycle_at_2ms() {
    let lin = bicycle_at_2ms();
    // Unstable by itself below the weave speed.
    assert!(lin.modes().unwrap()[0].value.re > 0.0);
    let q = DMatrix::from_diagonal(&nalgebra::DVector::from_row_slice(&[10.0, 1.0, 1.0, 0.1]));
    let lqr = Lqr::new(&lin, &q, &DMatrix::identity(1, 1)).unwrap();
    let least = lqr.closed_loop_eigenvalues()[0];
    assert!(least.re < 0.0, "{least}");
}

#[test]
fn no_stabilizing_solution_is_an_error_that_says_why() {
    // The unstable mode x₁' = x₁ is not reached by the input.
    let a = DMatrix::from_row_slice(2, 2, &[1.0, 0.0, 0.0, -1.0]);
    let b = DMatrix::from_row_slice(2, 1, &[0.0, 1.0]);
    let e = solve_care(&a, &b, &DMatrix::identity(2, 2), &DMatrix::identity(1, 1)).unwrap_err();
    assert!(matches!(e, Error::NoStabilizingSolution { .. }), "{e}");
    // An undamped oscillator that Q does not see: eigenvalues on the imaginary axis.
    let a = DMatrix::from_row_slice(2, 2, &[0.0, 1.0, -1.0, 0.0]);
    let e = solve_care(&a, &b, &DMatrix::zeros(2, 2), &DMatrix::identity(1, 1)).unwrap_err();
    assert!(matches!(e, Error::NoStabilizingSolution { .. }), "{e}");
    println!("{e}");
    // R must be positive definite.
    let e = solve_care(&a, &b, &DMatrix::identity(2, 2), &DMatrix::zeros(1, 1)).unwrap_err();
    assert!(
        matches!(e, Error::InvalidWeights { matrix: "R", .. }),
        "{e}"
    );
}
