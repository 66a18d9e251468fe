//! One instance of the FMU: the model with its parameters, the time, state and inputs, the
//! experiment's settings and the mode; and reading and writing its variables by value
//! reference, each refused with a reason where the standard does not allow it.
//!
//! Instances share nothing: two robots with different parameters run side by side in one
//! process.

use super::description::{DEFAULT_TOLERANCE, absolute_tolerance};
use super::logger::{Category, Logger};
use super::modes::Mode;
use super::types::{Interface, Status};
use super::variables::{self, DEFAULT_STEP, INTEGRATORS, Role, Table};
use crate::model::Model;
use crate::passes;
use crate::primal::Which;
use hamel_runtime::{HamelSystem, Parameters, Singularity, Vector};

pub type State<M> = <<M as Model>::System as HamelSystem>::State;
pub type Inputs<M> = <<M as Model>::System as HamelSystem>::Inputs;

/// Why a call did not succeed: `fmi2Discard` (the model cannot be evaluated there, the step
/// could not be completed) or `fmi2Error`, with the message for the logger.
#[derive(Clone, Debug, PartialEq)]
pub struct Refusal {
    pub status: Status,
    pub message: String,
}

impl Refusal {
    pub fn error(message: impl Into<String>) -> Refusal {
        Refusal {
            status: Status::Error,
            message: message.into(),
        }
    }

    pub fn discard(message: impl Into<String>) -> Refusal {
        Refusal {
            status: Status::Discard,
            message: message.into(),
        }
    }
}

pub type Outcome = Result<(), Refusal>;

/// What `fmi2SetupExperiment` said.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Experiment {
    pub tolerance: Option<f64>,
    pub start: f64,
    pub stop: Option<f64>,
}

/// Co-Simulation's memory between communication steps.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stepping {
    /// The first step of the next `fmi2DoStep`: the largest the last one took.
    pub initial_step: Option<f64>,
    /// Where the last `fmi2DoStep` that failed left the state.
    pub last_successful_time: f64,
    /// Whether the model cannot go on (a step failed).
    pub terminated: bool,
}

pub struct Instance<M: Model> {
    pub interface: Interface,
    pub logger: Logger,
    pub mode: Mode,
    pub table: Table,
    pub system: M::System,
    /// The right-hand side's values that depend on the parameters alone, prepared whenever
    /// a parameter changes.
    pub prepared: Vec<f64>,
    pub t: f64,
    pub x: State<M>,
    pub u: Inputs<M>,
    pub experiment: Experiment,
    /// The Co-Simulation integrator: an index into [`INTEGRATORS`].
    pub method: usize,
    /// The fixed-step integrators' step.
    pub step: f64,
    pub stepping: Stepping,
}

/// Whether every value is finite. Their sum is finite only if each value is (an infinity or
/// a NaN among them makes it an infinity or a NaN), so a finite sum answers with one test;
/// a sum that is not finite is told apart from one that overflowed by testing each value.
/// Added in order, the values are read as the right-hand side stored them, 8 bytes at a
/// time: the test of each value's exponent bits is vectorized into 16-byte loads, which
/// straddle two of those stores and wait for them to reach the cache.
#[inline]
pub fn all_finite(values: &[f64]) -> bool {
    values.iter().fold(0.0, |sum, v| sum + v).is_finite() || each_finite(values)
}

#[cold]
#[inline(never)]
fn each_finite(values: &[f64]) -> bool {
    values.iter().all(|v| v.is_finite())
}

/// The error for a singularity met at (t, x).
pub fn singular<M: Model>(s: Singularity, t: f64, x: &State<M>) -> String {
    M::System::singular(s, t, x).to_string()
}

impl<M: Model> Instance<M> {
    pub fn new(interface: Interface, logger: Logger) -> Instance<M> {
        let system = M::System::default();
        let mut instance = Instance {
            interface,
            logger,
            mode: Mode::Instantiated,
            table: Table::of::<M>(),
            system,
            prepared: vec![0.0; <M::System as HamelSystem>::PREPARED_LEN],
            t: 0.0,
            x: State::<M>::zeros(),
            u: Inputs::<M>::zeros(),
            experiment: Experiment {
                tolerance: None,
                start: 0.0,
                stop: None,
            },
            method: 0,
            step: DEFAULT_STEP,
            stepping: Stepping::default(),
        };
        instance.prepare();
        instance
    }

    /// `fmi2Reset`: as just instantiated, with the same interface and logger.
    pub fn reset(&mut self) {
        let logger = std::mem::replace(
            &mut self.logger,
            Logger::new(None, core::ptr::null_mut(), "", false),
        );
        *self = Instance::new(self.interface, logger);
    }

    pub fn prepare(&mut self) {
        self.system.prepare(&mut self.prepared);
    }

    pub fn log(&self, status: Status, category: Category, message: &str) {
        self.logger.log(status, category, message);
    }

    /// The name of value reference `vr`'s variable, for messages.
    pub fn name(&self, role: Role) -> String {
        variables::name::<M>(role)
    }

    fn role(&self, vr: u32) -> Result<Role, Refusal> {
        self.table.role(vr).ok_or_else(|| {
            Refusal::error(format!(
                "unknown value reference {vr}: this FMU's variables have the value references \
                 0 to {}",
                self.table.roles.len() - 1
            ))
        })
    }

    /// Co-Simulation's tolerances: the importer's relative tolerance (fmi2SetupExperiment),
    /// else the default, and the absolute tolerance that goes with it.
    pub fn tolerances(&self) -> (f64, f64) {
        let rtol = self.experiment.tolerance.unwrap_or(DEFAULT_TOLERANCE);
        (rtol, absolute_tolerance(rtol))
    }

    /// The state the values are read from: before initialization is over, the start values
    /// with the dependent coordinates solved (what `fmi2ExitInitializationMode` will make
    /// them); afterwards the state itself.
    pub fn current(&self) -> Result<State<M>, Refusal> {
        match self.mode {
            Mode::Instantiated | Mode::Initialization if <M::System as HamelSystem>::K > 0 => {
                self.consistent()
            }
            _ => Ok(self.x),
        }
    }

    /// The start values with the coordinates the holonomic constraints determine solved
    /// for, from the start values as guesses (`HamelSystem::assemble`), and the state
    /// checked (`HamelSystem::state_from_speeds`: the parameters, the configuration, the
    /// mass matrix).
    pub fn consistent(&self) -> Result<State<M>, Refusal> {
        let q = M::System::coordinates_of(&self.x);
        let speeds = M::System::speeds_of(&self.x);
        let q = self
            .system
            .assemble(self.t, &q)
            .map_err(|e| Refusal::error(format!("the start values are not consistent: {e}")))?;
        self.system
            .state_from_speeds(self.t, &q, &speeds)
            .map_err(|e| Refusal::error(format!("the start values are not a valid state: {e}")))
    }

    /// ẋ at (t, x) with the inputs and parameters: the generated right-hand side, as a
    /// hamel simulation calls it. A singularity, or a value that is not finite, is
    /// `fmi2Discard` (the importer may try a smaller step).
    pub fn derivatives(&self, x: &State<M>) -> Result<State<M>, Refusal> {
        let mut dx = State::<M>::zeros();
        self.derivatives_into(x, &mut dx)?;
        Ok(dx)
    }

    /// [`Self::derivatives`] into `dx` (the importer's array, in `fmi2GetDerivatives`).
    #[inline]
    pub fn derivatives_into(&self, x: &State<M>, dx: &mut State<M>) -> Result<(), Refusal> {
        match self
            .system
            .rhs_prepared(&self.prepared, self.t, x, &self.u, dx)
        {
            Ok(()) if all_finite(dx.as_ref()) => Ok(()),
            outcome => Err(self.not_derivatives(x, dx, outcome.err())),
        }
    }

    /// Why the derivatives at x are not: a singularity, or a value that is not finite.
    #[cold]
    #[inline(never)]
    fn not_derivatives(&self, x: &State<M>, dx: &State<M>, s: Option<Singularity>) -> Refusal {
        if let Some(s) = s {
            return Refusal::discard(singular::<M>(s, self.t, x));
        }
        let i = dx.as_ref().iter().position(|v| !v.is_finite()).unwrap_or(0);
        Refusal::discard(format!(
            "der({}) = {} is not finite at t = {}, state {}",
            self.name(Role::State(i)),
            dx.as_ref()[i],
            self.t,
            M::System::named_state(x)
        ))
    }

    /// z = (x, u, p, t) for the generated code's parametric functions.
    pub fn point(&self, x: &State<M>) -> M::Array<f64> {
        let s = self.table.sizes;
        let mut z = M::array(0.0);
        let zs = z.as_mut();
        zs[..s.nx].copy_from_slice(x.as_ref());
        zs[s.u()..s.p()].copy_from_slice(self.u.as_ref());
        for (slot, name) in zs[s.p()..s.t()]
            .iter_mut()
            .zip(<M::System as Parameters>::NAMES)
        {
            *slot = self.system.get(name).unwrap_or(f64::NAN);
        }
        zs[s.t()] = self.t;
        z
    }

    /// The model's outputs y at x.
    pub fn outputs(&self, x: &State<M>) -> Result<M::Array<f64>, Refusal> {
        let mut y = M::array(0.0);
        passes::value::<M>(Which::Outputs, self.point(x).as_ref(), y.as_mut())
            .map_err(|f| Refusal::discard(f.message))?;
        Ok(y)
    }

    /// The energy, the constraint rows and the holonomic constraints at x, in the order of
    /// their value references.
    pub fn monitors(&self, system: &M::System, t: f64, x: &State<M>) -> Result<Vec<f64>, Refusal> {
        let energy = system
            .energy(t, x)
            .map_err(|s| Refusal::discard(singular::<M>(s, t, x)))?;
        let qd = system
            .generalized_velocities(t, x)
            .map_err(|s| Refusal::discard(singular::<M>(s, t, x)))?;
        let q = M::System::coordinates_of(x);
        let rows = system.constraint_residual(t, &q, &qd);
        let holonomic = system.holonomic_residual(t, &q);
        let mut out = vec![energy];
        out.extend_from_slice(rows.as_ref());
        out.extend_from_slice(holonomic.as_ref());
        Ok(out)
    }

    /// `fmi2GetReal`.
    pub fn get_real(&self, vrs: &[u32], values: &mut [f64]) -> Outcome {
        let x = self.current()?;
        // Each group is computed once per call, when the first of its variables is asked.
        let mut dx = None;
        let mut y = None;
        let mut monitors = None;
        for (vr, value) in vrs.iter().zip(values.iter_mut()) {
            *value = match self.role(*vr)? {
                Role::Time => self.t,
                Role::State(i) => x.as_ref()[i],
                Role::Derivative(i) => {
                    if dx.is_none() {
                        dx = Some(self.derivatives(&x)?);
                    }
                    dx.as_ref().map_or(f64::NAN, |d| d.as_ref()[i])
                }
                Role::Input(i) => self.u.as_ref()[i],
                Role::Parameter(i) => {
                    let name = <M::System as Parameters>::NAMES[i];
                    self.system.get(name).unwrap_or(f64::NAN)
                }
                Role::Output(i) => {
                    if y.is_none() {
                        y = Some(self.outputs(&x)?);
                    }
                    y.as_ref().map_or(f64::NAN, |y| y.as_ref()[i])
                }
                role @ (Role::Energy | Role::Constraint(_) | Role::Holonomic(_)) => {
                    if monitors.is_none() {
                        monitors = Some(self.monitors(&self.system, self.t, &x)?);
                    }
                    let at = match role {
                        Role::Constraint(i) => 1 + i,
                        Role::Holonomic(i) => 1 + self.table.p + i,
                        _ => 0,
                    };
                    monitors.as_ref().map_or(f64::NAN, |m| m[at])
                }
                Role::Step => self.step,
                Role::Integrator => {
                    return Err(Refusal::error(format!(
                        "{} is an enumeration: read it with fmi2GetInteger",
                        self.name(Role::Integrator)
                    )));
                }
            };
        }
        Ok(())
    }

    /// `fmi2SetReal`: start values before initialization, inputs at any time, tunable
    /// parameters outside continuous-time mode; every value finite.
    pub fn set_real(&mut self, vrs: &[u32], values: &[f64]) -> Outcome {
        let starting = matches!(self.mode, Mode::Instantiated | Mode::Initialization);
        let mut parameters_changed = false;
        for (vr, value) in vrs.iter().zip(values) {
            let role = self.role(*vr)?;
            let name = self.name(role);
            if !value.is_finite() {
                return Err(Refusal::error(format!(
                    "{name} = {value} is not a finite number"
                )));
            }
            match role {
                Role::State(i) if starting => self.x.as_mut()[i] = *value,
                Role::State(_) => {
                    return Err(Refusal::error(format!(
                        "{name} is a state: its start value is set before initialization; \
                         afterwards {}",
                        match self.interface {
                            Interface::ModelExchange => "fmi2SetContinuousStates sets it",
                            Interface::CoSimulation => "the FMU integrates it",
                        }
                    )));
                }
                Role::Input(i) => self.u.as_mut()[i] = *value,
                Role::Parameter(i) if self.mode != Mode::Continuous => {
                    let key = <M::System as Parameters>::NAMES[i];
                    self.system
                        .set(key, *value)
                        .map_err(|e| Refusal::error(e.to_string()))?;
                    parameters_changed = true;
                }
                Role::Parameter(_) => {
                    return Err(Refusal::error(format!(
                        "{name} is a tunable parameter: it changes at an event (fmi2EnterEventMode \
                         first), not in continuous-time mode"
                    )));
                }
                Role::Step if starting => {
                    if *value <= 0.0 {
                        return Err(Refusal::error(format!(
                            "{name} = {value}: the step must be positive"
                        )));
                    }
                    self.step = *value;
                }
                Role::Step => {
                    return Err(Refusal::error(format!(
                        "{name} is a fixed parameter: it is set before initialization"
                    )));
                }
                Role::Time => {
                    return Err(Refusal::error(
                        "time is the independent variable: fmi2SetupExperiment sets its start, \
                         fmi2SetTime (Model Exchange) or fmi2DoStep (Co-Simulation) moves it",
                    ));
                }
                Role::Integrator => {
                    return Err(Refusal::error(format!(
                        "{name} is an enumeration: set it with fmi2SetInteger"
                    )));
                }
                Role::Derivative(_)
                | Role::Output(_)
                | Role::Energy
                | Role::Constraint(_)
                | Role::Holonomic(_) => {
                    return Err(Refusal::error(format!(
                        "{name} is computed by the model and cannot be set"
                    )));
                }
            }
        }
        if parameters_changed {
            self.prepare();
        }
        Ok(())
    }

    /// `fmi2GetInteger`: the integrator.
    pub fn get_integer(&self, vrs: &[u32], values: &mut [i32]) -> Outcome {
        for (vr, value) in vrs.iter().zip(values.iter_mut()) {
            match self.role(*vr)? {
                Role::Integrator => *value = self.method as i32 + 1,
                role => return Err(not_integer(&self.name(role))),
            }
        }
        Ok(())
    }

    /// `fmi2SetInteger`: the integrator, before initialization.
    pub fn set_integer(&mut self, vrs: &[u32], values: &[i32]) -> Outcome {
        for (vr, value) in vrs.iter().zip(values) {
            let role = self.role(*vr)?;
            let name = self.name(role);
            if role != Role::Integrator {
                return Err(not_integer(&name));
            }
            if !matches!(self.mode, Mode::Instantiated | Mode::Initialization) {
                return Err(Refusal::error(format!(
                    "{name} is a fixed parameter: it is set before initialization"
                )));
            }
            let known: Vec<String> = INTEGRATORS
                .iter()
                .enumerate()
                .map(|(i, (n, _, _))| format!("{} ({n})", i + 1))
                .collect();
            let index = usize::try_from(*value)
                .ok()
                .and_then(|v| v.checked_sub(1))
                .filter(|i| *i < INTEGRATORS.len())
                .ok_or_else(|| {
                    Refusal::error(format!(
                        "{name} = {value} is not an integrator; they are {}",
                        known.join(", ")
                    ))
                })?;
            self.method = index;
        }
        Ok(())
    }
}

fn not_integer(name: &str) -> Refusal {
    Refusal::error(format!(
        "{name} is not an Integer or Enumeration variable (the only one is hamel.integrator)"
    ))
}

#[cfg(test)]
mod tests {
    use super::all_finite;

    #[test]
    fn all_finite_tells_an_overflowing_sum_from_a_value_that_is_not_finite() {
        assert!(all_finite(&[1.0, -2.0, 0.0]));
        assert!(all_finite(&[]));
        // The sum overflows; every value is finite.
        assert!(all_finite(&[f64::MAX, f64::MAX, -1.0]));
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            assert!(!all_finite(&[1.0, bad, 2.0]), "{bad}");
            assert!(!all_finite(&[f64::MAX, f64::MAX, bad]), "{bad}");
        }
        assert!(!all_finite(&[f64::INFINITY, f64::NEG_INFINITY]));
    }
}
