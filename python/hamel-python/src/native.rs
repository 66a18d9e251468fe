//! The two `#[pyclass]`es every model shares: [`NativeModelType`], a model's class (its
//! description, and making models from keyword parameters), and [`NativeModel`], a model with
//! its parameters. Arguments are checked here, with errors that name them.

use numpy::{PyArray1, PyReadonlyArray1, PyUntypedArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyString};

use crate::describe::Description;
use crate::ensemble::{Cases, NativeTable, RowOutputs};
use crate::errors::to_py;
use crate::events::EventSpec;
use crate::inputs::{InputSpec, type_name};
use crate::linear::{NativeLinearization, NativeLqr};
use crate::model::{Hooks, Model};
use crate::object::{ModelObject, Object, not_plain};
use crate::run::NativeRun;
use crate::settings::{MethodArgs, RunSetup};
use crate::study::{StudyResult, StudySpec};

/// Making models of one type.
trait ModelKind: Send + Sync {
    fn description(&self) -> &'static Description;
    fn create(&self, values: &[(String, f64)]) -> PyResult<Box<dyn ModelObject>>;
}

struct Kind<S: Model> {
    hooks: Hooks<S>,
    description: &'static Description,
}

impl<S: Model> ModelKind for Kind<S> {
    fn description(&self) -> &'static Description {
        self.description
    }

    fn create(&self, values: &[(String, f64)]) -> PyResult<Box<dyn ModelObject>> {
        let d = self.description;
        let mut model = (self.hooks.factory.make)().ok_or_else(|| to_py(&not_plain(d.name)))?;
        if !self.hooks.factory.defaults {
            let missing: Vec<&str> = S::NAMES
                .iter()
                .filter(|n| !values.iter().any(|(v, _)| v == *n))
                .copied()
                .collect();
            if !missing.is_empty() && values.iter().all(|(v, _)| S::NAMES.contains(&v.as_str())) {
                return Err(PyTypeError::new_err(format!(
                    "{}() has no default parameters (the model has no `Default`): give {}",
                    d.name,
                    missing
                        .iter()
                        .map(|m| format!("{m}=..."))
                        .collect::<Vec<_>>()
                        .join(", ")
                )));
            }
        }
        for (name, value) in values {
            model.set(name, *value).map_err(|e| to_py(&e))?;
        }
        Ok(Box::new(Object {
            model,
            hooks: self.hooks.clone(),
            description: d,
        }))
    }
}

/// A model's class: `hamel.Model` subclasses hold one as `_native`.
#[pyclass(frozen, module = "hamel")]
pub struct NativeModelType {
    kind: Box<dyn ModelKind>,
}

impl NativeModelType {
    pub fn new<S: Model>(name: &'static str, hooks: Hooks<S>) -> Self {
        // One description per exported model type, for the life of the module.
        let description = Box::leak(Box::new(Description::of::<S>(name, &hooks)));
        NativeModelType {
            kind: Box::new(Kind { hooks, description }),
        }
    }
}

/// `{name: value}` from a dict of numbers; a value that is not a number is a `TypeError`
/// naming its key.
fn numbers(dict: Option<&Bound<'_, PyDict>>, argument: &str) -> PyResult<Vec<(String, f64)>> {
    let Some(dict) = dict else {
        return Ok(Vec::new());
    };
    let mut values = Vec::with_capacity(dict.len());
    for (key, value) in dict.iter() {
        let key: String = key
            .extract()
            .map_err(|_| PyTypeError::new_err(format!("{argument}: names must be strings")))?;
        let number: f64 = value.extract().map_err(|_| {
            PyTypeError::new_err(format!(
                "{argument}{}{key}: expected a number, got {}",
                if argument.is_empty() { "" } else { "." },
                type_name(&value)
            ))
        })?;
        values.push((key, number));
    }
    Ok(values)
}

/// A one-dimensional array of `names.len()` numbers (a NumPy array or a sequence).
pub fn vector_arg(
    value: &Bound<'_, PyAny>,
    argument: &str,
    names: &[&str],
    what: &str,
) -> PyResult<Vec<f64>> {
    let values = if let Ok(a) = value.cast::<numpy::PyArrayDyn<f64>>() {
        if a.ndim() != 1 {
            return Err(PyValueError::new_err(format!(
                "{argument}: expected a one-dimensional array of {} numbers ({what}), got an array of shape {:?}",
                names.len(),
                a.shape()
            )));
        }
        let a: PyReadonlyArray1<f64> = a.extract()?;
        a.as_array().to_vec()
    } else if value.is_instance_of::<PyString>() || value.is_instance_of::<PyDict>() {
        return Err(PyTypeError::new_err(format!(
            "{argument}: expected an array of {} numbers ({what}), got {}",
            names.len(),
            type_name(value)
        )));
    } else {
        value.extract::<Vec<f64>>().map_err(|_| {
            PyTypeError::new_err(format!(
                "{argument}: expected an array of {} numbers ({what}), got {}",
                names.len(),
                type_name(value)
            ))
        })?
    };
    if values.len() != names.len() {
        return Err(PyValueError::new_err(format!(
            "{argument}: {} values given; {what} has {} ({})",
            values.len(),
            names.len(),
            names.join(", ")
        )));
    }
    Ok(values)
}

#[pymethods]
impl NativeModelType {
    /// The model's description: names, units, defaults.
    fn describe<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        self.kind.description().to_dict(py)
    }

    /// A model with these parameters (the others at their defaults).
    #[pyo3(signature = (parameters=None))]
    fn create(&self, parameters: Option<&Bound<'_, PyDict>>) -> PyResult<NativeModel> {
        let values = numbers(parameters, "")?;
        Ok(NativeModel {
            object: self.kind.create(&values)?,
        })
    }
}

/// A model with its parameters: `hamel.Model` instances hold one as `_native`.
#[pyclass(frozen, module = "hamel")]
pub struct NativeModel {
    object: Box<dyn ModelObject>,
}

impl NativeModel {
    fn d(&self) -> &Description {
        self.object.description()
    }

    fn state_arg(&self, x: &Bound<'_, PyAny>, argument: &str) -> PyResult<Vec<f64>> {
        let d = self.d();
        vector_arg(x, argument, d.state, &format!("the state of {}", d.name))
    }

    fn inputs_arg(&self, u: Option<&Bound<'_, PyAny>>) -> PyResult<Vec<f64>> {
        let d = self.d();
        match u.filter(|u| !u.is_none()) {
            None => Ok(vec![0.0; d.inputs.len()]),
            Some(u) => vector_arg(u, "u", d.inputs, &format!("the inputs of {}", d.name)),
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn setup(
        &self,
        t0: f64,
        t_end: f64,
        dt: f64,
        method: MethodArgs<'_>,
        inputs: Option<&Bound<'_, PyAny>>,
        events: Option<&Bound<'_, PyList>>,
        lambdas: bool,
        project: bool,
        max_samples: Option<u64>,
    ) -> PyResult<RunSetup> {
        let d = self.d();
        let lqr = inputs
            .and_then(|i| i.cast::<NativeLqr>().ok())
            .map(|l| l.get().lqr.clone());
        let events = match events {
            Some(list) => list
                .iter()
                .map(|e| EventSpec::parse(&e, d.state))
                .collect::<PyResult<Vec<_>>>()?,
            None => Vec::new(),
        };
        Ok(RunSetup {
            t0,
            t_end,
            dt,
            method: method.method()?,
            inputs: InputSpec::parse(inputs, d.inputs, lqr)?,
            events,
            lambdas,
            project,
            max_samples,
        })
    }
}

#[pymethods]
impl NativeModel {
    fn describe<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        self.d().to_dict(py)
    }

    /// The parameters' values, in the order of their names.
    fn parameter_values(&self) -> Vec<f64> {
        self.object.parameter_values()
    }

    /// The same model with some parameters changed.
    #[pyo3(signature = (parameters=None))]
    fn with_parameters(&self, parameters: Option<&Bound<'_, PyDict>>) -> PyResult<NativeModel> {
        let values = numbers(parameters, "")?;
        let object = self
            .object
            .with_parameters(&values)
            .map_err(|e| to_py(&e))?;
        Ok(NativeModel { object })
    }

    /// A state by the names of its coordinates and speeds (or velocities), the rest zero.
    #[pyo3(signature = (values=None, velocities=None, t=0.0))]
    fn state<'py>(
        &self,
        py: Python<'py>,
        values: Option<&Bound<'py, PyDict>>,
        velocities: Option<&Bound<'py, PyDict>>,
        t: f64,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let values = numbers(values, "")?;
        let velocities = velocities
            .map(|v| numbers(Some(v), "velocities"))
            .transpose()?;
        let x = self
            .object
            .state(t, &values, velocities.as_deref())
            .map_err(|e| to_py(&e))?;
        Ok(PyArray1::from_vec(py, x))
    }

    /// A run: see `hamel.Model.simulate`.
    #[pyo3(signature = (x0, *, t0=0.0, t_end=10.0, dt=0.01, method="dopri5", rtol=None, atol=None,
        step=None, max_steps=None, max_step=None, initial_step=None, min_step=None, inputs=None,
        events=None, lambdas=false, project=false, max_samples=None))]
    #[allow(clippy::too_many_arguments)]
    fn simulate(
        &self,
        py: Python<'_>,
        x0: &Bound<'_, PyAny>,
        t0: f64,
        t_end: f64,
        dt: f64,
        method: &str,
        rtol: Option<f64>,
        atol: Option<f64>,
        step: Option<f64>,
        max_steps: Option<usize>,
        max_step: Option<f64>,
        initial_step: Option<f64>,
        min_step: Option<f64>,
        inputs: Option<&Bound<'_, PyAny>>,
        events: Option<&Bound<'_, PyList>>,
        lambdas: bool,
        project: bool,
        max_samples: Option<u64>,
    ) -> PyResult<NativeRun> {
        let x0 = self.state_arg(x0, "x0")?;
        let method = MethodArgs {
            method,
            rtol,
            atol,
            step,
            max_steps,
            max_step,
            initial_step,
            min_step,
            dt,
        };
        let setup = self.setup(
            t0,
            t_end,
            dt,
            method,
            inputs,
            events,
            lambdas,
            project,
            max_samples,
        )?;
        let trajectory = self.object.simulate(py, &x0, &setup)?;
        Ok(NativeRun { trajectory })
    }

    /// Many runs: see `hamel.Model.ensemble`.
    #[pyo3(signature = (count, parameters, states, *, t0=0.0, t_end=10.0, dt=0.01, method="dopri5",
        rtol=None, atol=None, step=None, max_steps=None, max_step=None, initial_step=None,
        min_step=None, inputs=None, events=None, lambdas=false, project=false, max_samples=None,
        final_state=true, summary=true, sample_at=Vec::new(), threads=None))]
    #[allow(clippy::too_many_arguments)]
    fn ensemble(
        &self,
        py: Python<'_>,
        count: usize,
        parameters: Vec<(String, PyReadonlyArray1<'_, f64>)>,
        states: &Bound<'_, PyAny>,
        t0: f64,
        t_end: f64,
        dt: f64,
        method: &str,
        rtol: Option<f64>,
        atol: Option<f64>,
        step: Option<f64>,
        max_steps: Option<usize>,
        max_step: Option<f64>,
        initial_step: Option<f64>,
        min_step: Option<f64>,
        inputs: Option<&Bound<'_, PyAny>>,
        events: Option<&Bound<'_, PyList>>,
        lambdas: bool,
        project: bool,
        max_samples: Option<u64>,
        final_state: bool,
        summary: bool,
        sample_at: Vec<f64>,
        threads: Option<usize>,
    ) -> PyResult<NativeTable> {
        let method = MethodArgs {
            method,
            rtol,
            atol,
            step,
            max_steps,
            max_step,
            initial_step,
            min_step,
            dt,
        };
        let setup = self.setup(
            t0,
            t_end,
            dt,
            method,
            inputs,
            events,
            lambdas,
            project,
            max_samples,
        )?;
        let cases = Cases::parse(count, parameters, states, self.d())?;
        let outputs = RowOutputs {
            final_state,
            summary,
            events: setup.events.iter().map(|e| e.name.clone()).collect(),
            sample_at,
        };
        if threads == Some(0) {
            return Err(PyValueError::new_err(
                "threads: at least 1 (None: every core)",
            ));
        }
        let table = self
            .object
            .ensemble(py, &cases, &setup, &outputs, threads)?;
        Ok(NativeTable { table })
    }

    /// A study over a table of cases: see `hamel.study`.
    #[pyo3(signature = (name, names, rows, arguments, table_path, *, t0=0.0, t_end=10.0, dt=0.01,
        method="dopri5", rtol=None, atol=None, step=None, max_steps=None, max_step=None,
        initial_step=None, min_step=None, inputs=None, events=None, lambdas=false, project=false,
        max_samples=None, final_state=true, summary=true, sample_at=Vec::new(), threads=None))]
    #[allow(clippy::too_many_arguments)]
    fn study(
        &self,
        py: Python<'_>,
        name: String,
        names: Vec<String>,
        rows: Vec<Vec<f64>>,
        arguments: Option<Vec<String>>,
        table_path: String,
        t0: f64,
        t_end: f64,
        dt: f64,
        method: &str,
        rtol: Option<f64>,
        atol: Option<f64>,
        step: Option<f64>,
        max_steps: Option<usize>,
        max_step: Option<f64>,
        initial_step: Option<f64>,
        min_step: Option<f64>,
        inputs: Option<&Bound<'_, PyAny>>,
        events: Option<&Bound<'_, PyList>>,
        lambdas: bool,
        project: bool,
        max_samples: Option<u64>,
        final_state: bool,
        summary: bool,
        sample_at: Vec<f64>,
        threads: Option<usize>,
    ) -> PyResult<Option<NativeTable>> {
        let d = self.d();
        for n in &names {
            let known = d.parameters.contains(&n.as_str())
                || d.coordinates.contains(&n.as_str())
                || d.speeds.contains(&n.as_str());
            if !known {
                return Err(PyValueError::new_err(format!(
                    "cases: the column `{n}` is neither a parameter nor a coordinate or speed of {}",
                    d.name
                )));
            }
        }
        if threads == Some(0) {
            return Err(PyValueError::new_err(
                "threads: at least 1 (None: every core)",
            ));
        }
        let method = MethodArgs {
            method,
            rtol,
            atol,
            step,
            max_steps,
            max_step,
            initial_step,
            min_step,
            dt,
        };
        let setup = self.setup(
            t0,
            t_end,
            dt,
            method,
            inputs,
            events,
            lambdas,
            project,
            max_samples,
        )?;
        let outputs = RowOutputs {
            final_state,
            summary,
            events: setup.events.iter().map(|e| e.name.clone()).collect(),
            sample_at,
        };
        let spec = StudySpec {
            name,
            names,
            rows,
            arguments,
            table_path,
            threads,
        };
        match self.object.study(py, &spec, &setup, &outputs)? {
            StudyResult::Table(table) => Ok(Some(NativeTable { table })),
            StudyResult::Done => Ok(None),
        }
    }

    /// The linearization at (t, x, u).
    #[pyo3(signature = (x, u=None, t=0.0))]
    fn linearize(
        &self,
        x: &Bound<'_, PyAny>,
        u: Option<&Bound<'_, PyAny>>,
        t: f64,
    ) -> PyResult<NativeLinearization> {
        let x = self.state_arg(x, "x")?;
        let u = self.inputs_arg(u)?;
        let linearization = self.object.linearize(t, &x, &u).map_err(|e| to_py(&e))?;
        Ok(NativeLinearization { linearization })
    }

    /// ẋ = F(t, x, u).
    #[pyo3(signature = (x, u=None, t=0.0))]
    fn rhs<'py>(
        &self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
        u: Option<&Bound<'py, PyAny>>,
        t: f64,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let x = self.state_arg(x, "x")?;
        let u = self.inputs_arg(u)?;
        let dx = self.object.rhs(t, &x, &u).map_err(|e| to_py(&e))?;
        Ok(PyArray1::from_vec(py, dx))
    }

    #[pyo3(signature = (x, t=0.0))]
    fn energy(&self, x: &Bound<'_, PyAny>, t: f64) -> PyResult<f64> {
        let x = self.state_arg(x, "x")?;
        self.object.energy(t, &x).map_err(|e| to_py(&e))
    }

    #[pyo3(signature = (x, u=None, t=0.0))]
    fn constraint_forces<'py>(
        &self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
        u: Option<&Bound<'py, PyAny>>,
        t: f64,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let x = self.state_arg(x, "x")?;
        let u = self.inputs_arg(u)?;
        let lambda = self
            .object
            .constraint_forces(t, &x, &u)
            .map_err(|e| to_py(&e))?;
        Ok(PyArray1::from_vec(py, lambda))
    }

    #[pyo3(signature = (x, t=0.0))]
    fn outputs<'py>(
        &self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
        t: f64,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let x = self.state_arg(x, "x")?;
        match self.object.outputs(t, &x) {
            Some(y) => Ok(PyArray1::from_vec(py, y)),
            None => Err(PyTypeError::new_err(format!(
                "{} states no outputs (`#[outputs]`)",
                self.d().name
            ))),
        }
    }

    /// The run's 3D scene as an HTML page.
    #[pyo3(signature = (run, show=None, title=None))]
    fn scene(
        &self,
        run: &Bound<'_, PyAny>,
        show: Option<Vec<String>>,
        title: Option<String>,
    ) -> PyResult<String> {
        let run = run.cast::<NativeRun>().map_err(|_| {
            PyTypeError::new_err("run: expected a run of this model (`model.simulate(...)`)")
        })?;
        let trajectory = &run.get().trajectory;
        match self
            .object
            .scene(trajectory, show.as_deref(), title.as_deref())
        {
            Some(Ok(html)) => Ok(html),
            Some(Err(message)) => Err(to_py(&hamel::Error::case_failed("scene", message))),
            None => Err(PyTypeError::new_err(format!(
                "{} states no bodies (`#[bodies]`), so it has no scene",
                self.d().name
            ))),
        }
    }
}
