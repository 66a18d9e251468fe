//! The sparsity of each derivative block and where the compiled code's entries go.
//!
//! The compiled code of a function (feature `compiled`) writes its derivatives' entries that
//! are not a constant zero on the model's graph, over its own columns (x, u, the parameters
//! it reads, t), in two stages: by x, u and t, and by the parameters. A block whose stage is
//! compiled has exactly those entries as its sparsity; any other block has the entries the
//! dependency tables allow (a superset), computed by dual numbers. [`Structure`] gives each
//! block's pattern; [`Plans`] checks that the compiled code's places of its entries
//! ([`crate::layout`], computed when the library compiled) are those of the patterns, and
//! says which outputs the compiled code fills.

use super::sparsity::Pattern;
use super::{Content, Function, Kind};
use crate::layout::{DISCARD, Destinations, Slot};
use crate::model::{Model, Tables, local_columns};
use crate::primal::Primal;
use core::mem::MaybeUninit;
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

/// Which outputs of `jac_f` or `jac_adj1_f` the compiled code fills, each straight into
/// CasADi's array through [`Destinations`].
#[derive(Clone, Debug, Default)]
pub struct Direct {
    /// For each output: `Some(parameters)` if the compiled code fills it (in the stage by p
    /// if `parameters`); `None` if not (it has no compiled stage, or the layout disagreed
    /// with a pattern: then no output is filled so).
    pub outputs: Vec<Option<bool>>,
    /// Whether every output with nonzeros is filled by the compiled code.
    pub all: bool,
    /// Whether the layout agrees with the patterns: if not, no call of the compiled code.
    agree: bool,
    /// The outputs of the stage by p.
    pub by_parameters: Vec<usize>,
    /// The outputs the compiled code fills that have nonzeros (the only ones a call gives
    /// their array: the others get nothing).
    filled: Vec<usize>,
}

impl Direct {
    /// `expected`: for each entry the compiled code puts (its index in the layout's table),
    /// its places as the patterns give them (`None`: an entry this function never puts);
    /// `layout` the places the library was compiled with; `stage` for each output, its
    /// stage if compiled; `nnz` each output's nonzeros; `scratch` the scratch buffer's
    /// length. Any disagreement, and no output is filled by the compiled code (a place
    /// could be beyond its output).
    fn new(
        expected: &[(usize, Option<[Slot; 2]>)],
        layout: &[[Slot; 2]],
        stage: &[Option<bool>],
        nnz: &[usize],
        scratch: usize,
    ) -> Direct {
        let mut filled = vec![0usize; nnz.len()];
        let mut seen = vec![false; layout.len()];
        let mut agree = true;
        for &(e, places) in expected {
            match seen.get_mut(e) {
                Some(seen) if !*seen => *seen = true,
                _ => agree = false,
            }
            let Some(places) = places else {
                continue;
            };
            agree &= layout.get(e) == Some(&places);
            for (output, _) in places {
                if let Some(f) = filled.get_mut(output) {
                    *f += 1;
                }
            }
        }
        // An entry the patterns have no place for goes nowhere; an output the code writes
        // fits the scratch buffer (where it goes when CasADi does not ask for it).
        agree &= layout
            .iter()
            .zip(&seen)
            .all(|(places, &seen)| seen || places.iter().all(|p| p.0 == DISCARD));
        agree &=
            (0..nnz.len()).all(|k| filled[k] <= nnz[k] && (filled[k] == 0 || nnz[k] <= scratch));
        let outputs: Vec<Option<bool>> = (0..nnz.len())
            .map(|k| match stage[k] {
                _ if !agree => None,
                _ if nnz[k] == 0 => Some(false),
                Some(parameters) if filled[k] == nnz[k] => Some(parameters),
                _ => None,
            })
            .collect();
        Direct {
            agree,
            filled: (0..outputs.len().min(DISCARD))
                .filter(|&k| outputs[k].is_some() && nnz[k] > 0)
                .collect(),
            all: outputs.iter().all(Option::is_some),
            by_parameters: (0..outputs.len())
                .filter(|&k| outputs[k] == Some(true) && nnz[k] > 0)
                .collect(),
            outputs,
        }
    }

    /// Whether the compiled layout agrees with the outputs' patterns (when not, the
    /// compiled code is never called for this function).
    pub fn agrees(&self) -> bool {
        self.agree
    }

    /// For the wanted outputs (`wanted(k)`): whether each is filled by the compiled code
    /// (`None` if one is not), and whether one is of the stage by p.
    #[inline(always)]
    pub fn stages(&self, wanted: impl Fn(usize) -> bool) -> Option<bool> {
        if !self.agree {
            return None;
        }
        if self.all {
            return Some(self.by_parameters.iter().any(|&k| wanted(k)));
        }
        let mut parameters = false;
        for (k, stage) in self.outputs.iter().enumerate() {
            if wanted(k) {
                parameters |= (*stage)?;
            }
        }
        Some(parameters)
    }

    /// The destinations of a call: output k's array if `wanted(k)` gives it and the compiled
    /// code fills it, else `scratch`.
    #[inline(always)]
    pub fn destinations(
        &self,
        to: &mut Destinations,
        given: impl Fn(usize) -> *mut f64,
        scratch: &mut [MaybeUninit<f64>],
    ) {
        // Filled in place (returned, the array was copied: a `memcpy` a call).
        let scratch = scratch.as_mut_ptr().cast::<f64>();
        fill(to, scratch);
        for &k in &self.filled {
            let out = given(k);
            if !out.is_null() {
                if let Some(to) = to.get_mut(k) {
                    *to = out;
                }
            }
        }
    }
}

/// Every destination `to`: two a store with SSE2 on x86-64 (the exported crate's opt-level
/// 2 stores them one by one), a dozen instructions fewer in every call of `jac_f` and
/// `jac_adj1_f`.
#[inline(always)]
fn fill(destinations: &mut Destinations, to: *mut f64) {
    #[cfg(target_arch = "x86_64")]
    {
        use core::arch::x86_64::{__m128i, _mm_set1_epi64x, _mm_storeu_si128};
        // SAFETY: SSE2 is part of x86-64; a pointer is 64 bits there.
        let pair = unsafe { _mm_set1_epi64x(to as i64) };
        let mut pairs = destinations.chunks_exact_mut(2);
        for two in &mut pairs {
            // SAFETY: SSE2 as above; an unaligned store of two pointers, both in the array.
            unsafe { _mm_storeu_si128(two.as_mut_ptr().cast::<__m128i>(), pair) };
        }
        for one in pairs.into_remainder() {
            *one = to;
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    destinations.fill(to);
}

/// For `jac_f` and `jac_adj1_f`, the outputs the compiled code fills; for `adj1_f`, where
/// each block's components are among the compiled code's columns.
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
    pub jacobian: Direct,
    pub second: Direct,
    /// For each input block, (column, component of the block).
    pub adjoint: Vec<Vec<(usize, usize)>>,
    /// `fwd<N>_f`'s products of the Jacobian with the directions.
    pub products: Products,
    /// Whether `fwd<N>_f`'s products can be fused into the compiled Jacobian
    /// ([`crate::model::Model::products_of`], the right-hand side's): its stage by x, u and
    /// t is compiled, and each of its entries lies within the outputs and the compiled
    /// code's columns (the rows the fused products read and write).
    pub fused: bool,
    /// Where each of `jac_f`'s outputs starts in one array holding them all (for the
    /// products), and the end of the last.
    pub offsets: Vec<usize>,
    pub end: usize,
}

/// A Jacobian entry as a term of forward derivatives: derivative[row] += J[entry] ·
/// direction[column] (a component of z), for every direction at once.
#[derive(Clone, Copy, Debug)]
struct Term {
    entry: u32,
    row: u32,
    column: u32,
}

/// `fwd<N>_f` as products of the compiled Jacobian (`jac_f`'s outputs one after the other,
/// [`Plans::offsets`]) with the directions: its entries by x, u and t, then those by p.
#[derive(Clone, Debug, Default)]
pub struct Products {
    terms: Vec<Term>,
    /// How many of `terms` are by x, u and t.
    states: usize,
    /// Whether the compiled code fills every block by x, u and t, and every block by p (else
    /// no products of those).
    compiled: [bool; 2],
    /// The lengths the terms need: of the Jacobian's array, the derivatives and the
    /// directions (one more than the largest entry, row and column); those by x, u and t,
    /// then all of them.
    needs: [[usize; 3]; 2],
}

impl Products {
    fn new(primal: &Primal, function: &Function, direct: &Direct, offsets: &[usize]) -> Products {
        // Indices of arrays the size of a model's derivatives: far below u32::MAX.
        let narrow = |v: usize| u32::try_from(v).ok();
        let terms = |parameters: bool| -> Vec<Term> {
            let mut terms = Vec::new();
            for (k, (port, content)) in function.outputs.iter().enumerate() {
                let Content::Jacobian(i) = *content else {
                    continue;
                };
                if direct.outputs.get(k) != Some(&Some(parameters)) {
                    continue;
                }
                let (block, pattern) = (&primal.inputs[i], &port.pattern);
                for c in 0..pattern.ncol {
                    for slot in pattern.column(c) {
                        let term = Term {
                            entry: narrow(offsets[k] + slot).unwrap_or(u32::MAX),
                            row: narrow(pattern.row(slot)).unwrap_or(u32::MAX),
                            column: narrow(block.offset + c).unwrap_or(u32::MAX),
                        };
                        terms.push(term);
                    }
                }
            }
            terms
        };
        let mut all = terms(false);
        let states = all.len();
        all.extend(terms(true));
        let needs = [&all[..states], &all[..]].map(|terms| {
            let most = |pick: fn(&Term) -> u32| {
                terms
                    .iter()
                    .map(|t| pick(t) as usize + 1)
                    .max()
                    .unwrap_or(0)
            };
            [most(|t| t.entry), most(|t| t.row), most(|t| t.column)]
        });
        let compiled = [false, true].map(|parameters| {
            direct.agree
                && function.outputs.iter().enumerate().all(|(k, (port, c))| {
                    !matches!(c, Content::Jacobian(i) if is_parameters(primal, *i) == parameters)
                        || port.pattern.nnz() == 0
                        || direct.outputs.get(k) == Some(&Some(parameters))
                })
        });
        Products {
            terms: all,
            states,
            compiled,
            needs,
        }
    }

    /// How many components of the directions the products by x, u and t (and by p, if
    /// `parameters`) read: those a call must give.
    #[inline(always)]
    pub fn columns(&self, parameters: bool) -> usize {
        self.needs[usize::from(parameters)][2]
    }

    /// Whether the products by x, u and t (and by p, if `parameters`) are compiled: else the
    /// compiled Jacobian must not be called for them.
    #[inline(always)]
    pub fn compiled(&self, parameters: bool) -> bool {
        self.compiled[0] && (!parameters || self.compiled[1])
    }

    /// derivatives += J · directions, `N` directions at once (each component of z holds its
    /// `N` values side by side); by p only if `parameters`. `false` (having added nothing)
    /// if an array is shorter than the terms need, or those products are not compiled.
    ///
    /// # Safety
    /// Every entry of `jacobian` a term reads (those by p only if `parameters`) is
    /// initialized: the compiled code filled `jac_f`'s outputs into it (at
    /// [`Plans::offsets`]).
    #[inline(always)]
    pub unsafe fn add<const N: usize>(
        &self,
        parameters: bool,
        jacobian: &[MaybeUninit<f64>],
        directions: &[[f64; N]],
        derivatives: &mut [[f64; N]],
    ) -> bool {
        let [entries, rows, columns] = self.needs[usize::from(parameters)];
        if jacobian.len() < entries
            || derivatives.len() < rows
            || directions.len() < columns
            || !self.compiled(parameters)
        {
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
            // that long (checked above); the entry is initialized (the contract).
            let (entry, direction, derivative) = unsafe {
                (
                    jacobian.get_unchecked(term.entry as usize).assume_init(),
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
#[doc(hidden)]
#[inline(always)]
pub fn add_scaled<const N: usize>(a: f64, x: &[f64; N], y: &mut [f64; N]) {
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
    pub fn new(
        primal: &Primal,
        structure: &Structure,
        functions: &[Function; 8],
        scratch: usize,
    ) -> Option<Plans> {
        let (tables, local) = structure.compiled.as_ref()?;
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
        let jacobian_function = &functions[Kind::Jacobian as usize];
        let jacobian = jacobian_direct(primal, structure, tables, jacobian_function, scratch);
        let second = second_direct(
            primal,
            structure,
            tables,
            &functions[Kind::AdjointJacobian as usize],
            scratch,
        );
        let mut offsets = Vec::new();
        let mut end = 0;
        for (port, _) in &jacobian_function.outputs {
            offsets.push(end);
            end += port.pattern.nnz();
        }
        // The products' array is a scratch buffer (with one more value, where the entries
        // that go nowhere are put): without room, no compiled products.
        let products = if end < scratch {
            Products::new(primal, jacobian_function, &jacobian, &offsets)
        } else {
            Products::default()
        };
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
        let fused = primal.which == crate::primal::Which::Rhs
            && tables.compiled[0]
            && tables.jacobian[..tables.states[0].min(tables.jacobian.len())]
                .iter()
                .all(|&(r, c)| r < primal.output.1 && c < local.len());
        Some(Plans {
            fused,
            local: local.clone(),
            runs,
            parameters: first..last,
            jacobian,
            second,
            adjoint,
            products,
            offsets,
            end,
        })
    }
}

impl Plans {
    /// The destinations of `jac_f`'s outputs one after the other from `base` (at
    /// [`Plans::offsets`]), and of the entries that go nowhere just after them.
    ///
    /// # Safety
    /// `base` points to a buffer longer than [`Plans::end`] (the scratch buffer, when the
    /// products are compiled).
    #[inline(always)]
    pub unsafe fn stacked(&self, base: *mut f64) -> Destinations {
        // SAFETY: within the buffer (the contract).
        let mut to = [unsafe { base.add(self.end) }; DISCARD + 1];
        for (k, &offset) in self.offsets.iter().enumerate().take(DISCARD) {
            // SAFETY: as above.
            to[k] = unsafe { base.add(offset) };
        }
        to
    }
}

/// Each output's stage if compiled (`stage(i)` for its content) and its nonzeros.
fn outputs(
    function: &Function,
    stage: impl Fn(&Content) -> Option<bool>,
) -> (Vec<Option<bool>>, Vec<usize>) {
    let nnz: Vec<usize> = function
        .outputs
        .iter()
        .map(|(p, _)| p.pattern.nnz())
        .collect();
    let stages = function
        .outputs
        .iter()
        .zip(&nnz)
        .map(|((_, content), _)| stage(content))
        .collect();
    (stages, nnz)
}

/// `jac_f`'s outputs the compiled code fills: entry e, (row r, column of block k at w),
/// goes to output k at the pattern's place of (r, w).
fn jacobian_direct(
    primal: &Primal,
    structure: &Structure,
    tables: &Tables,
    function: &Function,
    scratch: usize,
) -> Direct {
    let (stage, nnz) = outputs(function, |content| match *content {
        Content::Jacobian(i) => {
            let parameters = is_parameters(primal, i);
            structure.stage(0, parameters).map(|_| parameters)
        }
        _ => None,
    });
    let mut expected = Vec::new();
    for parameters in [false, true] {
        for (e, r, k, w) in structure
            .jacobian_entries(primal, parameters)
            .unwrap_or_default()
        {
            let place = function.outputs[k].0.pattern.position(r, w);
            let place = place.map_or((usize::MAX, 0), |s| (k, s));
            expected.push((e, Some([place, (DISCARD, 0)])));
        }
    }
    let layout: Vec<[Slot; 2]> = tables
        .layout
        .jacobian
        .iter()
        .map(|&s| [s, (DISCARD, 0)])
        .collect();
    Direct::new(&expected, &layout, &stage, &nnz, scratch)
}

/// `jac_adj1_f`'s outputs the compiled code fills: the second derivatives' entry e, (a, b),
/// goes to block (a's, b's) at (a, b) and, off the diagonal, to block (b's, a's) at (b, a);
/// the Jacobian's entry e to the transposed block of its column's.
fn second_direct(
    primal: &Primal,
    structure: &Structure,
    tables: &Tables,
    function: &Function,
    scratch: usize,
) -> Direct {
    let nb = primal.inputs.len();
    let output = |i: usize, j: usize| i * (nb + 2) + j;
    let (stage, nnz) = outputs(function, |content| match *content {
        Content::Second(i, j) => {
            let parameters = is_parameters(primal, i) || is_parameters(primal, j);
            structure.stage(1, parameters).map(|_| parameters)
        }
        // The second derivatives' stage computes the Jacobian too.
        Content::Transposed(i) => {
            let parameters = is_parameters(primal, i);
            structure.stage(1, parameters)?;
            structure.stage(0, parameters).map(|_| parameters)
        }
        _ => None,
    });
    let place = |o: usize, a: usize, b: usize| -> Slot {
        let position = function
            .outputs
            .get(o)
            .and_then(|p| p.0.pattern.position(a, b));
        position.map_or((usize::MAX, 0), |s| (o, s))
    };
    let mut expected: Vec<(usize, Option<[Slot; 2]>)> = Vec::new();
    for parameters in [false, true] {
        for (e, ka, wa, kb, wb) in structure
            .second_entries(primal, parameters)
            .unwrap_or_default()
        {
            let here = place(output(ka, kb), wa, wb);
            // `second_entries` lists the mirror of an entry right after it.
            match expected.last_mut() {
                Some((last, Some(places))) if *last == e && places[1].0 == DISCARD => {
                    places[1] = here;
                }
                _ => expected.push((e, Some([here, (DISCARD, 0)]))),
            }
        }
    }
    // The Jacobian's entries, which the code puts with the second derivatives' stage.
    let nh = tables.second.len();
    for parameters in [false, true] {
        let put = structure.stage(1, parameters).is_some();
        for (e, r, k, w) in structure
            .jacobian_entries(primal, parameters)
            .unwrap_or_default()
        {
            let places = put.then(|| [place(output(k, nb + 1), w, r), (DISCARD, 0)]);
            expected.push((nh + e, places));
        }
    }
    let mut layout: Vec<[Slot; 2]> = tables.layout.second.to_vec();
    layout.extend(tables.layout.transposed.iter().map(|&s| [s, (DISCARD, 0)]));
    Direct::new(&expected, &layout, &stage, &nnz, scratch)
}
