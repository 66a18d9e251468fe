//! `fmi2GetDerivatives` against the Rust right-hand side it wraps, on the paper's robot:
//!
//! ```text
//! cargo bench -p hamel-export --bench fmi2_derivatives [-- ROUNDS BATCH]
//! ```
//!
//! A: `fmi2GetDerivatives` of an instance in continuous-time mode, called through a
//! function pointer as an importer calls the FMU's symbol (the same code as the FMU's
//! library: `hamel_export::fmi2!`, release profile). B: `HamelSystem::rhs_prepared`, what a
//! hamel simulation calls at every stage; C: `HamelSystem::rhs`. The three alternate in
//! batches of BATCH calls, ROUNDS times (interleaved: the machine's drift hits all three);
//! printed are the median time per call of each and the median of the per-round ratios A/B and
//! A/C with their 10th and 90th percentiles. Also D: `fmi2SetTime`, `fmi2SetContinuousStates`
//! and `fmi2GetDerivatives`, what an importer's evaluation costs, against B.

use core::ffi::{c_char, c_int, c_void};
use hamel_export::fmi2::types::{CallbackFunctions, EventInfo, Status};
use hamel_models::MobileRobot;
use hamel_runtime::HamelSystem;
use std::hint::black_box;
use std::time::Instant;

hamel_export::model!(Robot => MobileRobot);
hamel_export::fmi2!(Robot, "MobileRobot");

type Component = *mut c_void;
type GetDerivatives = unsafe extern "C" fn(Component, *mut f64, usize) -> Status;
type SetStates = unsafe extern "C" fn(Component, *const f64, usize) -> Status;
type SetTime = unsafe extern "C" fn(Component, f64) -> Status;

unsafe extern "C" {
    fn fmi2Instantiate(
        name: *const c_char,
        kind: c_int,
        guid: *const c_char,
        resources: *const c_char,
        functions: *const CallbackFunctions,
        visible: c_int,
        logging_on: c_int,
    ) -> Component;
    fn fmi2SetupExperiment(
        c: Component,
        td: c_int,
        tol: f64,
        t0: f64,
        sd: c_int,
        t1: f64,
    ) -> Status;
    fn fmi2SetReal(c: Component, vr: *const u32, n: usize, v: *const f64) -> Status;
    fn fmi2EnterInitializationMode(c: Component) -> Status;
    fn fmi2ExitInitializationMode(c: Component) -> Status;
    fn fmi2NewDiscreteStates(c: Component, info: *mut EventInfo) -> Status;
    fn fmi2EnterContinuousTimeMode(c: Component) -> Status;
    fn fmi2GetDerivatives(c: Component, dx: *mut f64, n: usize) -> Status;
    fn fmi2SetContinuousStates(c: Component, x: *const f64, n: usize) -> Status;
    fn fmi2SetTime(c: Component, t: f64) -> Status;
    fn fmi2FreeInstance(c: Component);
}

const X: [f64; 8] = [0.1, -0.2, 0.3, 0.4, -0.5, 0.2, 0.5, 0.4];
const U: [f64; 2] = [0.1, 0.05];

/// An instance of the robot in continuous-time mode at (t, X, U).
fn running_instance() -> Component {
    let functions = CallbackFunctions {
        logger: None,
        allocate_memory: None,
        free_memory: None,
        step_finished: None,
        component_environment: core::ptr::null_mut(),
    };
    let guid = std::ffi::CString::new(hamel_export::fmi2::guid::<Robot>("MobileRobot")).unwrap();
    let table = hamel_export::fmi2::variables::Table::of::<Robot>();
    use hamel_export::fmi2::variables::Role;
    // SAFETY: valid arguments, each call's status checked.
    unsafe {
        let c = fmi2Instantiate(
            c"bench".as_ptr(),
            0,
            guid.as_ptr(),
            c"".as_ptr(),
            &functions,
            0,
            0,
        );
        assert!(!c.is_null());
        assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0), Status::Ok);
        for (i, v) in X.iter().enumerate() {
            assert_eq!(
                fmi2SetReal(c, &table.reference(Role::State(i)), 1, v),
                Status::Ok
            );
        }
        for (i, v) in U.iter().enumerate() {
            assert_eq!(
                fmi2SetReal(c, &table.reference(Role::Input(i)), 1, v),
                Status::Ok
            );
        }
        assert_eq!(fmi2EnterInitializationMode(c), Status::Ok);
        assert_eq!(fmi2ExitInitializationMode(c), Status::Ok);
        let mut info = EventInfo::default();
        assert_eq!(fmi2NewDiscreteStates(c, &mut info), Status::Ok);
        assert_eq!(fmi2EnterContinuousTimeMode(c), Status::Ok);
        c
    }
}

/// Seconds per call of `f`, over `batch` calls.
fn time(batch: usize, mut f: impl FnMut()) -> f64 {
    let start = Instant::now();
    for _ in 0..batch {
        f();
    }
    start.elapsed().as_secs_f64() / batch as f64
}

fn quantile(values: &mut [f64], q: f64) -> f64 {
    values.sort_by(f64::total_cmp);
    values[((values.len() - 1) as f64 * q).round() as usize]
}

fn main() {
    let args: Vec<usize> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .collect();
    let rounds = args.first().copied().unwrap_or(31);
    let batch = args.get(1).copied().unwrap_or(200_000);
    let c = running_instance();
    let robot = MobileRobot::default();
    let mut prepared = vec![0.0; MobileRobot::PREPARED_LEN];
    robot.prepare(&mut prepared);
    // Through pointers the optimizer cannot see through, as an importer calls the symbol.
    let get: GetDerivatives = black_box(fmi2GetDerivatives);
    let set_states: SetStates = black_box(fmi2SetContinuousStates);
    let set_time: SetTime = black_box(fmi2SetTime);
    // The same values from both sides first.
    let (mut a, mut b) = ([0.0; 8], [0.0; 8]);
    // SAFETY: a live instance and 8 values.
    assert_eq!(unsafe { get(c, a.as_mut_ptr(), 8) }, Status::Ok);
    robot.rhs_prepared(&prepared, 0.0, &X, &U, &mut b).unwrap();
    assert_eq!(
        a, b,
        "fmi2GetDerivatives is the model's right-hand side, bit for bit"
    );

    let mut fmu = |dx: &mut [f64; 8]| {
        // SAFETY: as above.
        let status = unsafe { get(black_box(c), dx.as_mut_ptr(), 8) };
        black_box(status);
    };
    let mut importer = |dx: &mut [f64; 8]| {
        // SAFETY: as above.
        unsafe {
            black_box(set_time(black_box(c), black_box(0.0)));
            black_box(set_states(black_box(c), black_box(&X).as_ptr(), 8));
            black_box(get(black_box(c), dx.as_mut_ptr(), 8));
        }
    };
    let prepared_rhs = |dx: &mut [f64; 8]| {
        let r = black_box(&robot).rhs_prepared(
            black_box(&prepared),
            black_box(0.0),
            black_box(&X),
            black_box(&U),
            dx,
        );
        let _ = black_box(r);
    };
    let plain_rhs = |dx: &mut [f64; 8]| {
        let r = black_box(&robot).rhs(black_box(0.0), black_box(&X), black_box(&U), dx);
        let _ = black_box(r);
    };
    let mut dx = [0.0; 8];
    let (mut ta, mut tb, mut tc, mut td) = (vec![], vec![], vec![], vec![]);
    let (mut ab, mut ac, mut db) = (vec![], vec![], vec![]);
    for _ in 0..rounds {
        let a = time(batch, || fmu(&mut dx));
        let b = time(batch, || prepared_rhs(&mut dx));
        let c_ = time(batch, || plain_rhs(&mut dx));
        let d = time(batch, || importer(&mut dx));
        ta.push(a);
        tb.push(b);
        tc.push(c_);
        td.push(d);
        ab.push(a / b);
        ac.push(a / c_);
        db.push(d / b);
    }
    black_box(dx);
    let ns = |v: &mut Vec<f64>| 1e9 * quantile(v, 0.5);
    println!(
        "per call (median of {rounds} rounds of {batch}): A fmi2GetDerivatives {:.1} ns, \
         B rhs_prepared {:.1} ns, C rhs {:.1} ns, D set time + states + derivatives {:.1} ns",
        ns(&mut ta),
        ns(&mut tb),
        ns(&mut tc),
        ns(&mut td)
    );
    for (name, ratios) in [("A/B", &mut ab), ("A/C", &mut ac), ("D/B", &mut db)] {
        println!(
            "{name}: median {:.3} (p10 {:.3}, p90 {:.3})",
            quantile(ratios, 0.5),
            quantile(ratios, 0.1),
            quantile(ratios, 0.9)
        );
    }
    // SAFETY: made by fmi2Instantiate, freed once.
    unsafe { fmi2FreeInstance(c) };
}
