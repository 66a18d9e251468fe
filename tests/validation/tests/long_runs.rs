//! What long (or endless) runs need: every integration ends, the progress callback reports
//! and cancels, and the extra columns (inputs, user outputs, constraint forces) and the
//! streamed CSV carry what the in-memory trajectory does.
//!
//! 1. Former hangs: settings that used to make a run step forever (a largest or fixed step of
//!    1e-300, an RK4 step of 1e-9 over 10 s) return an `Err` naming t, h and the state, at
//!    once; so do a run that reaches its step limit and one whose step falls below the floor.
//!    The one timing assertion of the suite, < 1 s of wall time for the call, is about a hang,
//!    not about speed: each of these calls does at most a few hundred steps. The calls run on
//!    a thread of their own, so that a hang that comes back fails the test after 10 s with a
//!    message instead of never ending (removing the fixed-step refusal did exactly that).
//! 2. Progress: increasing times, fractions in [0, 1], a final call; `Break` cancels, and the
//!    run returns what it recorded up to there with `Summary::stopped` saying so.
//! 3. Extra outputs: the input, output and λ columns against the functions that define them,
//!    row by row; `Simulation::stream` into a `CsvSink` against `Trajectory::write_csv`.
//! 4. The implicit integrators (`long_runs/implicit.rs`, which lists what it checks).
//! 5. Radau5 on the standard stiff test set (`long_runs/stiff_set.rs`).
// The implicit integrators on the catalogue's models: orders, symmetry, bounded energy, the
// vertical disk's closed form, stiffness.
mod implicit;

// A singular mass matrix at the end of a curved ridge names the speed whose inertia diverges.
mod ridge_skate;

// Radau5 on the standard stiff test set.
mod stiff_set;

use std::cell::RefCell;
use std::ops::ControlFlow;
use std::sync::mpsc;
use std::thread;
use std::time::{Duration, Instant};

use crate::common::planar_closed_forms::KnifeStart;
use hamel::models::{KnifeEdge, MobileRobot};
use hamel::{
    CsvSink, DormandPrince, Error, Event, HamelSystem, Integrator, NamedValues, Progress, Rk4,
    Simulation, Stopped, Summary, Trajectory,
};

/// A former hang must return within this wall time (the calls below take micro- to
/// milliseconds; a hang takes hours).
const HANG_LIMIT: Duration = Duration::from_secs(1);

/// The knife edge on a level plane and its start (closed form in `planar_closed_forms`).
fn level_knife() -> (KnifeEdge, KnifeStart, [f64; 5]) {
    let sys = KnifeEdge {
        incline: 0.0,
        ..KnifeEdge::default()
    };
    let s = KnifeStart {
        x0: 0.3,
        y0: -0.2,
        phi0: 0.4,
        v: 0.8,
        omega: 1.7,
    };
    let x0 = sys
        .state_from_speeds(0.0, &[s.x0, s.y0, s.phi0], &[s.v, s.omega])
        .unwrap();
    (sys, s, x0)
}

/// The wall time of one call.
fn timed<T>(f: impl FnOnce() -> T) -> (T, Duration) {
    let started = Instant::now();
    let out = f();
    (out, started.elapsed())
}

/// How long to wait for a run on its own thread before calling it a hang: a failure with a
/// message rather than a test that never ends (the thread is left to the process's exit).
const HANG_WAIT: Duration = Duration::from_secs(10);

/// A 10 s knife-edge run with `integrator`, on a thread of its own: its result and the wall
/// time of the call itself (the thread's start and the channel excluded).
fn ten_seconds<I: Integrator + Send + 'static>(
    integrator: I,
) -> (Result<Trajectory, Error>, Duration) {
    let (send, receive) = mpsc::channel();
    thread::spawn(move || {
        let (sys, _, x0) = level_knife();
        let sim = Simulation::new(&sys, x0).end_time(10.0);
        // The receiver is gone only after a timeout, which has failed the test already.
        let _ = send.send(timed(|| sim.run_constant(&integrator, [])));
    });
    receive
        .recv_timeout(HANG_WAIT)
        .unwrap_or_else(|_| panic!("no result after {HANG_WAIT:?}: the run hangs"))
}

/// The state named in an error is the model's, by name.
fn assert_named_knife_state(state: &NamedValues, what: &str) {
    let names: Vec<&str> = state.0.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, KnifeEdge::STATE, "{what}: {state:?}");
}

/// `DormandPrince::with_max_step(1e-300)`, `with_fixed_step(1e-300)` and `Rk4::new(1e-9)`
/// over 10 s would need 1e301, 1e301 and 1e10 steps, beyond `MAX_STEPS` (1e7): each is
/// refused before the first step with `TooManySteps` at t = 0, with that step size, the
/// number of steps it would need and the initial state; the message says all of it.
#[test]
fn former_hangs_return_errors_at_once() {
    let (_, _, x0) = level_knife();
    // Each call timed by itself (`ten_seconds`).
    let cases = [
        (
            "DormandPrince::with_max_step(1e-300)",
            ten_seconds(DormandPrince::new(1e-8, 1e-8).with_max_step(1e-300)),
            1e-300,
            1e301,
        ),
        (
            "DormandPrince::with_fixed_step(1e-300)",
            ten_seconds(DormandPrince::new(1e-8, 1e-8).with_fixed_step(1e-300)),
            1e-300,
            1e301,
        ),
        (
            "Rk4::new(1e-9)",
            ten_seconds(Rk4::new(1e-9)),
            1e-9,
            1e10_f64,
        ),
    ];
    for (what, (result, elapsed), step, needed) in cases {
        println!("{what}: {elapsed:?}: {result:?}");
        assert!(elapsed < HANG_LIMIT, "{what} took {elapsed:?}");
        match result {
            Err(
                ref e @ Error::TooManySteps {
                    t,
                    steps,
                    h,
                    planned,
                    ref state,
                },
            ) => {
                assert_eq!((t, h), (0.0, step), "{what}: {e}");
                assert!(planned, "{what}: refused before the first step");
                // The steps it would need (saturated at usize::MAX for 1e301).
                assert!(
                    steps as f64 >= needed.min(usize::MAX as f64) * (1.0 - 1e-9),
                    "{what}: {steps} steps"
                );
                assert_named_knife_state(state, what);
                let values: Vec<f64> = state.0.iter().map(|(_, v)| *v).collect();
                assert_eq!(values, x0, "{what}: the state named is the initial one");
                let message = e.to_string();
                assert!(
                    message.contains("t = 0")
                        && message.contains("phi = 0.4")
                        && message.contains("more than the limit"),
                    "{what}: {message}"
                );
            }
            other => panic!("{what}: expected TooManySteps, got {other:?}"),
        }
    }
}

/// A run that reaches its step limit (`with_max_steps(100)` where several hundred steps are
/// needed) stops there with `TooManySteps`: 100 steps, the time reached (between 0 and 10),
/// the step size then, and the state at that time, which is the closed-form motion's to the
/// integration's accuracy (rtol = atol = 1e-12: 1e-9 is a generous bound after 100 steps).
/// The same for RK4 with `with_max_steps(100)` and a step that would need 1000.
#[test]
fn step_limits_end_runs_with_the_state_reached() {
    let (_, s, _) = level_knife();
    let adaptive = DormandPrince::new(1e-12, 1e-12).with_max_steps(100);
    let (result, elapsed) = ten_seconds(adaptive);
    assert!(elapsed < HANG_LIMIT, "{elapsed:?}");
    // How many steps the run needs without the limit.
    let needed = ten_seconds(DormandPrince::new(1e-12, 1e-12))
        .0
        .unwrap()
        .summary()
        .steps;
    assert!(needed > 200, "{needed} steps");
    match result {
        Err(Error::TooManySteps {
            t, steps, h, state, ..
        }) => {
            assert_eq!(steps, 100);
            assert!(
                t > 0.0 && t < 10.0 && h > 0.0 && h < 10.0,
                "t = {t}, h = {h}"
            );
            assert_named_knife_state(&state, "DormandPrince, 100 steps");
            for ((name, value), exact) in state.0.iter().zip(s.state(t)) {
                assert!(
                    (value - exact).abs() < 1e-9,
                    "{name} = {value} at t = {t}: {exact}"
                );
            }
            println!(
                "DormandPrince with_max_steps(100) (needs {needed}): TooManySteps at t = {t}, h = {h:.3e}, in {elapsed:?}"
            );
        }
        other => panic!("expected TooManySteps, got {other:?}"),
    }

    let (result, elapsed) = ten_seconds(Rk4::new(0.01).with_max_steps(100));
    assert!(elapsed < HANG_LIMIT, "{elapsed:?}");
    match result {
        Err(Error::TooManySteps { t, steps, h, .. }) => {
            // Refused up front: 10 s / 0.01 = 1000 steps > 100.
            assert_eq!((t, h), (0.0, 0.01));
            assert!(steps >= 1000, "{steps}");
            println!("Rk4 with_max_steps(100): TooManySteps, {steps} needed, in {elapsed:?}");
        }
        other => panic!("expected TooManySteps, got {other:?}"),
    }
}

/// The step-size floor: the mobile robot driven by a torque that jumps at t = 5 s. At the
/// jump the solution's derivative is discontinuous, so Dormand–Prince's steps shrink until
/// the local error (proportional to the step there) passes the tolerance: at rtol = atol =
/// 1e-10 that is far below 1e-5 s, the floor set with `with_min_step(1e-6)` (relative to the
/// 10 s span). The run ends with `StepSizeUnderflow` at the jump, with the step below the
/// floor and the robot's state, at once. Without the floor the default (1e-12 of the span)
/// lets the same run through.
#[test]
fn the_step_size_floor_ends_a_run_at_a_discontinuity() {
    let sys = MobileRobot::default();
    let x0 = sys
        .state_from_speeds(0.0, &[0.0, 0.0, 0.1, 0.0, 0.0], &[0.5, 0.2, 0.0])
        .unwrap();
    let jump = |t: f64, _: &[f64; 8]| if t < 5.0 { [0.0, 0.0] } else { [2.0, -1.5] };
    let sim = Simulation::new(&sys, x0)
        .end_time(10.0)
        .sample_interval(0.1);
    let floored = DormandPrince::new(1e-10, 1e-10).with_min_step(1e-6);
    let (result, elapsed) = timed(|| sim.run(&floored, jump));
    assert!(elapsed < HANG_LIMIT, "{elapsed:?}");
    match result {
        Err(ref e @ Error::StepSizeUnderflow { t, h, ref state }) => {
            assert!((t - 5.0).abs() < 1e-3, "at t = {t}: {e}");
            assert!(h < 1e-5, "h = {h}");
            let names: Vec<&str> = state.0.iter().map(|(n, _)| n.as_str()).collect();
            // The robot's state, and the work done on it (integrated alongside).
            assert_eq!(&names[..8], MobileRobot::STATE, "{state:?}");
            assert!(state.0.iter().all(|(_, v)| v.is_finite()));
            println!("floor 1e-5 s: StepSizeUnderflow at t = {t}, h = {h:.3e}, in {elapsed:?}");
        }
        other => panic!("expected StepSizeUnderflow, got {other:?}"),
    }
    let through = sim.run(&DormandPrince::new(1e-10, 1e-10), jump).unwrap();
    assert_eq!(*through.times().last().unwrap(), 10.0);
}

/// What a progress callback saw.
#[derive(Clone, Copy, Debug)]
struct Call {
    t: f64,
    fraction: f64,
    steps: usize,
    elapsed: Duration,
    span: (f64, f64),
}

/// The checks every sequence of progress calls must pass: times and step counts never
/// decrease, fractions are in [0, 1] and are (t − t0)/(t_end − t0), the span is the run's.
fn check_calls(calls: &[Call], span: (f64, f64)) {
    assert!(!calls.is_empty());
    for c in calls {
        assert_eq!(c.span, span);
        assert!((0.0..=1.0).contains(&c.fraction), "{c:?}");
        assert_eq!(
            c.fraction,
            ((c.t - span.0) / (span.1 - span.0)).clamp(0.0, 1.0)
        );
        assert!(c.t >= span.0 && c.t <= span.1, "{c:?}");
    }
    for w in calls.windows(2) {
        assert!(w[0].t <= w[1].t, "{w:?}");
        assert!(
            w[0].steps <= w[1].steps && w[0].elapsed <= w[1].elapsed,
            "{w:?}"
        );
    }
}

/// A callback recording its calls, which asks to stop at call `cancel_at` (1-based), if any.
fn recorder(
    calls: &RefCell<Vec<Call>>,
    cancel_at: Option<usize>,
) -> impl Fn(&Progress) -> ControlFlow<()> + '_ {
    move |p: &Progress| {
        let mut calls = calls.borrow_mut();
        calls.push(Call {
            t: p.t,
            fraction: p.fraction(),
            steps: p.steps,
            elapsed: p.elapsed,
            span: (p.t0, p.t_end),
        });
        if Some(calls.len()) == cancel_at {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    }
}

/// A short run (milliseconds: no interval of 50 ms passes) calls back at its start and once
/// at its end, with t = t_end, fraction 1 and the run's step count; a run started at t0 ≠ 0 reports fractions
/// of its own span. A run ended by a terminal event makes its last call at the event.
#[test]
fn progress_reports_the_end_of_a_run() {
    let (sys, s, x0) = level_knife();
    let calls = RefCell::new(Vec::new());
    let run = Simulation::new(&sys, x0)
        .start_time(2.0)
        .end_time(6.0)
        .on_progress(recorder(&calls, None))
        .run_constant(&DormandPrince::new(1e-10, 1e-10), [])
        .unwrap();
    let calls = calls.into_inner();
    check_calls(&calls, (2.0, 6.0));
    assert_eq!(
        (calls[0].t, calls[0].fraction, calls[0].steps),
        (2.0, 0.0, 0)
    );
    let last = calls.last().unwrap();
    assert_eq!((last.t, last.fraction), (6.0, 1.0));
    assert_eq!(last.steps, run.summary().steps);
    assert_eq!(run.summary().stopped, None);

    let c = s.x_at_sine(0.3);
    let calls = RefCell::new(Vec::new());
    let run = Simulation::new(&sys, x0)
        .end_time(10.0)
        .event(Event::new("x", move |_, x: &[f64; 5]| x[0] - c).terminal())
        .on_progress(recorder(&calls, None))
        .run_constant(&DormandPrince::new(1e-12, 1e-12), [])
        .unwrap();
    let calls = calls.into_inner();
    check_calls(&calls, (0.0, 10.0));
    let t_event = run.event_times("x")[0];
    assert_eq!(calls.last().unwrap().t, t_event);
    assert!(calls.last().unwrap().fraction < 1.0);
}

/// `Break` cancels a run that would take many seconds: it returns `Ok` with the samples up to
/// the time the callback was called at (a step's end, or a sample), where the last row is;
/// `stopped` is `Cancelled` at that time; the callback was called at the start, then at
/// least every 50 ms, and once more at the end with that time. The state in the last row is the closed-form motion's.
/// Once with Dormand–Prince (the stop falls inside the sample grid, between samples) and once
/// with RK4 (steps land on its sub-steps).
#[test]
fn progress_break_cancels_a_run() {
    // 2e7 steps for 1e6 s with Dormand–Prince (many seconds, and more than the default
    // step limit); 1e7 steps for 1000 s with RK4.
    cancel_case(
        "DormandPrince 1e-12",
        &DormandPrince::new(1e-12, 1e-12),
        1e6,
    );
    cancel_case("Rk4 1e-4", &Rk4::new(1e-4), 1e3);
}

/// A run of the level knife edge to `t_end` with `integrator`, cancelled at the fourth
/// progress call (the third after the one at the start), and its checks.
fn cancel_case<I: Integrator>(what: &str, integrator: &I, t_end: f64) {
    let (sys, s, x0) = level_knife();
    let calls = RefCell::new(Vec::new());
    let sim = Simulation::new(&sys, x0)
        .end_time(t_end)
        .sample_interval(t_end / 1e4)
        .on_progress(recorder(&calls, Some(4)));
    let (result, elapsed) = timed(|| sim.run_constant(integrator, []));
    let trajectory = result.unwrap_or_else(|e| panic!("{what}: {e}"));
    let calls = calls.borrow().clone();
    check_calls(&calls, (0.0, t_end));
    assert_eq!(
        calls.len(),
        5,
        "{what}: one call at the start, three more, the last cancels, one at the end"
    );
    assert_eq!((calls[0].t, calls[0].steps), (0.0, 0), "{what}: {calls:?}");
    let cancel = calls[3];
    assert_eq!(
        calls[4].t, cancel.t,
        "{what}: the final call is at the stop"
    );
    assert!(
        calls[1].elapsed >= Duration::from_millis(50)
            && calls[3].elapsed >= Duration::from_millis(150),
        "{what}: at most every 50 ms after the start: {calls:?}"
    );
    assert!(cancel.t < t_end);
    assert_eq!(
        trajectory.summary().stopped,
        Some(Stopped::Cancelled { t: cancel.t }),
        "{what}"
    );
    let times = trajectory.times();
    assert_eq!(*times.last().unwrap(), cancel.t, "{what}");
    assert!(times.windows(2).all(|w| w[0] < w[1]));
    // Every grid sample before the stop is there.
    let dt = t_end / 1e4;
    let before = times.len() - 1;
    assert!(
        times[..before]
            .iter()
            .enumerate()
            .all(|(i, t)| *t == i as f64 * dt)
    );
    assert!(times[before - 1] < cancel.t && cancel.t <= times[before - 1] + dt);
    assert_eq!(trajectory.summary().samples, trajectory.len());
    // The last row is the motion at the stop (a loose bound: a long run accumulates
    // phase error, but nothing near a wrong state).
    let last = trajectory.row(trajectory.len() - 1).unwrap();
    let exact = s.state(cancel.t);
    for (value, exact) in last[1..6].iter().zip(exact) {
        assert!(
            (value - exact).abs() < 1e-5 * (1.0 + exact.abs()),
            "{what}: {last:?} against {exact:?}"
        );
    }
    println!(
        "{what}: cancelled at t = {} after {:?} ({} steps); calls at {:?}",
        cancel.t,
        elapsed,
        cancel.steps,
        calls.iter().map(|c| c.elapsed).collect::<Vec<_>>()
    );
}

/// The mobile robot's inputs as a feedback law and a schedule: a damped steering torque and a
/// sine, so that the recorded inputs depend on both t and x.
fn robot_inputs(t: f64, x: &[f64; 8]) -> [f64; 2] {
    [
        0.3 * (2.0 * t).sin() - 0.1 * x[6],
        0.2 * t.cos() - 0.1 * x[7],
    ]
}

/// The columns a run records, and each against its definition at every row, exactly: the
/// inputs are `robot_inputs(t, x)` of the row's t and state, the user outputs their
/// closures, `lambda_<constraint>` the model's `constraint_forces(t, x, u)`. (The recorder
/// calls the same functions on the same numbers, so the comparison is bitwise.)
#[test]
fn input_output_and_constraint_force_columns() {
    let sys = MobileRobot::default();
    let x0 = sys
        .state_from_speeds(0.0, &[0.1, -0.2, 0.05, 0.0, 0.0], &[0.4, 0.3, -0.1])
        .unwrap();
    let heading = |x: &[f64; 8]| sys.r * (x[3] - x[4]) / sys.b;
    let run = Simulation::new(&sys, x0)
        .end_time(3.0)
        .sample_interval(0.05)
        .output("x_plus_y", |_, x| x[0] + x[1])
        .output("heading", move |_, x| heading(x))
        .output("t_squared", |t, _| t * t)
        .record_constraint_forces(true)
        .run(&DormandPrince::new(1e-10, 1e-10), robot_inputs)
        .unwrap();
    let mut expected: Vec<String> = ["t"]
        .iter()
        .chain(MobileRobot::STATE)
        .chain(MobileRobot::INPUTS)
        .map(|s| s.to_string())
        .collect();
    expected.extend(
        [
            "x_plus_y",
            "heading",
            "t_squared",
            "energy",
            "energy_balance",
        ]
        .map(String::from),
    );
    expected.extend(
        MobileRobot::CONSTRAINTS
            .iter()
            .map(|c| format!("lambda_{c}")),
    );
    assert_eq!(run.names(), expected);
    assert_eq!(MobileRobot::INPUTS, ["tau1", "tau2"]);
    assert_eq!(MobileRobot::CONSTRAINTS.len(), 2);
    assert_eq!(run.len(), 61);

    let column = |name: &str| {
        run.column(name)
            .unwrap_or_else(|| panic!("no column {name}"))
    };
    let lambda: Vec<&[f64]> = MobileRobot::CONSTRAINTS
        .iter()
        .map(|c| column(&format!("lambda_{c}")))
        .collect();
    let mut largest_lambda = 0.0f64;
    for (i, &t) in run.times().iter().enumerate() {
        let mut x = [0.0; 8];
        for (xi, name) in x.iter_mut().zip(MobileRobot::STATE) {
            *xi = column(name)[i];
        }
        let u = robot_inputs(t, &x);
        assert_eq!(
            [column("tau1")[i], column("tau2")[i]],
            u,
            "inputs at t = {t}"
        );
        assert_eq!(column("x_plus_y")[i], x[0] + x[1]);
        assert_eq!(column("heading")[i], heading(&x));
        assert_eq!(column("t_squared")[i], t * t);
        let forces = sys.constraint_forces(t, &x, &u).unwrap();
        for (k, f) in forces.iter().enumerate() {
            assert_eq!(lambda[k][i], *f, "λ{k} at t = {t}");
            largest_lambda = largest_lambda.max(f.abs());
        }
    }
    // The inputs did vary, and the forces are not trivially zero.
    let tau1 = column("tau1");
    assert!(tau1.iter().any(|v| (v - tau1[0]).abs() > 0.1));
    assert!(largest_lambda > 1e-3, "{largest_lambda}");
}

/// Parses CSV text into its header and rows of numbers.
fn parse_csv(text: &str) -> (Vec<String>, Vec<Vec<f64>>) {
    let mut lines = text.lines();
    let header = lines
        .next()
        .expect("a header")
        .split(',')
        .map(String::from)
        .collect();
    let rows = lines
        .map(|line| {
            line.split(',')
                .map(|f| {
                    f.parse::<f64>()
                        .unwrap_or_else(|_| panic!("not a number: {f}"))
                })
                .collect()
        })
        .collect();
    (header, rows)
}

/// `stream` into a `CsvSink` writes what `run` keeps, in the same CSV: the same header and
/// rows (parsed and compared value by value, and as text), the same summary — for a run to
/// its end time and for one ended by a terminal event, with inputs, outputs and λ columns.
#[test]
fn streamed_csv_equals_the_trajectory() {
    let sys = MobileRobot::default();
    let x0 = sys
        .state_from_speeds(0.0, &[0.0, 0.0, 0.1, 0.0, 0.0], &[0.5, 0.2, 0.1])
        .unwrap();
    let integrator = DormandPrince::new(1e-9, 1e-9);
    for terminal in [false, true] {
        let mut sim = Simulation::new(&sys, x0)
            .end_time(4.0)
            .sample_interval(0.03)
            .output("x_plus_y", |_, x| x[0] + x[1])
            .record_constraint_forces(true);
        if terminal {
            // The speed w3 swings between about ±12 under these inputs; the run stops
            // where it first falls through −8 (near t = 1.4 s).
            sim = sim.event(
                Event::new("swing", |_, x: &[f64; 8]| x[5] + 8.0)
                    .falling()
                    .terminal(),
            );
        }
        let run = sim.run(&integrator, robot_inputs).unwrap();
        let mut buffer: Vec<u8> = Vec::new();
        let summary: Summary = {
            let mut sink = CsvSink::new(&mut buffer, "memory");
            let summary = sim.stream(&integrator, robot_inputs, &mut sink).unwrap();
            assert_eq!(sink.rows(), run.len());
            summary
        };
        let streamed = String::from_utf8(buffer).unwrap();
        let mut written = Vec::new();
        run.write_csv(&mut written).unwrap();
        let written = String::from_utf8(written).unwrap();

        let (header, rows) = parse_csv(&streamed);
        assert_eq!(header, run.names());
        assert_eq!(rows.len(), run.len());
        for (i, row) in rows.iter().enumerate() {
            let kept = run.row(i).unwrap();
            assert_eq!(row.len(), kept.len());
            for (a, b) in row.iter().zip(&kept) {
                assert_eq!(
                    a.to_bits(),
                    b.to_bits(),
                    "row {i}: {row:?} against {kept:?}"
                );
            }
        }
        assert_eq!(parse_csv(&written), (header, rows));
        assert_eq!(streamed, written);
        assert_eq!(&summary, run.summary());
        if terminal {
            let t = run.event_times("swing");
            assert_eq!(t.len(), 1);
            assert!(t[0] < 4.0);
            assert_eq!(
                summary.stopped,
                Some(Stopped::Event {
                    name: "swing".into(),
                    t: t[0],
                })
            );
            assert_eq!(*run.times().last().unwrap(), t[0]);
        } else {
            assert_eq!(summary.stopped, None);
        }
        println!(
            "streamed CSV (terminal event: {terminal}): {} rows, {} bytes, identical",
            run.len(),
            streamed.len()
        );
    }
}
