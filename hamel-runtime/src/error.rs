//! Everything that can go wrong at run time, as one error type.

use crate::named::NamedValues;

/// Why a right-hand-side evaluation produced no derivative. Returned by generated code on the
/// cold path, without allocating; [`crate::Simulation`] turns it into an [`Error`] that names
/// the time and state (see [`crate::HamelSystem::singular`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Singularity {
    /// A pivot of the reduced mass matrix's LDLᵀ factorization is zero to rounding (relative
    /// to the matrix's trace): the motion along free quasi-velocity number `speed` has no
    /// inertia.
    MassMatrix { speed: usize, value: f64 },
    /// A pivot of the LU factorization of A(q) vanishes: the constraints and quasi-velocities
    /// do not determine the velocity of coordinate number `coordinate` here.
    Transformation { coordinate: usize, value: f64 },
    /// A pivot of the reduced mass matrix's LDLᵀ factorization is negative beyond rounding:
    /// the kinetic energy of some admissible motion along free quasi-velocity number `speed`
    /// (with the speeds before it) is negative, which no physical parameters give.
    IndefiniteMassMatrix { speed: usize, value: f64 },
    /// A value the checks read is not a finite number: with `speed` `Some(j)`, the pivot for
    /// free quasi-velocity number j or the reduced mass matrix's scale; with
    /// `None`, an entry of A(q) (B computed by LU). Not a singular matrix: the right-hand side
    /// is undefined here.
    NonFinite { speed: Option<usize> },
}

impl Singularity {
    /// What a failed check of the LDLᵀ pivot `pivot` for free quasi-velocity number `speed`
    /// means, the matrix's scale being `scale` (Σ|M_kk|, its trace) and the check
    /// `pivot > tolerance·scale` (generated code calls this on the cold path): a value that is
    /// not finite, a pivot negative beyond that tolerance (an indefinite matrix), or one that
    /// is zero to it (a singular matrix).
    pub fn mass_pivot(speed: usize, pivot: f64, scale: f64, tolerance: f64) -> Singularity {
        if !(pivot.is_finite() && scale.is_finite()) {
            Singularity::NonFinite { speed: Some(speed) }
        } else if pivot < -tolerance * scale.abs() {
            Singularity::IndefiniteMassMatrix {
                speed,
                value: pivot,
            }
        } else {
            Singularity::MassMatrix {
                speed,
                value: pivot,
            }
        }
    }

    /// What a failed check of the LDLᵀ pivots means, from all of them and the diagonal entries
    /// of the reduced mass matrix, the check being `pivot > tolerance·Σ|diagonal|` for each
    /// (generated code calls this on the cold path): the first speed whose pivot or diagonal
    /// entry is not finite ([`Singularity::NonFinite`]; a NaN spoils the scale, and so every
    /// check, but it belongs to one speed), or else the first pivot that fails, as
    /// [`Singularity::mass_pivot`] tells.
    pub fn mass_pivots(pivots: &[f64], diagonal: &[f64], tolerance: f64) -> Singularity {
        let finite =
            |k: usize| pivots[k].is_finite() && diagonal.get(k).is_none_or(|d| d.is_finite());
        if let Some(speed) = (0..pivots.len()).find(|&k| !finite(k)) {
            return Singularity::NonFinite { speed: Some(speed) };
        }
        let scale: f64 = diagonal.iter().map(|d| d.abs()).sum();
        // Every value is finite here, so `<=` is the negation of the check's `>`.
        let speed = pivots
            .iter()
            .position(|&p| p <= tolerance * scale)
            .unwrap_or(0);
        let pivot = pivots.get(speed).copied().unwrap_or(f64::NAN);
        Singularity::mass_pivot(speed, pivot, scale, tolerance)
    }

    /// The full error at time `t` and `state`, naming the coordinate or speed concerned.
    pub fn at(self, t: f64, state: NamedValues, coordinates: &[&str], speeds: &[&str]) -> Error {
        let name = |names: &[&str], i: usize| {
            names
                .get(i)
                .map_or_else(|| format!("#{i}"), |n| (*n).to_string())
        };
        match self {
            Singularity::MassMatrix { speed, value } => Error::SingularMassMatrix {
                t,
                speed: name(speeds, speed),
                value,
                state,
            },
            Singularity::Transformation { coordinate, value } => Error::SingularTransformation {
                t,
                coordinate: name(coordinates, coordinate),
                value,
                state,
            },
            Singularity::IndefiniteMassMatrix { speed, value } => Error::IndefiniteMassMatrix {
                t,
                speed: name(speeds, speed),
                value,
                state,
            },
            Singularity::NonFinite { speed } => Error::NonFiniteDynamics {
                t,
                speed: speed.map(|j| name(speeds, j)),
                state,
            },
        }
    }
}

impl core::fmt::Display for Singularity {
    /// What was singular, by the index of the speed or coordinate (the generated code does not
    /// know the time and state; [`Singularity::at`] gives the error that names them).
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match *self {
            Singularity::MassMatrix { speed, value } => write!(
                f,
                "the reduced mass matrix is singular: its pivot for speed #{speed} is {}",
                Num(value)
            ),
            Singularity::Transformation { coordinate, value } => write!(
                f,
                "A(q) is singular: its pivot for coordinate #{coordinate} is {}; the \
                 constraints and quasi-velocities do not determine that coordinate's velocity",
                Num(value)
            ),
            Singularity::IndefiniteMassMatrix { speed, value } => write!(
                f,
                "the reduced mass matrix is not positive definite: its pivot for speed \
                 #{speed} is {}",
                Num(value)
            ),
            Singularity::NonFinite { speed: Some(speed) } => write!(
                f,
                "the reduced mass matrix has a value that is not a finite number, for speed \
                 #{speed}"
            ),
            Singularity::NonFinite { speed: None } => {
                f.write_str("A(q) has an entry that is not a finite number")
            }
        }
    }
}

/// `?` takes a [`Singularity`] into `Box<dyn std::error::Error>`.
impl std::error::Error for Singularity {}

/// A number in a message: four significant digits, exponent form only when very small or
/// large (`-0.2`, `3.8e-10`, `1.825`), where `{:e}` would print `-2e-1` and `{}` `0.00000001`.
pub struct Num(pub f64);

impl core::fmt::Display for Num {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let v = self.0;
        if v == 0.0 || !v.is_finite() {
            return write!(f, "{v}");
        }
        let trim = |s: String| -> String {
            match s.split_once('e') {
                Some((mantissa, exponent)) if mantissa.contains('.') => {
                    format!(
                        "{}e{exponent}",
                        mantissa.trim_end_matches('0').trim_end_matches('.')
                    )
                }
                Some(_) => s,
                None if s.contains('.') => {
                    s.trim_end_matches('0').trim_end_matches('.').to_string()
                }
                None => s,
            }
        };
        let magnitude = v.abs();
        if (1e-3..1e5).contains(&magnitude) {
            let decimals = (3 - magnitude.log10().floor() as i32).max(0) as usize;
            f.write_str(&trim(format!("{v:.decimals$}")))
        } else {
            f.write_str(&trim(format!("{v:.3e}")))
        }
    }
}

impl core::fmt::Debug for Error {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        core::fmt::Display::fmt(self, f)
    }
}

/// Why Newton's method found no configuration that satisfies a holonomic constraint (see
/// [`Error::Assembly`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AssemblyFailure {
    /// The constraint or its derivative is not a finite number at the configuration reached
    /// (a coordinate outside the constraint's domain, or a parameter that makes it infinite).
    NonFinite,
    /// The derivative of the constraints with respect to the dependent coordinates is
    /// singular: `pivot` is the vanishing pivot of its LU factorization, its row scaled to a
    /// largest entry of 1. The coordinate does not enter the constraint here, so Newton's
    /// method cannot move it.
    Singular { pivot: f64 },
    /// No step along Newton's direction, down to a 2⁻⁴⁰th of it, reduced the residual: the
    /// iteration is stuck where |f| is smallest but not zero.
    Stalled { iterations: usize },
    /// The residual still exceeded the tolerance after this many iterations.
    NoConvergence { iterations: usize },
}

impl core::fmt::Display for AssemblyFailure {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            AssemblyFailure::NonFinite => f.write_str("its value is not a finite number"),
            AssemblyFailure::Singular { pivot } => write!(
                f,
                "it does not depend on the coordinate it determines here (its derivative with \
                 respect to that coordinate is {} relative to the others)",
                Num(*pivot)
            ),
            AssemblyFailure::Stalled { iterations } => write!(
                f,
                "Newton's method got stuck after {iterations} iterations where the residual is \
                 smallest but not zero"
            ),
            AssemblyFailure::NoConvergence { iterations } => {
                write!(
                    f,
                    "Newton's method did not converge in {iterations} iterations"
                )
            }
        }
    }
}

/// Everything that can go wrong when building states and running simulations.
///
/// `Debug` prints the same message as `Display` (as anyhow's errors do): `fn main() ->
/// Result<(), hamel::Error>` and `unwrap` print an error with `Debug`, and a user reads the
/// message there, not the variant's fields. Match on the variant for the values.
#[derive(Clone, PartialEq, thiserror::Error)]
pub enum Error {
    #[error("parameter `{name}` is {}: parameters must be finite numbers", Num(*value))]
    InvalidParameter { name: String, value: f64 },

    #[error("unknown parameter `{name}`; the parameters are: {known}")]
    UnknownParameter { name: String, known: String },

    #[error("initial value of `{name}` is {}: it must be a finite number", Num(*value))]
    NonFiniteInitialValue { name: String, value: f64 },

    #[error(
        "the initial velocities violate constraint `{name}`: its residual is {}, more than the \
         tolerance {}; choose velocities that satisfy the constraints, or start from the \
         quasi-velocities with `state_from_speeds`", Num(*residual), Num(*tolerance)
    )]
    ConstraintViolation {
        name: String,
        residual: f64,
        tolerance: f64,
    },

    #[error(
        "singular reduced mass matrix at t = {}: the motion along `{speed}` has no inertia here \
         (its pivot in the LDLᵀ factorization, {}, is zero to rounding beside the matrix's \
         trace); check the kinetic energy, or whether the model's geometry degenerates at this \
         configuration; state: {state}",
        Num(*t), Num(*value)
    )]
    SingularMassMatrix {
        t: f64,
        speed: String,
        value: f64,
        state: NamedValues,
    },

    /// The reduced mass matrix became singular during a run because the inertia of the motion
    /// along `speed` grew without bound: its diagonal entry is `value`, `growth` times what it
    /// was at the start, while the other speeds' pivots stayed what they were and became zero
    /// to rounding beside it. The model's geometry degenerates here (a slope or lever arm
    /// that becomes infinite).
    #[error(
        "the inertia of the motion along `{speed}` grows without bound at t = {}: its entry in \
         the reduced mass matrix is {}, {} times its value at the start, and the other speeds' \
         pivots are zero to rounding beside it; the model's geometry degenerates here (a slope \
         or a lever arm that becomes infinite): end the run before, or change the coordinates \
         or the model there; state: {state}",
        Num(*t), Num(*value), Num(*growth)
    )]
    UnboundedInertia {
        t: f64,
        speed: String,
        value: f64,
        growth: f64,
        state: NamedValues,
    },

    #[error(
        "singular velocity transformation at t = {}: the constraints and quasi-velocities do not \
         determine the velocity of `{coordinate}` at this configuration (the LU pivot of A(q) for it \
         is {}); choose quasi-velocities that complete the constraints here; state: {state}",
        Num(*t), Num(*value)
    )]
    SingularTransformation {
        t: f64,
        coordinate: String,
        value: f64,
        state: NamedValues,
    },

    #[error(
        "the `#[velocities]` function is not the inverse of the constraints and quasi-velocities: \
         A(q)·B(q) differs from the identity by {} at {configuration}", Num(*defect)
    )]
    InverseMismatch {
        defect: f64,
        configuration: NamedValues,
    },

    /// An adaptive step fell below the smallest the integration may take at t (a few ulps
    /// of t, and the method's `min_step`): whether or not steps were taken before it.
    #[error(
        "step size underflow at t = {}: a step of {} is below the smallest step the \
         integration may take there; the solution may have a singularity near t, or the \
         tolerance ask for more than `f64` can give; state: {state}",
        Num(*t), Num(*h)
    )]
    StepSizeUnderflow { t: f64, h: f64, state: NamedValues },

    /// The simplified Newton iteration that solves an implicit method's stage equations did
    /// not converge within a step from (t, `state`), even with the Jacobian evaluated afresh
    /// at the step's start — and for an adaptive method, not after the step was reduced
    /// again and again: the step is too large for how fast the right-hand side changes, the
    /// right-hand side is not smooth there, or the Jacobian is not the right-hand side's.
    /// `iterations` is the number of iterations of the last attempt, `increment` its last
    /// scaled increment of the stage values, `rate` its observed contraction factor (≥ 1:
    /// diverging).
    #[error(
        "the implicit stage equations did not converge at t = {} with a step of {}: after \
         {iterations} Newton iterations the stages still change by {} (relative to their \
         size), each increment {} times the one before (diverging when above 1); use a smaller \
         step (or a tolerance for an adaptive method), check that the right-hand side is \
         smooth here, and that a hand-written Jacobian (`Ode::jacobian`) is the right-hand \
         side's; state: {state}",
        Num(*t), Num(*h), Num(*increment), Num(*rate)
    )]
    NewtonNotConverged {
        t: f64,
        h: f64,
        iterations: usize,
        increment: f64,
        rate: f64,
        state: NamedValues,
    },

    /// The iteration matrix I − h·(A ⊗ J) of an implicit method's stage equations (or
    /// Radau5's error estimate's) is singular at (t, `state`) for the step h: ∂f/∂x has the
    /// eigenvalue λ = `growth` ± `frequency`·i with h·μ·λ = 1 for an eigenvalue μ of the
    /// method's matrix A. That needs Re λ > 0: a motion that grows as e^(λt), on about the
    /// time scale of the step. A stable stiff system never makes the matrix singular, however
    /// large the step.
    #[error(
        "the implicit method's iteration matrix I − h·A⊗∂f/∂x is singular at t = {} with a step \
         of {}: ∂f/∂x has the eigenvalue {} ± {}i, a motion that grows by a factor e every {} \
         s, and the step meets it; use a step well below that time scale (a smaller `step`, \
         or `with_max_step` for an adaptive method), or check the model for the instability; \
         state: {state}",
        Num(*t), Num(*h), Num(*growth), Num(frequency.abs()), Num(1.0 / *growth)
    )]
    SingularIterationMatrix {
        t: f64,
        h: f64,
        growth: f64,
        frequency: f64,
        state: NamedValues,
    },

    /// The span to integrate is shorter than an adaptive step can resolve at its start time:
    /// refused before the first step (not reported as a step that shrank).
    #[error(
        "the span from t = {} to t = {} ({}) is too short to integrate: at this time a step \
         must exceed 16 ulps of t ({}); end later, or take the initial state as the result; \
         state: {state}",
        Num(*t0), Num(*t_end), Num(*t_end - *t0), Num(16.0 * f64::EPSILON * t0.abs())
    )]
    SpanTooShort {
        t0: f64,
        t_end: f64,
        state: NamedValues,
    },

    /// An integration used up its steps (`with_max_steps`) before the end, or — `planned` —
    /// its fixed or largest step would need more of them than the limit allows for the span,
    /// which is refused before the first step (then `steps` is the number needed, saturated
    /// at `usize::MAX`).
    #[error("{}", Error::too_many_steps_message(*t, *steps, *h, *planned, state))]
    TooManySteps {
        t: f64,
        steps: usize,
        h: f64,
        planned: bool,
        state: NamedValues,
    },

    #[error("the state became non-finite at t = {}: {state}", Num(*t))]
    NonFiniteState { t: f64, state: NamedValues },

    /// The right-hand side returned a value that is not a number (`value`, NaN) for the rate
    /// of the component `rate` at (t, `state`), a finite state: an integration that met it
    /// where no smaller step avoided it ends here, rather than with a step that shrank to
    /// nothing (a step-size underflow) or a Newton iteration that failed, which would blame
    /// the method.
    #[error(
        "the right-hand side returned {} for the rate of `{rate}` at t = {}, in a state \
         whose components are all finite; check the model's equations (a division by zero, \
         a square root or logarithm of a negative number, an overflow) at this state; \
         state: {state}",
        Num(*value), Num(*t)
    )]
    NonFiniteRate {
        t: f64,
        rate: String,
        value: f64,
        state: NamedValues,
    },

    #[error("invalid setting `{name}` = {}: {reason}", Num(*value))]
    InvalidSetting {
        name: &'static str,
        value: f64,
        reason: &'static str,
    },

    /// A run's span and sample interval give more samples than its limit
    /// (`Simulation::max_samples`): refused before the run, which would not end in any
    /// useful time.
    #[error(
        "samples every {} over a span of {} would be {} samples, more than the limit {} \
         (`max_samples`); sample less often, shorten the run or raise the limit",
        Num(*interval), Num(*span), Num(*samples), Num(*limit as f64)
    )]
    TooManySamples {
        interval: f64,
        span: f64,
        samples: f64,
        limit: u64,
    },

    /// A parameter table or a study's table (CSV) is malformed: `line` is its line (the
    /// header is line 1), `column` the column's name (empty when the line as a whole is
    /// wrong).
    #[error("{}", Error::table_message(file, *line, column, problem))]
    Table {
        file: String,
        line: usize,
        column: String,
        problem: String,
    },

    /// A shard specification `i/n` that is not one: `i` and `n` whole numbers, 0 ≤ i < n.
    #[error(
        "the shard `{spec}` {reason}: a shard is `i/n`, the i-th of n equal parts of the \
         table's rows, counted from 0 (`--shard 0/8` … `--shard 7/8`)"
    )]
    InvalidShard { spec: String, reason: &'static str },

    /// A case of a study panicked; the study went on without it.
    #[error("case {case} panicked: {message}")]
    CasePanicked { case: usize, message: String },

    /// A study's progress callback panicked: the study stopped, no case starting after it.
    #[error(
        "the study's progress callback panicked: {message}; the study was stopped (fix the \
         callback given to `on_progress`, or run without it)"
    )]
    ProgressPanicked { message: String },

    /// A name that cannot be a column's: an output's (`Simulation::output`), a study's
    /// parameter's or output's, or a table's column's (`kind` says which).
    #[error("the {kind} name {name:?} cannot name a column: {reason}")]
    InvalidColumnName {
        kind: &'static str,
        name: String,
        reason: &'static str,
    },

    #[error("cannot write {path}: {message}")]
    Io { path: String, message: String },

    /// A file could not be read: missing, unreadable, or not what it should be.
    #[error("cannot read {path}: {message}")]
    Read { path: String, message: String },

    /// A case of a study failed for a reason of its own (a reversal that never came, no
    /// stable range in the scan): `kind` groups such failures in the study's table
    /// (`error_kind`), `message` says what happened to the study's user.
    #[error("{message}")]
    CaseFailed { kind: String, message: String },

    /// Newton's method found no value of a dependent coordinate that satisfies its holonomic
    /// constraint, starting from the values in `configuration` (the configuration given to
    /// `assemble`, or the state after an integrator step when projecting).
    #[error(
        "cannot satisfy the holonomic constraint `{constraint}` at t = {}: {failure} (residual {}); \
         start from a better value of `{coordinate}`, the coordinate it determines, or check the \
         other coordinates, for which the constraint may have no solution; start: {configuration}",
        Num(*t), Num(*residual)
    )]
    Assembly {
        /// The constraint's name (one of the last `K` of `HamelSystem::CONSTRAINTS`).
        constraint: String,
        /// The dependent coordinate Newton's method solved for.
        coordinate: String,
        t: f64,
        failure: AssemblyFailure,
        /// The constraint's residual f(t, q) where the iteration stopped.
        residual: f64,
        configuration: NamedValues,
    },

    /// A configuration given to `state_from_velocities` or `state_from_speeds` does not
    /// satisfy a holonomic constraint.
    #[error(
        "the configuration violates the holonomic constraint `{constraint}` at t = {}: its residual \
         is {}, more than the tolerance {}; solve `{coordinate}`, the coordinate it determines, \
         with `assemble`, or build the state with `state_builder`, which does; configuration: \
         {configuration}",
        Num(*t), Num(*residual), Num(*tolerance)
    )]
    HolonomicViolation {
        constraint: String,
        coordinate: String,
        t: f64,
        residual: f64,
        tolerance: f64,
        configuration: NamedValues,
    },

    /// A hand-written `HamelSystem` whose constants and types disagree (generated code cannot
    /// produce this).
    #[error(
        "the model's implementation of `HamelSystem` is inconsistent: {what}; `#[hamel_system]` \
         generates consistent ones, so fix the hand-written implementation"
    )]
    InconsistentModel { what: String },

    /// A state builder was given a name that is neither a coordinate nor a speed.
    #[error("unknown name `{name}`: a state is set by the names of its {known}")]
    UnknownStateName { name: String, known: String },

    /// `HamelSystem::linearize` was given a time, state component or input that is not a
    /// finite number (`name` is `t`, a state name or an input name).
    #[error("the operating point's `{name}` is {}: a linearization needs finite values", Num(*value))]
    NonFiniteOperatingPoint {
        /// `t`, or the name of the state component or input.
        name: String,
        /// The value given.
        value: f64,
    },

    /// A function of a system was given a time, state component or input that is not a
    /// finite number.
    #[error("`{function}` was given `{name}` = {}: it needs finite numbers", Num(*value))]
    NonFiniteArgument {
        /// The function called (`constraint_forces`).
        function: &'static str,
        /// `t`, or the name of the state component or input.
        name: String,
        value: f64,
    },

    /// The inputs of a run (its input function, or the constant inputs given) are not finite
    /// numbers at time `t`.
    #[error(
        "the input `{name}` is {} at t = {}: the inputs of a run must be finite numbers; check \
         the input function (or the constant inputs) at this time and state; state: {state}",
        Num(*value), Num(*t)
    )]
    NonFiniteInput {
        /// The input's name.
        name: String,
        value: f64,
        t: f64,
        state: NamedValues,
    },

    /// A derivative of a linearization is not a finite number: the model is not
    /// differentiable at the operating point (a square root at 0, say), or overflows there.
    #[error(
        "{of} has the derivative {} with respect to `{by}` {at}: a linearization needs \
         finite derivatives; the model may not be differentiable there, or overflow",
        Num(*value)
    )]
    NonFiniteDerivative {
        /// What is differentiated: "the rate of `v`", or a holonomic constraint.
        of: String,
        /// The state or input it is differentiated by.
        by: String,
        /// The derivative (infinite or NaN).
        value: f64,
        /// Where: the operating point, or the matrix given to `Linearization::new`.
        at: String,
    },

    /// A linearization or mode was asked for a state or input it does not have.
    #[error("unknown {kind} `{name}`; the {kind}s are: {known}")]
    UnknownName {
        /// "state" or "input".
        kind: &'static str,
        /// The name asked for.
        name: String,
        /// The names there are, comma-separated.
        known: String,
    },

    /// The same name was given twice where each must appear once.
    #[error("the {kind} `{name}` is given twice: {context}")]
    DuplicateName {
        /// "state" or "input".
        kind: &'static str,
        /// The name given twice.
        name: String,
        /// Where: what the names are for.
        context: &'static str,
    },

    /// Matrices or names whose sizes do not fit together.
    #[error("sizes do not fit: {what}")]
    DimensionMismatch {
        /// The sizes given and those needed.
        what: String,
    },

    /// `Linearization::reduce` was asked to drop a state that a kept state depends on.
    #[error(
        "cannot drop `{name}`: the rate of the kept state `{kept}` depends on it (the derivative \
         is {}, beyond the tolerance {} for rounding), so it is neither cyclic nor a coordinate \
         a holonomic constraint determines; keep `{name}`, or drop `{kept}` too",
        Num(*derivative), Num(*tolerance)
    )]
    NotCyclic {
        /// The state asked to be dropped.
        name: String,
        /// The first kept state whose rate depends on it.
        kept: String,
        /// ∂(rate of `kept`)/∂`name`, after any dependent coordinates dropped with it are
        /// eliminated.
        derivative: f64,
        /// The largest derivative taken for rounding (`CYCLIC_TOLERANCE` times the largest
        /// |Aᵢⱼ|).
        tolerance: f64,
    },

    /// `Linearization::reduce` cannot eliminate a dependent coordinate: at the operating point
    /// the holonomic constraints it is eliminated with do not determine it.
    #[error(
        "cannot eliminate `{coordinate}` through the holonomic constraint `{constraint}`: at the \
         operating point the constraints do not determine it (the LU pivot for it is {}, \
         relative to the constraint's largest derivative); keep `{coordinate}`",
        Num(*pivot)
    )]
    SingularElimination {
        /// The dependent coordinate to eliminate.
        coordinate: String,
        /// The holonomic constraint that determines it.
        constraint: String,
        /// The LU pivot for it, its constraint row scaled to a largest derivative of 1.
        pivot: f64,
    },

    /// nalgebra's Schur or singular value decomposition gave no answer for a linearization's
    /// modes, or an eigenvalue is too large for an `f64`.
    #[error("no eigen-analysis of A: {reason}")]
    EigenAnalysis {
        /// Which, and why.
        reason: String,
    },

    /// A state builder was given both velocities and speeds.
    #[error(
        "both the velocities and the speed `{speed}` were given: the speeds follow from the \
         velocities, so give either the velocities or the speeds"
    )]
    AmbiguousState { speed: String },

    /// A root finder was given an interval whose ends do not bracket a sign change.
    #[error("{}", Error::bracket_message(what, *a, *b, *fa, *fb))]
    RootNotBracketed {
        what: &'static str,
        a: f64,
        b: f64,
        fa: f64,
        fb: f64,
    },

    /// The function whose root is sought is not finite inside its bracket.
    #[error("{what} is not finite at {}, inside the interval where its sign change is sought", Num(*at))]
    NonFiniteRootFunction { what: &'static str, at: f64 },

    /// The root finder did not converge (a function that is not continuous in its bracket).
    #[error(
        "cannot locate where {what} changes sign: near {} it is still {}; the function may jump \
         there rather than pass through zero",
        Num(*near), Num(*residual)
    )]
    RootNotFound {
        what: &'static str,
        near: f64,
        residual: f64,
    },

    /// An event function returned a value that is not finite.
    #[error(
        "the event function `{name}` is {} at t = {}: event functions must be finite along the \
         run; state: {state}", Num(*value), Num(*t)
    )]
    NonFiniteEvent {
        name: String,
        t: f64,
        value: f64,
        state: NamedValues,
    },

    /// The reduced mass matrix is indefinite at a state: a pivot of its LDLᵀ factorization
    /// is negative beyond rounding. Met by a run (at the time it is met, the start time for a
    /// matrix indefinite from the start) or when a state is built.
    #[error(
        "the reduced mass matrix is not positive definite at t = {}: the kinetic energy of a \
         motion along `{speed}` (with the speeds before it) is negative, its pivot in the LDLᵀ \
         factorization being {}; no physical parameters give that: check the parameters for a \
         negative mass or moment of inertia (or one too small for the others), then the \
         kinetic energy; state: {state}",
        Num(*t), Num(*value)
    )]
    IndefiniteMassMatrix {
        t: f64,
        /// The speed whose pivot is negative (the first, in the order of the speeds).
        speed: String,
        /// The pivot.
        value: f64,
        state: NamedValues,
    },

    /// A body of the model (`#[bodies]`) has a mass or an inertia no matter gives: refused
    /// when a state is built and when a run starts.
    #[error(
        "body `{body}` is not a physical rigid body: {reason}; check the parameters its mass \
         and inertia are made of"
    )]
    UnphysicalBody { body: String, reason: String },

    /// A singular velocity transformation or mass matrix met where an orientation of three
    /// turns (Euler or Tait–Bryan angles) is at its own singularity: two of its turns are
    /// about one axis, and its angular velocity does not determine their rates. No choice of
    /// quasi-velocities helps; a quaternion orientation has no singularity.
    #[error(
        "{cause}. Here the orientation `{orientation}` is at its singularity: two of its turns \
         are about one axis, so its angular velocity does not determine their rates, whatever \
         the quasi-velocities; orient the body by a quaternion, `Rotation3::from_quaternion(w, \
         x, y, z)` with the row q·q̇ = 0 in `#[constraints]` (hamel::docs::geometry, \
         \"Choosing an orientation parametrization\"), or keep the motion away from it"
    )]
    SingularOrientation {
        /// The orientation as the model writes it, by the coordinates' names.
        orientation: String,
        /// The singularity met.
        cause: Box<Error>,
    },

    /// A body's orientation or shape, or a contact's surface, is no geometry a body can
    /// have (a radius that is not positive, a frame that is not a rotation, a ball larger
    /// than its bowl, a contact point that does not exist): refused when a state is built,
    /// when a run starts and when the model is linearized.
    #[error("{what} is impossible: {reason}")]
    ImpossibleGeometry { what: String, reason: String },

    /// No input acts on an output within the order of Lie derivatives the model generates
    /// (`control(order = k)`): every L_{g_j} L_f^i h of the output, i < k, is zero at the
    /// state, so its relative degree is larger than k, or not defined there.
    #[error(
        "no input acts on the output `{output}` through its first {order} derivatives along the \
         motion at t = {}: every L_g L_f^i h of it, i < {order}, is zero here, so its relative \
         degree exceeds {order} (generate more with `control(order = ..)`) or is not defined at \
         this state; state: {state}",
        Num(*t)
    )]
    RelativeDegree {
        output: String,
        order: usize,
        t: f64,
        state: NamedValues,
    },

    /// The decoupling matrix A(x) = (L_{g_j} L_f^{r_i − 1} h_i) is singular to rounding: the
    /// outputs cannot be steered independently at this state, and the exact linearization
    /// u = A⁻¹(v − b) does not exist there.
    #[error(
        "the decoupling matrix L_g L_f^(r-1) h is singular at t = {}: its singular values are \
         {} (ratio {} of the smallest to the largest, at most {} counts as singular), so the \
         outputs cannot be steered independently here; choose other outputs or keep the motion \
         away from this state; state: {state}",
        Num(*t), Error::list(singular_values), Num(Error::ratio(singular_values)), Num(*tolerance)
    )]
    SingularDecoupling {
        t: f64,
        state: NamedValues,
        /// The decoupling matrix's singular values, largest first.
        singular_values: Vec<f64>,
        /// The ratio of the smallest to the largest below which it counts as singular.
        tolerance: f64,
    },

    /// The algebraic Riccati equation has no stabilizing solution (or none was found to
    /// rounding): (A, B) is not stabilizable, or (Q, A) has a mode on the imaginary axis that
    /// Q does not see.
    #[error(
        "the Riccati equation A'P + PA - PBR^-1B'P + Q = 0 has no stabilizing solution: {reason}"
    )]
    NoStabilizingSolution {
        /// What was found instead.
        reason: String,
    },

    /// A weight matrix of a linear-quadratic design is not what the design needs.
    #[error("the weight matrix {matrix} {reason}")]
    InvalidWeights {
        /// "Q" or "R".
        matrix: &'static str,
        /// What is wrong with it, and how to fix it.
        reason: String,
    },

    /// A reference trajectory for an output gives another number of values than the output
    /// needs: the value and its derivatives up to the output's relative degree.
    #[error(
        "the reference for the output `{output}` gives {given} values at t = {}; it needs \
         {expected}: the output's value and its derivatives up to its relative degree, {}",
        Num(*t), expected - 1
    )]
    InvalidReference {
        output: String,
        expected: usize,
        given: usize,
        t: f64,
    },

    /// The right-hand side met a value that is not a finite number in the matrices it
    /// factors: the reduced mass matrix (`speed` names the first speed whose pivot or diagonal
    /// entry is not finite) or A(q) (`speed` is `None`).
    #[error("{}", Error::non_finite_message(*t, speed.as_deref(), state))]
    NonFiniteDynamics {
        t: f64,
        speed: Option<String>,
        state: NamedValues,
    },
}

impl Error {
    /// Values for a message: `3.2, 1.5e-14`.
    fn list(values: &[f64]) -> String {
        values
            .iter()
            .map(|v| Num(*v).to_string())
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// The smallest over the largest of some non-negative values (0 when they are all 0).
    fn ratio(values: &[f64]) -> f64 {
        let largest = values.iter().fold(0.0f64, |m, v| m.max(*v));
        let smallest = values.iter().fold(f64::INFINITY, |m, v| m.min(*v));
        if largest > 0.0 {
            smallest / largest
        } else {
            0.0
        }
    }

    /// The message of [`Error::Table`], for `Display`.
    fn table_message(file: &str, line: usize, column: &str, problem: &str) -> String {
        if column.is_empty() {
            format!("{file}, line {line}: {problem}")
        } else {
            format!("{file}, line {line}, column `{column}`: {problem}")
        }
    }

    /// The message of [`Error::TooManySteps`], for `Display`.
    fn too_many_steps_message(
        t: f64,
        steps: usize,
        h: f64,
        planned: bool,
        state: &NamedValues,
    ) -> String {
        if planned {
            return format!(
                "steps of {} from t = {} would need {} steps to the end, more than the limit \
                 (`with_max_steps`); use a larger step or raise the limit; state: {state}",
                Num(h),
                Num(t),
                Num(steps as f64)
            );
        }
        format!(
            "the integration took {steps} steps and got only to t = {}, with steps of {}: the \
             solution may have a singularity near there, or the tolerance be too tight for the \
             span; loosen the tolerance, shorten the run or raise the limit with \
             `with_max_steps`; state: {state}",
            Num(t),
            Num(h)
        )
    }

    /// The message of [`Error::NonFiniteDynamics`], for `Display`.
    fn non_finite_message(t: f64, speed: Option<&str>, state: &NamedValues) -> String {
        let place = match speed {
            Some(speed) => format!("in the reduced mass matrix, for `{speed}`"),
            None => "in the matrix A(q) of the constraints and quasi-velocities".to_string(),
        };
        format!(
            "the right-hand side produced a value that is not a finite number at t = {} ({place}): \
             the state is likely outside the model's geometry (a square root of a negative \
             number, a division by zero there), or a parameter makes a division by zero; state: \
             {state}",
            Num(t)
        )
    }
}
