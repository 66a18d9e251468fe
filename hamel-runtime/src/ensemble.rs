//! Studies: one computation — a simulation, a linearization, a search for a critical speed —
//! run for many cases (parameter sets, initial states, input functions) on every core, as
//! Julia's `EnsembleProblem` does, with rows that pandas and polars read as they are.
//!
//! * [`Ensemble`] runs a case function in parallel (rayon) and returns one result per case,
//!   in case order: identical for any number of threads, because each case is computed
//!   alone, from its index. A case that fails — an `Err`, or a panic — is a row carrying its
//!   error; it never aborts the study.
//! * [`Table`] is a study's result: named `f64` columns, the case index and the error of each
//!   row, written to CSV (here) or Parquet (`hamel::parquet`, feature `parquet`).
//! * [`Outputs`] and [`ModeColumns`] choose what a row keeps of a run or of a linearization:
//!   the final state, the summary, event times, chosen samples; eigenvalues and modes.
//! * [`ParameterTable`] reads a study's cases from CSV, and [`Shard`] splits them among the
//!   tasks of a batch engine (a Slurm job array, Ray or Dask tasks): "run row i, write a
//!   result", each shard written whole or not at all and complete only once its manifest is
//!   written after it ([`write_shard`], [`shard_state`]).
//!
//! `hamel::study` (in the `hamel` crate) builds a study's command line on these.

mod quotes;
mod select;
pub(crate) mod shard;
mod table;

pub use select::{ModeColumns, Outputs};
pub use shard::{
    Program, Shard, ShardFile, ShardStamp, ShardState, Written, check_writable, manifest_path,
    remove_leftovers, shard_state, write_complete, write_shard,
};
pub use table::{CASE_COLUMN, CaseError, CsvWriter, ParameterTable, Table};

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use rayon::prelude::*;

use crate::error::Error;

/// How often, at most, a study's progress callback is called (besides at the end).
const PROGRESS_INTERVAL: Duration = Duration::from_millis(100);

/// Where a study is, for its progress callback.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StudyProgress {
    /// Cases finished (successfully or not).
    pub done: usize,
    /// Cases that ended in an error so far.
    pub failed: usize,
    /// Cases in the study.
    pub total: usize,
    /// Wall-clock time since the study started.
    pub elapsed: Duration,
}

impl StudyProgress {
    /// The fraction of the cases done, in [0, 1].
    pub fn fraction(&self) -> f64 {
        if self.total == 0 {
            1.0
        } else {
            self.done as f64 / self.total as f64
        }
    }
}

/// A progress callback; it may be called from any of the study's threads.
type StudyProgressFn<'a> = Box<dyn Fn(&StudyProgress) + Send + Sync + 'a>;

/// A study of `cases` cases, run in parallel:
///
/// ```
/// use hamel_runtime::Ensemble;
///
/// // The case function gets the case's index and returns its result.
/// let squares = Ensemble::new(5).threads(2).run(|i| Ok((i * i) as f64))?;
/// assert_eq!(squares.iter().map(|r| *r.as_ref().unwrap()).sum::<f64>(), 30.0);
/// # Ok::<(), hamel_runtime::Error>(())
/// ```
pub struct Ensemble<'a> {
    cases: usize,
    /// The number of the first case in a larger study, for messages ([`Self::first_case`]).
    first: usize,
    threads: Option<usize>,
    progress: Option<StudyProgressFn<'a>>,
}

impl<'a> Ensemble<'a> {
    /// A study of `cases` cases, numbered 0 … cases − 1, on rayon's global pool (every core)
    /// unless [`Self::threads`] says otherwise.
    pub fn new(cases: usize) -> Self {
        Ensemble {
            cases,
            first: 0,
            threads: None,
            progress: None,
        }
    }

    /// Numbers the cases from `first` in messages ([`Error::CasePanicked`]): for a block of a
    /// larger study, whose case 8 is the study's case `first + 8`. `case(i)` still gets
    /// i = 0 … cases − 1.
    ///
    /// ```
    /// use hamel_runtime::{Ensemble, Error};
    ///
    /// let block = Ensemble::new(10).first_case(20).run(|i| {
    ///     if i == 8 { panic!("no") } else { Ok(i) }
    /// })?;
    /// let e = block[8].as_ref().unwrap_err();
    /// assert!(matches!(e, Error::CasePanicked { case: 28, .. }), "{e}");
    /// # Ok::<(), Error>(())
    /// ```
    pub fn first_case(mut self, first: usize) -> Self {
        self.first = first;
        self
    }

    /// Runs the study on a pool of its own with `n` threads (≥ 1): for a study that must
    /// leave cores free, and for checking that the results do not depend on the count.
    pub fn threads(mut self, n: usize) -> Self {
        self.threads = Some(n);
        self
    }

    /// Calls `f` with the study's progress, every 100 ms at most and once at the end (from
    /// whichever thread finished a case: `f` must be `Sync`; a progress bar of `indicatif`
    /// is).
    pub fn on_progress(mut self, f: impl Fn(&StudyProgress) + Send + Sync + 'a) -> Self {
        self.progress = Some(Box::new(f));
        self
    }

    /// The number of cases.
    pub fn cases(&self) -> usize {
        self.cases
    }

    /// Runs `case(i)` for every case i, in parallel, and returns the results in case order.
    /// A case that returns an error, or panics ([`Error::CasePanicked`], with the panic's
    /// message), gives its error in its place; the others run on. The outer `Err` is for the
    /// study's own settings (a thread count of 0, or a pool the system cannot start) and for
    /// a progress callback that panics ([`Error::ProgressPanicked`]): the study stops at
    /// once (no case starts after it), instead of the panic tearing through the pool.
    pub fn run<T: Send>(
        &self,
        case: impl Fn(usize) -> Result<T, Error> + Sync,
    ) -> Result<Vec<Result<T, Error>>, Error> {
        let tracker = Tracker::new(self.cases, self.progress.as_deref());
        let work = || {
            (0..self.cases)
                .into_par_iter()
                .map(|i| {
                    if tracker.stopped() {
                        return Err(Error::ProgressPanicked {
                            message: String::new(),
                        });
                    }
                    let result = guarded(i, self.first, &case);
                    tracker.finished(result.is_err());
                    result
                })
                .collect::<Vec<_>>()
        };
        let results = match self.threads {
            None => work(),
            Some(0) => {
                return Err(Error::InvalidSetting {
                    name: "threads",
                    value: 0.0,
                    reason: "a study needs at least one thread",
                });
            }
            Some(n) => rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .map_err(|e| Error::Io {
                    path: format!("a pool of {n} threads"),
                    message: e.to_string(),
                })?
                .install(work),
        };
        tracker.report();
        match tracker.panicked() {
            Some(message) => Err(Error::ProgressPanicked { message }),
            None => Ok(results),
        }
    }

    /// Runs the study into a [`Table`] with the columns `names`: `case(i)` gives row i's
    /// values, one per column (a row of another length is an error in its place); a failed
    /// case's row is NaN, with its error's kind and message.
    pub fn table(
        &self,
        names: Vec<String>,
        case: impl Fn(usize) -> Result<Vec<f64>, Error> + Sync,
    ) -> Result<Table, Error> {
        self.table_of(names, (0..self.cases).map(|i| i as u64).collect(), case)
    }

    /// [`Self::table`] for cases whose indices in a larger study are `indices` (a shard's
    /// rows): `case` gets the position in `indices`, the table records the index. An index
    /// given twice is refused before any case runs.
    pub fn table_of(
        &self,
        names: Vec<String>,
        indices: Vec<u64>,
        case: impl Fn(usize) -> Result<Vec<f64>, Error> + Sync,
    ) -> Result<Table, Error> {
        if indices.len() != self.cases {
            return Err(Error::DimensionMismatch {
                what: format!(
                    "{} case indices for a study of {} cases",
                    indices.len(),
                    self.cases
                ),
            });
        }
        // Names that cannot be columns, and indices given twice, are refused before anything
        // runs.
        let mut table = Table::new(names)?;
        let mut seen = std::collections::HashSet::with_capacity(indices.len());
        if let Some(i) = indices.iter().find(|&&i| !seen.insert(i)) {
            return Err(Error::DuplicateName {
                kind: "case index",
                name: i.to_string(),
                context: "each case of a study has one row",
            });
        }
        let width = table.names().len();
        let rows = self.run(|i| {
            let values = case(i)?;
            if values.len() == width {
                Ok(values)
            } else {
                Err(Error::DimensionMismatch {
                    what: format!(
                        "case {} gave {} values for {width} columns",
                        indices[i],
                        values.len()
                    ),
                })
            }
        })?;
        for (index, row) in indices.iter().zip(rows) {
            // A panic is named by the case's index in the study, not its place here.
            let row = row.map_err(|e| match e {
                Error::CasePanicked { message, .. } => Error::CasePanicked {
                    case: *index as usize,
                    message,
                },
                other => other,
            });
            table.push(*index, row)?;
        }
        Ok(table)
    }
}

/// `case(i)`, its panic caught and turned into an error naming the case `first + i`: one
/// case must not end the study.
fn guarded<T>(
    i: usize,
    first: usize,
    case: &(impl Fn(usize) -> Result<T, Error> + Sync),
) -> Result<T, Error> {
    match catch_unwind(AssertUnwindSafe(|| case(i))) {
        Ok(result) => result,
        Err(payload) => Err(Error::CasePanicked {
            case: first + i,
            message: panic_message(payload.as_ref()),
        }),
    }
}

/// The message a panic was raised with.
fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| (*s).to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "(no message)".to_string())
}

/// Counts finished cases across threads and calls the progress callback now and then.
struct Tracker<'p, 'a> {
    total: usize,
    done: AtomicUsize,
    failed: AtomicUsize,
    started: Instant,
    /// When the callback was last called; locked only to call it, by one thread at a time.
    last: Mutex<Instant>,
    progress: Option<&'p (dyn Fn(&StudyProgress) + Send + Sync + 'a)>,
    /// Set when the callback panicked: no case starts after it, and the callback is not
    /// called again.
    stop: AtomicBool,
    /// The callback's panic message.
    panic: Mutex<Option<String>>,
}

impl<'p, 'a> Tracker<'p, 'a> {
    fn new(
        total: usize,
        progress: Option<&'p (dyn Fn(&StudyProgress) + Send + Sync + 'a)>,
    ) -> Self {
        let now = Instant::now();
        Tracker {
            total,
            done: AtomicUsize::new(0),
            failed: AtomicUsize::new(0),
            started: now,
            last: Mutex::new(now),
            progress,
            stop: AtomicBool::new(false),
            panic: Mutex::new(None),
        }
    }

    /// Whether the callback has panicked (the study is stopping).
    fn stopped(&self) -> bool {
        self.stop.load(Ordering::Relaxed)
    }

    /// The callback's panic message, if it panicked.
    fn panicked(&self) -> Option<String> {
        self.panic.lock().ok().and_then(|m| m.clone())
    }

    /// One more case finished; the callback is called if it is due and no other thread is
    /// calling it.
    fn finished(&self, failed: bool) {
        self.done.fetch_add(1, Ordering::Relaxed);
        if failed {
            self.failed.fetch_add(1, Ordering::Relaxed);
        }
        if self.progress.is_none() {
            return;
        }
        if let Ok(mut last) = self.last.try_lock() {
            if last.elapsed() >= PROGRESS_INTERVAL {
                *last = Instant::now();
                self.report();
            }
        }
    }

    /// Calls the callback, its panic caught: recorded, and the study stopped.
    fn report(&self) {
        let Some(progress) = self.progress.filter(|_| !self.stopped()) else {
            return;
        };
        let now = StudyProgress {
            done: self.done.load(Ordering::Relaxed),
            failed: self.failed.load(Ordering::Relaxed),
            total: self.total,
            elapsed: self.started.elapsed(),
        };
        if let Err(payload) = catch_unwind(AssertUnwindSafe(|| progress(&now))) {
            self.stop.store(true, Ordering::Relaxed);
            if let Ok(mut slot) = self.panic.lock() {
                slot.get_or_insert_with(|| panic_message(payload.as_ref()));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A progress callback that panics used to unwind out of `run` (the cases' panics were
    /// caught, the callback's not); now the study stops and `run` returns an error naming it.
    #[test]
    fn a_panicking_progress_callback_is_an_error_not_an_unwind() {
        let study = Ensemble::new(8)
            .threads(2)
            .on_progress(|_| panic!("the progress bar broke"));
        let result = std::panic::catch_unwind(AssertUnwindSafe(|| study.run(|i| Ok(i as f64))));
        match result {
            Ok(Err(Error::ProgressPanicked { message })) => {
                assert_eq!(message, "the progress bar broke");
            }
            Ok(other) => panic!("expected ProgressPanicked, got {other:?}"),
            Err(_) => panic!("the callback's panic escaped Ensemble::run"),
        }
        // A study whose callback is well is unchanged.
        let fine = Ensemble::new(4).threads(2).on_progress(|_| {});
        assert_eq!(fine.run(Ok).unwrap().len(), 4);
    }
}
