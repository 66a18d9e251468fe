//! Everything that can go wrong at run time, as one error type.

use crate::named::NamedValues;

/// Why a right-hand-side evaluation produced no derivative. Returned by generated code on the
/// cold path, without allocating; [`crate::Simulation`] turns it into an [`Error`] that names
/// the time and state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Singularity {
    /// A pivot of the reduced mass matrix's LDLᵀ factorization is not positive.
    MassMatrix { pivot: usize, value: f64 },
    /// A pivot of the LU factorization of A(q) vanishes: constraints and quasi-velocities
    /// are not independent at this configuration.
    Transformation { pivot: usize, value: f64 },
}

impl Singularity {
    /// The full error, at time `t` and state `state`.
    pub fn at(self, t: f64, state: NamedValues) -> Error {
        match self {
            Singularity::MassMatrix { pivot, value } => Error::SingularMassMatrix {
                t,
                pivot,
                value,
                state,
            },
            Singularity::Transformation { pivot, value } => Error::SingularTransformation {
                t,
                pivot,
                value,
                state,
            },
        }
    }
}

#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum Error {
    #[error("parameter `{name}` is {value}: parameters must be finite numbers")]
    InvalidParameter { name: String, value: f64 },

    #[error("unknown parameter `{name}`; the parameters are: {known}")]
    UnknownParameter { name: String, known: String },

    #[error("initial value of `{name}` is {value}: it must be a finite number")]
    NonFiniteInitialValue { name: String, value: f64 },

    #[error(
        "the initial velocities violate constraint `{name}`: its residual is {residual:e}, more than the \
         tolerance {tolerance:e}; choose velocities that satisfy the constraints, or start from the \
         quasi-velocities with `state_from_speeds`"
    )]
    ConstraintViolation {
        name: String,
        residual: f64,
        tolerance: f64,
    },

    #[error(
        "singular reduced mass matrix at t = {t}: pivot {pivot} of its factorization is {value:e}; \
         state: {state}"
    )]
    SingularMassMatrix {
        t: f64,
        pivot: usize,
        value: f64,
        state: NamedValues,
    },

    #[error(
        "singular velocity transformation at t = {t}: the constraints and quasi-velocities are not \
         independent at this configuration (pivot {pivot} of A(q) is {value:e}); choose \
         quasi-velocities that complete the constraints here; state: {state}"
    )]
    SingularTransformation {
        t: f64,
        pivot: usize,
        value: f64,
        state: NamedValues,
    },

    #[error(
        "the `#[velocities]` function is not the inverse of the constraints and quasi-velocities: \
         A(q)·B(q) differs from the identity by {defect:e} at {configuration}"
    )]
    InverseMismatch {
        defect: f64,
        configuration: NamedValues,
    },

    #[error("step size underflow at t = {t}: the step shrank to {h:e}; state: {state}")]
    StepSizeUnderflow { t: f64, h: f64, state: NamedValues },

    #[error("the state became non-finite at t = {t}: {state}")]
    NonFiniteState { t: f64, state: NamedValues },

    #[error("invalid setting `{name}` = {value}: {reason}")]
    InvalidSetting {
        name: &'static str,
        value: f64,
        reason: &'static str,
    },

    #[error("cannot write {path}: {message}")]
    Io { path: String, message: String },
}
