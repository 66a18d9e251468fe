//! The model's function evaluated once over a chosen scalar: plain values, one direction of
//! dual numbers (a Jacobian column, a forward derivative) or one pair of hyper-dual
//! directions (a second derivative). Every argument is in the flat vector z; nothing is
//! allocated (the arrays are the model's own stack arrays). What the compiled code gives
//! (feature `compiled`) is not computed here: these passes are the derivatives of a stage
//! too large to compile, and all of them without the feature.

use crate::abi::{Failure, Status};
use crate::hyper::Hyper;
use crate::model::Model;
use crate::primal::Which;
use crate::units;
use hamel_runtime::{HamelSystem, NamedValues, Scalar, Singularity};
use num_dual::Dual64;

/// The function `which` over the scalar `S` at z (as built by `seed`), into `out`.
fn run<M: Model, S: Scalar>(
    which: Which,
    z: &[f64],
    seed: impl Fn(usize, f64) -> S,
) -> Result<M::Array<S>, Failure> {
    let mut zs = M::array(S::from_f64(0.0));
    for (i, (slot, &value)) in zs.as_mut().iter_mut().zip(z).enumerate() {
        *slot = seed(i, value);
    }
    let mut out = M::array(S::from_f64(0.0));
    match which {
        Which::Rhs => units::rhs::call::<M, S>(&zs, &mut out).map_err(|s| singular::<M>(s, z))?,
        Which::Outputs => units::outputs::call::<M, S>(&zs, &mut out),
        Which::Lie => units::lie::call::<M, S>(&zs, &mut out).map_err(|s| singular::<M>(s, z))?,
    }
    Ok(out)
}

/// The error for a singularity met at z, naming the state.
pub fn singular<M: Model>(s: Singularity, z: &[f64]) -> Failure {
    let names = <M::System as HamelSystem>::STATE;
    let state = NamedValues::new(names, &z[..names.len().min(z.len())]);
    Failure::new(Status::Singular, format!("{s} at {state}"))
}

/// The values of `which` at z into `out` (its first entries).
pub fn value<M: Model>(which: Which, z: &[f64], out: &mut [f64]) -> Result<(), Failure> {
    let result = run::<M, f64>(which, z, |_, v| v)?;
    for (o, r) in out.iter_mut().zip(result.as_ref()) {
        *o = *r;
    }
    Ok(())
}

/// ∂out/∂z · `direction` (a forward derivative) into `out`; `direction` over z.
pub fn forward<M: Model>(
    which: Which,
    z: &[f64],
    direction: &[f64],
    out: &mut [f64],
) -> Result<(), Failure> {
    let result = run::<M, Dual64>(which, z, |i, v| {
        Dual64::new(v, direction.get(i).copied().unwrap_or(0.0))
    })?;
    for (o, r) in out.iter_mut().zip(result.as_ref()) {
        *o = r.eps;
    }
    Ok(())
}

/// The column ∂out/∂z_c into `out`.
pub fn column<M: Model>(which: Which, z: &[f64], c: usize, out: &mut [f64]) -> Result<(), Failure> {
    let result = run::<M, Dual64>(which, z, |i, v| {
        Dual64::new(v, if i == c { 1.0 } else { 0.0 })
    })?;
    for (o, r) in out.iter_mut().zip(result.as_ref()) {
        *o = r.eps;
    }
    Ok(())
}

/// ∂²out/∂z_a∂z_b into `out`.
pub fn second<M: Model>(
    which: Which,
    z: &[f64],
    (a, b): (usize, usize),
    out: &mut [f64],
) -> Result<(), Failure> {
    let one = |hit: bool| if hit { 1.0 } else { 0.0 };
    let result = run::<M, Hyper>(which, z, |i, v| Hyper::seeded(v, one(i == a), one(i == b)))?;
    for (o, r) in out.iter_mut().zip(result.as_ref()) {
        *o = r.0.eps1eps2;
    }
    Ok(())
}
