//! The plain C functions of a model ([`crate::c_api!`]): every array comes with its length,
//! checked against the model's; values are checked finite; the results are those of the
//! CasADi function `<model>_f` (the same code path).

use crate::abi::{Failure, check_finite, check_len, slice, slice_mut};
use crate::model::{Model, Sizes};
use crate::passes;
use crate::primal::Which;
use hamel_runtime::{HamelSystem, Parameters};

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

/// `<model>_rhs`.
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
    passes::value::<M>(Which::Rhs, z.as_ref(), out)
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
