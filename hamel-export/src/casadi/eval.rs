//! Evaluating one function of a family from CasADi's arrays of pointers: `arg[i]` the
//! nonzeros of input i (null: all zero), `res[i]` where to write those of output i (null: not
//! wanted, not computed). With compiled code (feature `compiled`) each result is one call of
//! the code `#[hamel_system]` emitted for it, with the values that depend on the parameters
//! alone prepared once per parameter set; what is not compiled (a stage too large, or all of
//! it without the feature) is computed by dual-number passes, only for the directions a
//! wanted output needs and the generated code's graph says can be nonzero.

use super::plan::Direct;
use super::{Content, Family, Function, Kind, fast};
use crate::abi::{Failure, Status, all_finite, check_finite, slice, slice_mut};
use crate::layout::Destinations;
use crate::model::Model;
use crate::passes::{self, singular};
use crate::primal::{Block, Primal, Which};
use hamel_runtime::{HamelSystem, Parameters, Singularity};

/// Evaluate `kind` of the family of `which` for CasADi, as [`eval`], the family described
/// by `family` (on first use). The calls of the right-hand side that need none of its
/// description (`f`, `fwd1_f`, `adj1_f` at a finite point: the model's sizes are constants)
/// are taken first without it: its first-use check and the loads of what [`eval`] asks of
/// it cost as much as their point's finite check.
///
/// # Safety
/// As [`eval`].
#[inline(always)]
pub unsafe fn call<M: Model>(
    which: Which,
    family: fn() -> &'static Family,
    kind: Kind,
    arg: *const *const f64,
    res: *const *mut f64,
) -> Result<(), Failure> {
    if arg.is_null() || res.is_null() {
        return Err(null_arrays());
    }
    // With compiled code every family has its plans, which is what `eval` asks before the
    // same calls.
    let fast = which == Which::Rhs && M::COMPILED;
    // SAFETY (each call below): the caller's contract, which is `fast`'s and `eval`'s.
    let result = match kind {
        Kind::Value | Kind::Forward if fast => unsafe { fast::rhs::<M>(kind, arg, res) },
        Kind::Adjoint if fast => unsafe { fast::adjoint::<M>(arg, res) },
        // The other calls need the family: `eval` inlined, for this `kind` alone.
        _ => return unsafe { eval::<M>(family(), kind, arg, res) },
    };
    match result {
        Some(Ok(())) => Ok(()),
        Some(Err(e)) => Err(unsafe { fast::singular_at::<M>(e, arg) }),
        // Declined (a null block, a value that is not finite): the general path.
        None => unsafe { general::<M>(family(), kind, arg, res) },
    }
}

/// [`eval`]'s general path out of line, for the calls [`call`] declines (rare): inlined,
/// its code made the fast calls' frame larger (registers saved and restored on every call).
/// Not `eval` itself: its fast path would only decline the same call again.
///
/// # Safety
/// As [`eval`].
#[inline(never)]
unsafe fn general<M: Model>(
    family: &Family,
    kind: Kind,
    arg: *const *const f64,
    res: *const *mut f64,
) -> Result<(), Failure> {
    // SAFETY: the caller's contract.
    unsafe { general_path::<M>(family, kind, arg, res) }
}

/// Evaluate `kind` of `family` for CasADi: 0 on success; otherwise the failure.
///
/// # Safety
/// `arg` and `res` must be CasADi's arrays for this function: at least `n_in` and `n_out`
/// pointers, each null or pointing to as many values as the port's pattern has nonzeros.
#[inline(always)]
pub unsafe fn eval<M: Model>(
    family: &Family,
    kind: Kind,
    arg: *const *const f64,
    res: *const *mut f64,
) -> Result<(), Failure> {
    if arg.is_null() || res.is_null() {
        return Err(null_arrays());
    }
    // Only with compiled code (which `plans` stands for): without it the fast path would read
    // the point and hand every call on.
    if family.primal.which == Which::Rhs && family.plans.is_some() {
        // SAFETY: the caller's contract, which is `fast`'s.
        let fast = match kind {
            Kind::Value | Kind::Forward => unsafe { fast::rhs::<M>(kind, arg, res) }
                .map(|r| r.map_err(|e| unsafe { fast::singular_at::<M>(e, arg) })),
            Kind::Forward2 => unsafe { fast::forwards::<M, 2>(family, arg, res) },
            Kind::Forward4 => unsafe { fast::forwards::<M, 4>(family, arg, res) },
            Kind::Forward8 => unsafe { fast::forwards::<M, 8>(family, arg, res) },
            Kind::Adjoint => unsafe { fast::adjoint::<M>(arg, res) }
                .map(|r| r.map_err(|e| unsafe { fast::singular_at::<M>(e, arg) })),
            Kind::Jacobian | Kind::AdjointJacobian => unsafe {
                fast::sparse::<M>(family, kind, arg, res)
            },
        };
        if let Some(result) = fast {
            return result;
        }
    }
    // SAFETY: the caller's contract.
    unsafe { general_path::<M>(family, kind, arg, res) }
}

/// [`eval`] by the family's description and dual numbers: any call, read port by port, every
/// value checked (what the fast paths decline comes here).
///
/// # Safety
/// As [`eval`], with `arg` and `res` not null.
#[inline(always)]
unsafe fn general_path<M: Model>(
    family: &Family,
    kind: Kind,
    arg: *const *const f64,
    res: *const *mut f64,
) -> Result<(), Failure> {
    let f = family.function(kind);
    let primal = &family.primal;
    // SAFETY: CasADi's arrays hold a pointer per port (the caller's contract).
    let input = |k: usize| -> Result<Option<&[f64]>, Failure> {
        let ptr = unsafe { *arg.add(k) };
        if ptr.is_null() {
            return Ok(None);
        }
        let port = &f.inputs[k];
        unsafe { slice(ptr, port.pattern.nnz(), port.name()) }.map(Some)
    };
    let mut z = M::array(0.0f64);
    for (k, block) in primal.inputs.iter().enumerate() {
        if let Some(values) = input(k)? {
            z.as_mut()[block.offset..block.offset + block.len].copy_from_slice(values);
        }
    }
    // One pass over z (the blocks CasADi did not give are zeros); only when it finds a value
    // that is not finite, the block and the component's label for the message.
    if !all_finite(z.as_ref()) {
        name_not_finite::<M>(primal, z.as_ref())?;
    }
    let nb = primal.inputs.len();
    let mut outputs = Outputs { f, res };
    match kind {
        Kind::Value => with_run::<M, _>(family, &z, |r| r.value(&mut outputs)),
        Kind::Jacobian => with_run::<M, _>(family, &z, |r| r.jacobian(&mut outputs)),
        Kind::Forward | Kind::Forward2 | Kind::Forward4 | Kind::Forward8 => {
            // The directions, block by block (at most x, u, p, t), read where they are given:
            // a column of the block per direction.
            let mut seeds: Seeds = [None; 4];
            for (k, seed) in seeds.iter_mut().enumerate().take(nb) {
                if let Some(values) = input(nb + 1 + k)? {
                    check_finite(f.inputs[nb + 1 + k].name(), values, &[])?;
                    *seed = Some(values);
                }
            }
            let n = kind.directions();
            with_run::<M, _>(family, &z, |r| r.forward(n, &seeds, &mut outputs))
        }
        Kind::Adjoint | Kind::AdjointJacobian => {
            let mut weights = M::array(0.0f64);
            let weights = &mut weights.as_mut()[..primal.output.1];
            if let Some(values) = input(nb + 1)? {
                check_finite(f.inputs[nb + 1].name(), values, &[])?;
                weights.copy_from_slice(values);
            }
            if kind == Kind::Adjoint {
                with_run::<M, _>(family, &z, |r| r.adjoint(weights, &mut outputs))
            } else {
                with_run::<M, _>(family, &z, |r| r.adjoint_jacobian(weights, &mut outputs))
            }
        }
    }
}

/// `then` with the evaluation at `z`, its parameters' prepared values at hand.
#[inline(always)]
fn with_run<M: Model, R>(family: &Family, z: &M::Array<f64>, then: impl FnOnce(&Run<M>) -> R) -> R {
    let s = family.primal.sizes;
    M::with_prepared(&z.as_ref()[s.p()..s.t()], |prepared| {
        then(&Run {
            family,
            prepared,
            z,
        })
    })
}

/// The refusal of null argument or result arrays.
#[cold]
#[inline(never)]
fn null_arrays() -> Failure {
    Failure::new(
        Status::NullPointer,
        "the argument or result array is a null pointer",
    )
}

/// The refusal of a point with a value that is not finite: its block and component named.
#[cold]
#[inline(never)]
fn name_not_finite<M: Model>(primal: &Primal, z: &[f64]) -> Result<(), Failure> {
    for block in &primal.inputs {
        let values = &z[block.offset..block.offset + block.len];
        check_finite(block.name, values, labels::<M>(block))?;
    }
    Ok(())
}

/// The names of a block's components, for messages.
fn labels<M: Model>(block: &Block) -> &'static [&'static str] {
    match block.name {
        "x" => <M::System as HamelSystem>::STATE,
        "u" => <M::System as HamelSystem>::INPUTS,
        "p" => <M::System as Parameters>::NAMES,
        _ => &[],
    }
}

/// `N` columns of `len` values (CasADi's stacked directions) into `len` components of `N`
/// values each.
#[inline(always)]
pub(super) fn transpose_into<const N: usize>(columns: &[f64], to: &mut [[f64; N]]) {
    let len = to.len();
    for (d, column) in columns.chunks_exact(len.max(1)).take(N).enumerate() {
        for (to, &v) in to.iter_mut().zip(column) {
            to[d] = v;
        }
    }
}

/// The converse: components of `N` values into `N` columns of `out.len() / N` values.
#[inline(always)]
pub(super) fn transpose_from<const N: usize>(from: &[[f64; N]], out: &mut [f64]) {
    let len = out.len() / N;
    for (d, column) in out.chunks_exact_mut(len.max(1)).take(N).enumerate() {
        for (out, from) in column.iter_mut().zip(from) {
            *out = from[d];
        }
    }
}

/// Forward seeds by input block (at most x, u, p, t); `None`: zero.
type Seeds<'a> = [Option<&'a [f64]>; 4];

/// The result arrays, by output.
struct Outputs<'f> {
    f: &'f Function,
    res: *const *mut f64,
}

impl Outputs<'_> {
    /// Output `k`'s nonzeros to write, or `None` when CasADi does not want it.
    fn get(&mut self, k: usize) -> Result<Option<&mut [f64]>, Failure> {
        let Some((port, _)) = self.f.outputs.get(k) else {
            return Ok(None);
        };
        // SAFETY: CasADi's array holds a pointer per output (the contract of `eval`).
        let ptr = unsafe { *self.res.add(k) };
        if ptr.is_null() {
            return Ok(None);
        }
        // SAFETY: as many values as the pattern's nonzeros (the contract of `eval`).
        unsafe { slice_mut(ptr, port.pattern.nnz(), port.name()) }.map(Some)
    }

    /// Whether output `k` is wanted.
    fn wanted(&self, k: usize) -> bool {
        k < self.f.outputs.len() && unsafe { !(*self.res.add(k)).is_null() }
    }
}

/// One evaluation: the family, the prepared values and the point.
struct Run<'a, M: Model> {
    family: &'a Family,
    prepared: &'a M::Prepared,
    z: &'a M::Array<f64>,
}

impl<M: Model> Run<'_, M> {
    fn primal(&self) -> &Primal {
        &self.family.primal
    }

    fn singular(&self, e: hamel_runtime::Singularity) -> Failure {
        singular::<M>(e, self.z.as_ref())
    }

    /// `f`: the values.
    fn value(&self, outputs: &mut Outputs) -> Result<(), Failure> {
        let which = self.primal().which;
        let Some(out) = outputs.get(0)? else {
            return Ok(());
        };
        match M::compiled_value(which, self.prepared, self.z, out) {
            Some(result) => result.map_err(|e| self.singular(e)),
            None => passes::value::<M>(which, self.z.as_ref(), out),
        }
    }

    /// `jac_f`: the wanted blocks, from the compiled code where it fills them, the others
    /// by dual numbers.
    fn jacobian(&self, outputs: &mut Outputs) -> Result<(), Failure> {
        let mut done = [false; MAX_OUTPUTS];
        if let Some(plans) = &self.family.plans {
            self.direct(
                &plans.jacobian,
                outputs,
                &mut done,
                |to, parameters| unsafe {
                    M::compiled_jacobian(self.primal().which, self.prepared, self.z, parameters, to)
                },
            )?;
        }
        jacobian_by_passes::<M>(self.primal(), self.z.as_ref(), outputs, &done)
    }

    /// The wanted outputs `direct` says the compiled code fills, by `call` (with the
    /// destinations and whether the stage by p is asked for), marked `done`.
    ///
    /// `call` must be the compiled code of the function `direct` describes, which writes
    /// into the destinations only (`Model::compiled_jacobian`'s or `compiled_second`'s
    /// contract, which the destinations made here fulfil).
    fn direct(
        &self,
        direct: &Direct,
        outputs: &mut Outputs,
        done: &mut [bool; MAX_OUTPUTS],
        call: impl FnOnce(&Destinations, bool) -> Option<Result<bool, Singularity>>,
    ) -> Result<(), Failure> {
        let n = outputs.f.outputs.len().min(MAX_OUTPUTS);
        let mut wanted = [false; MAX_OUTPUTS];
        for (k, w) in wanted.iter_mut().enumerate().take(n) {
            *w = outputs.wanted(k) && direct.outputs.get(k).copied().flatten().is_some();
        }
        // Their stages: the one by p only if one of them is by p.
        let Some(parameters) = direct.stages(|k| wanted.get(k) == Some(&true)) else {
            return Ok(());
        };
        if !wanted.contains(&true) {
            return Ok(());
        }
        // Each wanted output's array, checked as the general path checks any output.
        for k in (0..n).filter(|&k| wanted[k]) {
            outputs.get(k)?;
        }
        let mut scratch = M::scratch();
        let given = |k: usize| {
            if wanted.get(k) == Some(&true) {
                // SAFETY: CasADi's array holds a pointer per output (the contract of `eval`).
                unsafe { *outputs.res.add(k) }
            } else {
                core::ptr::null_mut()
            }
        };
        let mut to = [core::ptr::null_mut(); crate::layout::DISCARD + 1];
        direct.destinations(&mut to, given, scratch.as_mut());
        match call(&to, parameters) {
            Some(Ok(true)) => {
                for (d, &w) in done.iter_mut().zip(&wanted) {
                    *d |= w;
                }
                Ok(())
            }
            Some(Err(e)) => Err(self.singular(e)),
            Some(Ok(false)) | None => Ok(()),
        }
    }

    /// `fwd<n>_f`: `n` forward derivatives, along the directions given block by block (a
    /// column of each block per direction; `None`: zero).
    fn forward(&self, n: usize, seeds: &Seeds, outputs: &mut Outputs) -> Result<(), Failure> {
        let Some(out) = outputs.get(0)? else {
            return Ok(());
        };
        // Several directions: the Jacobian once, then a product per direction.
        if n > 1 {
            if let Some(result) = self.forward_by_jacobian(n, seeds, out) {
                return result;
            }
        }
        let blocks = &self.primal().inputs;
        let no = self.primal().output.1;
        for d in 0..n {
            let mut column: Seeds = [None; 4];
            for ((to, from), block) in column.iter_mut().zip(seeds).zip(blocks) {
                *to = from.and_then(|s| s.get(d * block.len..(d + 1) * block.len));
            }
            if let Some(out) = out.get_mut(d * no..(d + 1) * no) {
                self.direction(&column, out)?;
            }
        }
        Ok(())
    }

    /// The `n` forward derivatives as products of the compiled Jacobian (by p only if a
    /// direction has a component in p) with the directions; `None` (having written nothing)
    /// where that stage is not compiled.
    fn forward_by_jacobian(
        &self,
        n: usize,
        seeds: &Seeds,
        out: &mut [f64],
    ) -> Option<Result<(), Failure>> {
        match n {
            2 => self.products::<2>(seeds, out),
            4 => self.products::<4>(seeds, out),
            8 => self.products::<8>(seeds, out),
            _ => None,
        }
    }

    /// [`Run::forward_by_jacobian`] for `N` directions: the directions and the derivatives
    /// are held direction-minor (`[f64; N]` per component), so that each Jacobian entry
    /// multiplies all `N` at once.
    #[inline(always)]
    fn products<const N: usize>(
        &self,
        seeds: &Seeds,
        out: &mut [f64],
    ) -> Option<Result<(), Failure>> {
        let plans = self.family.plans.as_ref()?;
        let primal = self.primal();
        // The directions over z, by component.
        let mut directions = M::array([0.0f64; N]);
        let mut parameters = false;
        for (block, seed) in primal.inputs.iter().zip(seeds) {
            let Some(seed) = seed else {
                continue;
            };
            let to = directions
                .as_mut()
                .get_mut(block.offset..block.offset + block.len)?;
            transpose_into(seed, to);
            parameters |= block.name == "p" && seed.iter().any(|&v| v != 0.0);
        }
        if !plans.products.compiled(parameters) {
            return None;
        }
        let mut derivatives = M::array([0.0f64; N]);
        let mut jacobian = M::scratch();
        let jacobian = jacobian.as_mut();
        // SAFETY: the buffer is longer than `jac_f`'s outputs one after the other (`Plans`
        // made no products otherwise, which `compiled` checked).
        let to = unsafe { plans.stacked(jacobian.as_mut_ptr().cast::<f64>()) };
        // SAFETY: each output's slots lie within its part of the buffer.
        let written =
            unsafe { M::compiled_jacobian(primal.which, self.prepared, self.z, parameters, &to) }?;
        match written {
            Err(e) => Some(Err(self.singular(e))),
            Ok(false) => None,
            // SAFETY: the compiled code filled every output the products read.
            Ok(true) => unsafe {
                plans.products.add(
                    parameters,
                    jacobian,
                    directions.as_ref(),
                    derivatives.as_mut(),
                )
            }
            .then(|| {
                transpose_from(derivatives.as_ref(), out);
                Ok(())
            }),
        }
    }

    /// One forward derivative along the direction given block by block (`None`: zero).
    fn direction(&self, seeds: &Seeds, out: &mut [f64]) -> Result<(), Failure> {
        let which = self.primal().which;
        if let Some(plans) = &self.family.plans {
            // The direction over the compiled code's columns, copied from the blocks in runs.
            let mut local = M::array(0.0f64);
            for &(block, within, column, len) in &plans.runs {
                if let Some(Some(seed)) = seeds.get(block) {
                    let to = local.as_mut().get_mut(column..column + len);
                    if let (Some(to), Some(from)) = (to, seed.get(within..within + len)) {
                        to.copy_from_slice(from);
                    }
                }
            }
            let local = &local.as_ref()[..plans.local.len()];
            let parameters = local[plans.parameters.clone()].iter().any(|&d| d != 0.0);
            if let Some(result) =
                M::compiled_forward(which, self.prepared, self.z, local, parameters, out)
            {
                return result.map_err(|e| self.singular(e));
            }
        }
        let mut direction = M::array(0.0f64);
        for (block, seed) in self.primal().inputs.iter().zip(seeds) {
            if let Some(seed) = seed {
                direction.as_mut()[block.offset..block.offset + block.len].copy_from_slice(seed);
            }
        }
        passes::forward::<M>(which, self.z.as_ref(), direction.as_ref(), out)
    }

    /// `adj1_f`: (∂out/∂block)ᵀ λ for each wanted block.
    fn adjoint(&self, weights: &[f64], outputs: &mut Outputs) -> Result<(), Failure> {
        let primal = self.primal();
        if let Some(plans) = &self.family.plans {
            let parameters = primal
                .inputs
                .iter()
                .enumerate()
                .any(|(k, b)| b.name == "p" && outputs.wanted(k));
            let mut local = M::array(core::mem::MaybeUninit::<f64>::uninit());
            let written = M::compiled_adjoint(
                primal.which,
                self.prepared,
                self.z,
                weights,
                parameters,
                &mut local,
            );
            if let Some(result) = written {
                result.map_err(|e| self.singular(e))?;
                for (k, columns) in plans.adjoint.iter().enumerate() {
                    if let Some(out) = outputs.get(k)? {
                        out.fill(0.0);
                        for &(c, w) in columns {
                            // SAFETY: `c` is a local column (the plans' columns), all of
                            // which `compiled_adjoint` wrote (the parameters' too: their
                            // block is wanted, so `parameters`).
                            out[w] = unsafe { local.as_ref()[c].assume_init() };
                        }
                    }
                }
                return Ok(());
            }
        }
        adjoint_by_passes::<M>(primal, self.z.as_ref(), weights, outputs)
    }

    /// `jac_adj1_f`: the wanted second-derivative blocks and transposed Jacobian blocks.
    fn adjoint_jacobian(&self, weights: &[f64], outputs: &mut Outputs) -> Result<(), Failure> {
        let mut done = [false; MAX_OUTPUTS];
        if let Some(plans) = &self.family.plans {
            self.direct(&plans.second, outputs, &mut done, |to, parameters| unsafe {
                M::compiled_second(
                    self.primal().which,
                    self.prepared,
                    self.z,
                    weights,
                    parameters,
                    to,
                )
            })?;
        }
        second_by_passes::<M>(self.primal(), self.z.as_ref(), weights, outputs, &done)
    }
}

/// The most outputs a function has: `jac_adj1_f` of a time-dependent model, 4 × 6 (for each
/// of x, u, p, t: the blocks by x, u, p, t, out and adj).
const MAX_OUTPUTS: usize = 24;

/// The columns ∂out/∂z_c of a block that can be nonzero.
fn live_columns<'a>(primal: &'a Primal, block: &'a Block) -> impl Iterator<Item = usize> + 'a {
    (block.offset..block.offset + block.len)
        .filter(|&c| (0..primal.output.1).any(|r| primal.depends_on(r, c)))
}

/// `jac_f` by dual numbers: each wanted block not `done`, column by column.
fn jacobian_by_passes<M: Model>(
    primal: &Primal,
    z: &[f64],
    outputs: &mut Outputs,
    done: &[bool],
) -> Result<(), Failure> {
    let mut column = M::array(0.0f64);
    for (k, block) in primal.inputs.iter().enumerate() {
        if done.get(k).copied().unwrap_or(false) || !outputs.wanted(k) {
            continue;
        }
        let pattern = &outputs.f.outputs[k].0.pattern;
        outputs.get(k)?.unwrap_or_default().fill(0.0);
        for c in live_columns(primal, block) {
            passes::column::<M>(primal.which, z, c, column.as_mut())?;
            let values = outputs.get(k)?.unwrap_or_default();
            for slot in pattern.column(c - block.offset) {
                values[slot] = column.as_ref()[pattern.row(slot)];
            }
        }
    }
    Ok(())
}

/// `adj1_f` by dual numbers: (∂out/∂block)ᵀ λ for each wanted block.
fn adjoint_by_passes<M: Model>(
    primal: &Primal,
    z: &[f64],
    weights: &[f64],
    outputs: &mut Outputs,
) -> Result<(), Failure> {
    let mut column = M::array(0.0f64);
    for (k, block) in primal.inputs.iter().enumerate() {
        let Some(values) = outputs.get(k)? else {
            continue;
        };
        values.fill(0.0);
        for c in live_columns(primal, block) {
            passes::column::<M>(primal.which, z, c, column.as_mut())?;
            values[c - block.offset] = dot(weights, column.as_ref());
        }
    }
    Ok(())
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// `jac_adj1_f` by dual and hyper-dual numbers: the wanted outputs not `done`, each
/// unordered pair of directions computed once and written wherever it is wanted (H is
/// symmetric), and the transposed Jacobian blocks.
fn second_by_passes<M: Model>(
    primal: &Primal,
    z: &[f64],
    weights: &[f64],
    outputs: &mut Outputs,
    done: &[bool],
) -> Result<(), Failure> {
    let f = outputs.f;
    let open =
        |outputs: &Outputs, k: usize| outputs.wanted(k) && !done.get(k).copied().unwrap_or(false);
    // At most four blocks: x, u, p, t.
    let mut wanted_second = [[false; 4]; 4];
    let mut column = M::array(0.0f64);
    for k in 0..f.outputs.len() {
        if !open(outputs, k) {
            continue;
        }
        match f.outputs[k].1 {
            Content::Second(i, j) => {
                wanted_second[i][j] = true;
                outputs.get(k)?.unwrap_or_default().fill(0.0);
            }
            Content::Transposed(i) => {
                let block = &primal.inputs[i];
                let pattern = &f.outputs[k].0.pattern;
                outputs.get(k)?.unwrap_or_default().fill(0.0);
                for c in live_columns(primal, block) {
                    passes::column::<M>(primal.which, z, c, column.as_mut())?;
                    let values = outputs.get(k)?.unwrap_or_default();
                    for r in 0..primal.output.1 {
                        if let Some(slot) = pattern.position(c - block.offset, r) {
                            values[slot] = column.as_ref()[r];
                        }
                    }
                }
            }
            _ => {}
        }
    }
    // Nothing left to compute (the compiled code wrote every wanted block): not even the
    // walk over the pairs of directions, which costs more than the compiled code.
    if !wanted_second.iter().flatten().any(|&w| w) {
        return Ok(());
    }
    let blocks = &primal.inputs;
    let live = || {
        blocks
            .iter()
            .enumerate()
            .flat_map(|(i, b)| live_columns(primal, b).map(move |c| (i, c)))
    };
    let mut second = M::array(0.0f64);
    for (i, a) in live() {
        for (j, b) in live().filter(|&(_, b)| b >= a) {
            let wanted = wanted_second[i][j] || wanted_second[j][i];
            if !wanted || !primal.pair(a, b) {
                continue;
            }
            passes::second::<M>(primal.which, z, (a, b), second.as_mut())?;
            let h = dot(weights, second.as_ref());
            let at = |blk: usize, c: usize| (blk, c - blocks[blk].offset);
            write_second(f, outputs, at(i, a), at(j, b), h, done)?;
            if a != b {
                write_second(f, outputs, at(j, b), at(i, a), h, done)?;
            }
        }
    }
    Ok(())
}

/// Write H(a, b) into the wanted block (i, j) holding it, at row a, column b, unless the
/// compiled code wrote that block.
fn write_second(
    f: &Function,
    outputs: &mut Outputs,
    (i, a): (usize, usize),
    (j, b): (usize, usize),
    value: f64,
    done: &[bool],
) -> Result<(), Failure> {
    let Some(k) = f
        .outputs
        .iter()
        .position(|(_, content)| *content == Content::Second(i, j))
    else {
        return Ok(());
    };
    if done.get(k).copied().unwrap_or(false) {
        return Ok(());
    }
    let pattern = &f.outputs[k].0.pattern;
    if let (Some(slot), Some(values)) = (pattern.position(a, b), outputs.get(k)?) {
        values[slot] = value;
    }
    Ok(())
}
