//! Events against closed forms: the times at which the knife edge's heading and position and
//! the Chaplygin sleigh's speed and heading cross given values, located by the runtime on the
//! integrator's dense output, against the exact times of `common/planar_closed_forms.rs`;
//! direction filtering, several crossings in order, recording against terminal events, the
//! exact end of a run at a terminal event, and the event tolerance.
//!
//! The error of a located time t_e against the exact t* splits into two parts. With g the
//! event function along the exact motion and g_h along the computed one,
//! g(t_e) = g_h(t_e) − (g_h − g)(t_e), and g(t_e) ≈ ġ (t_e − t*), so
//!
//!   t_e − t* ≈ [g_h(t_e) − (g_h − g)(t_e)] / ġ:
//!
//! the *location* part g_h(t_e)/ġ — how far from the root of the dense output Brent's method
//! stopped (g_h at the recorded state) — and the *integration* part (g_h − g)(t_e)/ġ — the
//! integrator's error in the state at t_e, carried into g. Each test prints both (`cargo test
//! -p hamel-validation --test models -- events:: --nocapture`). The bound asserted on every event time is
//! `EVENT_TIME_TOL` = 1e-10 absolute, with Dormand–Prince at rtol = atol = 1e-12, whose state
//! errors over these runs (a few turns) stay near 1e-11 (`classic_models.rs` bounds the knife
//! edge's at 1e-8 and measures 1e-10 over longer runs); the location part with the default
//! `EVENT_TOLERANCE` (1e-12 of a step) is ≤ 1e-13.

use std::f64::consts::PI;

use crate::common::planar_closed_forms::{KnifeStart, SleighMotion};
use hamel::models::{ChaplyginSleigh, KnifeEdge};
use hamel::{
    DormandPrince, EVENT_TOLERANCE, Event, EventRecord, HamelSystem, Rk4, Simulation, Stopped,
    Trajectory,
};

/// The bound on |t_e − t*| for every event time (absolute, seconds).
const EVENT_TIME_TOL: f64 = 1e-10;

/// The bound on the state at a terminal event against the closed form: the integration's
/// error at rtol = atol = 1e-12 over a few turns (measured ~1e-11, printed).
const STATE_TOL: f64 = 1e-10;

/// The integrator of every closed-form comparison.
fn tight() -> DormandPrince {
    DormandPrince::new(1e-12, 1e-12)
}

/// The knife edge on a level plane: no force acts, so v and ω are constant.
fn level_knife() -> KnifeEdge {
    KnifeEdge {
        incline: 0.0,
        ..KnifeEdge::default()
    }
}

/// The starts: turning left and right, a backward one.
fn knife_starts() -> Vec<KnifeStart> {
    vec![
        KnifeStart {
            x0: 0.3,
            y0: -0.2,
            phi0: 0.4,
            v: 0.8,
            omega: 1.7,
        },
        KnifeStart {
            x0: -1.0,
            y0: 2.0,
            phi0: -2.0,
            v: 1.5,
            omega: -0.9,
        },
        KnifeStart {
            x0: 0.0,
            y0: 0.0,
            phi0: 1.0,
            v: -0.6,
            omega: 2.5,
        },
    ]
}

fn knife_x0(sys: &KnifeEdge, s: &KnifeStart) -> [f64; 5] {
    sys.state_from_speeds(0.0, &[s.x0, s.y0, s.phi0], &[s.v, s.omega])
        .expect("a regular state")
}

/// The state of an event record as the model's state vector.
fn state_of<S: HamelSystem>(event: &EventRecord) -> S::State {
    let mut x = <S::State as hamel::Vector>::zeros();
    for (xi, name) in x.as_mut().iter_mut().zip(S::STATE) {
        *xi = event
            .state
            .get(name)
            .expect("every state component is named");
    }
    x
}

/// The events called `name`.
fn named<'a>(run: &'a Trajectory, name: &'a str) -> impl Iterator<Item = &'a EventRecord> {
    run.events().iter().filter(move |e| e.name == name)
}

/// Pairs located events with exact times one to one and returns the worst |t_e − t*|,
/// asserting the count and the bound.
fn compare_times(what: &str, located: &[f64], exact: &[f64], bound: f64) -> f64 {
    assert_eq!(
        located.len(),
        exact.len(),
        "{what}: located {located:?}, exact {exact:?}"
    );
    let mut worst = 0.0f64;
    for (te, ts) in located.iter().zip(exact) {
        let err = (te - ts).abs();
        assert!(
            err <= bound,
            "{what}: located t = {te}, exact {ts}, error {err:e} > {bound:e}"
        );
        worst = worst.max(err);
    }
    worst
}

/// The closed form itself, by central differences against the ODEs it claims to solve (the
/// knife edge: ẋ = v cos φ, ẏ = v sin φ; the sleigh: v̇ = aω², ω̇ = −m a v ω/J, θ̇ = ω), and its
/// inverse functions (crossing times) against the forward ones. Without this, a wrong closed
/// form could only be blamed on the runtime.
#[test]
fn closed_forms_solve_their_equations() {
    let h = 1e-5;
    // Central differences: error h² f'''/6 ≈ 1e-10 of the derivatives' size, plus rounding
    // ε/h ≈ 1e-11.
    let diff_tol = 1e-8;
    for s in knife_starts() {
        for t in [0.0, 0.37, 1.9, 4.2] {
            let (a, b) = (s.state(t + h), s.state(t - h));
            let x = s.state(t);
            let d: Vec<f64> = (0..3).map(|i| (a[i] - b[i]) / (2.0 * h)).collect();
            let expected = [s.v * x[2].cos(), s.v * x[2].sin(), s.omega];
            for (di, ei) in d.iter().zip(expected) {
                assert!((di - ei).abs() < diff_tol, "knife {s:?} t = {t}: {d:?}");
            }
        }
        let c = s.x_at_sine(0.3);
        for (t, rising) in s.x_crossings(c, 10.0) {
            assert!((s.state(t)[0] - c).abs() < 1e-14, "{s:?}: x({t}) ≠ {c}");
            let slope = (s.state(t + h)[0] - s.state(t - h)[0]) / (2.0 * h);
            assert_eq!(slope > 0.0, rising, "{s:?}: direction at t = {t}");
        }
        let target = s.phi0 + 0.77 * s.omega;
        assert!((s.state(s.heading_time(target))[2] - target).abs() < 1e-15);
    }
    for (m, inertia, a, v0, w0) in [
        (2.0, 0.5, 0.4, 0.2, 1.5),
        (2.0, 0.5, 0.4, -0.5, -1.0),
        (1.0, 0.05, 0.6, 0.1, 3.0),
    ] {
        let f = SleighMotion::new(m, inertia, a, 0.3, v0, w0);
        assert!((f.v(0.0) - v0).abs() < 1e-15 && (f.omega(0.0) - w0).abs() < 1e-14);
        assert!((f.theta(0.0) - 0.3).abs() < 1e-15);
        for t in [0.0, 0.5, 2.0, 6.0] {
            let dv = (f.v(t + h) - f.v(t - h)) / (2.0 * h);
            let dw = (f.omega(t + h) - f.omega(t - h)) / (2.0 * h);
            let dth = (f.theta(t + h) - f.theta(t - h)) / (2.0 * h);
            let (v, w) = (f.v(t), f.omega(t));
            assert!((dv - a * w * w).abs() < diff_tol, "sleigh v̇ at {t}");
            assert!(
                (dw + m * a * v * w / f.j).abs() < diff_tol,
                "sleigh ω̇ at {t}"
            );
            assert!((dth - w).abs() < diff_tol, "sleigh θ̇ at {t}");
        }
        for fraction in [0.0, 0.5, 0.9] {
            let t = f.speed_time(fraction);
            if t > 0.0 {
                assert!((f.v(t) - fraction * f.limit).abs() < 1e-14);
            }
        }
        let c = f.theta(1.3);
        assert!((f.heading_time(c) - 1.3).abs() < 1e-13);
    }
}

/// The knife edge's heading φ = φ₀ + ωt crosses c at (c − φ₀)/ω. Dormand–Prince integrates
/// φ̇ = ω (constant) exactly up to rounding and its dense output is then linear in t, so the
/// error here is location and rounding only: g_h(t_e) is printed as the location part.
/// Events on φ − c for several c, and on sin φ, which crosses zero at every φ = nπ, rising
/// at even n (cos φ > 0 for ω > 0) and falling at odd n.
#[test]
fn knife_edge_heading_events_match_the_closed_form() {
    let sys = level_knife();
    let t_end = 10.0;
    let mut worst = 0.0f64;
    let mut worst_residual = 0.0f64;
    for s in knife_starts() {
        let phi_end = s.phi0 + s.omega * t_end;
        // Values between φ₀ and φ(t_end), not at the ends.
        let targets: Vec<f64> = [0.13, 0.5, 0.91]
            .iter()
            .map(|f| s.phi0 + f * (phi_end - s.phi0))
            .collect();
        let mut sim = Simulation::new(&sys, knife_x0(&sys, &s))
            .end_time(t_end)
            .sample_interval(0.5);
        for (i, c) in targets.iter().copied().enumerate() {
            sim = sim.event(Event::new(format!("phi{i}"), move |_, x: &[f64; 5]| {
                x[2] - c
            }));
        }
        sim = sim.event(Event::new("sin_phi", |_, x: &[f64; 5]| x[2].sin()));
        let run = sim.run_constant(&tight(), []).expect("the run");
        for (i, c) in targets.iter().enumerate() {
            let name = format!("phi{i}");
            let exact = [s.heading_time(*c)];
            worst = worst.max(compare_times(
                &name,
                &run.event_times(&name),
                &exact,
                EVENT_TIME_TOL,
            ));
            for e in named(&run, &name) {
                let residual = (e.state.get("phi").unwrap() - c).abs() / s.omega.abs();
                worst_residual = worst_residual.max(residual);
            }
        }
        // sin φ = 0 at φ = nπ for n between φ₀/π and φ(t_end)/π.
        let (lo, hi) = if s.omega > 0.0 {
            (s.phi0, phi_end)
        } else {
            (phi_end, s.phi0)
        };
        let mut exact: Vec<f64> = ((lo / PI).ceil() as i64..=(hi / PI).floor() as i64)
            .map(|n| s.heading_time(n as f64 * PI))
            .filter(|t| *t > 0.0)
            .collect();
        exact.sort_by(f64::total_cmp);
        assert!(exact.len() >= 2, "several crossings: {exact:?}");
        worst = worst.max(compare_times(
            "sin φ",
            &run.event_times("sin_phi"),
            &exact,
            EVENT_TIME_TOL,
        ));
        // Every recorded state is the computed motion at the event's time.
        for e in run.events() {
            let x = state_of::<KnifeEdge>(e);
            assert!((x[2] - (s.phi0 + s.omega * e.t)).abs() < 1e-12, "{e:?}");
            assert!(!e.terminal);
        }
        assert_eq!(run.summary().stopped, None);
        assert_eq!(*run.times().last().unwrap(), t_end);
    }
    println!(
        "knife edge heading events: worst |t_e − t*| = {worst:.2e} s (location only: φ is \
         integrated exactly); worst location residual |φ_h(t_e) − c|/|ω| = {worst_residual:.2e} s"
    );
}

/// x = c on the knife edge's circle: twice a turn, rising where cos φ has the sign of v and
/// falling at the other crossing. Times against `x_crossings`, for an event of either
/// direction, a rising and a falling one: the counts add up, each is in time order, and the
/// either-way event's times are the rising and falling ones merged.
#[test]
fn knife_edge_position_events_directions_and_order() {
    let sys = level_knife();
    let t_end = 20.0;
    let (mut worst, mut worst_location, mut worst_integration) = (0.0f64, 0.0f64, 0.0f64);
    for s in knife_starts() {
        for sine in [0.3, -0.55] {
            let c = s.x_at_sine(sine);
            let run = Simulation::new(&sys, knife_x0(&sys, &s))
                .end_time(t_end)
                .sample_interval(0.25)
                .event(Event::new("either", move |_, x: &[f64; 5]| x[0] - c))
                .event(Event::new("up", move |_, x: &[f64; 5]| x[0] - c).rising())
                .event(Event::new("down", move |_, x: &[f64; 5]| x[0] - c).falling())
                .run_constant(&tight(), [])
                .expect("the run");
            let exact = s.x_crossings(c, t_end);
            let all: Vec<f64> = exact.iter().map(|e| e.0).collect();
            let up: Vec<f64> = exact.iter().filter(|e| e.1).map(|e| e.0).collect();
            let down: Vec<f64> = exact.iter().filter(|e| !e.1).map(|e| e.0).collect();
            assert!(up.len() >= 2 && down.len() >= 2, "{s:?}: {exact:?}");
            let what = format!("{s:?}, x = {c}");
            for (name, times) in [("either", &all), ("up", &up), ("down", &down)] {
                let located = run.event_times(name);
                assert!(
                    located.windows(2).all(|w| w[0] < w[1]),
                    "{what} {name}: not in order: {located:?}"
                );
                worst = worst.max(compare_times(
                    &format!("{what} {name}"),
                    &located,
                    times,
                    EVENT_TIME_TOL,
                ));
            }
            // The same crossings, found by three functions: identical times.
            let mut merged = [run.event_times("up"), run.event_times("down")].concat();
            merged.sort_by(f64::total_cmp);
            assert_eq!(merged, run.event_times("either"), "{what}");
            // The whole list is in time order.
            assert!(run.events().windows(2).all(|w| w[0].t <= w[1].t));
            // The split of the error: location (g at the recorded state) and integration
            // (the recorded state against the exact one at t_e), both over |ẋ|.
            for e in named(&run, "either") {
                let x = state_of::<KnifeEdge>(e);
                let exact_state = s.state(e.t);
                let speed = (s.v * exact_state[2].cos()).abs();
                worst_location = worst_location.max((x[0] - c).abs() / speed);
                worst_integration = worst_integration.max((x[0] - exact_state[0]).abs() / speed);
            }
        }
    }
    println!(
        "knife edge x = c events: worst |t_e − t*| = {worst:.2e} s; location part \
         |x_h(t_e) − c|/|ẋ| ≤ {worst_location:.2e} s, integration part |x_h − x|(t_e)/|ẋ| ≤ \
         {worst_integration:.2e} s"
    );
}

/// The sleighs and starts: the default sleigh turning left from a slow start, the same
/// reversing from a backward start (v₀ < 0, turning right), and a light one with a small
/// inertia turning fast.
fn sleigh_cases() -> Vec<(ChaplyginSleigh, [f64; 3])> {
    vec![
        (ChaplyginSleigh::default(), [0.3, 0.2, 1.5]),
        (ChaplyginSleigh::default(), [-1.2, -0.5, -1.0]),
        (
            ChaplyginSleigh {
                m: 1.0,
                inertia: 0.05,
                a: 0.6,
            },
            [2.0, 0.1, 3.0],
        ),
    ]
}

fn sleigh_motion(sys: &ChaplyginSleigh, [theta0, v0, w0]: [f64; 3]) -> SleighMotion {
    SleighMotion::new(sys.m, sys.inertia, sys.a, theta0, v0, w0)
}

/// The sleigh's speed v = V tanh(kVt + s₀) crosses f·V (V = √(2E/m), its limit) at
/// t = (artanh f − artanh(v₀/V))/(kV); its heading crosses c at the inverse of the
/// Gudermannian form. Events at f = 0 (a backward start reverses), 0.5, 0.9, 0.99 and at
/// θ halfway to its limit, against those times.
#[test]
fn sleigh_speed_and_heading_events_match_the_closed_form() {
    let (mut worst, mut worst_location, mut worst_integration) = (0.0f64, 0.0f64, 0.0f64);
    for (sys, start) in sleigh_cases() {
        let f = sleigh_motion(&sys, start);
        let [theta0, v0, w0] = start;
        let x0 = sys
            .state_from_speeds(0.0, &[0.1, -0.4, theta0], &[v0, w0])
            .expect("a regular state");
        let fractions = [0.0, 0.5, 0.9, 0.99];
        let t_end = f.speed_time(0.995);
        // The heading's limit is θ₀ ± (√(m/J)/k)(π/2 − gd(s₀)); halfway to it.
        let theta_limit =
            theta0 + w0.signum() * (f.m / f.j).sqrt() / f.k * (PI / 2.0 - f.s0.sinh().atan());
        let theta_half = 0.5 * (theta0 + theta_limit);
        let limit = f.limit;
        let mut sim = Simulation::new(&sys, x0)
            .end_time(t_end)
            .sample_interval(0.1)
            .event(Event::new("theta_half", move |_, x: &[f64; 5]| {
                x[2] - theta_half
            }));
        for fraction in fractions {
            sim = sim.event(
                Event::new(format!("v{fraction}"), move |_, x: &[f64; 5]| {
                    x[3] - fraction * limit
                })
                .rising(),
            );
        }
        let run = sim.run_constant(&tight(), []).expect("the run");
        for fraction in fractions {
            let name = format!("v{fraction}");
            let t = f.speed_time(fraction);
            let exact: Vec<f64> = if t > 0.0 { vec![t] } else { vec![] };
            worst = worst.max(compare_times(
                &format!("{start:?} {name}"),
                &run.event_times(&name),
                &exact,
                EVENT_TIME_TOL,
            ));
            for e in named(&run, &name) {
                let x = state_of::<ChaplyginSleigh>(e);
                let vdot = sys.a * f.omega(e.t).powi(2);
                worst_location = worst_location.max((x[3] - fraction * limit).abs() / vdot);
                worst_integration = worst_integration.max((x[3] - f.v(e.t)).abs() / vdot);
            }
        }
        worst = worst.max(compare_times(
            &format!("{start:?} theta_half"),
            &run.event_times("theta_half"),
            &[f.heading_time(theta_half)],
            EVENT_TIME_TOL,
        ));
        // A backward start reverses; a forward one never has v = 0 after t = 0.
        assert_eq!(run.event_times("v0").len(), usize::from(v0 < 0.0));
    }
    println!(
        "sleigh v = fV and θ events: worst |t_e − t*| = {worst:.2e} s; location part \
         |v_h(t_e) − fV|/v̇ ≤ {worst_location:.2e} s, integration part |v_h − v|(t_e)/v̇ ≤ \
         {worst_integration:.2e} s"
    );
}

/// A terminal event ends the run at its time: the last row's t is the event's t, bitwise;
/// the last row's state is the event's state, bitwise; the summary says which event stopped
/// the run and when; the state there matches the closed form; later events (even in the
/// same step) are not recorded; earlier non-terminal ones are. Knife edge (x = c, the second
/// crossing, with a recording event at the first) and sleigh (v = 0.9 V).
#[test]
fn terminal_events_end_the_run_at_their_exact_time() {
    let (mut worst_t, mut worst_state) = (0.0f64, 0.0f64);

    // Knife edge: stop at the second falling crossing of x = c.
    let sys = level_knife();
    for s in knife_starts() {
        let c = s.x_at_sine(0.3);
        let exact = s.x_crossings(c, 100.0);
        let falling: Vec<f64> = exact.iter().filter(|e| !e.1).map(|e| e.0).collect();
        let t_stop = falling[1];
        let run = Simulation::new(&sys, knife_x0(&sys, &s))
            .end_time(100.0)
            .sample_interval(0.1)
            .event(Event::new("cross", move |_, x: &[f64; 5]| x[0] - c))
            .event(
                Event::new("second_fall", {
                    let first = falling[0];
                    // x − c once the first fall is past, −1 before it: the switch, from −1 to
                    // x − c < 0 just after a fall, is no crossing; the next fall is.
                    move |t, x: &[f64; 5]| if t > first + 1e-3 { x[0] - c } else { -1.0 }
                })
                .falling()
                .terminal(),
            )
            .run_constant(&tight(), [])
            .expect("the run");
        let what = format!("knife {s:?}");
        let stop = check_terminal::<KnifeEdge>(&run, "second_fall", &what);
        worst_t = worst_t.max(compare_times(&what, &[stop.t], &[t_stop], EVENT_TIME_TOL));
        let x = state_of::<KnifeEdge>(&stop);
        for (xi, ei) in x.iter().zip(s.state(t_stop)) {
            assert!((xi - ei).abs() <= STATE_TOL, "{what}: {x:?} at the stop");
            worst_state = worst_state.max((xi - ei).abs());
        }
        // Every crossing of x = c up to the stop was recorded, in order, by the recording
        // event; the one at the stop too (it is found in the same step, at the same time).
        let recorded = run.event_times("cross");
        let expected: Vec<f64> = exact
            .iter()
            .map(|e| e.0)
            .filter(|t| *t <= t_stop + 1e-9)
            .collect();
        compare_times(
            &format!("{what} cross"),
            &recorded,
            &expected,
            EVENT_TIME_TOL,
        );
    }

    // Sleigh: stop at v = 0.9 V; a later event (v = 0.99 V) is never recorded.
    for (sys, start) in sleigh_cases() {
        let f = sleigh_motion(&sys, start);
        let [theta0, v0, w0] = start;
        let x0 = sys
            .state_from_speeds(0.0, &[0.1, -0.4, theta0], &[v0, w0])
            .unwrap();
        let limit = f.limit;
        let t_stop = f.speed_time(0.9);
        let run = Simulation::new(&sys, x0)
            .end_time(f.speed_time(0.999))
            .sample_interval(0.1)
            .event(Event::new("half", move |_, x: &[f64; 5]| x[3] - 0.5 * limit).rising())
            .event(
                Event::new("ninety", move |_, x: &[f64; 5]| x[3] - 0.9 * limit)
                    .rising()
                    .terminal(),
            )
            .event(Event::new("later", move |_, x: &[f64; 5]| x[3] - 0.99 * limit).rising())
            // A zero 1e-9 s after the terminal one, in the same step: found, then dropped,
            // for it did not happen.
            .event(Event::new("just_after", move |t, _: &[f64; 5]| t - t_stop - 1e-9).rising())
            .run_constant(&tight(), [])
            .unwrap();
        let what = format!("sleigh {start:?}");
        let stop = check_terminal::<ChaplyginSleigh>(&run, "ninety", &what);
        worst_t = worst_t.max(compare_times(&what, &[stop.t], &[t_stop], EVENT_TIME_TOL));
        let x = state_of::<ChaplyginSleigh>(&stop);
        for (xi, ei) in
            [x[2], x[3], x[4]]
                .iter()
                .zip([f.theta(t_stop), f.v(t_stop), f.omega(t_stop)])
        {
            assert!((xi - ei).abs() <= STATE_TOL, "{what}: {x:?} at the stop");
            worst_state = worst_state.max((xi - ei).abs());
        }
        assert_eq!(run.event_times("half").len(), 1, "{what}");
        assert!(run.event_times("later").is_empty(), "{what}");
        assert!(run.event_times("just_after").is_empty(), "{what}");
    }
    println!(
        "terminal events: worst |t_stop − t*| = {worst_t:.2e} s; worst state error there \
         {worst_state:.2e}"
    );
}

/// The checks every terminal stop must pass; returns the terminal event.
fn check_terminal<S: HamelSystem>(run: &Trajectory, name: &str, what: &str) -> EventRecord {
    let last = run.events().last().expect("events").clone();
    assert_eq!(
        last.name, name,
        "{what}: the last event is the terminal one"
    );
    assert!(last.terminal, "{what}");
    assert_eq!(
        run.events().iter().filter(|e| e.terminal).count(),
        1,
        "{what}: one terminal event"
    );
    let t_last = *run.times().last().unwrap();
    assert_eq!(
        t_last.to_bits(),
        last.t.to_bits(),
        "{what}: the last row is at {t_last}, the event at {}",
        last.t
    );
    assert_eq!(
        run.summary().stopped,
        Some(Stopped::Event {
            name: name.to_string(),
            t: last.t,
        }),
        "{what}"
    );
    // The last row's state is the event's.
    for name in S::STATE {
        let column = run.column(name).unwrap();
        assert_eq!(
            column.last().unwrap().to_bits(),
            last.state.get(name).unwrap().to_bits(),
            "{what}: {name} in the last row and at the event"
        );
    }
    assert_eq!(run.summary().samples, run.len());
    // Sample times before the stop stay on the grid, ascending.
    assert!(run.times().windows(2).all(|w| w[0] < w[1]), "{what}");
    last
}

/// The same event function recording and terminal: recording, every crossing over the span
/// is found and the run reaches its end time with `stopped` None; terminal, only the first
/// is, and the run ends there.
#[test]
fn recording_and_terminal_events_differ_only_in_where_the_run_ends() {
    let sys = level_knife();
    let s = knife_starts()[0];
    let c = s.phi0 + 0.1;
    // sin(φ − c) crosses zero every π/ω.
    let g = move |_: f64, x: &[f64; 5]| (x[2] - c).sin();
    let sim = |terminal: bool| {
        let event = Event::new("g", g);
        let event = if terminal { event.terminal() } else { event };
        Simulation::new(&sys, knife_x0(&sys, &s))
            .end_time(10.0)
            .sample_interval(0.1)
            .event(event)
            .run_constant(&tight(), [])
            .unwrap()
    };
    let recording = sim(false);
    let terminal = sim(true);
    let exact: Vec<f64> = (0..)
        .map(|n| s.heading_time(c + n as f64 * PI))
        .filter(|t| *t > 0.0)
        .take_while(|t| *t <= 10.0)
        .collect();
    assert!(exact.len() >= 4);
    let worst = compare_times(
        "recording",
        &recording.event_times("g"),
        &exact,
        EVENT_TIME_TOL,
    );
    assert_eq!(recording.summary().stopped, None);
    assert_eq!(*recording.times().last().unwrap(), 10.0);
    assert!(recording.events().iter().all(|e| !e.terminal));
    assert_eq!(recording.len(), 101);

    compare_times(
        "terminal",
        &terminal.event_times("g"),
        &exact[..1],
        EVENT_TIME_TOL,
    );
    assert_eq!(terminal.event_times("g")[0], recording.event_times("g")[0]);
    check_terminal::<KnifeEdge>(&terminal, "g", "terminal sin(φ − c)");
    // Up to the stop the two runs recorded the same samples.
    let n = terminal.len() - 1;
    assert_eq!(&terminal.times()[..n], &recording.times()[..n]);
    assert_eq!(
        &terminal.column("x").unwrap()[..n],
        &recording.column("x").unwrap()[..n]
    );
    println!(
        "recording vs terminal: worst |t_e − t*| = {worst:.2e} s over {} crossings",
        exact.len()
    );
}

/// The event tolerance is honoured: at a loose 1e-4 (relative to the step) the located times
/// err by more than at the default and stay within the tolerance's bound (half of it times
/// the step, plus the integration error), and the default meets `EVENT_TIME_TOL`. The events
/// are on x = c of the knife edge (x is a sine of t, so Brent's method does not land on the
/// root in one secant step as it would for the linear φ), with the steps capped at 0.05 s so
/// that the loose bound is known: 0.5 · 1e-4 · 0.05 = 2.5e-6 s.
#[test]
fn event_tolerance_is_honoured() {
    let sys = level_knife();
    let integrator = tight().with_max_step(0.05);
    let mut worst = [0.0f64; 2];
    for s in knife_starts() {
        let c = s.x_at_sine(0.3);
        let exact: Vec<f64> = s.x_crossings(c, 20.0).iter().map(|e| e.0).collect();
        for (k, tolerance) in [(0, EVENT_TOLERANCE), (1, 1e-4)] {
            let run = Simulation::new(&sys, knife_x0(&sys, &s))
                .end_time(20.0)
                .sample_interval(0.5)
                .event_tolerance(tolerance)
                .event(Event::new("x", move |_, x: &[f64; 5]| x[0] - c))
                .run_constant(&integrator, [])
                .unwrap();
            let bound = if k == 0 {
                EVENT_TIME_TOL
            } else {
                0.5 * tolerance * 0.05 + EVENT_TIME_TOL
            };
            worst[k] = worst[k].max(compare_times(
                &format!("{s:?} tolerance {tolerance:e}"),
                &run.event_times("x"),
                &exact,
                bound,
            ));
        }
    }
    println!(
        "event tolerance: worst |t_e − t*| {:.2e} s at the default {EVENT_TOLERANCE:e}, {:.2e} s \
         at 1e-4",
        worst[0], worst[1]
    );
    assert!(
        worst[1] > 100.0 * worst[0],
        "a loose tolerance should show: {worst:?}"
    );
}

/// Events under RK4 are located on its cubic Hermite interpolant, whose error (third order
/// within the step) adds to the integration's: with h = 1e-3 both are far below
/// `EVENT_TIME_TOL` for the knife edge. A terminal event ends an RK4 run exactly as it does
/// a Dormand–Prince one.
#[test]
fn events_under_rk4() {
    let sys = level_knife();
    let mut worst = 0.0f64;
    for s in knife_starts() {
        let c = s.x_at_sine(0.3);
        let exact = s.x_crossings(c, 50.0);
        let times: Vec<f64> = exact.iter().map(|e| e.0).collect();
        let run = Simulation::new(&sys, knife_x0(&sys, &s))
            .end_time(50.0)
            .sample_interval(0.1)
            .event(Event::new("x", move |_, x: &[f64; 5]| x[0] - c))
            .event(
                Event::new("stop", move |_, x: &[f64; 5]| x[0] - c)
                    .falling()
                    .terminal(),
            )
            .run_constant(&Rk4::new(1e-3), [])
            .unwrap();
        let t_stop = exact.iter().find(|e| !e.1).unwrap().0;
        let n = times.iter().position(|t| *t == t_stop).unwrap() + 1;
        worst = worst.max(compare_times(
            &format!("rk4 {s:?}"),
            &run.event_times("x"),
            &times[..n],
            EVENT_TIME_TOL,
        ));
        let stop = check_terminal::<KnifeEdge>(&run, "stop", &format!("rk4 {s:?}"));
        worst = worst.max((stop.t - t_stop).abs());
    }
    println!("RK4 (h = 1e-3) x = c events: worst |t_e − t*| = {worst:.2e} s");
}
