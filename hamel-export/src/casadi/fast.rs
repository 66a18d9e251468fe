//! The calls an NLP solver makes, on the right-hand side with x, u and p given: `f`,
//! `fwd1_f` and `fwd<N>_f` (CasADi evaluates the Jacobian of its own graph by forward
//! derivatives: the parking example makes, a solve, 30,640 calls of `fwd8_f` and 16,640 of
//! `fwd1_f` — 261,760 of `fwd1_f` without `fwd<N>_f` —, 16,000 of `jac_adj1_f`, 61,520 of
//! `f`, 14,000 of `adj1_f`), `adj1_f`, `jac_f` and `jac_adj1_f`.
//! Here the blocks' sizes are constants of the model, so reading the point is a few moves,
//! not a walk over the function's ports. Every other call, and every call this path declines
//! (a null block, a value that is not finite, a nonzero direction in p or t, a wanted block
//! the compiled code does not give), takes the general path of [`super::eval`], which
//! refuses it or computes it with the same compiled code.

use super::eval::{transpose_from, transpose_into};
use super::{Family, Kind};
use crate::abi::{Failure, FiniteSum, all_finite, all_zero};
use crate::model::{Model, Sizes};
use crate::passes::singular;
use crate::primal::Which;
use core::mem::MaybeUninit;
use hamel_runtime::Singularity;

/// The point (x, u, p and t) as z, read with the model's sizes; `None` if a block is null
/// or the values' sum not finite (the general path takes the call: zeros for a null block;
/// the refusal naming a value that is not finite, or the call computed if the sum only
/// overflowed).
///
/// # Safety
/// `arg` is CasADi's non-null array of inputs of a function of the right-hand side.
#[inline(always)]
unsafe fn point<M: Model>(
    arg: *const *const f64,
    z: &mut M::Array<MaybeUninit<f64>>,
) -> Option<&M::Array<f64>> {
    // SAFETY: the caller's contract.
    let sum = unsafe { copy_point::<M>(arg, z) }?;
    // SAFETY: `copy_point` wrote every value.
    sum.finite().then(|| unsafe { M::assume_init_ref(z) })
}

/// The point copied into `z` (every value of it written), and the sum of its values for
/// the caller to check ([`FiniteSum`]), with its other inputs' if it has any; `None` if a
/// block is null. The blocks are checked for null before any is read, and each is copied
/// and added in one pass into an array not zeroed first: zeros stored, the copy, and a
/// pass over the copy again were 70 instructions of `f`'s 625 a call (the robot,
/// `hamel-export/bench/instructions.sh` and callgrind's report of `mobile_robot_f`).
///
/// # Safety
/// As [`point`].
#[inline(always)]
unsafe fn copy_point<M: Model>(
    arg: *const *const f64,
    z: &mut M::Array<MaybeUninit<f64>>,
) -> Option<FiniteSum> {
    let s = Sizes::of::<M>();
    // SAFETY: CasADi's array holds a pointer per input (the caller's contract).
    let given = |k: usize| unsafe { *arg.add(k) };
    // x, u, p (and t): CasADi's inputs 0, 1, 2 (and 3).
    let (x, u, p) = (given(0), given(1), given(2));
    let t = if M::TIME_DEPENDENT { given(3) } else { x };
    // Their addresses' minimum is zero exactly when one of them is null (a block of no
    // values is never read: its address counts as not null): one test, where a test and a
    // flag per block cost 3 instructions more of every call (`adj1_f`,
    // `hamel-export/bench/instructions.sh`).
    let address = |block: *const f64, len: usize| if len > 0 { block as usize } else { 1 };
    let t_address = if M::TIME_DEPENDENT { t as usize } else { 1 };
    let least = address(x, s.nx)
        .min(address(u, s.nu))
        .min(address(p, s.np))
        .min(t_address);
    if least == 0 {
        return None;
    }
    let to = z.as_mut();
    let mut sum = FiniteSum::new();
    let mut copy = |block: *const f64, start: usize, len: usize| {
        if len > 0 {
            // SAFETY: a non-null input points to its port's nonzeros: the dense block.
            let from = unsafe { core::slice::from_raw_parts(block, len) };
            sum.copy(from, &mut to[start..start + len]);
        }
    };
    copy(x, 0, s.nx);
    copy(u, s.u(), s.nu);
    copy(p, s.p(), s.np);
    if M::TIME_DEPENDENT {
        copy(t, s.t(), 1);
    } else {
        to[s.t()].write(0.0);
    }
    // The rest of the array (longer than z when the outputs are): zeros.
    for rest in &mut to[s.z()..] {
        rest.write(0.0);
    }
    Some(sum)
}

/// How many of CasADi's inputs are the point: x, u, p (and t).
fn point_blocks<M: Model>() -> usize {
    3 + usize::from(M::TIME_DEPENDENT)
}

/// An adjoint's weights (the input after the point and the nominal output): CasADi's own
/// array, read in place (only read, by code that writes elsewhere), or `zeros` when null;
/// their values added to `sum`, which the caller checks (as the point's: one check of
/// both).
///
/// # Safety
/// `arg` is CasADi's non-null array of inputs of `adj1_f` or `jac_adj1_f` of the right-hand
/// side; a non-null input points to as many values as `zeros` holds, valid for the call.
#[inline(always)]
unsafe fn weights<'a, M: Model>(
    arg: *const *const f64,
    zeros: &'a [f64],
    sum: &mut FiniteSum,
) -> &'a [f64] {
    // SAFETY: CasADi's array holds a pointer per input (the caller's contract).
    let given = unsafe { *arg.add(point_blocks::<M>() + 1) };
    if given.is_null() {
        return zeros;
    }
    // SAFETY: a non-null input points to its port's nonzeros: as many as the weights.
    let weights = unsafe { core::slice::from_raw_parts(given, zeros.len()) };
    sum.add(weights);
    weights
}

/// Forward seed block `k` (0: x, 1: u, 2: p, 3: t), after the point and the nominal output.
///
/// # Safety
/// `arg` is CasADi's non-null array of inputs of `fwd<N>_f` of the right-hand side.
#[inline(always)]
unsafe fn seed<M: Model>(arg: *const *const f64, k: usize) -> *const f64 {
    // SAFETY: CasADi's array holds a pointer per input (the caller's contract).
    unsafe { *arg.add(point_blocks::<M>() + 1 + k) }
}

/// Whether the `n` directions have none in p or t (null or zero seeds): the fast paths
/// differentiate by x and u only; CasADi gives zeros where the parameters are fixed.
///
/// # Safety
/// As [`seed`]; a non-null seed points to its block's `n` columns, dense.
#[inline(always)]
unsafe fn fixed_parameters<M: Model>(arg: *const *const f64, n: usize) -> bool {
    let zero = |k: usize, len: usize| {
        // SAFETY: the caller's contract.
        let block = unsafe { seed::<M>(arg, k) };
        block.is_null()
            // SAFETY: a non-null seed points to its block's values, dense.
            || all_zero(unsafe { core::slice::from_raw_parts(block, len) })
    };
    zero(2, Sizes::of::<M>().np * n) && (!M::TIME_DEPENDENT || zero(3, n))
}

/// The one dense output of `f` or `fwd<N>_f`, `len` values; `None` if CasADi did not ask for
/// it (a null pointer).
///
/// # Safety
/// `res` is CasADi's non-null array of outputs; a non-null output has `len` writable values.
#[inline(always)]
unsafe fn dense_output<'a>(res: *const *mut f64, len: usize) -> Option<&'a mut [f64]> {
    // SAFETY: CasADi's array holds a pointer per output (the caller's contract).
    let out = unsafe { *res };
    // SAFETY: non-null, `len` writable values (the caller's contract).
    (!out.is_null()).then(|| unsafe { core::slice::from_raw_parts_mut(out, len) })
}

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
) -> Option<Result<(), Singularity>> {
    let s = Sizes::of::<M>();
    let mut storage = M::array(MaybeUninit::<f64>::uninit());
    // SAFETY: the caller's contract.
    let z = unsafe { point::<M>(arg, &mut storage) }?;
    // SAFETY: the only output is ẋ or its derivative, dense (the caller's contract).
    let Some(out) = (unsafe { dense_output(res, s.nx) }) else {
        return Some(Ok(()));
    };
    let parameters = &z.as_ref()[s.p()..s.t()];
    let written = match kind {
        Kind::Value => M::with_prepared(parameters, |prepared| {
            M::compiled_value(Which::Rhs, prepared, z, out)
        }),
        Kind::Forward => {
            // A direction in p or t takes the general path.
            // SAFETY: the caller's contract.
            if !unsafe { fixed_parameters::<M>(arg, 1) } {
                return None;
            }
            // The compiled code's columns: x, u, the parameters it reads, t.
            let mut local = M::array(0.0f64);
            {
                let local = local.as_mut();
                for (k, (start, len)) in [(0, s.nx), (s.nx, s.nu)].into_iter().enumerate() {
                    // SAFETY: the caller's contract.
                    let block = unsafe { seed::<M>(arg, k) };
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
                    z,
                    &local.as_ref()[..columns],
                    false,
                    out,
                )
            })
        }
        _ => return None,
    };
    // `None`: no compiled code (nothing was written); the general path computes it.
    written
}

/// Seed block `k` (`N` columns of `len` values; null: zeros) into components
/// `start..start + len` of `directions`; `false` if a value is not finite.
///
/// # Safety
/// As [`seed`]; a non-null seed points to its block's `N` columns, dense.
#[inline(always)]
unsafe fn read_seeds<M: Model, const N: usize>(
    arg: *const *const f64,
    k: usize,
    start: usize,
    len: usize,
    directions: &mut [[f64; N]],
) -> bool {
    // SAFETY: the caller's contract.
    let block = unsafe { seed::<M>(arg, k) };
    if len == 0 || block.is_null() {
        return true;
    }
    // SAFETY: as above.
    let columns = unsafe { core::slice::from_raw_parts(block, len * N) };
    match directions.get_mut(start..start + len) {
        Some(to) if all_finite(columns) => {
            transpose_into(columns, to);
            true
        }
        _ => false,
    }
}

/// `fwd<N>_f` of the right-hand side (N > 1) when the call has the common shape (the
/// point and the directions finite, none in p or t): the compiled Jacobian once, and its
/// products with the `N` directions; `None` (having written nothing) to take the general
/// path.
///
/// # Safety
/// As [`super::eval`]: `arg` and `res` are non-null CasADi arrays for this function.
#[inline(always)]
pub unsafe fn forwards<M: Model, const N: usize>(
    family: &Family,
    arg: *const *const f64,
    res: *const *mut f64,
) -> Option<Result<(), Failure>> {
    let plans = family.plans.as_ref()?;
    let s = Sizes::of::<M>();
    let mut storage = M::array(MaybeUninit::<f64>::uninit());
    // SAFETY: the caller's contract.
    let z = unsafe { point::<M>(arg, &mut storage) }?;
    // SAFETY: the only output is the N derivatives of ẋ, dense, a column each (the
    // caller's contract).
    let Some(out) = (unsafe { dense_output(res, s.nx * N) }) else {
        return Some(Ok(()));
    };
    // The seeds follow the nominal output: x, u, p (and t), N columns each. Directions in p
    // or t take the general path.
    // SAFETY: the caller's contract.
    if !unsafe { fixed_parameters::<M>(arg, N) } {
        return None;
    }
    // Only the components the products read (over z, and over the compiled code's columns
    // for the fused products), and the derivatives of ẋ, set to zeros (not the arrays'
    // whole length: that was a sixth of `fwd8_f`'s instructions).
    let mut array = M::array(MaybeUninit::<[f64; N]>::uninit());
    let columns = plans.products.columns(false).max(plans.local.len());
    let directions = zeroed(array.as_mut(), columns);
    // The seeds in x and in u, one call each (not a loop over the two blocks: at the exported
    // crate's opt-level 2 the loop is not unrolled, and the blocks' lengths are then not
    // constants).
    // SAFETY (both): the caller's contract.
    if !unsafe { read_seeds::<M, N>(arg, 0, 0, s.nx, directions) }
        || !unsafe { read_seeds::<M, N>(arg, 1, s.nx, s.nu, directions) }
    {
        return None;
    }
    let mut derivatives = M::array(MaybeUninit::<[f64; N]>::uninit());
    zeroed(derivatives.as_mut(), s.nx);
    if plans.fused {
        // SAFETY: the directions' first `columns` rows (at least the compiled code's
        // columns) and the derivatives' first nx are zeros or seeds.
        return unsafe { fused::<M, N>(z, &array, &mut derivatives, out) };
    }
    if !plans.products.compiled(false) {
        return None;
    }
    // SAFETY: as above.
    let (directions, derivatives) = unsafe {
        (
            initialized(array.as_ref(), columns),
            initialized_mut(derivatives.as_mut(), s.nx),
        )
    };
    // `jac_f`'s outputs one after the other in a scratch buffer, then their products.
    let mut jacobian = M::scratch();
    let jacobian = jacobian.as_mut();
    let base = jacobian.as_mut_ptr().cast::<f64>();
    // SAFETY: the buffer is longer than the outputs (`Plans::new` made no products
    // otherwise, which `compiled` checked).
    let to = unsafe { plans.stacked(base) };
    let written = M::with_prepared(&z.as_ref()[s.p()..s.t()], |prepared| {
        // SAFETY: each output's slots lie within its part of the buffer.
        unsafe { M::compiled_jacobian(Which::Rhs, prepared, z, false, &to) }
    });
    match written? {
        Err(e) => Some(Err(singular::<M>(e, z.as_ref()))),
        Ok(false) => None,
        // SAFETY: the compiled code filled every output by x, u and t, all the terms read
        // without p.
        Ok(true) => {
            unsafe { plans.products.add(false, jacobian, directions, derivatives) }.then(|| {
                transpose_from(derivatives, out);
                Ok(())
            })
        }
    }
}

/// `fwd<N>_f`'s derivatives as products of the compiled Jacobian's entries with the
/// directions, each entry multiplied as the compiled code gives it ([`Model::products_of`]):
/// each entry stored and read back with its row and column from a table was 388 of
/// `fwd2_f`'s 1484 instructions a call and 474 of `fwd4_f`'s 1811 (the robot's 28 entries;
/// `hamel-export/bench/instructions.sh`).
///
/// # Safety
/// The first rows of `directions` (as many as the compiled code's columns) and of
/// `derivatives` (nx) are initialized; `plans.fused` holds (the tables' entries lie within
/// them).
#[inline(always)]
unsafe fn fused<M: Model, const N: usize>(
    z: &M::Array<f64>,
    directions: &M::Array<MaybeUninit<[f64; N]>>,
    derivatives: &mut M::Array<MaybeUninit<[f64; N]>>,
    out: &mut [f64],
) -> Option<Result<(), Failure>> {
    let s = Sizes::of::<M>();
    let written = M::with_prepared(&z.as_ref()[s.p()..s.t()], |prepared| {
        // SAFETY: the caller's contract, which is `products_of`'s.
        unsafe { crate::units::products::call::<M, N>(prepared, z, directions, derivatives) }
    });
    match written? {
        Err(e) => Some(Err(singular::<M>(e, z.as_ref()))),
        Ok(false) => None,
        Ok(true) => {
            // SAFETY: the first nx rows are initialized (the caller's contract).
            transpose_from(unsafe { initialized(derivatives.as_ref(), s.nx) }, out);
            Some(Ok(()))
        }
    }
}

/// The first `len` of `rows` (at most all), which are initialized.
///
/// # Safety
/// The first `len` rows are initialized.
#[inline(always)]
unsafe fn initialized<const N: usize>(rows: &[MaybeUninit<[f64; N]>], len: usize) -> &[[f64; N]] {
    let rows = &rows[..len.min(rows.len())];
    // SAFETY: initialized (the caller's contract); `MaybeUninit<T>` has `T`'s layout.
    unsafe { &*(core::ptr::from_ref(rows) as *const [[f64; N]]) }
}

/// As [`initialized`], to write.
///
/// # Safety
/// As [`initialized`].
#[inline(always)]
unsafe fn initialized_mut<const N: usize>(
    rows: &mut [MaybeUninit<[f64; N]>],
    len: usize,
) -> &mut [[f64; N]] {
    let len = len.min(rows.len());
    let rows = &mut rows[..len];
    // SAFETY: as above.
    unsafe { &mut *(core::ptr::from_mut(rows) as *mut [[f64; N]]) }
}

/// The first `len` of `rows` (at most all), set to zeros.
#[inline(always)]
fn zeroed<const N: usize>(rows: &mut [MaybeUninit<[f64; N]>], len: usize) -> &mut [[f64; N]] {
    let len = len.min(rows.len());
    let rows = &mut rows[..len];
    for row in rows.iter_mut() {
        row.write([0.0; N]);
    }
    // SAFETY: every one of these rows was written just above.
    unsafe { &mut *(core::ptr::from_mut(rows) as *mut [[f64; N]]) }
}

/// `adj1_f` of the right-hand side: (∂ẋ/∂x)ᵀλ, (∂ẋ/∂u)ᵀλ, (∂ẋ/∂p)ᵀλ (and ∂ẋ/∂t·λ) from the
/// compiled adjoint over its columns (x, u, the parameters it reads, t); `None` (having
/// written nothing) to take the general path.
///
/// # Safety
/// As [`super::eval`]: `arg` and `res` are non-null CasADi arrays for this function.
#[inline(always)]
pub unsafe fn adjoint<M: Model>(
    arg: *const *const f64,
    res: *const *mut f64,
) -> Option<Result<(), Singularity>> {
    let s = Sizes::of::<M>();
    let mut storage = M::array(MaybeUninit::<f64>::uninit());
    // The point and the weights checked by one sum.
    // SAFETY (both): the caller's contract.
    let mut sum = unsafe { copy_point::<M>(arg, &mut storage) }?;
    let weights = unsafe { weights::<M>(arg, ZEROS.get(..s.nx)?, &mut sum) };
    if !sum.finite() {
        return None;
    }
    // SAFETY: `copy_point` wrote every value.
    let z = unsafe { M::assume_init_ref(&storage) };
    // SAFETY: CasADi's array holds a pointer per output (the caller's contract).
    let out = |k: usize| unsafe { *res.add(k) };
    let parameters = s.np > 0 && !out(2).is_null();
    let columns = s.p() + M::READ.len() + 1;
    // Not zeroed first (11 instructions of `adj1_f` for the robot,
    // `hamel-export/bench/instructions.sh`): the compiled adjoint writes every one of the
    // first `columns` values (the parameters' with `parameters`), all that is read below.
    let mut local = M::array(MaybeUninit::<f64>::uninit());
    let written = M::with_prepared(&z.as_ref()[s.p()..s.t()], |prepared| {
        M::compiled_adjoint(Which::Rhs, prepared, z, weights, parameters, &mut local)
    });
    if let Err(e) = written? {
        return Some(Err(e));
    }
    // Indexed within the whole array, whose length is a constant (not within its first
    // `columns`: their bounds were checked at run time, value by value, about 20
    // instructions of `adj1_f` for the robot; `hamel-export/bench/instructions.sh`).
    let local = local.as_ref();
    // SAFETY (each read below): values among the first `columns`, every one of which
    // `compiled_adjoint` wrote on `Some(Ok(()))` (the parameters' read only with
    // `parameters`); `MaybeUninit<f64>` has the layout of `f64`.
    let values = |range: core::ops::Range<usize>| unsafe {
        &*(core::ptr::from_ref(&local[range]) as *const [f64])
    };
    // SAFETY (each block below): a non-null output points to its port's nonzeros, dense.
    for (k, (start, len)) in [(0, s.nx), (s.nx, s.nu)].into_iter().enumerate() {
        if len > 0 && !out(k).is_null() {
            unsafe { core::slice::from_raw_parts_mut(out(k), len) }
                .copy_from_slice(values(start..start + len));
        }
    }
    if parameters {
        let adj_p = unsafe { core::slice::from_raw_parts_mut(out(2), s.np) };
        // Zeros where no column writes (none when every parameter is read).
        if !M::READS_ALL {
            adj_p.fill(0.0);
        }
        for (column, &read) in M::READ.iter().enumerate() {
            adj_p[read] = values(s.p() + column..s.p() + column + 1)[0];
        }
    }
    if M::TIME_DEPENDENT && !out(3).is_null() {
        unsafe { *out(3) = values(columns - 1..columns)[0] };
    }
    Some(Ok(()))
}

/// The refusal of a singularity that [`rhs`] or [`adjoint`] met, naming the state, read
/// again from `arg`: out of line, so that the fast calls carry the singularity alone, not
/// the point for its message (10 instructions fewer in `adj1_f` of the robot,
/// `hamel-export/bench/instructions.sh`).
///
/// # Safety
/// As [`rhs`], for the call that met the singularity.
#[cold]
#[inline(never)]
pub unsafe fn singular_at<M: Model>(e: Singularity, arg: *const *const f64) -> Failure {
    // SAFETY: the caller's contract.
    let mut storage = M::array(MaybeUninit::<f64>::uninit());
    match unsafe { point::<M>(arg, &mut storage) } {
        Some(z) => singular::<M>(e, z.as_ref()),
        None => singular::<M>(e, M::array(0.0).as_ref()),
    }
}

/// Zero weights, for a null adjoint seed (CasADi's zeros): a model with more states takes
/// the general path then.
static ZEROS: [f64; 256] = [0.0; 256];

/// `jac_f` (the blocks by x, u, t and, when wanted, by p) or `jac_adj1_f` (the weighted
/// second derivatives and the transposed Jacobian blocks) of the right-hand side, when every
/// wanted block is filled by the compiled code, which writes each entry straight into its
/// place; `None` (having written nothing) to take the general path.
///
/// # Safety
/// As [`super::eval`]: `arg` and `res` are non-null CasADi arrays for this function.
#[inline(always)]
pub unsafe fn sparse<M: Model>(
    family: &Family,
    kind: Kind,
    arg: *const *const f64,
    res: *const *mut f64,
) -> Option<Result<(), Failure>> {
    let plans = family.plans.as_ref()?;
    let s = Sizes::of::<M>();
    let mut storage = M::array(MaybeUninit::<f64>::uninit());
    // SAFETY: the caller's contract.
    let z = unsafe { point::<M>(arg, &mut storage) }?;
    let second = kind == Kind::AdjointJacobian;
    // The weights of `jac_adj1_f` only (none for `jac_f`).
    let mut array;
    let weights: &[f64] = if second {
        // Copied: the compiled code writes into CasADi's outputs while it reads them.
        // SAFETY: the caller's contract.
        let mut sum = FiniteSum::new();
        let given = unsafe { weights::<M>(arg, ZEROS.get(..s.nx)?, &mut sum) };
        if !sum.finite() {
            return None;
        }
        array = M::array(0.0f64);
        let weights = &mut array.as_mut()[..s.nx];
        weights.copy_from_slice(given);
        weights
    } else {
        &[]
    };
    let direct = if second {
        &plans.second
    } else {
        &plans.jacobian
    };
    // SAFETY: CasADi's array holds a pointer per output (the caller's contract).
    let given = |k: usize| unsafe { *res.add(k) };
    let parameters = direct.stages(|k| !given(k).is_null())?;
    let mut scratch = M::scratch();
    let mut to = [core::ptr::null_mut(); crate::layout::DISCARD + 1];
    direct.destinations(&mut to, given, scratch.as_mut());
    let written = M::with_prepared(&z.as_ref()[s.p()..s.t()], |prepared| {
        // SAFETY: every destination is a wanted output the compiled code fills (its
        // slots are its nonzeros: `Plans::new` checked the layout against its pattern) or
        // the scratch buffer, which holds any output.
        unsafe {
            if second {
                M::compiled_second(Which::Rhs, prepared, z, weights, parameters, &to)
            } else {
                M::compiled_jacobian(Which::Rhs, prepared, z, parameters, &to)
            }
        }
    });
    match written? {
        Err(e) => Some(Err(singular::<M>(e, z.as_ref()))),
        // A stage asked for not compiled (the plans say it is): the general path.
        Ok(false) => None,
        Ok(true) => Some(Ok(())),
    }
}
