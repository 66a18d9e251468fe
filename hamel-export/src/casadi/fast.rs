//! The calls an NLP solver makes most: `f` and `fwd1_f` of the right-hand side with x, u and
//! p given (CasADi evaluates a Jacobian of its own graph by forward derivatives, one
//! direction per call: the parking example makes 260,000 calls of `fwd1_f` a solve). Here
//! the blocks' sizes are constants of the model, so reading them is a few moves, not a walk
//! over the function's ports; every other call, and every call this path declines (a null
//! block, a value that is not finite, a nonzero direction in p or t), takes the general path of
//! [`super::eval`], which refuses or computes it with the same code.

use super::Kind;
use crate::abi::{Failure, all_finite};
use crate::model::{Model, Sizes};
use crate::passes::singular;
use crate::primal::Which;

/// `f` or `fwd1_f` of the right-hand side when the call has the common shape; `None` (having
/// written nothing) to take the general path.
///
/// # Safety
/// As [`super::eval`]: `arg` and `res` are non-null CasADi arrays for this function.
#[inline(always)]
pub unsafe fn rhs<M: Model>(
    kind: Kind,
    arg: *const *const f64,
    res: *const *mut f64,
) -> Option<Result<(), Failure>> {
    let s = Sizes::of::<M>();
    // The blocks x, u, p (and t): CasADi's inputs 0, 1, 2 (and 3).
    let blocks = 3 + usize::from(M::TIME_DEPENDENT);
    // SAFETY: CasADi's array holds a pointer per input (the caller's contract).
    let given = |k: usize| unsafe { *arg.add(k) };
    let mut z = M::array(0.0f64);
    {
        let z = z.as_mut();
        for (k, (start, len)) in [(0, s.nx), (s.u(), s.nu), (s.p(), s.np)]
            .into_iter()
            .enumerate()
        {
            if len > 0 {
                let block = given(k);
                if block.is_null() {
                    return None;
                }
                // SAFETY: a non-null input points to its port's nonzeros: the dense block.
                z[start..start + len]
                    .copy_from_slice(unsafe { core::slice::from_raw_parts(block, len) });
            }
        }
        if M::TIME_DEPENDENT {
            let t = given(3);
            if t.is_null() {
                return None;
            }
            // SAFETY: as above, one value.
            z[s.t()] = unsafe { *t };
        }
    }
    if !all_finite(&z.as_ref()[..s.z()]) {
        return None;
    }
    // SAFETY: CasADi's array holds a pointer per output; the only output is ẋ or its
    // derivative, dense.
    let out = unsafe { *res };
    if out.is_null() {
        return Some(Ok(()));
    }
    // SAFETY: non-null, nx writable values (the caller's contract).
    let out = unsafe { core::slice::from_raw_parts_mut(out, s.nx) };
    let parameters = &z.as_ref()[s.p()..s.t()];
    let written = match kind {
        Kind::Value => M::with_prepared(parameters, |prepared| {
            M::compiled_value(Which::Rhs, prepared, &z, out)
        }),
        Kind::Forward => {
            // The seeds follow the nominal output: x, u, p (and t). A direction in p or t takes
            // the general path; CasADi gives one of zeros where the parameters are fixed.
            let seed = |k: usize| given(blocks + 1 + k);
            // SAFETY: a non-null seed points to its block's values, dense.
            let zero = |k: usize, len: usize| {
                let block = seed(k);
                block.is_null()
                    || unsafe { core::slice::from_raw_parts(block, len) }
                        .iter()
                        .all(|&v| v == 0.0)
            };
            if !zero(2, s.np) || (M::TIME_DEPENDENT && !zero(3, 1)) {
                return None;
            }
            // The compiled code's columns: x, u, the parameters it reads, t.
            let mut local = M::array(0.0f64);
            {
                let local = local.as_mut();
                for (k, (start, len)) in [(0, s.nx), (s.nx, s.nu)].into_iter().enumerate() {
                    let block = seed(k);
                    if len > 0 && !block.is_null() {
                        // SAFETY: a non-null seed points to its block's values, dense.
                        local[start..start + len]
                            .copy_from_slice(unsafe { core::slice::from_raw_parts(block, len) });
                    }
                }
                if !all_finite(&local[..s.p()]) {
                    return None;
                }
            }
            let columns = s.p() + M::READ.len() + 1;
            M::with_prepared(parameters, |prepared| {
                M::compiled_forward(
                    Which::Rhs,
                    prepared,
                    &z,
                    &local.as_ref()[..columns],
                    false,
                    out,
                )
            })
        }
        _ => return None,
    };
    // `None`: no compiled code (nothing was written); the general path computes it.
    Some(written?.map_err(|e| singular::<M>(e, z.as_ref())))
}
