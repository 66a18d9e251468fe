//! The plain C functions of a model ([`crate::c_api!`]): every array comes with its length,
//! checked against the model's; values are checked finite. `<model>_rhs` is the model's own
//! right-hand side (the code a hamel simulation runs); the CasADi function `<model>_f` is its
//! form with the parameters as arguments: the tests check that the two agree bit for bit.

use crate::abi::{Failure, Status, check_finite, check_len, slice, slice_mut};
use crate::model::{Model, Sizes};
use crate::passes;
use crate::primal::Which;
use hamel_runtime::{HamelSystem, Parameters, Vector};

type In = (*const f64, usize);
type Out = (*mut f64, usize);

/// z = (x, u, p, t) from the caller's arrays, each checked; without `u` (the outputs do
/// not read it) its entries are zero.
///
/// # Safety
/// Each pointer is null or points to as many values as its length says.
unsafe fn point<M: Model>(t: f64, x: In, u: Option<In>, p: In) -> Result<M::Array<f64>, Failure> {
    let s = Sizes::of::<M>();
    let mut z = M::array(0.0f64);
    let parts = [
        ("x", Some(x), s.nx, 0, <M::System as HamelSystem>::STATE),
        ("u", u, s.nu, s.u(), <M::System as HamelSystem>::INPUTS),
        ("p", Some(p), s.np, s.p(), <M::System as Parameters>::NAMES),
    ];
    for (name, given, expected, offset, labels) in parts {
        let Some((ptr, len)) = given else {
            continue;
        };
        check_len(name, len, expected)?;
        // SAFETY: `len` values (the caller's contract), the length checked.
        let values = unsafe { slice(ptr, len, name) }?;
        check_finite(name, values, labels)?;
        z.as_mut()[offset..offset + len].copy_from_slice(values);
    }
    check_finite("t", &[t], &[])?;
    z.as_mut()[s.t()] = t;
    Ok(z)
}

/// `<model>_rhs`: the model's own `HamelSystem::rhs` (what a hamel simulation integrates),
/// with the parameters set from `p` by name.
///
/// # Safety
/// Each pointer is null or points to as many values as its length says.
pub unsafe fn rhs<M: Model>(t: f64, x: In, u: In, p: In, xdot: Out) -> Result<(), Failure> {
    let s = Sizes::of::<M>();
    // SAFETY: the caller's contract.
    let z = unsafe { point::<M>(t, x, Some(u), p) }?;
    check_len("xdot", xdot.1, s.nx)?;
    // SAFETY: `xdot.1` writable values (the caller's contract), the length checked.
    let out = unsafe { slice_mut(xdot.0, xdot.1, "xdot") }?;
    let z = z.as_ref();
    let system = system::<M>(&z[s.p()..s.t()])?;
    let mut state = <M::System as HamelSystem>::State::zeros();
    state.as_mut().copy_from_slice(&z[..s.nx]);
    let mut inputs = <M::System as HamelSystem>::Inputs::zeros();
    inputs.as_mut().copy_from_slice(&z[s.u()..s.p()]);
    let mut dx = <M::System as HamelSystem>::State::zeros();
    system.rhs(t, &state, &inputs, &mut dx).map_err(|e| {
        Failure::new(
            Status::Singular,
            format!("{e} at {}", M::System::named_state(&state)),
        )
    })?;
    out.copy_from_slice(dx.as_ref());
    Ok(())
}

/// The model with the parameters `p` (finite: checked), set by name.
pub fn system<M: Model>(p: &[f64]) -> Result<M::System, Failure> {
    let mut system = M::System::default();
    for (name, value) in <M::System as Parameters>::NAMES.iter().zip(p) {
        system
            .set(name, *value)
            .map_err(|e| Failure::new(Status::NonFinite, e.to_string()))?;
    }
    Ok(system)
}

/// `<model>_outputs`.
///
/// # Safety
/// Each pointer is null or points to as many values as its length says.
pub unsafe fn outputs<M: Model>(t: f64, x: In, p: In, y: Out) -> Result<(), Failure> {
    let s = Sizes::of::<M>();
    // SAFETY: the caller's contract.
    let z = unsafe { point::<M>(t, x, None, p) }?;
    check_len("y", y.1, s.ny)?;
    // SAFETY: `y.1` writable values (the caller's contract), the length checked.
    let out = unsafe { slice_mut(y.0, y.1, "y") }?;
    passes::value::<M>(Which::Outputs, z.as_ref(), out)
}

/// `<model>_default_parameters`: the `Default` of the model's struct, in the order of p.
///
/// # Safety
/// `p` is null or points to `np` writable values.
pub unsafe fn default_parameters<M: Model>(p: *mut f64, np: usize) -> Result<(), Failure> {
    let names = <M::System as Parameters>::NAMES;
    check_len("p", np, names.len())?;
    // SAFETY: `np` writable values (the caller's contract), the length checked.
    let out = unsafe { slice_mut(p, np, "p") }?;
    let system = M::System::default();
    for (slot, name) in out.iter_mut().zip(names) {
        *slot = system.get(name).unwrap_or(f64::NAN);
    }
    Ok(())
}
