//! A finished run for Python: the trajectory as Rust recorded it, its columns handed to NumPy
//! as views (no copy), its events and summary.

use numpy::ndarray::ArrayView1;
use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::PyKeyError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use hamel::{Stopped, Trajectory};

/// A run: `hamel.Run` wraps it.
#[pyclass(frozen, module = "hamel")]
pub struct NativeRun {
    pub trajectory: Trajectory,
}

#[pymethods]
impl NativeRun {
    /// The column names, `t` first.
    fn names(&self) -> Vec<String> {
        self.trajectory.names().to_vec()
    }

    fn __len__(&self) -> usize {
        self.trajectory.len()
    }

    /// The column `name` as a read-only NumPy array that views the run's memory.
    fn column<'py>(slf: Bound<'py, Self>, name: &str) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let this = slf.get();
        let Some(column) = this.trajectory.column(name) else {
            return Err(PyKeyError::new_err(format!(
                "the run has no column `{name}`; its columns are: {}",
                this.trajectory.names().join(", ")
            )));
        };
        let view = ArrayView1::from(column);
        // SAFETY: the column lives in the trajectory, which this frozen object owns and never
        // changes; the array holds a reference to the object, so the memory outlives it.
        let array = unsafe { PyArray1::borrow_from_array(&view, slf.clone().into_any()) };
        array.readwrite().make_nonwriteable();
        Ok(array)
    }

    /// The events: `(name, t, state as a dict, terminal)` in time order.
    fn events<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let list = PyList::empty(py);
        for e in self.trajectory.events() {
            let state = PyDict::new(py);
            for (name, value) in &e.state.0 {
                state.set_item(name, value)?;
            }
            list.append((e.name.clone(), e.t, state, e.terminal))?;
        }
        Ok(list)
    }

    /// The summary's figures as a dict.
    fn summary<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let s = self.trajectory.summary();
        let d = PyDict::new(py);
        d.set_item("steps", s.steps)?;
        d.set_item("rejected", s.rejected)?;
        d.set_item("evaluations", s.evaluations)?;
        d.set_item("samples", s.samples)?;
        d.set_item("max_constraint_residual", s.max_constraint_residual)?;
        d.set_item("initial_energy", s.initial_energy)?;
        d.set_item("max_energy_drift", s.max_energy_drift)?;
        d.set_item("relative_energy_drift", s.relative_energy_drift)?;
        d.set_item("energy_scale", s.energy_scale.value())?;
        d.set_item("conservative", s.conservative)?;
        d.set_item("holonomic_constraints", s.holonomic_constraints)?;
        d.set_item("max_holonomic_residual", s.max_holonomic_residual)?;
        d.set_item("work", s.work)?;
        d.set_item("max_energy_balance", s.max_energy_balance)?;
        d.set_item("relative_energy_balance", s.relative_energy_balance)?;
        d.set_item("energy_error", s.energy_error())?;
        d.set_item("energy_inaccurate", s.energy_inaccurate())?;
        let (stopped, stopped_at) = match &s.stopped {
            None => (None, None),
            Some(Stopped::Event { name, t }) => (Some(format!("event {name}")), Some(*t)),
            Some(Stopped::Cancelled { t }) => (Some("cancelled".to_string()), Some(*t)),
        };
        d.set_item("stopped", stopped)?;
        d.set_item("stopped_at", stopped_at)?;
        d.set_item("singular_crossings", s.singular_crossings.len())?;
        d.set_item("symmetric_not_reversible", s.symmetric_not_reversible)?;
        Ok(d)
    }

    /// The summary as Rust prints it.
    fn summary_text(&self) -> String {
        self.trajectory.summary().to_string()
    }

    /// The run as CSV text (the same bytes as `Trajectory::write_csv`).
    fn csv(&self) -> PyResult<String> {
        let mut bytes = Vec::new();
        self.trajectory
            .write_csv(&mut bytes)
            .map_err(|e| pyo3::exceptions::PyOSError::new_err(e.to_string()))?;
        Ok(String::from_utf8_lossy(&bytes).into_owned())
    }
}
