//! hamel's errors as Python exceptions: the classes are defined in Python (`hamel.errors`, one
//! per kind, `hamel.Error` their base) and looked up here, so that every extension module of
//! models — the catalogue, a compiled model, a user's crate — raises the same classes. Each
//! carries the kind (`Error::kind`), the message (the same text as in Rust), and, where the
//! error names them, the time and the state by name.

use pyo3::prelude::*;
use pyo3::types::PyDict;

use hamel::{Error, NamedValues};

/// The Python exception for a hamel error.
pub fn to_py(e: &Error) -> PyErr {
    Python::attach(|py| build(py, e).unwrap_or_else(|failed| failed))
}

fn build(py: Python<'_>, e: &Error) -> PyResult<PyErr> {
    let (t, state) = time_and_state(e);
    let state = match state {
        Some(values) => {
            let d = PyDict::new(py);
            for (name, value) in &values.0 {
                d.set_item(name, value)?;
            }
            Some(d)
        }
        None => None,
    };
    let make = py.import("hamel.errors")?.getattr("_from_rust")?;
    let exception = make.call1((e.kind(), e.to_string(), t, state))?;
    Ok(PyErr::from_value(exception))
}

/// The time and the state (or configuration) an error names, if it names them.
fn time_and_state(e: &Error) -> (Option<f64>, Option<&NamedValues>) {
    match e {
        Error::SingularMassMatrix { t, state, .. }
        | Error::UnboundedInertia { t, state, .. }
        | Error::SingularTransformation { t, state, .. }
        | Error::StepSizeUnderflow { t, state, .. }
        | Error::NewtonNotConverged { t, state, .. }
        | Error::SingularIterationMatrix { t, state, .. }
        | Error::TooManySteps { t, state, .. }
        | Error::NonFiniteState { t, state }
        | Error::NonFiniteRate { t, state, .. }
        | Error::NonFiniteInput { t, state, .. }
        | Error::NonFiniteEvent { t, state, .. }
        | Error::IndefiniteMassMatrix { t, state, .. }
        | Error::RelativeDegree { t, state, .. }
        | Error::SingularDecoupling { t, state, .. }
        | Error::NonFiniteDynamics { t, state, .. } => (Some(*t), Some(state)),
        Error::SpanTooShort { t0, state, .. } => (Some(*t0), Some(state)),
        Error::Assembly {
            t, configuration, ..
        }
        | Error::HolonomicViolation {
            t, configuration, ..
        } => (Some(*t), Some(configuration)),
        Error::InverseMismatch { configuration, .. } => (None, Some(configuration)),
        Error::InvalidReference { t, .. } => (Some(*t), None),
        // The singularity met names them.
        Error::SingularOrientation { cause, .. } => time_and_state(cause),
        _ => (None, None),
    }
}

/// A Rust panic caught at the boundary, as a Python exception (the interpreter goes on).
pub fn panicked(payload: Box<dyn std::any::Any + Send>) -> PyErr {
    let message = payload
        .downcast_ref::<&str>()
        .map(|s| (*s).to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "a panic without a message".into());
    to_py(&Error::case_failed(
        "panic",
        format!("hamel panicked (a bug in hamel or in the model; please report it): {message}"),
    ))
}
