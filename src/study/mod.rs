//! Studies of any model: one computation run for every row of a parameter table, with the
//! command line that runs it on this machine or as the tasks of a batch engine (feature
//! `study`, on by default). `hamel::docs::studies` is the guide.
//!
//! A [`Study`] is given its parameters (each with its unit, description and the values of
//! the default grid), its outputs, and the case: what one row of parameters gives. Its
//! [`Study::main`] is then the program:
//!
//! ```text
//! study                              the default grid here: <name>.csv, then the report
//! study --write-grid grid.csv        the default grid as a parameter table
//! study --table grid.csv --out results --shard 3/8    one task of a batch engine
//! study --table grid.csv --out results --shard env    the shard from a Slurm, PBS or LSF array
//! study --table grid.csv --merge results              the shards joined into one file
//! ```
//!
//! with `--threads N` and `--format csv|parquet` (Parquet when hamel is built with the
//! feature `parquet`; asked for without it, a clear error). A shard's file is written whole
//! and then its manifest, by atomic renames; a shard whose file and manifest agree with the
//! table is skipped, any other (missing, truncated, of an edited table) recomputed, so a
//! killed study restarted does only what is missing. The rows stream to the file a block at
//! a time: a shard of any size runs in bounded memory. The merged file is byte for byte the
//! file one task running the whole table writes.
//!
//! ```
//! use hamel::study::{Study, steps};
//! use hamel::Error;
//!
//! let study = Study::new("squares", "x² + y over a grid")
//!     .parameter("x", "m", "a length", steps(0.0, 0.5, 3))
//!     .parameter("y", "m²", "an area", [1.0, 2.0])
//!     .output("z", "m²", "x² + y")
//!     .case(|row| Ok(vec![row.get("x")?.powi(2) + row.get("y")?]));
//! let table = study.run(&study.grid()?, Some(1))?;
//! assert_eq!(table.names(), ["x", "y", "z"]);
//! assert_eq!(table.column("z").unwrap(), [1.0, 2.0, 1.25, 2.25, 2.0, 3.0]);
//! # Ok::<(), Error>(())
//! ```

mod array;
mod cli;
mod output;
mod panics;
mod progress;
mod stream;
#[cfg(test)]
mod tests;

use std::path::Path;
use std::process::ExitCode;
use std::time::Duration;

use crate::{Error, ParameterTable, Table};

pub use array::shard_from_environment;
pub use output::Format;

/// A column of a study: its name, unit and description (in `--help` and in Parquet's
/// metadata).
#[derive(Clone, Debug, PartialEq)]
pub struct Column {
    pub name: String,
    pub unit: String,
    pub description: String,
}

/// The case function: one row's outputs.
type CaseFn<'a> = Box<dyn Fn(&Row) -> Result<Vec<f64>, Error> + Sync + 'a>;

/// The report on a finished run of the whole grid.
type ReportFn<'a> = Box<dyn Fn(&Finished) -> Result<(), Error> + 'a>;

/// A study: its parameters, outputs and case (see the [module's documentation](self)).
pub struct Study<'a> {
    name: String,
    about: String,
    parameters: Vec<(Column, Vec<f64>)>,
    outputs: Vec<Column>,
    case: Option<CaseFn<'a>>,
    report: Option<ReportFn<'a>>,
    version: Option<String>,
}

/// One row of a study's parameter table, as its case sees it.
pub struct Row<'r> {
    index: usize,
    names: &'r [String],
    values: &'r [f64],
}

impl Row<'_> {
    /// The row's index in its parameter table (its case index).
    pub fn index(&self) -> usize {
        self.index
    }

    /// The value of the parameter `name`; a name that is not one of the study's parameters
    /// is [`Error::UnknownName`], listing them.
    pub fn get(&self, name: &str) -> Result<f64, Error> {
        match self.names.iter().position(|n| n == name) {
            Some(j) => Ok(self.values[j]),
            None => Err(Error::UnknownName {
                kind: "parameter",
                name: name.to_string(),
                known: self.names.join(", "),
            }),
        }
    }
}

/// A run of the whole grid on this machine, for the study's report.
pub struct Finished<'r> {
    /// The results, one row per case.
    pub table: &'r Table,
    /// The file they were written to.
    pub path: &'r Path,
    /// The threads the cases ran on, as asked (`--threads`), `None` for every core.
    pub threads: Option<usize>,
    /// The threads they ran on.
    pub threads_used: usize,
    /// The wall-clock time of the cases.
    pub elapsed: Duration,
}

/// `count` values `start + step·i`, i = 0 … count − 1 (each computed so, not accumulated).
pub fn steps(start: f64, step: f64, count: usize) -> Vec<f64> {
    (0..count).map(|i| start + step * i as f64).collect()
}

impl<'a> Study<'a> {
    /// A study called `name` (its default output file is `<name>.csv`), `about` saying what
    /// it computes (the first line of `--help`).
    pub fn new(name: &str, about: &str) -> Self {
        Study {
            name: name.to_string(),
            about: about.to_string(),
            parameters: Vec::new(),
            outputs: Vec::new(),
            case: None,
            report: None,
            version: None,
        }
    }

    /// The program's version, as its shards' manifests record it: shards of one study
    /// computed by programs of different versions are never mixed (a shard of another version
    /// is computed again, and a merge refuses it). Without it, the version is a hash of the
    /// running executable, so that any rebuild that changes the program counts as another;
    /// set it to resume or merge with a rebuilt program whose cases compute the same.
    pub fn version(mut self, version: &str) -> Self {
        self.version = Some(version.to_string());
        self
    }

    /// The program that computes the study's shards: its name and version, and hamel's.
    pub(crate) fn program(&self) -> crate::ensemble::Program {
        crate::ensemble::Program::new(&self.name, self.version.as_deref())
    }

    /// A parameter, its unit and description, and its values on the default grid (every
    /// combination of the parameters' values, the first parameter varying slowest).
    pub fn parameter(
        mut self,
        name: &str,
        unit: &str,
        description: &str,
        values: impl IntoIterator<Item = f64>,
    ) -> Self {
        self.parameters.push((
            column(name, unit, description),
            values.into_iter().collect(),
        ));
        self
    }

    /// An output: a value each case gives, in the order of the outputs.
    pub fn output(mut self, name: &str, unit: &str, description: &str) -> Self {
        self.outputs.push(column(name, unit, description));
        self
    }

    /// The case: a row's outputs, one per [`Self::output`]. An `Err` or a panic is the row's
    /// error (its kind and message); the row keeps its parameters.
    pub fn case(mut self, f: impl Fn(&Row) -> Result<Vec<f64>, Error> + Sync + 'a) -> Self {
        self.case = Some(Box::new(f));
        self
    }

    /// What a run of the whole grid on this machine does after writing its table: figures,
    /// checks, a summary.
    pub fn report(mut self, f: impl Fn(&Finished) -> Result<(), Error> + 'a) -> Self {
        self.report = Some(Box::new(f));
        self
    }

    /// The study's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The parameters' names, in order.
    pub fn parameter_names(&self) -> Vec<String> {
        self.parameters
            .iter()
            .map(|(c, _)| c.name.clone())
            .collect()
    }

    /// The result table's columns: the parameters, then the outputs.
    pub fn columns(&self) -> Vec<String> {
        self.described().into_iter().map(|c| c.name).collect()
    }

    /// Every column with its unit and description.
    pub fn described(&self) -> Vec<Column> {
        let parameters = self.parameters.iter().map(|(c, _)| c.clone());
        parameters.chain(self.outputs.iter().cloned()).collect()
    }

    /// The default grid: every combination of the parameters' values, the first varying
    /// slowest. A parameter without values, or a study without parameters, is an error.
    pub fn grid(&self) -> Result<ParameterTable, Error> {
        self.check()?;
        let mut rows: Vec<Vec<f64>> = vec![Vec::new()];
        for (_, values) in &self.parameters {
            rows = rows
                .iter()
                .flat_map(|row| {
                    values.iter().map(move |&v| {
                        let mut next = row.clone();
                        next.push(v);
                        next
                    })
                })
                .collect();
        }
        ParameterTable::from_rows(self.parameter_names(), rows)
    }

    /// Runs every row of `table` (columns: the study's parameters) on `threads` threads
    /// (`None`: every core; `Some(0)` is an error) and returns the results in memory. Cases
    /// that panic are rows with their error, and summed up on the standard error stream in
    /// a few lines (how many, and the first three with where they panicked).
    pub fn run(&self, table: &ParameterTable, threads: Option<usize>) -> Result<Table, Error> {
        let mut all = Table::new(self.columns())?;
        let mut keep = |block: &Table| all.append(block.clone());
        let done = stream::run(self, table, 0..table.len(), threads, false, &mut keep)?;
        if let Some(summary) = done.panics {
            use std::io::Write;
            let _ = writeln!(std::io::stderr(), "{summary}");
        }
        Ok(all)
    }

    /// The program: reads the command line (`--help` lists it), runs what it asks, prints
    /// errors (exit code 2 for a mistake in the command line, 1 for a run that failed).
    pub fn main(self) -> ExitCode {
        let args: Vec<String> = std::env::args().skip(1).collect();
        self.main_with(&args)
    }

    /// [`Self::main`] with these arguments.
    pub fn main_with(&self, args: &[String]) -> ExitCode {
        cli::main(self, args)
    }

    /// The study's own mistakes, before anything runs: no parameters, a parameter without
    /// values, no case, column names that cannot be.
    fn check(&self) -> Result<(), Error> {
        let invalid = |reason| Error::InvalidSetting {
            name: "study",
            value: 0.0,
            reason,
        };
        if self.parameters.is_empty() {
            return Err(invalid("a study needs parameters (`Study::parameter`)"));
        }
        if let Some((c, _)) = self.parameters.iter().find(|(_, v)| v.is_empty()) {
            return Err(Error::InvalidColumnName {
                kind: "parameter",
                name: c.name.clone(),
                reason: "a parameter needs at least one value on the default grid",
            });
        }
        if self.case.is_none() {
            return Err(invalid("a study needs its case (`Study::case`)"));
        }
        // Each name is checked as what it is, so that the error calls a parameter one.
        let outputs = self.outputs.iter().map(|c| c.name.clone()).collect();
        named("parameter", self.parameter_names())?;
        named("output", outputs)?;
        Table::new(self.columns()).map(|_| ())
    }
}

/// `names` checked as a table's columns, a bad one called a `kind` name.
fn named(kind: &'static str, names: Vec<String>) -> Result<(), Error> {
    Table::new(names).map(|_| ()).map_err(|e| match e {
        Error::InvalidColumnName { name, reason, .. } => {
            Error::InvalidColumnName { kind, name, reason }
        }
        other => other,
    })
}

fn column(name: &str, unit: &str, description: &str) -> Column {
    Column {
        name: name.to_string(),
        unit: unit.to_string(),
        description: description.to_string(),
    }
}
