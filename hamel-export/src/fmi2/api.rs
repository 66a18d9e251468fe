//! The functions behind the exported `fmi2…` symbols ([`crate::fmi2!`]), generic over the
//! model: each checks its pointers and the instance's mode, runs its body with panics caught
//! (none unwinds into the importer), reports a refusal through the logger, and returns the
//! status. An `fmi2Error` leaves the instance in the error mode, where only reading values,
//! `fmi2Reset` and `fmi2FreeInstance` remain, as the standard says.

use super::description::guid;
use super::instance::{Instance, Outcome, Refusal};
use super::logger::{Category, Logger};
use super::modes::{Function, Mode};
use super::snapshot::{Snapshot, sizes};
use super::types::*;
use crate::model::Model;
use core::ffi::{CStr, c_char};
use std::panic::{AssertUnwindSafe, catch_unwind};

/// What a caught panic says.
fn panic_message(panic: &(dyn std::any::Any + Send)) -> String {
    panic
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| panic.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "a panic".to_string())
}

/// Run `body` on the instance `c` as the function `name`: the mode checked, a refusal or a
/// panic logged and returned as its status. Inlined, with the refusals out of line, so that
/// a call that succeeds costs its checks and nothing else (`fmi2GetDerivatives` in
/// continuous-time mode checks less, and goes to [`run`] directly).
///
/// # Safety
/// `c` is null or an instance of `M` from [`instantiate`] not yet freed.
#[inline]
pub unsafe fn call<M: Model>(
    c: Component,
    function: Function,
    name: &str,
    body: impl FnOnce(&mut Instance<M>) -> Outcome,
) -> Status {
    if c.is_null() {
        return Status::Error;
    }
    // SAFETY: an instance of `M` (the caller's contract), used by one thread at a time (the
    // standard's).
    let instance = unsafe { &mut *(c as *mut Instance<M>) };
    if !function.permits(instance.interface, instance.mode) {
        return out_of_order(instance, function, name);
    }
    run(instance, name, body)
}

/// Run `body` on an instance whose mode allows it (checked by the caller): a refusal or a
/// panic logged and returned as its status.
#[inline]
pub fn run<M: Model>(
    instance: &mut Instance<M>,
    name: &str,
    body: impl FnOnce(&mut Instance<M>) -> Outcome,
) -> Status {
    match catch_unwind(AssertUnwindSafe(|| body(&mut *instance))) {
        Ok(Ok(())) => Status::Ok,
        Ok(Err(refusal)) => report(instance, name, refusal),
        Err(panic) => report_panic(instance, name, panic),
    }
}

/// A panic caught: `fmi2Error`, logged as the bug it is.
#[cold]
#[inline(never)]
fn report_panic<M: Model>(
    instance: &mut Instance<M>,
    name: &str,
    panic: Box<dyn std::any::Any + Send>,
) -> Status {
    let message = format!(
        "internal error (a bug, please report it): {}",
        panic_message(&*panic)
    );
    report(instance, name, Refusal::error(message))
}

/// A call the instance's mode or interface does not allow: `fmi2Error`, logged.
#[cold]
#[inline(never)]
fn out_of_order<M: Model>(instance: &mut Instance<M>, function: Function, name: &str) -> Status {
    let why = function
        .refusal(name, instance.interface, instance.mode)
        .unwrap_or_default();
    report(instance, name, Refusal::error(why))
}

/// A refusal logged, and an `fmi2Error` leaving the instance in the error mode.
#[cold]
#[inline(never)]
fn report<M: Model>(instance: &mut Instance<M>, name: &str, refusal: Refusal) -> Status {
    instance.log(
        refusal.status,
        Category::of(refusal.status),
        &format!("{name}: {}", refusal.message),
    );
    if refusal.status >= Status::Error {
        instance.mode = Mode::Error;
    }
    refusal.status
}

/// The `n` values at `ptr` (null only when `n` is 0).
///
/// # Safety
/// A non-null `ptr` points to `n` readable values.
#[inline]
pub unsafe fn read<'a, T>(ptr: *const T, n: usize, what: &str) -> Result<&'a [T], Refusal> {
    if n == 0 {
        return Ok(&[]);
    }
    if ptr.is_null() {
        return Err(null(what, n));
    }
    // SAFETY: non-null, `n` values (the caller's contract).
    Ok(unsafe { core::slice::from_raw_parts(ptr, n) })
}

/// The `n` values at `ptr` to write (null only when `n` is 0).
///
/// # Safety
/// A non-null `ptr` points to `n` writable values not otherwise accessed meanwhile.
#[inline]
pub unsafe fn write<'a, T>(ptr: *mut T, n: usize, what: &str) -> Result<&'a mut [T], Refusal> {
    if n == 0 {
        return Ok(&mut []);
    }
    if ptr.is_null() {
        return Err(null(what, n));
    }
    // SAFETY: non-null, `n` values (the caller's contract).
    Ok(unsafe { core::slice::from_raw_parts_mut(ptr, n) })
}

/// The refusal of a null pointer.
#[cold]
#[inline(never)]
fn null(what: &str, n: usize) -> Refusal {
    Refusal::error(format!("`{what}` is a null pointer, with {n} entries"))
}

/// One value to write.
///
/// # Safety
/// `ptr` is null or writable.
pub unsafe fn write_one<'a, T>(ptr: *mut T, what: &str) -> Result<&'a mut T, Refusal> {
    // SAFETY: the caller's contract.
    unsafe { ptr.as_mut() }.ok_or_else(|| Refusal::error(format!("`{what}` is a null pointer")))
}

/// A C string, or `None` for a null pointer.
///
/// # Safety
/// `ptr` is null or a NUL-terminated string.
pub unsafe fn text(ptr: *const c_char) -> Option<String> {
    if ptr.is_null() {
        return None;
    }
    // SAFETY: NUL-terminated (the caller's contract).
    Some(
        unsafe { CStr::from_ptr(ptr) }
            .to_string_lossy()
            .into_owned(),
    )
}

/// A length the caller gives must be the model's.
pub fn check_count(what: &str, given: usize, expected: usize) -> Outcome {
    if given == expected {
        Ok(())
    } else {
        Err(count_refusal(what, given, expected))
    }
}

/// The refusal of a length that is not the model's.
#[cold]
#[inline(never)]
pub fn count_refusal(what: &str, given: usize, expected: usize) -> Refusal {
    Refusal::error(format!(
        "`{what}` has {given} entries; the model has {expected}"
    ))
}

/// `fmi2Instantiate`: a new instance of `M`, or null (with the reason logged when there is a
/// logger) for an unknown interface or a GUID of another model.
///
/// # Safety
/// The strings are null or NUL-terminated; `functions` is null or points to the callbacks,
/// which stay valid for the instance's life.
#[allow(clippy::too_many_arguments)]
pub unsafe fn instantiate<M: Model>(
    identifier: &str,
    name: Text,
    kind: Integer,
    fmu_guid: Text,
    _resources: Text,
    functions: *const CallbackFunctions,
    _visible: Boolean,
    logging_on: Boolean,
) -> Component {
    let made = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: null or the importer's callbacks (the caller's contract).
        let functions = unsafe { functions.as_ref() }?;
        // SAFETY: null or NUL-terminated.
        let name = unsafe { text(name) }.unwrap_or_default();
        let logger = Logger::new(
            functions.logger,
            functions.component_environment,
            &name,
            logging_on != FALSE,
        );
        let refuse = |message: String| {
            logger.log(
                Status::Error,
                Category::Error,
                &format!("fmi2Instantiate: {message}"),
            );
            None
        };
        let Some(interface) = Interface::from_c(kind) else {
            return refuse(format!(
                "fmuType = {kind} is neither fmi2ModelExchange (0) nor fmi2CoSimulation (1)"
            ));
        };
        let expected = guid::<M>(identifier);
        // SAFETY: null or NUL-terminated.
        match unsafe { text(fmu_guid) } {
            Some(given) if given == expected => {}
            given => {
                return refuse(format!(
                    "the GUID {} is not this library's model's ({expected} for {identifier}): \
                     the binary and modelDescription.xml are of different models",
                    given.as_deref().unwrap_or("(null)")
                ));
            }
        }
        let instance = Box::new(Instance::<M>::new(interface, logger));
        Some(Box::into_raw(instance) as Component)
    }));
    made.ok().flatten().unwrap_or(core::ptr::null_mut())
}

/// `fmi2FreeInstance`.
///
/// # Safety
/// `c` is null or an instance of `M` from [`instantiate`], not used again.
pub unsafe fn free_instance<M: Model>(c: Component) {
    if c.is_null() {
        return;
    }
    let _ = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: made by `Box::into_raw` in `instantiate` and not yet freed.
        drop(unsafe { Box::from_raw(c as *mut Instance<M>) });
    }));
}

/// `fmi2SetDebugLogging`.
///
/// # Safety
/// `categories` is null or points to `n` NUL-terminated strings.
pub unsafe fn set_debug_logging<M: Model>(
    c: Component,
    on: Boolean,
    n: usize,
    categories: *const Text,
) -> Status {
    let name = "fmi2SetDebugLogging";
    // SAFETY: the caller's contract.
    unsafe {
        call::<M>(c, Function::SetDebugLogging, name, |inst| {
            let pointers = read(categories, n, "categories")?;
            let names: Vec<String> = pointers
                .iter()
                .map(|p| text(*p).unwrap_or_default())
                .collect();
            inst.logger
                .set_debug(on != FALSE, &names)
                .map_err(Refusal::error)
        })
    }
}

/// `fmi2SetupExperiment`.
///
/// # Safety
/// `c` as for [`call`].
pub unsafe fn setup_experiment<M: Model>(
    c: Component,
    tolerance_defined: Boolean,
    tolerance: Real,
    start: Real,
    stop_defined: Boolean,
    stop: Real,
) -> Status {
    // SAFETY: the caller's contract.
    unsafe {
        call::<M>(
            c,
            Function::SetupExperiment,
            "fmi2SetupExperiment",
            |inst| {
                let tolerance = (tolerance_defined != FALSE).then_some(tolerance);
                if let Some(tol) = tolerance.filter(|t| !(t.is_finite() && *t > 0.0 && *t < 1.0)) {
                    return Err(Refusal::error(format!(
                        "the tolerance {tol} must be a number between 0 and 1 (a relative tolerance)"
                    )));
                }
                if !start.is_finite() {
                    return Err(Refusal::error(format!(
                        "the start time {start} must be finite"
                    )));
                }
                let stop = (stop_defined != FALSE).then_some(stop);
                if let Some(s) = stop.filter(|s| !(s.is_finite() && *s >= start)) {
                    return Err(Refusal::error(format!(
                        "the stop time {s} must be finite and not before the start time {start}"
                    )));
                }
                inst.experiment.tolerance = tolerance;
                inst.experiment.start = start;
                inst.experiment.stop = stop;
                inst.t = start;
                Ok(())
            },
        )
    }
}

/// `fmi2EnterInitializationMode`.
///
/// # Safety
/// `c` as for [`call`].
pub unsafe fn enter_initialization_mode<M: Model>(c: Component) -> Status {
    let f = Function::EnterInitializationMode;
    // SAFETY: the caller's contract.
    unsafe {
        call::<M>(c, f, "fmi2EnterInitializationMode", |inst| {
            inst.mode = Mode::Initialization;
            Ok(())
        })
    }
}

/// `fmi2ExitInitializationMode`: the dependent coordinates solved from the start values,
/// the state checked (parameters, configuration, mass matrix) and the right-hand side
/// evaluated once, so that a model that cannot start says so here.
///
/// # Safety
/// `c` as for [`call`].
pub unsafe fn exit_initialization_mode<M: Model>(c: Component) -> Status {
    let f = Function::ExitInitializationMode;
    // SAFETY: the caller's contract.
    unsafe {
        call::<M>(c, f, "fmi2ExitInitializationMode", |inst| {
            let x = inst.consistent()?;
            inst.derivatives(&x).map_err(|r| {
                Refusal::error(format!("the model cannot start there: {}", r.message))
            })?;
            inst.x = x;
            inst.stepping.last_successful_time = inst.t;
            inst.mode = match inst.interface {
                Interface::ModelExchange => Mode::Event,
                Interface::CoSimulation => Mode::StepComplete,
            };
            let message = format!(
                "initialized at t = {}: {}",
                inst.t,
                <M::System as hamel_runtime::HamelSystem>::named_state(&inst.x)
            );
            inst.log(Status::Ok, Category::Events, &message);
            Ok(())
        })
    }
}

/// `fmi2Terminate`.
///
/// # Safety
/// `c` as for [`call`].
pub unsafe fn terminate<M: Model>(c: Component) -> Status {
    // SAFETY: the caller's contract.
    unsafe {
        call::<M>(c, Function::Terminate, "fmi2Terminate", |inst| {
            inst.terminate();
            Ok(())
        })
    }
}

/// `fmi2Reset`.
///
/// # Safety
/// `c` as for [`call`].
pub unsafe fn reset<M: Model>(c: Component) -> Status {
    // SAFETY: the caller's contract.
    unsafe {
        call::<M>(c, Function::Reset, "fmi2Reset", |inst| {
            inst.reset();
            Ok(())
        })
    }
}

/// `fmi2GetReal`.
///
/// # Safety
/// `c` as for [`call`]; `vr` and `value` null or of `n` entries.
pub unsafe fn get_real<M: Model>(
    c: Component,
    vr: *const ValueReference,
    n: usize,
    value: *mut Real,
) -> Status {
    // SAFETY: the caller's contract.
    unsafe {
        call::<M>(c, Function::GetReal, "fmi2GetReal", |inst| {
            inst.get_real(read(vr, n, "vr")?, write(value, n, "value")?)
        })
    }
}

/// `fmi2SetReal`.
///
/// # Safety
/// `c` as for [`call`]; `vr` and `value` null or of `n` entries.
pub unsafe fn set_real<M: Model>(
    c: Component,
    vr: *const ValueReference,
    n: usize,
    value: *const Real,
) -> Status {
    // SAFETY: the caller's contract.
    unsafe {
        call::<M>(c, Function::SetReal, "fmi2SetReal", |inst| {
            inst.set_real(read(vr, n, "vr")?, read(value, n, "value")?)
        })
    }
}

/// `fmi2GetInteger`.
///
/// # Safety
/// `c` as for [`call`]; `vr` and `value` null or of `n` entries.
pub unsafe fn get_integer<M: Model>(
    c: Component,
    vr: *const ValueReference,
    n: usize,
    value: *mut Integer,
) -> Status {
    // SAFETY: the caller's contract.
    unsafe {
        call::<M>(c, Function::GetInteger, "fmi2GetInteger", |inst| {
            inst.get_integer(read(vr, n, "vr")?, write(value, n, "value")?)
        })
    }
}

/// `fmi2SetInteger`.
///
/// # Safety
/// `c` as for [`call`]; `vr` and `value` null or of `n` entries.
pub unsafe fn set_integer<M: Model>(
    c: Component,
    vr: *const ValueReference,
    n: usize,
    value: *const Integer,
) -> Status {
    // SAFETY: the caller's contract.
    unsafe {
        call::<M>(c, Function::SetInteger, "fmi2SetInteger", |inst| {
            inst.set_integer(read(vr, n, "vr")?, read(value, n, "value")?)
        })
    }
}

/// `fmi2Get/SetBoolean`, `fmi2Get/SetString`: the FMU has no such variables, so any value
/// reference is refused (and an empty call succeeds).
///
/// # Safety
/// `c` as for [`call`]; `vr` null or of `n` entries.
pub unsafe fn no_variables<M: Model>(
    c: Component,
    function: Function,
    name: &str,
    vr: *const ValueReference,
    n: usize,
) -> Status {
    // SAFETY: the caller's contract.
    unsafe {
        call::<M>(c, function, name, |_| match read(vr, n, "vr")?.first() {
            None => Ok(()),
            Some(vr) => Err(Refusal::error(format!(
                "value reference {vr}: this FMU has no Boolean or String variables"
            ))),
        })
    }
}

/// The snapshot an `fmi2FMUstate` points to (null refused).
///
/// # Safety
/// `state` is null or from [`get_fmu_state`] or [`deserialize_fmu_state`], not yet freed.
unsafe fn snapshot<'a>(state: FmuState) -> Result<&'a Snapshot, Refusal> {
    // SAFETY: the caller's contract.
    unsafe { (state as *const Snapshot).as_ref() }
        .ok_or_else(|| Refusal::error("the FMU state is a null pointer"))
}

/// Store `snapshot` where `slot` points: over the snapshot there, or in a new one.
///
/// # Safety
/// `*slot` is null or a snapshot from this module, not yet freed.
unsafe fn store(slot: &mut FmuState, snapshot: Snapshot) {
    match unsafe { (*slot as *mut Snapshot).as_mut() } {
        Some(old) => *old = snapshot,
        None => *slot = Box::into_raw(Box::new(snapshot)) as FmuState,
    }
}

/// `fmi2GetFMUstate`: a new snapshot, or the one `*state` points to overwritten.
///
/// # Safety
/// `c` as for [`call`]; `state` null or writable, `*state` null or a live snapshot.
pub unsafe fn get_fmu_state<M: Model>(c: Component, state: *mut FmuState) -> Status {
    // SAFETY: the caller's contract.
    unsafe {
        call::<M>(c, Function::FmuState, "fmi2GetFMUstate", |inst| {
            store(write_one(state, "FMUstate")?, inst.snapshot());
            Ok(())
        })
    }
}

/// `fmi2SetFMUstate`.
///
/// # Safety
/// `c` as for [`call`]; `state` null or a live snapshot.
pub unsafe fn set_fmu_state<M: Model>(c: Component, state: FmuState) -> Status {
    // SAFETY: the caller's contract.
    unsafe {
        call::<M>(c, Function::FmuState, "fmi2SetFMUstate", |inst| {
            inst.restore(snapshot(state)?)
        })
    }
}

/// `fmi2FreeFMUstate`: the snapshot freed and `*state` set to null.
///
/// # Safety
/// `c` as for [`call`]; `state` null or writable, `*state` null or a live snapshot.
pub unsafe fn free_fmu_state<M: Model>(c: Component, state: *mut FmuState) -> Status {
    // SAFETY: the caller's contract.
    unsafe {
        call::<M>(c, Function::FmuState, "fmi2FreeFMUstate", |_| {
            let slot = write_one(state, "FMUstate")?;
            if !slot.is_null() {
                drop(Box::from_raw(*slot as *mut Snapshot));
                *slot = core::ptr::null_mut();
            }
            Ok(())
        })
    }
}

/// `fmi2SerializedFMUstateSize`.
///
/// # Safety
/// `c` as for [`call`]; `state` null or a live snapshot; `size` null or writable.
pub unsafe fn serialized_size<M: Model>(c: Component, state: FmuState, size: *mut usize) -> Status {
    // SAFETY: the caller's contract.
    unsafe {
        call::<M>(c, Function::FmuState, "fmi2SerializedFMUstateSize", |_| {
            *write_one(size, "size")? = snapshot(state)?.to_bytes().len();
            Ok(())
        })
    }
}

/// `fmi2SerializeFMUstate`: the bytes into the importer's array of the size it asked.
///
/// # Safety
/// `c` as for [`call`]; `state` null or a live snapshot; `bytes` null or of `size` entries.
pub unsafe fn serialize<M: Model>(
    c: Component,
    state: FmuState,
    bytes: *mut Byte,
    size: usize,
) -> Status {
    // SAFETY: the caller's contract.
    unsafe {
        call::<M>(c, Function::FmuState, "fmi2SerializeFMUstate", |_| {
            let serialized = snapshot(state)?.to_bytes();
            check_count("serializedState", size, serialized.len())?;
            let out = write(bytes as *mut u8, size, "serializedState")?;
            out.copy_from_slice(&serialized);
            Ok(())
        })
    }
}

/// `fmi2DeSerializeFMUstate`: a snapshot from bytes, checked, into `*state`.
///
/// # Safety
/// `c` as for [`call`]; `bytes` null or of `size` entries; `state` as for [`get_fmu_state`].
pub unsafe fn deserialize_fmu_state<M: Model>(
    c: Component,
    bytes: *const Byte,
    size: usize,
    state: *mut FmuState,
) -> Status {
    // SAFETY: the caller's contract.
    unsafe {
        call::<M>(c, Function::FmuState, "fmi2DeSerializeFMUstate", |_| {
            let given = read(bytes as *const u8, size, "serializedState")?;
            let restored = Snapshot::from_bytes(given, sizes::<M>())?;
            store(write_one(state, "FMUstate")?, restored);
            Ok(())
        })
    }
}

/// `fmi2GetDirectionalDerivative`.
///
/// # Safety
/// `c` as for [`call`]; the arrays null or of the lengths given.
pub unsafe fn get_directional_derivative<M: Model>(
    c: Component,
    unknowns: (*const ValueReference, usize),
    knowns: (*const ValueReference, usize),
    seeds: *const Real,
    out: *mut Real,
) -> Status {
    let f = Function::GetDirectionalDerivative;
    // SAFETY: the caller's contract.
    unsafe {
        call::<M>(c, f, "fmi2GetDirectionalDerivative", |inst| {
            inst.directional_derivative(
                read(unknowns.0, unknowns.1, "vUnknown_ref")?,
                read(knowns.0, knowns.1, "vKnown_ref")?,
                read(seeds, knowns.1, "dvKnown")?,
                write(out, unknowns.1, "dvUnknown")?,
            )
        })
    }
}
