//! Running a study's rows a block at a time: each block's cases on every thread of the
//! study's pool (an [`Ensemble`]), the block before written meanwhile, so that a study of any
//! size runs in the memory of two blocks and writing costs no computing time.

use std::ops::Range;
use std::sync::Arc;

use crate::ensemble::CaseError;
use crate::{Ensemble, Error, ParameterTable, Table};

use super::panics::{InCase, Panics};
use super::progress::Bar;
use super::{Row, Study};

/// Cases per block: enough that a block's last cases keep few threads waiting (a block
/// ends when its slowest case does), few enough that two blocks take little memory.
pub(crate) const BLOCK: usize = 4096;

/// What a run did.
pub(crate) struct Done {
    pub failed: usize,
    pub threads: usize,
    /// How many cases panicked and the first few, for the standard error stream (their
    /// panics were not printed one by one).
    pub panics: Option<String>,
}

/// Runs `rows` of `table` on `threads` threads (every core for `None`) and hands each block
/// of results, in row order, to `sink`; with `bar`, a progress bar on a terminal.
pub(crate) fn run(
    study: &Study,
    table: &ParameterTable,
    rows: Range<usize>,
    threads: Option<usize>,
    bar: bool,
    sink: &mut (dyn FnMut(&Table) -> Result<(), Error> + Send),
) -> Result<Done, Error> {
    study.check()?;
    if threads == Some(0) {
        return Err(Error::InvalidSetting {
            name: "threads",
            value: 0.0,
            reason: "a study runs on at least 1 thread (`None` for every core)",
        });
    }
    let order = parameter_order(study, table)?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads.unwrap_or(0))
        .build()
        .map_err(|e| Error::Io {
            path: format!("a pool of {} threads", threads.unwrap_or(0)),
            message: e.to_string(),
        })?;
    let progress = Bar::new(rows.len(), bar);
    let blocks: Vec<Range<usize>> = rows
        .clone()
        .step_by(BLOCK)
        .map(|start| start..(start + BLOCK).min(rows.end))
        .collect();
    let plan = Plan {
        case: study.case.as_deref().ok_or(Error::InvalidSetting {
            name: "study",
            value: 0.0,
            reason: "a study needs its case (`Study::case`)",
        })?,
        names: study.parameter_names(),
        columns: study.columns(),
        outputs: study.outputs.iter().map(|c| c.name.clone()).collect(),
        order,
        panics: Arc::new(Panics::default()),
    };
    let compute = |block: Range<usize>| plan.block(table, block, rows.start, &progress);
    let mut failed = 0;
    pool.install(|| -> Result<(), Error> {
        let mut pending: Option<Table> = None;
        for block in blocks {
            let (written, computed) = rayon::join(
                || pending.take().map_or(Ok(()), |b| sink(&b)),
                || compute(block),
            );
            written?;
            let computed = computed?;
            failed += computed.failed();
            pending = Some(computed);
        }
        pending.map_or(Ok(()), |b| sink(&b))
    })?;
    progress.finish();
    Ok(Done {
        failed,
        threads: pool.current_num_threads(),
        panics: plan.panics.summary(),
    })
}

/// Where each of the study's parameters is among the table's columns; a table whose columns
/// are not the study's parameters is refused, naming them.
fn parameter_order(study: &Study, table: &ParameterTable) -> Result<Vec<usize>, Error> {
    let wanted = study.parameter_names();
    let mismatch = || Error::DimensionMismatch {
        what: format!(
            "the parameter table's columns ({}) are not the study's parameters ({})",
            table.names().join(", "),
            wanted.join(", ")
        ),
    };
    if table.names().len() != wanted.len() {
        return Err(mismatch());
    }
    wanted
        .iter()
        .map(|w| {
            table
                .names()
                .iter()
                .position(|n| n == w)
                .ok_or_else(mismatch)
        })
        .collect()
}

/// What a block's cases need of the study (not the study itself, whose report need not be
/// shared between threads).
struct Plan<'s> {
    case: &'s (dyn Fn(&Row) -> Result<Vec<f64>, Error> + Sync),
    names: Vec<String>,
    columns: Vec<String>,
    outputs: Vec<String>,
    /// Where each parameter is among the table's columns.
    order: Vec<usize>,
    /// The cases' panics, recorded instead of printed.
    panics: Arc<Panics>,
}

impl Plan<'_> {
    /// Row r's parameters, in the study's order.
    fn parameters(&self, table: &ParameterTable, r: usize) -> Vec<f64> {
        let row = table.row(r).unwrap_or_default();
        self.order.iter().map(|&j| row[j]).collect()
    }

    /// The results of the rows `block`: each row's parameters (in the study's order) and
    /// outputs, or its parameters, NaN outputs and its error.
    fn block(
        &self,
        table: &ParameterTable,
        block: Range<usize>,
        first: usize,
        progress: &Bar,
    ) -> Result<Table, Error> {
        let width = self.outputs.len();
        let before = block.start - first;
        let ensemble = Ensemble::new(block.len())
            .first_case(block.start)
            .on_progress(|p| progress.set(before + p.done));
        let results = ensemble.run(|i| {
            let _recorded = InCase::new(&self.panics, block.start + i);
            let values = self.parameters(table, block.start + i);
            (self.case)(&Row {
                index: block.start + i,
                names: &self.names,
                values: &values,
            })
        })?;
        let mut out = Table::new(self.columns.clone())?;
        for (i, result) in results.into_iter().enumerate() {
            let r = block.start + i;
            let mut values = self.parameters(table, r);
            let error = match result {
                Ok(outputs) if outputs.len() == width => {
                    values.extend(outputs);
                    None
                }
                Ok(outputs) => {
                    values.extend(vec![f64::NAN; width]);
                    Some(CaseError::of(&Error::DimensionMismatch {
                        what: format!(
                            "the case gave {} values for the {width} outputs ({})",
                            outputs.len(),
                            self.outputs.join(", ")
                        ),
                    }))
                }
                Err(e) => {
                    values.extend(vec![f64::NAN; width]);
                    Some(CaseError::of(&e))
                }
            };
            out.push_row(r as u64, values, error)?;
        }
        Ok(out)
    }
}
