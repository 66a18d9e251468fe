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

/// Where one output's nonzeros come from: pairs (entry of the compiled array, slot of the
/// output), or the whole output copied from a range of entries.
#[derive(Clone, Debug, Default)]
pub struct Scatter {
    /// The output is filled by the compiled code (its stage is compiled).
    pub compiled: bool,
    /// Whether it is of the parameters' stage.
    pub parameters: bool,
    /// From the second derivatives' array.
    pub second: Vec<(usize, usize)>,
    /// From the Jacobian's array.
    pub jacobian: Vec<(usize, usize)>,
    /// The output is `jacobian` entries `start..start + nnz` in order (a plain copy).
    pub copy: Option<usize>,
}

impl Scatter {
    /// Write the output's nonzeros from the compiled arrays.
    #[inline]
    pub fn write(&self, out: &mut [f64], second: &[f64], jacobian: &[f64]) {
        if let Some(start) = self.copy {
            if let Some(from) = jacobian.get(start..start + out.len()) {
                out.copy_from_slice(from);
                return;
            }
        }
        out.fill(0.0);
        for &(e, slot) in &self.second {
            if let (Some(o), Some(v)) = (out.get_mut(slot), second.get(e)) {
                *o = *v;
            }
        }
        for &(e, slot) in &self.jacobian {
            if let (Some(o), Some(v)) = (out.get_mut(slot), jacobian.get(e)) {
                *o = *v;
            }
        }
    }
}

/// For `jac_f` and `jac_adj1_f`, each output's [`Scatter`]; for `adj1_f`, where each
/// block's components are among the compiled code's columns.
#[derive(Clone, Debug)]
pub struct Plans {
    /// The compiled code's columns as indices into z.
    pub local: Vec<usize>,
    /// Which of them are parameters.
    pub parameters: std::ops::Range<usize>,
    pub jacobian: Vec<Scatter>,
    pub second: Vec<Scatter>,
    /// For each input block, (column, component of the block).
    pub adjoint: Vec<Vec<(usize, usize)>>,
}

impl Plans {
    pub fn new(primal: &Primal, structure: &Structure, functions: &[Function; 5]) -> Option<Plans> {
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
        let jacobian = functions[Kind::Jacobian as usize]
            .outputs
            .iter()
            .map(|(port, content)| match *content {
                Content::Jacobian(i) => {
                    jacobian_scatter(primal, structure, i, |r, w| port.pattern.position(r, w))
                }
                _ => Scatter::default(),
            })
            .collect();
        let second = functions[Kind::AdjointJacobian as usize]
            .outputs
            .iter()
            .map(|(port, content)| match *content {
                Content::Second(i, j) => {
                    let parameters = is_parameters(primal, i) || is_parameters(primal, j);
                    match structure.second_entries(primal, parameters) {
                        Some(entries) => Scatter {
                            compiled: true,
                            parameters,
                            second: entries
                                .iter()
                                .filter(|e| e.1 == i && e.3 == j)
                                .filter_map(|e| Some((e.0, port.pattern.position(e.2, e.4)?)))
                                .collect(),
                            ..Scatter::default()
                        },
                        None => Scatter {
                            parameters,
                            ..Scatter::default()
                        },
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
            .collect();
        Some(Plans {
            local: local.clone(),
            parameters: first..last,
            jacobian,
            second,
            adjoint,
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
        return Scatter {
            parameters,
            ..Scatter::default()
        };
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
    Scatter {
        compiled: true,
        parameters,
        second: Vec::new(),
        jacobian,
        copy,
    }
}
