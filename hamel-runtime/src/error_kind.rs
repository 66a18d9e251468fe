//! A short, stable name for each kind of [`Error`]: a study's table records it beside the
//! message (`error_kind`), so that failed cases can be counted and grouped by why they
//! failed without parsing messages.

use crate::error::Error;

impl Error {
    /// A case's failure of its own ([`Error::CaseFailed`]): `kind` groups such failures in a
    /// study's table (`no_reversal`), `message` says what happened to the study's user.
    pub fn case_failed(kind: impl Into<String>, message: impl Into<String>) -> Error {
        Error::CaseFailed {
            kind: kind.into(),
            message: message.into(),
        }
    }

    /// The error's kind in snake case, the variant's name (`singular_mass_matrix`,
    /// `root_not_bracketed`, `case_panicked`), or the kind a case gave
    /// ([`Error::CaseFailed`]).
    ///
    /// ```
    /// use hamel_runtime::Error;
    ///
    /// let e = Error::InvalidSetting { name: "threads", value: 0.0, reason: "at least one" };
    /// assert_eq!(e.kind(), "invalid_setting");
    /// let e = Error::CaseFailed { kind: "no_reversal".into(), message: "no reversal".into() };
    /// assert_eq!(e.kind(), "no_reversal");
    /// ```
    pub fn kind(&self) -> &str {
        match self {
            Error::InvalidParameter { .. } => "invalid_parameter",
            Error::UnknownParameter { .. } => "unknown_parameter",
            Error::NonFiniteInitialValue { .. } => "non_finite_initial_value",
            Error::ConstraintViolation { .. } => "constraint_violation",
            Error::SingularMassMatrix { .. } => "singular_mass_matrix",
            Error::UnboundedInertia { .. } => "unbounded_inertia",
            Error::UnphysicalBody { .. } => "unphysical_body",
            Error::ImpossibleGeometry { .. } => "impossible_geometry",
            Error::SingularOrientation { .. } => "singular_orientation",
            Error::SingularTransformation { .. } => "singular_transformation",
            Error::InverseMismatch { .. } => "inverse_mismatch",
            Error::StepSizeUnderflow { .. } => "step_size_underflow",
            Error::NewtonNotConverged { .. } => "newton_not_converged",
            Error::SingularIterationMatrix { .. } => "singular_iteration_matrix",
            Error::SpanTooShort { .. } => "span_too_short",
            Error::TooManySteps { .. } => "too_many_steps",
            Error::NonFiniteState { .. } => "non_finite_state",
            Error::NonFiniteRate { .. } => "non_finite_rate",
            Error::InvalidSetting { .. } => "invalid_setting",
            Error::TooManySamples { .. } => "too_many_samples",
            Error::Table { .. } => "table",
            Error::InvalidShard { .. } => "invalid_shard",
            Error::CasePanicked { .. } => "case_panicked",
            Error::ProgressPanicked { .. } => "progress_panicked",
            Error::InvalidColumnName { .. } => "invalid_column_name",
            Error::Io { .. } => "io",
            Error::Read { .. } => "read",
            Error::CaseFailed { kind, .. } => kind,
            Error::Assembly { .. } => "assembly",
            Error::HolonomicViolation { .. } => "holonomic_violation",
            Error::InconsistentModel { .. } => "inconsistent_model",
            Error::UnknownStateName { .. } => "unknown_state_name",
            Error::NonFiniteOperatingPoint { .. } => "non_finite_operating_point",
            Error::NonFiniteArgument { .. } => "non_finite_argument",
            Error::NonFiniteInput { .. } => "non_finite_input",
            Error::NonFiniteDerivative { .. } => "non_finite_derivative",
            Error::UnknownName { .. } => "unknown_name",
            Error::DuplicateName { .. } => "duplicate_name",
            Error::DimensionMismatch { .. } => "dimension_mismatch",
            Error::NotCyclic { .. } => "not_cyclic",
            Error::SingularElimination { .. } => "singular_elimination",
            Error::EigenAnalysis { .. } => "eigen_analysis",
            Error::AmbiguousState { .. } => "ambiguous_state",
            Error::RootNotBracketed { .. } => "root_not_bracketed",
            Error::NonFiniteRootFunction { .. } => "non_finite_root_function",
            Error::RootNotFound { .. } => "root_not_found",
            Error::NonFiniteEvent { .. } => "non_finite_event",
            Error::IndefiniteMassMatrix { .. } => "indefinite_mass_matrix",
            Error::NonFiniteDynamics { .. } => "non_finite_dynamics",
            Error::RelativeDegree { .. } => "relative_degree",
            Error::SingularDecoupling { .. } => "singular_decoupling",
            Error::NoStabilizingSolution { .. } => "no_stabilizing_solution",
            Error::InvalidWeights { .. } => "invalid_weights",
            Error::InvalidReference { .. } => "invalid_reference",
        }
    }
}
