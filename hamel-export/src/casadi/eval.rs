//! Evaluating one function of a family from CasADi's arrays of pointers: `arg[i]` the
//! nonzeros of input i (null: all zero), `res[i]` where to write those of output i (null: not
//! wanted, not computed). Derivatives are computed by dual-number passes only for the
//! directions a wanted output needs and the generated code's graph says can be nonzero.

use super::{Content, Family, Function, Kind};
use crate::abi::{Failure, Status, check_finite, slice, slice_mut};
use crate::model::Model;
use crate::passes;
use crate::primal::{Block, Primal};
use hamel_runtime::{HamelSystem, Parameters};

/// Evaluate `kind` of `family` for CasADi: 0 on success; otherwise the failure.
///
/// # Safety
/// `arg` and `res` must be CasADi's arrays for this function: at least `n_in` and `n_out`
/// pointers, each null or pointing to as many values as the port's pattern has nonzeros.
pub unsafe fn eval<M: Model>(
    family: &Family,
    kind: Kind,
    arg: *const *const f64,
    res: *const *mut f64,
) -> Result<(), Failure> {
    if arg.is_null() || res.is_null() {
        return Err(Failure::new(
            Status::NullPointer,
            "the argument or result array is a null pointer",
        ));
    }
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
            check_finite(block.name, values, labels::<M>(block))?;
            z.as_mut()[block.offset..block.offset + block.len].copy_from_slice(values);
        }
    }
    let z = z.as_ref();
    let nb = primal.inputs.len();
    let mut outputs = Outputs { f, res };
    match kind {
        Kind::Value => {
            if let Some(out) = outputs.get(0)? {
                passes::value::<M>(primal.which, z, out)?;
            }
        }
        Kind::Jacobian => jacobian::<M>(primal, z, &mut outputs)?,
        Kind::Forward => {
            let mut direction = M::array(0.0f64);
            for (k, block) in primal.inputs.iter().enumerate() {
                if let Some(values) = input(nb + 1 + k)? {
                    check_finite(f.inputs[nb + 1 + k].name(), values, &[])?;
                    direction.as_mut()[block.offset..block.offset + block.len]
                        .copy_from_slice(values);
                }
            }
            if let Some(out) = outputs.get(0)? {
                passes::forward::<M>(primal.which, z, direction.as_ref(), out)?;
            }
        }
        Kind::Adjoint | Kind::AdjointJacobian => {
            let mut weights = M::array(0.0f64);
            if let Some(values) = input(nb + 1)? {
                check_finite(f.inputs[nb + 1].name(), values, &[])?;
                weights.as_mut()[..values.len()].copy_from_slice(values);
            }
            let weights = &weights.as_ref()[..primal.output.1];
            if kind == Kind::Adjoint {
                adjoint::<M>(primal, z, weights, &mut outputs)?;
            } else {
                adjoint_jacobian::<M>(primal, z, weights, &mut outputs)?;
            }
        }
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

/// The columns ∂out/∂z_c of a block that can be nonzero.
fn live_columns<'a>(primal: &'a Primal, block: &'a Block) -> impl Iterator<Item = usize> + 'a {
    (block.offset..block.offset + block.len)
        .filter(|&c| (0..primal.output.1).any(|r| primal.depends_on(r, c)))
}

/// `jac_f`: each wanted block column by column.
fn jacobian<M: Model>(primal: &Primal, z: &[f64], outputs: &mut Outputs) -> Result<(), Failure> {
    let mut column = M::array(0.0f64);
    for (k, block) in primal.inputs.iter().enumerate() {
        if !outputs.wanted(k) {
            continue;
        }
        let pattern = &outputs.f.outputs[k].0.pattern;
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

/// `adj1_f`: (∂out/∂block)ᵀ λ for each wanted block.
fn adjoint<M: Model>(
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

/// `jac_adj1_f`: the wanted second-derivative blocks, each unordered pair of directions
/// computed once and written wherever it is wanted (H is symmetric), and the transposed
/// Jacobian blocks.
fn adjoint_jacobian<M: Model>(
    primal: &Primal,
    z: &[f64],
    weights: &[f64],
    outputs: &mut Outputs,
) -> Result<(), Failure> {
    let f = outputs.f;
    // At most four blocks: x, u, p, t.
    let mut wanted_second = [[false; 4]; 4];
    let mut column = M::array(0.0f64);
    for k in 0..f.outputs.len() {
        match f.outputs[k].1 {
            Content::Second(i, j) if outputs.wanted(k) => {
                wanted_second[i][j] = true;
                outputs.get(k)?.unwrap_or_default().fill(0.0);
            }
            Content::Transposed(i) if outputs.wanted(k) => {
                let block = &primal.inputs[i];
                let pattern = &f.outputs[k].0.pattern;
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
            write_second(
                f,
                outputs,
                (i, a - blocks[i].offset),
                (j, b - blocks[j].offset),
                h,
            )?;
            if a != b {
                write_second(
                    f,
                    outputs,
                    (j, b - blocks[j].offset),
                    (i, a - blocks[i].offset),
                    h,
                )?;
            }
        }
    }
    Ok(())
}

/// Write H(a, b) into the wanted block (i, j) holding it, at row a, column b.
fn write_second(
    f: &Function,
    outputs: &mut Outputs,
    (i, a): (usize, usize),
    (j, b): (usize, usize),
    value: f64,
) -> Result<(), Failure> {
    let Some(k) = f
        .outputs
        .iter()
        .position(|(_, content)| *content == Content::Second(i, j))
    else {
        return Ok(());
    };
    let pattern = &f.outputs[k].0.pattern;
    if let (Some(slot), Some(values)) = (pattern.position(a, b), outputs.get(k)?) {
        values[slot] = value;
    }
    Ok(())
}
