//! Studies from Python: a model's runs over the rows of a table (a DataFrame's columns are
//! parameters and initial values by name), made into a `hamel::study::Study`, so that the
//! tables, shards, manifests and merges are exactly those of the Rust command line: in memory
//! (`Study::run`), or as one task of a batch engine and the merge of the tasks' shards
//! (`Study::main_with` with `--table`, `--out`, `--shard`, `--merge`).

use std::process::ExitCode;
use std::thread;
use std::time::Duration;

use pyo3::prelude::*;

use hamel::study::Study;
use hamel::{Error, Outputs, ParameterTable, Table};

use crate::ensemble::RowOutputs;
use crate::errors::to_py;
use crate::interrupt::{Failure, Watch};
use crate::model::Model;
use crate::object::{Object, build_state, run};
use crate::settings::RunSetup;

/// A study's table and what to do with it.
pub struct StudySpec {
    pub name: String,
    /// The columns (parameters and initial values by name) and the rows.
    pub names: Vec<String>,
    pub rows: Vec<Vec<f64>>,
    /// `None`: run in memory and return the table; else the command line's arguments after
    /// `--table FILE` (`--out DIR --shard i/n`, `--merge DIR`, `--format`, `--threads`).
    pub arguments: Option<Vec<String>>,
    /// Where the table is written for the command line.
    pub table_path: String,
    pub threads: Option<usize>,
}

/// What a study gives back: its table (in memory) or the command line's success.
pub enum StudyResult {
    Table(Table),
    Done,
}

/// The study of `object`'s model over `spec`'s table. (A `Study` is not `Sync`: it is made
/// on the thread that runs it.)
fn make_study<'a, S: Model>(
    object: &'a Object<S>,
    spec: &'a StudySpec,
    setup: &'a RunSetup,
    outputs: &'a Outputs,
    failure: &'a Failure,
) -> Study<'a> {
    let d = object.description;
    let mut study = Study::new(
        &spec.name,
        &format!("runs of {} over a table of cases", d.name),
    );
    for (j, name) in spec.names.iter().enumerate() {
        let (unit, description) = match d.parameters.iter().position(|p| p == name) {
            Some(i) => (
                d.parameter_units[i].unwrap_or(""),
                d.parameter_docs[i].to_string(),
            ),
            None => (
                d.units
                    .iter()
                    .find(|(n, _)| n == name)
                    .map_or("", |(_, u)| *u),
                format!("initial value of {name}"),
            ),
        };
        study = study.parameter(name, unit, &description, spec.rows.iter().map(|r| r[j]));
    }
    for name in outputs.names::<S>() {
        let unit = name
            .strip_prefix("final_")
            .and_then(|s| d.units.iter().find(|(n, _)| *n == s))
            .map_or("", |(_, u)| *u);
        study = study.output(&name, unit, "");
    }
    study.case(move |row: &hamel::study::Row| -> Result<Vec<f64>, Error> {
        if failure.is_set() {
            return Err(Error::case_failed(
                "interrupted",
                "the study was interrupted before this case ran",
            ));
        }
        let mut parameters = Vec::new();
        let mut values = Vec::new();
        for name in &spec.names {
            let value = row.get(name)?;
            if d.parameters.contains(&name.as_str()) {
                parameters.push((name.clone(), value));
            } else {
                values.push((name.clone(), value));
            }
        }
        let model = object.model_with(&parameters)?;
        let x0 = build_state(&model, setup.t0, &values, None)?;
        let trajectory = run(&model, x0, setup, failure, Watch::Flag)?;
        if failure.is_set() {
            return Err(Error::case_failed(
                "interrupted",
                "the study was interrupted during this case",
            ));
        }
        outputs.values::<S>(&trajectory)
    })
}

/// Runs the study of `object`'s model, with Ctrl-C checked by this thread.
pub fn run_study<S: Model>(
    object: &Object<S>,
    py: Python<'_>,
    spec: &StudySpec,
    setup: &RunSetup,
    outputs: &RowOutputs,
) -> PyResult<StudyResult> {
    let outputs = outputs.outputs();
    let failure = Failure::default();
    let table =
        ParameterTable::from_rows(spec.names.clone(), spec.rows.clone()).map_err(|e| to_py(&e))?;
    let result = py.detach(|| {
        thread::scope(|scope| {
            let work = scope.spawn(|| -> Result<StudyResult, Error> {
                let study = make_study(object, spec, setup, &outputs, &failure);
                match &spec.arguments {
                    None => study.run(&table, spec.threads).map(StudyResult::Table),
                    Some(arguments) => {
                        std::fs::write(&spec.table_path, table.to_csv()).map_err(|e| {
                            Error::Io {
                                path: spec.table_path.clone(),
                                message: e.to_string(),
                            }
                        })?;
                        let mut args = vec!["--table".to_string(), spec.table_path.clone()];
                        args.extend(arguments.iter().cloned());
                        if study.main_with(&args) == ExitCode::SUCCESS {
                            Ok(StudyResult::Done)
                        } else {
                            Err(Error::case_failed(
                                "study",
                                format!("the study `{}` failed: its messages are above", spec.name),
                            ))
                        }
                    }
                }
            });
            while !work.is_finished() {
                thread::sleep(Duration::from_millis(10));
                failure.check_signals();
            }
            work.join()
        })
    });
    if let Some(e) = failure.take() {
        return Err(e);
    }
    match result {
        Ok(Ok(done)) => Ok(done),
        Ok(Err(e)) => Err(to_py(&e)),
        Err(payload) => Err(crate::errors::panicked(payload)),
    }
}
