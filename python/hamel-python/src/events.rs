//! A run's events as Python gives them: scipy-style functions g(t, x) (with the attributes
//! `terminal` and `direction`), or a state component crossing a value, which is evaluated in
//! Rust without the interpreter.

use numpy::PyArray1;
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;

use hamel::{Event, HamelSystem};

use crate::interrupt::Failure;

/// An event of a run.
pub struct EventSpec {
    pub name: String,
    pub kind: EventKind,
    /// > 0: rising only, < 0: falling only, 0: either (scipy's `direction`).
    pub direction: f64,
    pub terminal: bool,
}

pub enum EventKind {
    /// g(t, x) in Python.
    Callable(Py<PyAny>),
    /// g = x[index] − value.
    Threshold { index: usize, value: f64 },
}

impl EventSpec {
    /// One entry of the list the Python package makes of `events=`:
    /// `(name, function or None, state name or None, value, direction, terminal)`.
    pub fn parse(entry: &Bound<'_, PyAny>, state: &[&str]) -> PyResult<EventSpec> {
        type Entry<'py> = (
            String,
            Option<Bound<'py, PyAny>>,
            Option<String>,
            f64,
            f64,
            bool,
        );
        let (name, function, component, value, direction, terminal): Entry<'_> =
            entry.extract().map_err(|_| {
                PyTypeError::new_err(
                    "events: each event is a function g(t, x) (scipy's form) or a hamel.Event",
                )
            })?;
        let kind = match (function, component) {
            (Some(f), None) if f.is_callable() => EventKind::Callable(f.unbind()),
            (None, Some(c)) => match state.iter().position(|n| *n == c) {
                Some(index) => EventKind::Threshold { index, value },
                None => {
                    return Err(PyValueError::new_err(format!(
                        "events: the event `{name}` watches `{c}`, which is not a state; the \
                         states are: {}",
                        state.join(", ")
                    )));
                }
            },
            _ => {
                return Err(PyTypeError::new_err(format!(
                    "events: the event `{name}` needs either a function g(t, x) or a state to \
                     watch"
                )));
            }
        };
        if direction.is_nan() {
            return Err(PyValueError::new_err(format!(
                "events: the direction of `{name}` is NaN; it is > 0 (rising), < 0 (falling) or 0"
            )));
        }
        Ok(EventSpec {
            name,
            kind,
            direction,
            terminal,
        })
    }

    /// The event for a run of `S`. A Python error from g is kept in `failure`, and g is NaN
    /// then, which ends the run.
    pub fn event<'s, S: HamelSystem>(&'s self, failure: &'s Failure) -> Event<'s, S> {
        let event = match &self.kind {
            EventKind::Threshold { index, value } => {
                let (index, value) = (*index, *value);
                Event::new(self.name.clone(), move |_t, x: &S::State| {
                    x.as_ref()[index] - value
                })
            }
            EventKind::Callable(f) => Event::new(self.name.clone(), move |t, x: &S::State| {
                if failure.is_set() {
                    return f64::NAN;
                }
                match Python::attach(|py| call(py, f, t, x.as_ref())) {
                    Ok(v) => v,
                    Err(e) => {
                        failure.set(e);
                        f64::NAN
                    }
                }
            }),
        };
        let event = if self.direction > 0.0 {
            event.rising()
        } else if self.direction < 0.0 {
            event.falling()
        } else {
            event
        };
        if self.terminal {
            event.terminal()
        } else {
            event
        }
    }
}

fn call(py: Python<'_>, f: &Py<PyAny>, t: f64, x: &[f64]) -> PyResult<f64> {
    let state = PyArray1::from_slice(py, x);
    let result = f.bind(py).call1((t, state))?;
    result.extract::<f64>().map_err(|_| {
        PyTypeError::new_err(format!(
            "an event function returned {}: it must return a number",
            crate::inputs::type_name(&result)
        ))
    })
}
