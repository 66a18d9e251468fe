//! Ensembles: many runs of one model, each case its own parameters and initial state, on
//! every core with the interpreter released (`hamel::Ensemble`: rows in case order, the same
//! bits for any number of threads, a failed case a row with its error and the values it was
//! given). Ctrl-C stops them: the waiting thread checks for it and every case's run stops at
//! its next progress call.

use std::thread;
use std::time::Duration;

use numpy::ndarray::ArrayView1;
use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::exceptions::{PyKeyError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyList;

use hamel::{CaseError, Ensemble, Error, Outputs, Table, Vector};

use crate::describe::Description;
use crate::errors::to_py;
use crate::interrupt::{Failure, Watch};
use crate::model::Model;
use crate::object::{Object, build_state, run};
use crate::settings::RunSetup;

/// The cases of an ensemble.
pub struct Cases {
    pub count: usize,
    /// Parameters that vary, a value per case.
    pub parameters: Vec<(String, Vec<f64>)>,
    pub states: CaseStates,
}

/// The initial states of the cases.
pub enum CaseStates {
    /// One state for every case.
    Same(Vec<f64>),
    /// A whole state per case, row by row (count × state length).
    Full(Vec<f64>),
    /// Coordinates and speeds by name, a value per case; a state built from them for each
    /// case with its parameters (the rest zero, the dependent coordinates solved).
    Named(Vec<(String, Vec<f64>)>),
}

/// What a row keeps of its run, besides its parameters and named initial values.
pub struct RowOutputs {
    pub final_state: bool,
    pub summary: bool,
    pub events: Vec<String>,
    pub sample_at: Vec<f64>,
}

impl RowOutputs {
    pub(crate) fn outputs(&self) -> Outputs {
        let mut o = Outputs::new();
        if self.final_state {
            o = o.final_state();
        }
        if self.summary {
            o = o.summary();
        }
        for e in &self.events {
            o = o.event(e.clone());
        }
        for t in &self.sample_at {
            o = o.sample_at(*t);
        }
        o
    }
}

impl Cases {
    /// `parameters`: (name, values) pairs; `states`: a state (1-D), a state per case (2-D), or
    /// a list of (name, values) pairs.
    pub fn parse(
        count: usize,
        parameters: Vec<(String, PyReadonlyArray1<'_, f64>)>,
        states: &Bound<'_, PyAny>,
        d: &Description,
    ) -> PyResult<Cases> {
        let column = |name: &str,
                      values: &PyReadonlyArray1<'_, f64>,
                      argument: &str|
         -> PyResult<Vec<f64>> {
            let v = values.as_array().to_vec();
            if v.len() != count {
                return Err(PyValueError::new_err(format!(
                    "{argument}: the column `{name}` has {} values for {count} cases",
                    v.len()
                )));
            }
            Ok(v)
        };
        let mut params = Vec::with_capacity(parameters.len());
        for (name, values) in &parameters {
            if !d.parameters.contains(&name.as_str()) {
                return Err(PyKeyError::new_err(format!(
                    "parameters: `{name}` is not a parameter of {}; its parameters are: {}",
                    d.name,
                    d.parameters.join(", ")
                )));
            }
            params.push((name.clone(), column(name, values, "parameters")?));
        }
        let states = if let Ok(list) = states.cast::<PyList>() {
            let mut named = Vec::with_capacity(list.len());
            for item in list.iter() {
                let (name, values): (String, PyReadonlyArray1<'_, f64>) = item.extract()?;
                if !d.coordinates.contains(&name.as_str()) && !d.speeds.contains(&name.as_str()) {
                    return Err(PyKeyError::new_err(format!(
                        "states: `{name}` is neither a coordinate nor a speed of {}; its state is: {}",
                        d.name,
                        d.state.join(", ")
                    )));
                }
                let v = column(&name, &values, "states")?;
                named.push((name, v));
            }
            CaseStates::Named(named)
        } else if let Ok(x) = states.extract::<PyReadonlyArray1<'_, f64>>() {
            let x = x.as_array().to_vec();
            if x.len() != d.state.len() {
                return Err(PyValueError::new_err(format!(
                    "states: a state of {} has {} components ({}), not {}",
                    d.name,
                    d.state.len(),
                    d.state.join(", "),
                    x.len()
                )));
            }
            CaseStates::Same(x)
        } else if let Ok(x) = states.extract::<PyReadonlyArray2<'_, f64>>() {
            let shape = x.as_array().shape().to_vec();
            if shape != [count, d.state.len()] {
                return Err(PyValueError::new_err(format!(
                    "states: an array of shape {shape:?}; one state per case is ({count}, {})",
                    d.state.len()
                )));
            }
            CaseStates::Full(x.as_array().iter().copied().collect())
        } else {
            return Err(PyTypeError::new_err(
                "states: expected a state, an array of one state per case, or initial values by name",
            ));
        };
        Ok(Cases {
            count,
            parameters: params,
            states,
        })
    }

    /// The columns the table starts with: the parameters and named initial values given.
    fn names(&self) -> Vec<String> {
        let mut names: Vec<String> = self.parameters.iter().map(|(n, _)| n.clone()).collect();
        if let CaseStates::Named(named) = &self.states {
            names.extend(named.iter().map(|(n, _)| n.clone()));
        }
        names
    }

    fn given(&self, i: usize) -> Vec<f64> {
        let mut row: Vec<f64> = self.parameters.iter().map(|(_, v)| v[i]).collect();
        if let CaseStates::Named(named) = &self.states {
            row.extend(named.iter().map(|(_, v)| v[i]));
        }
        row
    }
}

/// Case `i`: its model, its state, its run, its row.
fn case<S: Model>(
    object: &Object<S>,
    cases: &Cases,
    setup: &RunSetup,
    outputs: &Outputs,
    failure: &Failure,
    i: usize,
) -> Result<Vec<f64>, Error> {
    if failure.is_set() {
        return Err(Error::case_failed(
            "interrupted",
            "the ensemble was interrupted before this case ran",
        ));
    }
    let values: Vec<(String, f64)> = cases
        .parameters
        .iter()
        .map(|(n, v)| (n.clone(), v[i]))
        .collect();
    let model = object.model_with(&values)?;
    let len = S::State::LEN;
    let x0 = match &cases.states {
        CaseStates::Same(x) => S::State::from_slice(x),
        CaseStates::Full(rows) => S::State::from_slice(&rows[i * len..(i + 1) * len]),
        CaseStates::Named(named) => {
            let values: Vec<(String, f64)> = named.iter().map(|(n, v)| (n.clone(), v[i])).collect();
            Some(build_state(&model, setup.t0, &values, None)?)
        }
    }
    .unwrap_or_else(S::State::zeros);
    let trajectory = run(&model, x0, setup, failure, Watch::Flag)?;
    if failure.is_set() {
        return Err(Error::case_failed(
            "interrupted",
            "the ensemble was interrupted during this case",
        ));
    }
    let mut row = cases.given(i);
    row.extend(outputs.values::<S>(&trajectory)?);
    Ok(row)
}

/// The rows in case order; a failed case keeps the values it was given (its parameters and
/// named initial values), NaN for the rest, as a study's table does.
fn fill(
    mut table: Table,
    cases: &Cases,
    rows: Vec<Result<Vec<f64>, Error>>,
) -> Result<Table, Error> {
    let width = table.names().len();
    for (i, row) in rows.into_iter().enumerate() {
        match row {
            Ok(values) => table.push(i as u64, Ok(values))?,
            Err(e) => {
                let mut values = cases.given(i);
                values.resize(width, f64::NAN);
                table.push_row(i as u64, values, Some(CaseError::of(&e)))?;
            }
        }
    }
    Ok(table)
}

/// The ensemble on a thread of its own (its cases on the pool), while this thread, released
/// from the interpreter, checks for Ctrl-C every 10 ms and stops every case when it comes.
pub fn run_cases<S: Model>(
    object: &Object<S>,
    py: Python<'_>,
    cases: &Cases,
    setup: &RunSetup,
    outputs: &RowOutputs,
    threads: Option<usize>,
) -> PyResult<Table> {
    let outputs = outputs.outputs();
    let mut names = cases.names();
    names.extend(outputs.names::<S>());
    let failure = Failure::default();
    let result = py.detach(|| {
        thread::scope(|scope| {
            let study = scope.spawn(|| {
                let mut ensemble = Ensemble::new(cases.count);
                if let Some(n) = threads {
                    ensemble = ensemble.threads(n);
                }
                // Names that cannot be columns are refused before any case runs.
                let table = Table::new(names)?;
                let rows = ensemble.run(|i| case(object, cases, setup, &outputs, &failure, i))?;
                fill(table, cases, rows)
            });
            while !study.is_finished() {
                thread::sleep(Duration::from_millis(10));
                failure.check_signals();
            }
            study.join()
        })
    });
    if let Some(e) = failure.take() {
        return Err(e);
    }
    match result {
        Ok(Ok(table)) => Ok(table),
        Ok(Err(e)) => Err(to_py(&e)),
        Err(payload) => Err(crate::errors::panicked(payload)),
    }
}

/// An ensemble's table: `hamel.Table` wraps it.
#[pyclass(frozen, module = "hamel")]
pub struct NativeTable {
    pub table: Table,
}

#[pymethods]
impl NativeTable {
    fn names(&self) -> Vec<String> {
        self.table.names().to_vec()
    }

    fn __len__(&self) -> usize {
        self.table.len()
    }

    /// The column `name` as a read-only NumPy array that views the table's memory.
    fn column<'py>(slf: Bound<'py, Self>, name: &str) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let this = slf.get();
        let Some(column) = this.table.column(name) else {
            return Err(PyKeyError::new_err(format!(
                "the table has no column `{name}`; its columns are: {}",
                this.table.names().join(", ")
            )));
        };
        let view = ArrayView1::from(column);
        // SAFETY: the column lives in the table, which this frozen object owns and never
        // changes; the array holds a reference to the object.
        let array = unsafe { PyArray1::borrow_from_array(&view, slf.clone().into_any()) };
        array.readwrite().make_nonwriteable();
        Ok(array)
    }

    /// The case indices, in row order.
    fn cases<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<u64>> {
        PyArray1::from_slice(py, self.table.cases())
    }

    /// Per row: None, or `(kind, message)` of the case's error.
    fn errors<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let list = PyList::empty(py);
        for e in self.table.errors() {
            match e {
                Some(e) => list.append((e.kind.clone(), e.message.clone()))?,
                None => list.append(py.None())?,
            }
        }
        Ok(list)
    }

    fn failed(&self) -> usize {
        self.table.failed()
    }

    /// The table as CSV text (the same bytes as `Table::write_csv`).
    fn csv(&self) -> PyResult<String> {
        let mut bytes = Vec::new();
        self.table
            .write_csv(&mut bytes)
            .map_err(|e| pyo3::exceptions::PyOSError::new_err(e.to_string()))?;
        Ok(String::from_utf8_lossy(&bytes).into_owned())
    }

    fn save_csv(&self, path: &str) -> PyResult<()> {
        self.table.save_csv(path).map_err(|e| to_py(&e))
    }

    fn __repr__(&self) -> String {
        format!(
            "<hamel table: {} rows, columns {}>",
            self.table.len(),
            self.table.names().join(", ")
        )
    }
}
