//! A run's inputs as Python gives them — constants, arrays sampled in time, a Python function
//! u(t, x), or an LQR design's feedback — and their values at (t, x) for a model.

use numpy::{PyArray1, PyReadonlyArray1};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};

use hamel::control::{Controller, Lqr, StateFeedback};
use hamel::{HamelSystem, Vector};

use crate::interrupt::{CHECK_EVERY, Failure, Watch, stop};

/// The inputs of a run.
pub enum InputSpec {
    /// One value per input (all zero when none are given).
    Constant(Vec<f64>),
    /// Values sampled at increasing times, linearly interpolated, held beyond the ends.
    Sampled {
        times: Vec<f64>,
        columns: Vec<Column>,
    },
    /// A Python function u(t, x) returning one value per input.
    Callable(Py<PyAny>),
    /// u = u₀ − K (x − x₀) of an LQR design (evaluated in Rust).
    Feedback(Lqr),
}

/// One input of sampled inputs.
pub enum Column {
    Constant(f64),
    Series(Vec<f64>),
}

impl InputSpec {
    /// `inputs=` of `simulate`: `None`, a number (one input), a sequence of one value per
    /// input, a dict by input name (numbers; with a key `"t"`, arrays sampled at those times),
    /// a callable u(t, x), or an LQR design (`lin.lqr(Q, R)`).
    pub fn parse(
        value: Option<&Bound<'_, PyAny>>,
        names: &[&str],
        lqr: Option<Lqr>,
    ) -> PyResult<InputSpec> {
        if let Some(lqr) = lqr {
            return Ok(InputSpec::Feedback(lqr));
        }
        let Some(value) = value.filter(|v| !v.is_none()) else {
            return Ok(InputSpec::Constant(vec![0.0; names.len()]));
        };
        if let Ok(dict) = value.cast::<PyDict>() {
            return parse_dict(dict, names);
        }
        if value.is_callable() {
            return Ok(InputSpec::Callable(value.clone().unbind()));
        }
        let values = values_of(value, "inputs")?;
        if values.len() != names.len() {
            return Err(PyValueError::new_err(format!(
                "inputs: {} values given, the model has {} inputs ({}); give one value per input, \
                 a dict by name, a function u(t, x) or sampled arrays",
                values.len(),
                names.len(),
                names.join(", ")
            )));
        }
        check_finite("inputs", names, &values)?;
        Ok(InputSpec::Constant(values))
    }
}

/// A number or a one-dimensional sequence of numbers.
fn values_of(value: &Bound<'_, PyAny>, argument: &str) -> PyResult<Vec<f64>> {
    if let Ok(v) = value.extract::<f64>() {
        return Ok(vec![v]);
    }
    if value.is_instance_of::<PyString>() {
        return Err(PyTypeError::new_err(format!(
            "{argument}: a string is not a number or a sequence of numbers"
        )));
    }
    if let Ok(a) = value.extract::<PyReadonlyArray1<f64>>() {
        return Ok(a
            .as_slice()
            .map_or_else(|_| a.as_array().to_vec(), <[f64]>::to_vec));
    }
    value.extract::<Vec<f64>>().map_err(|_| {
        PyTypeError::new_err(format!(
            "{argument}: expected a number or a one-dimensional sequence of numbers, got {}",
            type_name(value)
        ))
    })
}

pub fn type_name(value: &Bound<'_, PyAny>) -> String {
    value
        .get_type()
        .name()
        .map_or_else(|_| "an object".into(), |n| format!("`{n}`"))
}

fn check_finite(argument: &str, names: &[&str], values: &[f64]) -> PyResult<()> {
    for (name, v) in names.iter().zip(values) {
        if !v.is_finite() {
            return Err(PyValueError::new_err(format!(
                "{argument}: the input `{name}` is {v}; inputs must be finite numbers"
            )));
        }
    }
    Ok(())
}

fn parse_dict(dict: &Bound<'_, PyDict>, names: &[&str]) -> PyResult<InputSpec> {
    let times = match dict.get_item("t")? {
        Some(t) => Some(values_of(&t, "inputs[\"t\"]")?),
        None => None,
    };
    let mut columns: Vec<Column> = names.iter().map(|_| Column::Constant(0.0)).collect();
    for (key, value) in dict.iter() {
        let key: String = key.extract().map_err(|_| {
            PyTypeError::new_err("inputs: the keys of an inputs dict are the inputs' names")
        })?;
        if key == "t" {
            continue;
        }
        let Some(j) = names.iter().position(|n| *n == key) else {
            return Err(PyValueError::new_err(format!(
                "inputs: unknown input `{key}`; the model's inputs are: {}",
                if names.is_empty() {
                    "none".to_string()
                } else {
                    names.join(", ")
                }
            )));
        };
        let argument = format!("inputs[\"{key}\"]");
        let values = values_of(&value, &argument)?;
        let scalar = value.extract::<f64>().is_ok();
        if let Some(i) = values.iter().position(|v| !v.is_finite()) {
            return Err(PyValueError::new_err(format!(
                "{argument}: sample {i} is {}; inputs must be finite numbers",
                values[i]
            )));
        }
        columns[j] = match (&times, scalar) {
            (_, true) => Column::Constant(values[0]),
            (Some(t), false) if values.len() == t.len() => Column::Series(values),
            (Some(t), false) => {
                return Err(PyValueError::new_err(format!(
                    "{argument}: {} samples for {} times in inputs[\"t\"]",
                    values.len(),
                    t.len()
                )));
            }
            (None, false) => {
                return Err(PyValueError::new_err(format!(
                    "{argument}: an array of samples needs their times, inputs[\"t\"]"
                )));
            }
        };
    }
    let Some(times) = times else {
        let values = columns
            .iter()
            .map(|c| match c {
                Column::Constant(v) => *v,
                Column::Series(_) => 0.0,
            })
            .collect();
        return Ok(InputSpec::Constant(values));
    };
    if times.is_empty() {
        return Err(PyValueError::new_err("inputs[\"t\"]: no sample times"));
    }
    if let Some(i) =
        (0..times.len()).find(|&i| !times[i].is_finite() || (i > 0 && times[i] <= times[i - 1]))
    {
        return Err(PyValueError::new_err(format!(
            "inputs[\"t\"]: the sample times must be finite and increasing; entry {i} is {} after {}",
            times[i],
            if i > 0 {
                times[i - 1].to_string()
            } else {
                "nothing".into()
            }
        )));
    }
    Ok(InputSpec::Sampled { times, columns })
}

/// The inputs of one run of a model `S`: what the run's input function calls.
pub struct Inputs<'a, S: HamelSystem> {
    spec: &'a InputSpec,
    failure: &'a Failure,
    watch: Watch,
    /// Evaluations until the next look for Ctrl-C.
    countdown: u32,
    feedback: Option<StateFeedback<S>>,
    /// The interval of sampled inputs the last time fell in (times mostly increase).
    cursor: usize,
}

impl<'a, S: HamelSystem> Inputs<'a, S> {
    pub fn new(
        spec: &'a InputSpec,
        failure: &'a Failure,
        watch: Watch,
    ) -> Result<Self, hamel::Error> {
        let feedback = match spec {
            InputSpec::Feedback(lqr) => Some(lqr.feedback::<S>()?),
            _ => None,
        };
        Ok(Inputs {
            spec,
            failure,
            watch,
            countdown: CHECK_EVERY,
            feedback,
            cursor: 0,
        })
    }

    /// u(t, x). Every [`CHECK_EVERY`] evaluations a single run looks for Ctrl-C; a Python
    /// error kept (Ctrl-C, an exception of a function u, a stop asked by another thread) stops
    /// the run by unwinding ([`crate::interrupt::Stopped`]).
    pub fn at(&mut self, t: f64, x: &S::State) -> S::Inputs {
        self.countdown -= 1;
        if self.countdown == 0 {
            self.countdown = CHECK_EVERY;
            if self.watch == Watch::Signals {
                self.failure.check_signals();
            }
        }
        if self.failure.is_set() {
            stop();
        }
        let mut u = S::Inputs::zeros();
        match self.spec {
            InputSpec::Constant(values) => u.as_mut().copy_from_slice(values),
            InputSpec::Sampled { times, columns } => {
                let (i, w) = locate(times, t, &mut self.cursor);
                for (slot, column) in u.as_mut().iter_mut().zip(columns) {
                    *slot = match column {
                        Column::Constant(v) => *v,
                        Column::Series(v) if w == 0.0 => v[i],
                        Column::Series(v) => v[i] + w * (v[i + 1] - v[i]),
                    };
                }
            }
            InputSpec::Feedback(_) => {
                if let Some(f) = &self.feedback {
                    match f.control(t, x) {
                        Ok(v) => u = v,
                        Err(_) => u.as_mut().fill(f64::NAN),
                    }
                }
            }
            InputSpec::Callable(f) => {
                if let Err(e) = Python::attach(|py| call(py, f, t, x.as_ref(), u.as_mut())) {
                    self.failure.set(e);
                    stop();
                }
            }
        }
        u
    }
}

/// Calls u(t, x) and reads one value per input from what it returns.
fn call(py: Python<'_>, f: &Py<PyAny>, t: f64, x: &[f64], u: &mut [f64]) -> PyResult<()> {
    let state = PyArray1::from_slice(py, x);
    let result = f.bind(py).call1((t, state))?;
    let values = values_of(&result, "the input function's result").map_err(|_| {
        PyTypeError::new_err(format!(
            "the input function returned {}: it must return one number per input ({}), as a \
             sequence or array",
            type_name(&result),
            u.len()
        ))
    })?;
    if values.len() != u.len() {
        return Err(PyValueError::new_err(format!(
            "the input function returned {} values at t = {t}: the model has {} inputs",
            values.len(),
            u.len()
        )));
    }
    u.copy_from_slice(&values);
    Ok(())
}

/// The interval [tᵢ, tᵢ₊₁] of the sample times holding t and the weight of tᵢ₊₁; before the
/// first time or after the last, that sample with weight 0.
fn locate(times: &[f64], t: f64, cursor: &mut usize) -> (usize, f64) {
    let last = times.len() - 1;
    if t <= times[0] {
        return (0, 0.0);
    }
    if t >= times[last] {
        return (last, 0.0);
    }
    let mut i = (*cursor).min(last - 1);
    if !(times[i] <= t && t < times[i + 1]) {
        i = times.partition_point(|&s| s <= t) - 1;
    }
    *cursor = i;
    (i, (t - times[i]) / (times[i + 1] - times[i]))
}

#[cfg(test)]
mod tests {
    use super::locate;

    #[test]
    fn sampled_inputs_are_interpolated_and_held_at_the_ends() {
        let times = [0.0, 1.0, 3.0];
        let mut cursor = 0;
        assert_eq!(locate(&times, -1.0, &mut cursor), (0, 0.0));
        assert_eq!(locate(&times, 0.5, &mut cursor), (0, 0.5));
        assert_eq!(locate(&times, 2.0, &mut cursor), (1, 0.5));
        assert_eq!(locate(&times, 0.25, &mut cursor), (0, 0.25));
        assert_eq!(locate(&times, 3.0, &mut cursor), (2, 0.0));
        assert_eq!(locate(&times, 9.0, &mut cursor), (2, 0.0));
    }
}
