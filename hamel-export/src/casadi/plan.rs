//! The sparsity of each derivative block and where the compiled code's entries go.
//!
//! The compiled code of a function (feature `compiled`) writes its derivatives' entries that
//! are not a constant zero on the model's graph, over its own columns (x, u, the parameters
//! it reads, t), in two stages: by x, u and t, and by the parameters. A block whose stage is
//! compiled has exactly those entries as its sparsity; any other block has the entries the
//! dependency tables allow (a superset), computed by dual numbers. [`Structure`] gives each
//! block's pattern, [`Plans`] the copy from the compiled arrays into CasADi's outputs.

use super::sparsity::Pattern;
use super::{Content, Function, Kind};
use crate::model::{Model, Tables, local_columns};
use crate::primal::Primal;
use std::collections::HashSet;

/// A compiled second derivative's entry placed in the blocks: (index in the compiled array,
/// block of the row, row within it, block of the column, column within it).
type SecondEntry = (usize, usize, usize, usize, usize);

/// The compiled code's tables with its columns, or nothing.
#[derive(Clone, Debug)]
pub struct Structure {
    compiled: Option<(Tables, Vec<usize>)>,
}

/// Whether the input block `i` is the parameters (the second stage).
fn is_parameters(primal: &Primal, i: usize) -> bool {
    primal.inputs.get(i).is_some_and(|b| b.name == "p")
}

/// The input block holding z's component `z`, and where in it.
fn block_of(primal: &Primal, z: usize) -> Option<(usize, usize)> {
    primal
        .inputs
        .iter()
        .enumerate()
        .find(|(_, b)| (b.offset..b.offset + b.len).contains(&z))
        .map(|(k, b)| (k, z - b.offset))
}

impl Structure {
    pub fn new<M: Model>(primal: &Primal) -> Structure {
        Structure {
            compiled: M::tables(primal.which).map(|t| (t, local_columns::<M>())),
        }
    }

    /// The compiled code's tables and columns, if the stage (by the parameters or not) of
    /// table `which` (0: the Jacobian, 1: the second derivatives) is compiled.
    fn stage(&self, which: usize, parameters: bool) -> Option<(&Tables, &[usize])> {
        let (tables, local) = self.compiled.as_ref()?;
        tables.compiled[2 * which + usize::from(parameters)].then_some((tables, local.as_slice()))
    }

    /// The Jacobian's entries of a stage, with their indices: (index, row, block, within).
    fn jacobian_entries(
        &self,
        primal: &Primal,
        parameters: bool,
    ) -> Option<Vec<(usize, usize, usize, usize)>> {
        let (tables, local) = self.stage(0, parameters)?;
        let range = if parameters {
            tables.states[0]..tables.jacobian.len()
        } else {
            0..tables.states[0]
        };
        Some(
            range
                .filter_map(|e| {
                    let (r, c) = tables.jacobian[e];
                    let (k, w) = block_of(primal, *local.get(c)?)?;
                    Some((e, r, k, w))
                })
                .collect(),
        )
    }

    /// The second derivatives' entries of a stage, each in both orientations: (index, block
    /// of the row, within, block of the column, within).
    fn second_entries(&self, primal: &Primal, parameters: bool) -> Option<Vec<SecondEntry>> {
        let (tables, local) = self.stage(1, parameters)?;
        let range = if parameters {
            tables.states[1]..tables.second.len()
        } else {
            0..tables.states[1]
        };
        let mut all = Vec::new();
        for e in range {
            let (a, b) = tables.second[e];
            let (Some(&za), Some(&zb)) = (local.get(a), local.get(b)) else {
                continue;
            };
            let (Some((ka, wa)), Some((kb, wb))) = (block_of(primal, za), block_of(primal, zb))
            else {
                continue;
            };
            all.push((e, ka, wa, kb, wb));
            if a != b {
                all.push((e, kb, wb, ka, wa));
            }
        }
        Some(all)
    }

    /// The pattern of ∂out/∂(block i).
    pub fn jacobian(&self, primal: &Primal, i: usize) -> Pattern {
        let (no, b) = (primal.output.1, &primal.inputs[i]);
        match self.jacobian_entries(primal, is_parameters(primal, i)) {
            Some(entries) => {
                let set: HashSet<(usize, usize)> = entries
                    .iter()
                    .filter(|e| e.2 == i)
                    .map(|e| (e.1, e.3))
                    .collect();
                Pattern::new(no, b.len, |r, c| set.contains(&(r, c)))
            }
            None => Pattern::new(no, b.len, |r, c| primal.depends_on(r, b.offset + c)),
        }
    }

    /// The pattern of Σ λ_r ∂²out_r/∂(block i)∂(block j).
    pub fn second(&self, primal: &Primal, i: usize, j: usize) -> Pattern {
        let (bi, bj) = (&primal.inputs[i], &primal.inputs[j]);
        let parameters = is_parameters(primal, i) || is_parameters(primal, j);
        match self.second_entries(primal, parameters) {
            Some(entries) => {
                let set: HashSet<(usize, usize)> = entries
                    .iter()
                    .filter(|e| e.1 == i && e.3 == j)
                    .map(|e| (e.2, e.4))
                    .collect();
                Pattern::new(bi.len, bj.len, |a, b| set.contains(&(a, b)))
            }
            None => Pattern::new(bi.len, bj.len, |a, b| {
                primal.pair(bi.offset + a, bj.offset + b)
            }),
        }
    }
}

/// Where one output's nonzeros come from: pairs (entry of one compiled array, slot of the
/// output), or the whole output copied from a range of entries.
#[derive(Clone, Debug, Default)]
pub struct Scatter {
    /// The output is filled by the compiled code (its stage is compiled).
    pub compiled: bool,
    /// Whether it is of the parameters' stage.
    pub parameters: bool,
    /// Whether the entries are the second derivatives' (a block of `jac_adj1_f` by two
    /// inputs), not the Jacobian's: an output takes them from one array only.
    from_second: bool,
    /// (entry, slot) pairs.
    pairs: Vec<(u32, u32)>,
    /// The output is the array's entries `start..start + nnz` in order (a plain copy).
    copy: Option<usize>,
    /// The lengths the pairs need: of the array and of the output (one more than the
    /// largest index of each).
    needs: [usize; 2],
    /// Whether the pairs write every slot of the output (then it needs no zeros first).
    covers: bool,
    /// The output's nonzeros (its port's pattern's; set by [`Plans::new`]).
    pub len: usize,
}

impl Scatter {
    /// A scatter of the compiled code's entries (of the second derivatives' array or the
    /// Jacobian's), or of none (`Scatter::uncompiled`).
    fn new(
        parameters: bool,
        from_second: bool,
        pairs: Vec<(usize, usize)>,
        copy: Option<usize>,
    ) -> Scatter {
        let most = |pick: fn(&(usize, usize)) -> usize| {
            pairs.iter().map(|p| pick(p) + 1).max().unwrap_or(0)
        };
        let needs = [most(|p| p.0), most(|p| p.1)];
        let mut slots: Vec<usize> = pairs.iter().map(|p| p.1).collect();
        slots.sort_unstable();
        slots.dedup();
        let covers = slots.iter().enumerate().all(|(k, &slot)| k == slot);
        // Indices of arrays the size of a model's derivatives: far below u32::MAX.
        let pairs = pairs
            .into_iter()
            .filter_map(|(e, s)| Some((u32::try_from(e).ok()?, u32::try_from(s).ok()?)))
            .collect();
        Scatter {
            compiled: true,
            parameters,
            from_second,
            pairs,
            copy,
            needs,
            covers: covers && slots.len() == needs[1],
            len: 0,
        }
    }

    /// The scatter of an output with `len` nonzeros.
    fn of_len(self, len: usize) -> Scatter {
        Scatter { len, ..self }
    }

    /// An output the compiled code does not fill (computed by dual numbers).
    fn uncompiled(parameters: bool) -> Scatter {
        Scatter {
            parameters,
            ..Scatter::default()
        }
    }

    /// Write the output's nonzeros from the compiled arrays.
    #[inline]
    pub fn write(&self, out: &mut [f64], second: &[f64], jacobian: &[f64]) {
        let from = if self.from_second { second } else { jacobian };
        if let Some(start) = self.copy {
            if let Some(from) = from.get(start..start + out.len()) {
                out.copy_from_slice(from);
                return;
            }
        }
        let [entries, slots] = self.needs;
        if !(self.covers && out.len() == slots) {
            out.fill(0.0);
        }
        // The lengths checked once for every pair (not pair by pair: this copy runs on every
        // call of `jac_adj1_f`, hundreds of entries, and cost as much as computing them).
        if from.len() >= entries && out.len() >= slots {
            // SAFETY: `needs` exceeds every pair's entry and slot (`Scatter::new` computed it
            // from these pairs, which nothing changes after), and the slices are that long.
            unsafe { gather(out, from, &self.pairs) };
        }
    }
}

/// out[slot] = from[entry] for each pair.
///
/// # Safety
/// Every pair's entry is below `from.len()` and its slot below `out.len()` (what
/// `Scatter::needs` records of its own pairs, checked by `Scatter::write`).
#[inline(always)]
unsafe fn gather(out: &mut [f64], from: &[f64], pairs: &[(u32, u32)]) {
    for &(e, slot) in pairs {
        // SAFETY: within both slices (this function's contract).
        unsafe { *out.get_unchecked_mut(slot as usize) = *from.get_unchecked(e as usize) };
    }
}

/// One output of a [`Placement`].
#[derive(Clone, Debug)]
struct Placed {
    /// Its index among the function's outputs.
    output: usize,
    /// Whether the compiled code gives it, and whether it is of the parameters' stage.
    compiled: bool,
    parameters: bool,
    /// Whether its entries are the second derivatives' (else the Jacobian's).
    from_second: bool,
    /// The output is `from[start..start + len]` (a plain copy).
    copy: Option<usize>,
    /// Zeros first: the pairs do not write every slot.
    zero: bool,
    /// Its pairs among [`Placement::pairs`].
    pairs: std::ops::Range<usize>,
    /// Its nonzeros.
    len: usize,
}

/// The outputs of `jac_f` or `jac_adj1_f` that have nonzeros, with every entry's slot in one
/// flat list: what a call of the fast path writes, the arrays' lengths checked once for the
/// whole call. `jac_adj1_f` places hundreds of entries into a dozen outputs (259 into 11 for
/// the paper's robot); checked output by output, as [`Scatter::write`] does for the general
/// path, the bookkeeping cost a third as much as the copies.
#[derive(Clone, Debug, Default)]
pub struct Placement {
    outputs: Vec<Placed>,
    pairs: Vec<(u32, u32)>,
    /// The lengths the compiled arrays need: the second derivatives', the Jacobian's (one
    /// more than the largest entry a pair or a copy reads).
    needs: [usize; 2],
    /// Whether every output is compiled, and those of the parameters' stage.
    compiled: bool,
    by_parameters: Vec<usize>,
}

impl Placement {
    /// The placement of the outputs with nonzeros among `scatters`.
    fn new(scatters: &[Scatter]) -> Placement {
        let mut placement = Placement {
            compiled: true,
            ..Placement::default()
        };
        for (output, scatter) in scatters.iter().enumerate().filter(|(_, s)| s.len > 0) {
            let which = usize::from(!scatter.from_second);
            // A pair beyond the output (which `Scatter::write` would skip) is not placed: the
            // output is then left to the general path.
            let compiled = scatter.compiled && scatter.needs[1] <= scatter.len;
            let copy = scatter.copy.filter(|_| compiled);
            let need = match copy {
                Some(start) => start + scatter.len,
                None => scatter.needs[0],
            };
            if compiled {
                placement.needs[which] = placement.needs[which].max(need);
            }
            let start = placement.pairs.len();
            if compiled && copy.is_none() {
                placement.pairs.extend(&scatter.pairs);
            }
            placement.compiled &= compiled;
            if scatter.parameters {
                placement.by_parameters.push(output);
            }
            placement.outputs.push(Placed {
                output,
                compiled,
                parameters: scatter.parameters,
                from_second: scatter.from_second,
                copy,
                zero: !(scatter.covers && scatter.len == scatter.needs[1]),
                pairs: start..placement.pairs.len(),
                len: scatter.len,
            });
        }
        placement
    }

    /// Whether one of the wanted outputs is by p (the compiled code's second stage); `None`
    /// if the compiled code does not give one of them.
    ///
    /// # Safety
    /// `res` is CasADi's non-null array of this function's outputs (a pointer per output).
    #[inline(always)]
    pub unsafe fn stages(&self, res: *const *mut f64) -> Option<bool> {
        // SAFETY: a pointer per output (this function's contract).
        let wanted = |k: usize| !unsafe { *res.add(k) }.is_null();
        if self.compiled {
            return Some(self.by_parameters.iter().any(|&k| wanted(k)));
        }
        let mut parameters = false;
        for placed in &self.outputs {
            if wanted(placed.output) {
                if !placed.compiled {
                    return None;
                }
                parameters |= placed.parameters;
            }
        }
        Some(parameters)
    }

    /// Every wanted output from the compiled arrays; `false` (having written nothing) if an
    /// array is shorter than the entries need.
    ///
    /// # Safety
    /// `res` is CasADi's non-null array of this function's outputs, each null or pointing to
    /// its port's nonzeros, writable, and every wanted output is compiled
    /// ([`Placement::stages`] said so).
    #[inline(always)]
    pub unsafe fn write(&self, res: *const *mut f64, second: &[f64], jacobian: &[f64]) -> bool {
        if second.len() < self.needs[0] || jacobian.len() < self.needs[1] {
            return false;
        }
        for placed in &self.outputs {
            // SAFETY: a pointer per output (the contract).
            let out = unsafe { *res.add(placed.output) };
            if out.is_null() || !placed.compiled {
                continue;
            }
            let from = if placed.from_second { second } else { jacobian };
            // SAFETY (the copy, the zeros and the pairs): a wanted output has `placed.len`
            // writable values (the contract); a compiled output's pairs write below its
            // `needs[1]` ≤ `len` and read below its `needs[0]`, and a copy reads
            // `start..start + len`, all within `self.needs`, which the arrays reach (checked
            // above).
            unsafe {
                if let Some(start) = placed.copy {
                    core::ptr::copy_nonoverlapping(from.as_ptr().add(start), out, placed.len);
                    continue;
                }
                if placed.zero {
                    core::ptr::write_bytes(out, 0, placed.len);
                }
                place(out, from, self.pairs.get_unchecked(placed.pairs.clone()));
            }
        }
        true
    }
}

/// out[slot] = from[entry] for each pair, four pairs a step: the exported crate's
/// opt-level 2 does not unroll this loop through a raw pointer, and unrolled it takes about 5
/// instructions a pair instead of 7.
///
/// # Safety
/// Every pair's entry is below `from.len()` and its slot within the writable values at `out`.
#[inline(always)]
unsafe fn place(out: *mut f64, from: &[f64], pairs: &[(u32, u32)]) {
    let mut fours = pairs.chunks_exact(4);
    for four in &mut fours {
        for &(e, slot) in four {
            // SAFETY: within both (this function's contract).
            unsafe { *out.add(slot as usize) = *from.get_unchecked(e as usize) };
        }
    }
    for &(e, slot) in fours.remainder() {
        // SAFETY: as above.
        unsafe { *out.add(slot as usize) = *from.get_unchecked(e as usize) };
    }
}

/// For `jac_f` and `jac_adj1_f`, each output's [`Scatter`]; for `adj1_f`, where each
/// block's components are among the compiled code's columns.
#[derive(Clone, Debug)]
pub struct Plans {
    /// The compiled code's columns as indices into z.
    pub local: Vec<usize>,
    /// The same columns as runs of consecutive components of one input block: (block, first
    /// component, first column, length). A column in no block (the time of a model that
    /// does not depend on it) is in no run.
    pub runs: Vec<(usize, usize, usize, usize)>,
    /// Which of them are parameters.
    pub parameters: std::ops::Range<usize>,
    pub jacobian: Vec<Scatter>,
    pub second: Vec<Scatter>,
    /// The outputs of `jac_f` and of `jac_adj1_f` that have nonzeros (the only ones a call
    /// looks at: the others, such as the blocks by the nominal output, have nothing to
    /// write) as one flat list each, for the fast path (`super::fast`).
    pub jacobian_placement: Placement,
    pub second_placement: Placement,
    /// For each input block, (column, component of the block).
    pub adjoint: Vec<Vec<(usize, usize)>>,
    /// `fwd<N>_f`'s products of the Jacobian with the directions.
    pub products: Products,
}

/// A Jacobian entry as a term of forward derivatives: derivative[row] += J[entry] ·
/// direction[column] (a component of z), for every direction at once.
#[derive(Clone, Copy, Debug)]
struct Term {
    entry: u32,
    row: u32,
    column: u32,
}

/// `fwd<N>_f` as products of the compiled Jacobian with the directions: its entries by x, u
/// and t, then those by p.
#[derive(Clone, Debug, Default)]
pub struct Products {
    terms: Vec<Term>,
    /// How many of `terms` are by x, u and t.
    states: usize,
    /// The lengths the terms need: of the Jacobian's array, the derivatives and the
    /// directions (one more than the largest entry, row and column).
    needs: [usize; 3],
}

impl Products {
    fn new(primal: &Primal, structure: &Structure) -> Products {
        // Indices of arrays the size of a model's derivatives: far below u32::MAX.
        let narrow = |v: usize| u32::try_from(v).ok();
        let terms = |parameters: bool| -> Vec<Term> {
            structure
                .jacobian_entries(primal, parameters)
                .unwrap_or_default()
                .into_iter()
                .filter_map(|(e, r, k, w)| {
                    Some(Term {
                        entry: narrow(e)?,
                        row: narrow(r)?,
                        column: narrow(primal.inputs.get(k)?.offset + w)?,
                    })
                })
                .collect()
        };
        let mut all = terms(false);
        let states = all.len();
        all.extend(terms(true));
        let most =
            |pick: fn(&Term) -> u32| all.iter().map(|t| pick(t) as usize + 1).max().unwrap_or(0);
        let needs = [most(|t| t.entry), most(|t| t.row), most(|t| t.column)];
        Products {
            terms: all,
            states,
            needs,
        }
    }

    /// derivatives += J · directions, `N` directions at once (each component of z holds its
    /// `N` values side by side); by p only if `parameters`. `false` (having added nothing)
    /// if an array is shorter than the terms need.
    #[inline(always)]
    pub fn add<const N: usize>(
        &self,
        parameters: bool,
        jacobian: &[f64],
        directions: &[[f64; N]],
        derivatives: &mut [[f64; N]],
    ) -> bool {
        let [entries, rows, columns] = self.needs;
        if jacobian.len() < entries || derivatives.len() < rows || directions.len() < columns {
            return false;
        }
        let terms = if parameters {
            &self.terms[..]
        } else {
            &self.terms[..self.states]
        };
        for term in terms {
            // SAFETY: `needs` exceeds every term's entry, row and column (`Products::new`
            // computed it from these terms, which nothing changes after), and the arrays are
            // that long (checked above).
            let (entry, direction, derivative) = unsafe {
                (
                    *jacobian.get_unchecked(term.entry as usize),
                    directions.get_unchecked(term.column as usize),
                    derivatives.get_unchecked_mut(term.row as usize),
                )
            };
            add_scaled(entry, direction, derivative);
        }
        true
    }
}

/// y += a·x for `N` values, two at a time with SSE2 on x86-64 (which every x86-64 has): the
/// exported crate is built at opt-level 2, without the SLP vectorizer that paired these
/// products at opt-level 3 (`examples/export.rs` says why), and `fwd8_f` spent a third more
/// instructions on them unpaired. The same products and sums as the plain loop, bit for bit.
#[inline(always)]
fn add_scaled<const N: usize>(a: f64, x: &[f64; N], y: &mut [f64; N]) {
    #[cfg(target_arch = "x86_64")]
    if N % 2 == 0 {
        use core::arch::x86_64::{
            _mm_add_pd, _mm_loadu_pd, _mm_mul_pd, _mm_set1_pd, _mm_storeu_pd,
        };
        // SAFETY: SSE2 is part of x86-64.
        let a = unsafe { _mm_set1_pd(a) };
        for k in (0..N).step_by(2) {
            // SAFETY: SSE2 as above; k + 1 < N (N even), so both values of each pair are in
            // the arrays; unaligned loads and stores.
            unsafe {
                let (x, y) = (x.as_ptr().add(k), y.as_mut_ptr().add(k));
                _mm_storeu_pd(
                    y,
                    _mm_add_pd(_mm_loadu_pd(y), _mm_mul_pd(a, _mm_loadu_pd(x))),
                );
            }
        }
        return;
    }
    for d in 0..N {
        y[d] += a * x[d];
    }
}

impl Plans {
    pub fn new(primal: &Primal, structure: &Structure, functions: &[Function; 8]) -> Option<Plans> {
        let (_, local) = structure.compiled.as_ref()?;
        let s = &primal.sizes;
        let first = local
            .iter()
            .position(|&z| z >= s.p())
            .unwrap_or(local.len());
        let last = local
            .iter()
            .position(|&z| z >= s.t())
            .unwrap_or(local.len());
        let adjoint = (0..primal.inputs.len())
            .map(|k| {
                local
                    .iter()
                    .enumerate()
                    .filter_map(|(c, &z)| match block_of(primal, z) {
                        Some((block, w)) if block == k => Some((c, w)),
                        _ => None,
                    })
                    .collect()
            })
            .collect();
        let jacobian: Vec<Scatter> = functions[Kind::Jacobian as usize]
            .outputs
            .iter()
            .map(|(port, content)| match *content {
                Content::Jacobian(i) => {
                    jacobian_scatter(primal, structure, i, |r, w| port.pattern.position(r, w))
                }
                _ => Scatter::default(),
            })
            .zip(&functions[Kind::Jacobian as usize].outputs)
            .map(|(s, (port, _))| s.of_len(port.pattern.nnz()))
            .collect();
        let second: Vec<Scatter> = functions[Kind::AdjointJacobian as usize]
            .outputs
            .iter()
            .map(|(port, content)| match *content {
                Content::Second(i, j) => {
                    let parameters = is_parameters(primal, i) || is_parameters(primal, j);
                    match structure.second_entries(primal, parameters) {
                        Some(entries) => Scatter::new(
                            parameters,
                            true,
                            entries
                                .iter()
                                .filter(|e| e.1 == i && e.3 == j)
                                .filter_map(|e| Some((e.0, port.pattern.position(e.2, e.4)?)))
                                .collect(),
                            None,
                        ),
                        None => Scatter::uncompiled(parameters),
                    }
                }
                Content::Transposed(i) => {
                    let mut s =
                        jacobian_scatter(primal, structure, i, |r, w| port.pattern.position(w, r));
                    s.copy = None;
                    // The second derivatives' stage computes the Jacobian too.
                    s.compiled &= structure.stage(1, s.parameters).is_some();
                    s
                }
                _ => Scatter::default(),
            })
            .zip(&functions[Kind::AdjointJacobian as usize].outputs)
            .map(|(s, (port, _))| s.of_len(port.pattern.nnz()))
            .collect();
        let jacobian_placement = Placement::new(&jacobian);
        let second_placement = Placement::new(&second);
        let mut runs: Vec<(usize, usize, usize, usize)> = Vec::new();
        for (column, &z) in local.iter().enumerate() {
            let Some((block, within)) = block_of(primal, z) else {
                continue;
            };
            match runs.last_mut() {
                Some((b, w, c, len))
                    if *b == block && *w + *len == within && *c + *len == column =>
                {
                    *len += 1
                }
                _ => runs.push((block, within, column, 1)),
            }
        }
        Some(Plans {
            local: local.clone(),
            runs,
            parameters: first..last,
            jacobian,
            second,
            jacobian_placement,
            second_placement,
            adjoint,
            products: Products::new(primal, structure),
        })
    }
}

/// The scatter of the Jacobian's block `i` into an output whose slot of entry (row, within)
/// `slot` gives.
fn jacobian_scatter(
    primal: &Primal,
    structure: &Structure,
    i: usize,
    slot: impl Fn(usize, usize) -> Option<usize>,
) -> Scatter {
    let parameters = is_parameters(primal, i);
    let Some(entries) = structure.jacobian_entries(primal, parameters) else {
        return Scatter::uncompiled(parameters);
    };
    let jacobian: Vec<(usize, usize)> = entries
        .iter()
        .filter(|e| e.2 == i)
        .filter_map(|e| Some((e.0, slot(e.1, e.3)?)))
        .collect();
    // A plain copy when the entries are consecutive and land in slots 0, 1, 2, … in order.
    let copy = jacobian.first().map(|&(start, _)| start).filter(|&start| {
        jacobian
            .iter()
            .enumerate()
            .all(|(k, &(e, s))| e == start + k && s == k)
    });
    Scatter::new(parameters, false, jacobian, copy)
}
