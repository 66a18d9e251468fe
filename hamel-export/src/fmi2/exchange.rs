//! Model Exchange: the importer integrates. `fmi2GetDerivatives` is the generated
//! right-hand side at the time, state and inputs the importer set; the model has no events
//! and no discrete states of its own (hamel's events belong to a simulation, not to a
//! model), so event mode only passes through.

use super::api::{call, check_count, count_refusal, read, run, write, write_one};
use super::instance::{Instance, Refusal, State, all_finite};
use super::modes::{Function, Mode};
use super::types::*;
use crate::model::Model;
use hamel_runtime::{HamelSystem, Vector};

/// `fmi2EnterEventMode`.
///
/// # Safety
/// `c` is null or an instance of `M` not yet freed.
pub unsafe fn enter_event_mode<M: Model>(c: Component) -> Status {
    // SAFETY: the caller's contract.
    unsafe {
        call::<M>(c, Function::EnterEventMode, "fmi2EnterEventMode", |inst| {
            inst.mode = Mode::Event;
            Ok(())
        })
    }
}

/// `fmi2NewDiscreteStates`: nothing changes at an event of this model.
///
/// # Safety
/// `c` as above; `info` null or writable.
pub unsafe fn new_discrete_states<M: Model>(c: Component, info: *mut EventInfo) -> Status {
    let f = Function::NewDiscreteStates;
    // SAFETY: the caller's contract.
    unsafe {
        call::<M>(c, f, "fmi2NewDiscreteStates", |_| {
            *write_one(info, "fmi2EventInfo")? = EventInfo::default();
            Ok(())
        })
    }
}

/// `fmi2EnterContinuousTimeMode`.
///
/// # Safety
/// `c` as above.
pub unsafe fn enter_continuous_time_mode<M: Model>(c: Component) -> Status {
    let f = Function::EnterContinuousTimeMode;
    // SAFETY: the caller's contract.
    unsafe {
        call::<M>(c, f, "fmi2EnterContinuousTimeMode", |inst| {
            inst.mode = Mode::Continuous;
            Ok(())
        })
    }
}

/// `fmi2CompletedIntegratorStep`: no event, no termination.
///
/// # Safety
/// `c` as above; the flags null or writable.
pub unsafe fn completed_integrator_step<M: Model>(
    c: Component,
    enter_event_mode: *mut Boolean,
    terminate_simulation: *mut Boolean,
) -> Status {
    let f = Function::CompletedIntegratorStep;
    // SAFETY: the caller's contract.
    unsafe {
        call::<M>(c, f, "fmi2CompletedIntegratorStep", |_| {
            *write_one(enter_event_mode, "enterEventMode")? = FALSE;
            *write_one(terminate_simulation, "terminateSimulation")? = FALSE;
            Ok(())
        })
    }
}

/// The instance `c` if it is in continuous-time mode: where an importer's integrator calls
/// `fmi2SetTime`, `fmi2SetContinuousStates` and `fmi2GetDerivatives` at every stage. Only
/// Model Exchange enters that mode, and the state machine allows the three there (`modes`'
/// test), so this one comparison decides what [`call`]'s would.
///
/// # Safety
/// `c` is null or an instance of `M` used by one thread at a time.
#[inline]
unsafe fn continuous<'a, M: Model>(c: Component) -> Option<&'a mut Instance<M>> {
    // SAFETY: the caller's contract.
    unsafe { (c as *mut Instance<M>).as_mut() }.filter(|inst| inst.mode == Mode::Continuous)
}

/// `fmi2SetTime`.
///
/// # Safety
/// `c` as above.
#[inline]
pub unsafe fn set_time<M: Model>(c: Component, t: Real) -> Status {
    // SAFETY: the caller's contract.
    if let Some(inst) = unsafe { continuous::<M>(c) }.filter(|_| t.is_finite()) {
        inst.t = t;
        return Status::Ok;
    }
    // SAFETY: the caller's contract.
    unsafe { set_time_checked::<M>(c, t) }
}

/// `fmi2SetTime` through [`call`]: in event mode, or a call to refuse.
///
/// # Safety
/// As [`set_time`].
#[cold]
#[inline(never)]
unsafe fn set_time_checked<M: Model>(c: Component, t: Real) -> Status {
    // SAFETY: the caller's contract.
    unsafe {
        call::<M>(c, Function::SetTime, "fmi2SetTime", |inst| {
            if !t.is_finite() {
                return Err(Refusal::error(format!(
                    "the time {t} is not a finite number"
                )));
            }
            inst.t = t;
            Ok(())
        })
    }
}

/// `fmi2SetContinuousStates`: every value finite, named if not.
///
/// # Safety
/// `c` as above; `x` null or of `nx` entries.
#[inline]
pub unsafe fn set_continuous_states<M: Model>(c: Component, x: *const Real, nx: usize) -> Status {
    // SAFETY: the caller's contract.
    if let Some(inst) = unsafe { continuous::<M>(c) } {
        if nx == State::<M>::LEN && !x.is_null() {
            // SAFETY: non-null, `nx` values (the caller's contract).
            let values = unsafe { core::slice::from_raw_parts(x, nx) };
            if let Some(state) = State::<M>::head(values).filter(|_| all_finite(values)) {
                inst.x = *state;
                return Status::Ok;
            }
        }
    }
    // SAFETY: the caller's contract.
    unsafe { set_continuous_states_checked::<M>(c, x, nx) }
}

/// `fmi2SetContinuousStates` through [`call`]: a call to refuse, with the reason.
///
/// # Safety
/// As [`set_continuous_states`].
#[cold]
#[inline(never)]
unsafe fn set_continuous_states_checked<M: Model>(
    c: Component,
    x: *const Real,
    nx: usize,
) -> Status {
    let f = Function::SetContinuousStates;
    // SAFETY: the caller's contract.
    unsafe {
        call::<M>(c, f, "fmi2SetContinuousStates", |inst| {
            check_count("x", nx, inst.table.sizes.nx)?;
            let values = read(x, nx, "x")?;
            if let Some(i) = values.iter().position(|v| !v.is_finite()) {
                return Err(Refusal::error(format!(
                    "x[{i}] ({}) = {} is not a finite number",
                    <M::System as HamelSystem>::STATE[i],
                    values[i]
                )));
            }
            inst.x.as_mut().copy_from_slice(values);
            Ok(())
        })
    }
}

/// `fmi2GetDerivatives`: the generated right-hand side, allocation-free.
///
/// An importer's integrator calls it at every stage, in continuous-time mode with the
/// model's number of states: that call is checked by four comparisons (an instance, its
/// mode, the length, the array; see `continuous`) and goes straight to the right-hand
/// side, from the state `fmi2SetContinuousStates` checked, into the importer's array; every
/// other call takes [`call`]'s path, with its messages.
///
/// # Safety
/// `c` as above; `dx` null or of `nx` entries.
#[inline]
pub unsafe fn get_derivatives<M: Model>(c: Component, dx: *mut Real, nx: usize) -> Status {
    // SAFETY: the caller's contract.
    if let Some(inst) = unsafe { continuous::<M>(c) } {
        if nx == State::<M>::LEN && !dx.is_null() {
            // SAFETY: non-null, `nx` writable values (the caller's contract).
            let values = unsafe { core::slice::from_raw_parts_mut(dx, nx) };
            if let Some(out) = State::<M>::head_mut(values) {
                return run::<M>(inst, GET_DERIVATIVES, |inst| {
                    inst.derivatives_into(&inst.x, out)
                });
            }
        }
    }
    // SAFETY: the caller's contract.
    unsafe { get_derivatives_checked::<M>(c, dx, nx) }
}

const GET_DERIVATIVES: &str = "fmi2GetDerivatives";

/// `fmi2GetDerivatives` through [`call`]: outside continuous-time mode (the derivatives at
/// the start values, in initialization mode), or a call to refuse.
///
/// # Safety
/// As [`get_derivatives`].
#[cold]
#[inline(never)]
unsafe fn get_derivatives_checked<M: Model>(c: Component, dx: *mut Real, nx: usize) -> Status {
    // SAFETY: the caller's contract.
    unsafe {
        call::<M>(c, Function::GetDerivatives, GET_DERIVATIVES, |inst| {
            let out = write(dx, nx, "derivatives")?;
            let out = State::<M>::head_mut(out)
                .filter(|_| nx == inst.table.sizes.nx)
                .ok_or_else(|| count_refusal("derivatives", nx, inst.table.sizes.nx))?;
            inst.derivatives_into(&inst.current()?, out)
        })
    }
}

/// `fmi2GetEventIndicators`: the model has none.
///
/// # Safety
/// `c` as above.
pub unsafe fn get_event_indicators<M: Model>(c: Component, _z: *mut Real, nz: usize) -> Status {
    let f = Function::GetEventIndicators;
    // SAFETY: the caller's contract.
    unsafe {
        call::<M>(c, f, "fmi2GetEventIndicators", |_| {
            check_count("eventIndicators", nz, 0)
        })
    }
}

/// `fmi2GetContinuousStates`.
///
/// # Safety
/// `c` as above; `x` null or of `nx` entries.
pub unsafe fn get_continuous_states<M: Model>(c: Component, x: *mut Real, nx: usize) -> Status {
    let f = Function::GetContinuousStates;
    // SAFETY: the caller's contract.
    unsafe {
        call::<M>(c, f, "fmi2GetContinuousStates", |inst| {
            check_count("x", nx, inst.table.sizes.nx)?;
            let out = write(x, nx, "x")?;
            out.copy_from_slice(inst.current()?.as_ref());
            Ok(())
        })
    }
}

/// `fmi2GetNominalsOfContinuousStates`: 1 for every state (the model gives no scales; the
/// importer's absolute tolerance is then its relative one, FMPy's CVode included).
///
/// # Safety
/// `c` as above; `nominals` null or of `nx` entries.
pub unsafe fn get_nominals<M: Model>(c: Component, nominals: *mut Real, nx: usize) -> Status {
    let f = Function::GetNominalsOfContinuousStates;
    // SAFETY: the caller's contract.
    unsafe {
        call::<M>(c, f, "fmi2GetNominalsOfContinuousStates", |inst| {
            check_count("x_nominal", nx, inst.table.sizes.nx)?;
            write(nominals, nx, "x_nominal")?.fill(1.0);
            Ok(())
        })
    }
}
