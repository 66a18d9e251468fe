//! The robot's FMI 2.0 functions called as an importer calls them (the symbols of
//! `hamel_export::fmi2!`, linked into this test): two instances with different parameters
//! side by side, each equal to the model's own right-hand side bit for bit; exact directional
//! derivatives; every call out of order, unknown value reference, value that is not finite,
//! null pointer and failed step refused with its status and a message through the logger,
//! never a panic. FMPy runs the FMU itself in `tests/python/test_fmu.py`.

use core::ffi::{CStr, c_char, c_int, c_uint, c_void};
use hamel_export::fmi2::types::{CallbackFunctions, EventInfo, Logger, Status};
use hamel_export::fmi2::variables::{Role, Table};
use hamel_models::MobileRobot;
use hamel_runtime::{HamelSystem, Parameters};
use std::sync::Mutex;

hamel_export::model!(Robot => MobileRobot);
hamel_export::fmi2!(Robot, "MobileRobot");

type Component = *mut c_void;

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
    fn fmi2FreeInstance(c: Component);
    fn fmi2SetupExperiment(
        c: Component,
        td: c_int,
        tol: f64,
        t0: f64,
        sd: c_int,
        t1: f64,
    ) -> Status;
    fn fmi2EnterInitializationMode(c: Component) -> Status;
    fn fmi2ExitInitializationMode(c: Component) -> Status;
    fn fmi2Reset(c: Component) -> Status;
    fn fmi2SetReal(c: Component, vr: *const c_uint, n: usize, v: *const f64) -> Status;
    fn fmi2GetReal(c: Component, vr: *const c_uint, n: usize, v: *mut f64) -> Status;
    fn fmi2EnterEventMode(c: Component) -> Status;
    fn fmi2NewDiscreteStates(c: Component, info: *mut EventInfo) -> Status;
    fn fmi2EnterContinuousTimeMode(c: Component) -> Status;
    fn fmi2SetTime(c: Component, t: f64) -> Status;
    fn fmi2SetContinuousStates(c: Component, x: *const f64, n: usize) -> Status;
    fn fmi2GetDerivatives(c: Component, dx: *mut f64, n: usize) -> Status;
    fn fmi2GetDirectionalDerivative(
        c: Component,
        unknowns: *const c_uint,
        nu: usize,
        knowns: *const c_uint,
        nk: usize,
        seeds: *const f64,
        out: *mut f64,
    ) -> Status;
    fn fmi2DoStep(c: Component, t: f64, h: f64, no_set: c_int) -> Status;
    fn fmi2GetRealStatus(c: Component, kind: c_int, value: *mut f64) -> Status;
    fn fmi2GetFMUstate(c: Component, s: *mut *mut c_void) -> Status;
    fn fmi2SetFMUstate(c: Component, s: *mut c_void) -> Status;
    fn fmi2FreeFMUstate(c: Component, s: *mut *mut c_void) -> Status;
    fn fmi2SerializedFMUstateSize(c: Component, s: *mut c_void, size: *mut usize) -> Status;
    fn fmi2SerializeFMUstate(c: Component, s: *mut c_void, b: *mut c_char, n: usize) -> Status;
    fn fmi2DeSerializeFMUstate(
        c: Component,
        b: *const c_char,
        n: usize,
        s: *mut *mut c_void,
    ) -> Status;
    fn fmi2GetBooleanStatus(c: Component, kind: c_int, value: *mut c_int) -> Status;
}

/// The messages the FMU logged, with their status.
type Log = Mutex<Vec<(Status, String)>>;

/// The logger: FMI's is C-variadic, which stable Rust cannot define; the FMU passes no
/// variadic argument, so a function of the five fixed ones, called through the variadic
/// type, reads all there is (as FMPy's ctypes logger does).
unsafe extern "C" fn record(
    environment: *mut c_void,
    _instance: *const c_char,
    status: Status,
    _category: *const c_char,
    message: *const c_char,
) {
    // SAFETY: the environment is the `Log` below; the message a C string.
    let log = unsafe { &*(environment as *const Log) };
    let text = unsafe { CStr::from_ptr(message) }
        .to_string_lossy()
        .into_owned();
    log.lock().unwrap().push((status, text));
}

struct Fmu {
    c: Component,
    log: Box<Log>,
    _functions: Box<CallbackFunctions>,
}

impl Fmu {
    fn new(kind: c_int) -> Fmu {
        let log: Box<Log> = Box::default();
        // SAFETY: see `record`.
        let logger: Logger = unsafe {
            core::mem::transmute::<
                unsafe extern "C" fn(
                    *mut c_void,
                    *const c_char,
                    Status,
                    *const c_char,
                    *const c_char,
                ),
                Logger,
            >(record)
        };
        let functions = Box::new(CallbackFunctions {
            logger: Some(logger),
            allocate_memory: None,
            free_memory: None,
            step_finished: None,
            component_environment: &*log as *const Log as *mut c_void,
        });
        let guid =
            std::ffi::CString::new(hamel_export::fmi2::guid::<Robot>("MobileRobot")).unwrap();
        // SAFETY: valid strings and callbacks that outlive the instance.
        let c = unsafe {
            fmi2Instantiate(
                c"robot".as_ptr(),
                kind,
                guid.as_ptr(),
                c"".as_ptr(),
                &*functions,
                0,
                0,
            )
        };
        assert!(!c.is_null(), "{:?}", log.lock().unwrap());
        Fmu {
            c,
            log,
            _functions: functions,
        }
    }

    fn vr(role: Role) -> c_uint {
        Table::of::<Robot>().reference(role)
    }

    fn set(&self, role: Role, value: f64) -> Status {
        // SAFETY: one value reference and one value.
        unsafe { fmi2SetReal(self.c, &Self::vr(role), 1, &value) }
    }

    fn get(&self, role: Role) -> (Status, f64) {
        let mut value = f64::NAN;
        // SAFETY: as above.
        let status = unsafe { fmi2GetReal(self.c, &Self::vr(role), 1, &mut value) };
        (status, value)
    }

    /// The last message logged.
    fn last(&self) -> String {
        self.log
            .lock()
            .unwrap()
            .last()
            .map(|(_, m)| m.clone())
            .unwrap_or_default()
    }

    /// Setup, start values, initialization; Model Exchange ends in continuous-time mode.
    fn start(&self, state: &[f64; 8]) {
        unsafe {
            assert_eq!(fmi2SetupExperiment(self.c, 0, 0.0, 0.0, 0, 0.0), Status::Ok);
            for (i, v) in state.iter().enumerate() {
                assert_eq!(self.set(Role::State(i), *v), Status::Ok);
            }
            assert_eq!(fmi2EnterInitializationMode(self.c), Status::Ok);
            assert_eq!(
                fmi2ExitInitializationMode(self.c),
                Status::Ok,
                "{}",
                self.last()
            );
        }
    }

    fn derivatives(&self) -> (Status, [f64; 8]) {
        let mut dx = [0.0; 8];
        // SAFETY: 8 values.
        let status = unsafe { fmi2GetDerivatives(self.c, dx.as_mut_ptr(), 8) };
        (status, dx)
    }
}

impl Drop for Fmu {
    fn drop(&mut self) {
        // SAFETY: made by fmi2Instantiate, freed once.
        unsafe { fmi2FreeInstance(self.c) }
    }
}

const STATE: [f64; 8] = [0.1, -0.2, 0.3, 0.4, -0.5, 0.2, 0.5, 0.4];
const ME: c_int = 0;
const CS: c_int = 1;

fn continuous(fmu: &Fmu) {
    let mut info = EventInfo::default();
    unsafe {
        assert_eq!(fmi2NewDiscreteStates(fmu.c, &mut info), Status::Ok);
        assert_eq!(fmi2EnterContinuousTimeMode(fmu.c), Status::Ok);
    }
}

#[test]
fn two_robots_with_their_own_parameters_give_the_model_s_right_hand_side() {
    let (light, heavy) = (Fmu::new(ME), Fmu::new(ME));
    let m0 = MobileRobot::NAMES.iter().position(|n| *n == "m0").unwrap();
    assert_eq!(heavy.set(Role::Parameter(m0), 25.0), Status::Ok);
    for fmu in [&light, &heavy] {
        fmu.start(&STATE);
        continuous(fmu);
        assert_eq!(fmu.set(Role::Input(0), 0.1), Status::Ok);
    }
    let u = [0.1, 0.0];
    for (fmu, mass) in [(&light, 10.0), (&heavy, 25.0)] {
        let robot = MobileRobot {
            m0: mass,
            ..MobileRobot::default()
        };
        let mut expected = [0.0; 8];
        robot.rhs(0.0, &STATE, &u, &mut expected).unwrap();
        let (status, dx) = fmu.derivatives();
        assert_eq!(status, Status::Ok);
        assert_eq!(dx, expected, "bit for bit");
        assert_eq!(fmu.get(Role::Derivative(6)), (Status::Ok, expected[6]));
        assert_eq!(
            fmu.get(Role::Energy),
            (Status::Ok, robot.energy(0.0, &STATE).unwrap())
        );
    }
    assert_ne!(light.derivatives().1, heavy.derivatives().1);
}

#[test]
fn directional_derivatives_are_the_exact_jacobian() {
    let fmu = Fmu::new(ME);
    fmu.start(&STATE);
    continuous(&fmu);
    assert_eq!(fmu.set(Role::Input(1), -0.2), Status::Ok);
    let robot = MobileRobot::default();
    let (a, b) = robot.jacobian(0.0, &STATE, &[0.0, -0.2]).unwrap();
    let unknowns: Vec<c_uint> = (0..8).map(|i| Fmu::vr(Role::Derivative(i))).collect();
    for j in 0..10 {
        let known = if j < 8 {
            Role::State(j)
        } else {
            Role::Input(j - 8)
        };
        let mut column = [0.0; 8];
        let status = unsafe {
            fmi2GetDirectionalDerivative(
                fmu.c,
                unknowns.as_ptr(),
                8,
                &Fmu::vr(known),
                1,
                &1.0,
                column.as_mut_ptr(),
            )
        };
        assert_eq!(status, Status::Ok, "{}", fmu.last());
        for (i, value) in column.iter().enumerate() {
            let exact = if j < 8 {
                a[i * 8 + j]
            } else {
                b[i * 2 + j - 8]
            };
            assert!(
                (value - exact).abs() <= 1e-14 * exact.abs().max(1.0),
                "d der(x{i}) / d {known:?}: {value} against {exact}"
            );
        }
    }
}

#[test]
fn bad_calls_are_refused_with_a_message() {
    let fmu = Fmu::new(ME);
    // Out of order: the derivatives before initialization.
    assert_eq!(fmu.derivatives().0, Status::Error);
    assert!(fmu.last().contains("instantiated"), "{}", fmu.last());
    // The instance is in the error mode now: nothing but reading, reset and free.
    assert_eq!(fmu.set(Role::Input(0), 1.0), Status::Error);
    assert_eq!(unsafe { fmi2Reset(fmu.c) }, Status::Ok);
    // Unknown value references, values that are not finite, null pointers, a wrong length.
    let unknown = 10_000;
    assert_eq!(
        unsafe { fmi2SetReal(fmu.c, &unknown, 1, &1.0) },
        Status::Error
    );
    assert!(
        fmu.last().contains("unknown value reference 10000"),
        "{}",
        fmu.last()
    );
    unsafe { fmi2Reset(fmu.c) };
    assert_eq!(fmu.set(Role::State(2), f64::NAN), Status::Error);
    assert!(fmu.last().contains("alpha = NaN"), "{}", fmu.last());
    unsafe { fmi2Reset(fmu.c) };
    assert_eq!(
        unsafe { fmi2SetReal(fmu.c, core::ptr::null(), 2, core::ptr::null()) },
        Status::Error
    );
    assert!(fmu.last().contains("null pointer"), "{}", fmu.last());
    unsafe { fmi2Reset(fmu.c) };
    fmu.start(&STATE);
    continuous(&fmu);
    let x = [0.0; 7];
    assert_eq!(
        unsafe { fmi2SetContinuousStates(fmu.c, x.as_ptr(), 7) },
        Status::Error
    );
    assert!(
        fmu.last().contains("7 entries; the model has 8"),
        "{}",
        fmu.last()
    );
    unsafe { fmi2Reset(fmu.c) };
    // A state is not set by fmi2SetReal once the model runs; a computed value never is.
    fmu.start(&STATE);
    assert_eq!(fmu.set(Role::State(0), 1.0), Status::Error);
    assert!(
        fmu.last().contains("fmi2SetContinuousStates"),
        "{}",
        fmu.last()
    );
    unsafe { fmi2Reset(fmu.c) };
    assert_eq!(fmu.set(Role::Energy, 1.0), Status::Error);
    // A GUID of another model: no instance.
    let log: Box<Log> = Box::default();
    let functions = CallbackFunctions {
        logger: None,
        allocate_memory: None,
        free_memory: None,
        step_finished: None,
        component_environment: &*log as *const Log as *mut c_void,
    };
    let other = unsafe {
        fmi2Instantiate(
            c"x".as_ptr(),
            ME,
            c"{0}".as_ptr(),
            c"".as_ptr(),
            &functions,
            0,
            0,
        )
    };
    assert!(other.is_null());
}

/// `fmi2SetTime`, `fmi2SetContinuousStates` and `fmi2GetDerivatives` in continuous-time mode
/// have a path of their own (a few comparisons): what they must refuse there, they refuse.
#[test]
fn continuous_time_mode_refuses_what_it_must() {
    let fmu = Fmu::new(ME);
    let running = || {
        unsafe { fmi2Reset(fmu.c) };
        fmu.start(&STATE);
        continuous(&fmu);
    };
    running();
    assert_eq!(fmu.derivatives().0, Status::Ok);
    // A wrong length, either way, and a null array.
    for n in [7, 9] {
        let mut dx = [0.0; 9];
        let status = unsafe { fmi2GetDerivatives(fmu.c, dx.as_mut_ptr(), n) };
        assert_eq!(status, Status::Error);
        let expected = format!("`derivatives` has {n} entries; the model has 8");
        assert!(fmu.last().contains(&expected), "{}", fmu.last());
        running();
    }
    let status = unsafe { fmi2GetDerivatives(fmu.c, core::ptr::null_mut(), 8) };
    assert_eq!(status, Status::Error);
    assert!(fmu.last().contains("null pointer"), "{}", fmu.last());
    running();
    // A state or a time that is not finite, a null state.
    let mut x = STATE;
    x[2] = f64::NAN;
    assert_eq!(
        unsafe { fmi2SetContinuousStates(fmu.c, x.as_ptr(), 8) },
        Status::Error
    );
    assert!(fmu.last().contains("x[2] (alpha) = NaN"), "{}", fmu.last());
    running();
    assert_eq!(
        unsafe { fmi2SetContinuousStates(fmu.c, core::ptr::null(), 8) },
        Status::Error
    );
    assert!(fmu.last().contains("null pointer"), "{}", fmu.last());
    running();
    assert_eq!(unsafe { fmi2SetTime(fmu.c, f64::INFINITY) }, Status::Error);
    assert!(fmu.last().contains("time inf"), "{}", fmu.last());
    running();
    assert_eq!(unsafe { fmi2SetTime(fmu.c, 0.5) }, Status::Ok);
    // A finite state at which the right-hand side overflows: fmi2Discard, the derivative
    // named, and the importer may go on from another state.
    let mut x = STATE;
    x[5..].fill(1e200);
    assert_eq!(
        unsafe { fmi2SetContinuousStates(fmu.c, x.as_ptr(), 8) },
        Status::Ok
    );
    assert_eq!(fmu.derivatives().0, Status::Discard);
    assert!(fmu.last().contains("is not finite"), "{}", fmu.last());
    assert_eq!(
        unsafe { fmi2SetContinuousStates(fmu.c, STATE.as_ptr(), 8) },
        Status::Ok
    );
    assert_eq!(fmu.derivatives().0, Status::Ok, "{}", fmu.last());
    // In event mode the derivatives are there too; a Co-Simulation instance has none.
    assert_eq!(unsafe { fmi2EnterEventMode(fmu.c) }, Status::Ok);
    assert_eq!(fmu.derivatives().0, Status::Ok, "{}", fmu.last());
    let cs = Fmu::new(CS);
    cs.start(&STATE);
    assert_eq!(cs.derivatives().0, Status::Error);
    assert!(cs.last().contains("instantiated for"), "{}", cs.last());
}

#[test]
fn a_step_that_fails_is_discarded_and_says_where() {
    let fmu = Fmu::new(CS);
    fmu.start(&STATE);
    assert_eq!(unsafe { fmi2DoStep(fmu.c, 0.0, 0.01, 1) }, Status::Ok);
    // A communication point that is not the instance's time.
    assert_eq!(unsafe { fmi2DoStep(fmu.c, 0.5, 0.01, 1) }, Status::Error);
    assert!(fmu.last().contains("t = 0.01"), "{}", fmu.last());
    let fmu = Fmu::new(CS);
    fmu.start(&STATE);
    // Massless and without inertia, the robot has a singular mass matrix: the step cannot
    // be taken.
    for name in ["m0", "mw", "jx", "jy", "jz"] {
        let i = MobileRobot::NAMES.iter().position(|n| *n == name).unwrap();
        assert_eq!(
            fmu.set(Role::Parameter(i), 0.0),
            Status::Ok,
            "{}",
            fmu.last()
        );
    }
    assert_eq!(unsafe { fmi2DoStep(fmu.c, 0.0, 0.01, 1) }, Status::Discard);
    assert!(fmu.last().contains("t = 0"), "{}", fmu.last());
    let (mut time, mut terminated) = (f64::NAN, 0);
    unsafe {
        assert_eq!(fmi2GetRealStatus(fmu.c, 2, &mut time), Status::Ok);
        assert_eq!(fmi2GetBooleanStatus(fmu.c, 3, &mut terminated), Status::Ok);
    }
    assert_eq!((time, terminated), (0.0, 1));
    assert_eq!(unsafe { fmi2DoStep(fmu.c, 0.0, 0.01, 1) }, Status::Error);
}

#[test]
fn a_saved_state_runs_again_to_the_same_bits() {
    let fmu = Fmu::new(CS);
    fmu.start(&STATE);
    assert_eq!(fmu.set(Role::Input(0), 0.1), Status::Ok);
    let state = |fmu: &Fmu| -> Vec<f64> { (0..8).map(|i| fmu.get(Role::State(i)).1).collect() };
    unsafe {
        assert_eq!(fmi2DoStep(fmu.c, 0.0, 0.01, 1), Status::Ok);
        let mut saved = core::ptr::null_mut();
        assert_eq!(fmi2GetFMUstate(fmu.c, &mut saved), Status::Ok);
        assert_eq!(fmi2DoStep(fmu.c, 0.01, 0.01, 1), Status::Ok);
        let first = state(&fmu);
        // Back, and the same step again; then through bytes, into another instance.
        assert_eq!(fmi2SetFMUstate(fmu.c, saved), Status::Ok);
        assert_eq!(fmi2DoStep(fmu.c, 0.01, 0.01, 1), Status::Ok);
        assert_eq!(state(&fmu), first);
        let mut size = 0;
        assert_eq!(
            fmi2SerializedFMUstateSize(fmu.c, saved, &mut size),
            Status::Ok
        );
        let mut bytes = vec![0 as c_char; size];
        assert_eq!(
            fmi2SerializeFMUstate(fmu.c, saved, bytes.as_mut_ptr(), size),
            Status::Ok
        );
        let other = Fmu::new(CS);
        let mut restored = core::ptr::null_mut();
        assert_eq!(
            fmi2DeSerializeFMUstate(other.c, bytes.as_ptr(), size, &mut restored),
            Status::Ok
        );
        assert_eq!(fmi2SetFMUstate(other.c, restored), Status::Ok);
        assert_eq!(fmi2DoStep(other.c, 0.01, 0.01, 1), Status::Ok);
        assert_eq!(state(&other), first);
        // Bytes cut short are refused, and freeing sets the pointer to null.
        let mut cut = core::ptr::null_mut();
        assert_eq!(
            fmi2DeSerializeFMUstate(other.c, bytes.as_ptr(), size - 1, &mut cut),
            Status::Error
        );
        assert!(other.last().contains("cut short"), "{}", other.last());
        assert_eq!(fmi2FreeFMUstate(fmu.c, &mut saved), Status::Ok);
        assert!(saved.is_null());
        assert_eq!(fmi2FreeFMUstate(fmu.c, &mut restored), Status::Ok);
    }
}
