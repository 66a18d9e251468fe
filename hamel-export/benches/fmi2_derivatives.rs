//! `fmi2GetDerivatives` against the Rust right-hand side it wraps, on the paper's robot and
//! on the benchmark bicycle:
//!
//! ```text
//! cargo bench -p hamel-export --bench fmi2_derivatives [-- ROUNDS BATCH]
//! ```
//!
//! A: `fmi2GetDerivatives` of an instance in continuous-time mode, called through a
//! function pointer as an importer calls the FMU's symbol: the symbol's body, the function
//! `hamel_export::fmi2!` exports under that name, in the release profile. B:
//! `HamelSystem::rhs_prepared`, what a hamel simulation calls at every stage (and what the FMU
//! calls); C: `HamelSystem::rhs`, the model's right-hand side. They alternate in batches of
//! BATCH calls, ROUNDS times (interleaved: the machine's drift hits all of them); printed are
//! the median time per call of each and the median of the per-round ratios A/B and A/C with
//! their 10th and 90th percentiles. Also D: `fmi2SetTime`, `fmi2SetContinuousStates` and
//! `fmi2GetDerivatives`, an importer's evaluation, against B.

use hamel_export::Model;
use hamel_export::fmi2::types::{CallbackFunctions, Component, EventInfo, Status};
use hamel_export::fmi2::variables::{Role, Table};
use hamel_export::fmi2::{api, exchange};
use hamel_models::{MobileRobot, WhippleBicycle};
use hamel_runtime::{HamelSystem, Vector};
use std::hint::black_box;
use std::time::Instant;

hamel_export::model!(Robot => MobileRobot);
hamel_export::model!(Bicycle => WhippleBicycle);

type GetDerivatives = unsafe extern "C" fn(Component, *mut f64, usize) -> Status;
type SetStates = unsafe extern "C" fn(Component, *const f64, usize) -> Status;
type SetTime = unsafe extern "C" fn(Component, f64) -> Status;

/// The exported functions' bodies for model `M`, as `hamel_export::fmi2!` writes them.
unsafe extern "C" fn get_derivatives<M: Model>(c: Component, dx: *mut f64, n: usize) -> Status {
    unsafe { exchange::get_derivatives::<M>(c, dx, n) }
}

unsafe extern "C" fn set_states<M: Model>(c: Component, x: *const f64, n: usize) -> Status {
    unsafe { exchange::set_continuous_states::<M>(c, x, n) }
}

unsafe extern "C" fn set_time<M: Model>(c: Component, t: f64) -> Status {
    unsafe { exchange::set_time::<M>(c, t) }
}

/// An instance of `M` in continuous-time mode at (0, x, u).
fn running_instance<M: Model>(identifier: &str, x: &[f64], u: &[f64]) -> Component {
    let functions = CallbackFunctions {
        logger: None,
        allocate_memory: None,
        free_memory: None,
        step_finished: None,
        component_environment: core::ptr::null_mut(),
    };
    let guid = std::ffi::CString::new(hamel_export::fmi2::guid::<M>(identifier)).unwrap();
    let table = Table::of::<M>();
    // SAFETY: valid arguments, each call's status checked.
    unsafe {
        let c = api::instantiate::<M>(
            identifier,
            c"bench".as_ptr(),
            0,
            guid.as_ptr(),
            c"".as_ptr(),
            &functions,
            0,
            0,
        );
        assert!(!c.is_null());
        assert_eq!(
            api::setup_experiment::<M>(c, 0, 0.0, 0.0, 0, 0.0),
            Status::Ok
        );
        let roles = (0..x.len())
            .map(Role::State)
            .chain((0..u.len()).map(Role::Input));
        for (role, v) in roles.zip(x.iter().chain(u)) {
            assert_eq!(
                api::set_real::<M>(c, &table.reference(role), 1, v),
                Status::Ok
            );
        }
        assert_eq!(api::enter_initialization_mode::<M>(c), Status::Ok);
        assert_eq!(api::exit_initialization_mode::<M>(c), Status::Ok);
        let mut info = EventInfo::default();
        assert_eq!(exchange::new_discrete_states::<M>(c, &mut info), Status::Ok);
        assert_eq!(exchange::enter_continuous_time_mode::<M>(c), Status::Ok);
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

type State<M> = <<M as Model>::System as HamelSystem>::State;
type Inputs<M> = <<M as Model>::System as HamelSystem>::Inputs;

/// The four, interleaved, on model `M` at the state the FMU reached from `x` (its dependent
/// coordinates solved).
fn compare<M: Model>(identifier: &str, x: &[f64], u: &[f64], rounds: usize, batch: usize) {
    let c = running_instance::<M>(identifier, x, u);
    let system = M::System::default();
    let mut prepared = vec![0.0; <M::System as HamelSystem>::PREPARED_LEN];
    system.prepare(&mut prepared);
    let n = State::<M>::LEN;
    let mut x0 = State::<M>::zeros();
    // SAFETY: a live instance and n values.
    assert_eq!(
        unsafe { exchange::get_continuous_states::<M>(c, x0.as_mut().as_mut_ptr(), n) },
        Status::Ok
    );
    let u0 = Inputs::<M>::from_slice(u).unwrap();
    // Through pointers the optimizer cannot see through, as an importer calls the symbols.
    let get: GetDerivatives = black_box(get_derivatives::<M>);
    let put: SetStates = black_box(set_states::<M>);
    let clock: SetTime = black_box(set_time::<M>);
    let (mut a, mut b) = (State::<M>::zeros(), State::<M>::zeros());
    // SAFETY: as above.
    assert_eq!(unsafe { get(c, a.as_mut().as_mut_ptr(), n) }, Status::Ok);
    system
        .rhs_prepared(&prepared, 0.0, &x0, &u0, &mut b)
        .unwrap();
    assert_eq!(
        a, b,
        "fmi2GetDerivatives is the model's right-hand side, bit for bit"
    );

    let fmu = |dx: &mut State<M>| {
        // SAFETY: as above.
        black_box(unsafe { get(black_box(c), dx.as_mut().as_mut_ptr(), n) });
    };
    let importer = |dx: &mut State<M>| {
        // SAFETY: as above.
        unsafe {
            black_box(clock(black_box(c), black_box(0.0)));
            black_box(put(black_box(c), black_box(&x0).as_ref().as_ptr(), n));
            black_box(get(black_box(c), dx.as_mut().as_mut_ptr(), n));
        }
    };
    let prepared_rhs = |dx: &mut State<M>| {
        let r = black_box(&system).rhs_prepared(
            black_box(&prepared),
            black_box(0.0),
            black_box(&x0),
            black_box(&u0),
            dx,
        );
        let _ = black_box(r);
    };
    let plain_rhs = |dx: &mut State<M>| {
        let r = black_box(&system).rhs(black_box(0.0), black_box(&x0), black_box(&u0), dx);
        let _ = black_box(r);
    };
    let mut dx = State::<M>::zeros();
    let mut times = [vec![], vec![], vec![], vec![]];
    let mut ratios = [vec![], vec![], vec![]];
    for _ in 0..rounds {
        let ta = time(batch, || fmu(&mut dx));
        let tb = time(batch, || prepared_rhs(&mut dx));
        let tc = time(batch, || plain_rhs(&mut dx));
        let td = time(batch, || importer(&mut dx));
        for (v, t) in times.iter_mut().zip([ta, tb, tc, td]) {
            v.push(t);
        }
        for (v, r) in ratios.iter_mut().zip([ta / tb, ta / tc, td / tb]) {
            v.push(r);
        }
    }
    black_box(dx);
    let [ta, tb, tc, td] = &mut times;
    let ns = |v: &mut Vec<f64>| 1e9 * quantile(v, 0.5);
    println!(
        "{identifier}, per call (median of {rounds} rounds of {batch}): A fmi2GetDerivatives \
         {:.1} ns, B rhs_prepared {:.1} ns, C rhs {:.1} ns, D set time + states + derivatives \
         {:.1} ns",
        ns(ta),
        ns(tb),
        ns(tc),
        ns(td)
    );
    for (name, r) in ["A/B", "A/C", "D/B"].iter().zip(&mut ratios) {
        println!(
            "  {name}: median {:.3} (p10 {:.3}, p90 {:.3})",
            quantile(r, 0.5),
            quantile(r, 0.1),
            quantile(r, 0.9)
        );
    }
    // SAFETY: made by instantiate, freed once.
    unsafe { api::free_instance::<M>(c) };
}

fn main() {
    let args: Vec<usize> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .collect();
    let rounds = args.first().copied().unwrap_or(401);
    let batch = args.get(1).copied().unwrap_or(10_000);
    println!(
        "load: {}",
        std::fs::read_to_string("/proc/loadavg")
            .unwrap_or_default()
            .trim()
    );
    let robot = [0.1, -0.2, 0.3, 0.4, -0.5, 0.2, 0.5, 0.4];
    compare::<Robot>("MobileRobot", &robot, &[0.1, 0.05], rounds, batch);
    // The bicycle at 4.6 m/s, leaning by 0.05 rad, its pitch solved by the FMU.
    let mut bicycle = [0.0; 11];
    bicycle[3] = 0.05;
    bicycle[8] = 0.5;
    bicycle[10] = -4.6 / 0.3;
    compare::<Bicycle>("WhippleBicycle", &bicycle, &[0.0, 0.01], rounds, batch / 4);
}
