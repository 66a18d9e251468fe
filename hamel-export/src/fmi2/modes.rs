//! The state machine of an instance (FMI 2.0, sections 3.2.3 and 4.2.4): the modes, the
//! functions, and in which modes each function may be called. The table follows the
//! standard's, as the Modelica Association's reference FMUs implement it; a call in any other
//! mode is refused with `fmi2Error` and a message that names the mode.

use super::types::Interface;

/// Where an instance is in its life.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    Instantiated,
    Initialization,
    /// Model Exchange: event mode (after initialization and at events).
    Event,
    /// Model Exchange: continuous-time mode (the importer integrates).
    Continuous,
    /// Co-Simulation: between communication steps.
    StepComplete,
    /// Co-Simulation: `fmi2DoStep` returned `fmi2Discard`.
    StepFailed,
    Terminated,
    /// A call returned `fmi2Error`: only reading values, `fmi2Reset` and `fmi2FreeInstance`
    /// remain.
    Error,
}

impl Mode {
    #[inline]
    const fn bit(self) -> u16 {
        1 << self as u16
    }

    /// The mode as the standard names it, for messages.
    pub fn describe(self) -> &'static str {
        match self {
            Mode::Instantiated => "instantiated (before fmi2EnterInitializationMode)",
            Mode::Initialization => "initialization mode",
            Mode::Event => "event mode",
            Mode::Continuous => "continuous-time mode",
            Mode::StepComplete => "step complete",
            Mode::StepFailed => "step failed (fmi2DoStep returned fmi2Discard)",
            Mode::Terminated => "terminated",
            Mode::Error => "error (a call returned fmi2Error; fmi2Reset or fmi2FreeInstance)",
        }
    }
}

const fn any(modes: &[Mode]) -> u16 {
    let mut mask = 0;
    let mut i = 0;
    while i < modes.len() {
        mask |= modes[i].bit();
        i += 1;
    }
    mask
}

use Mode::*;

const EVERY: u16 = any(&[
    Instantiated,
    Initialization,
    Event,
    Continuous,
    StepComplete,
    StepFailed,
    Terminated,
    Error,
]);
const READ: u16 = any(&[
    Initialization,
    Event,
    Continuous,
    StepComplete,
    StepFailed,
    Terminated,
    Error,
]);

/// The functions that take an instance.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Function {
    SetDebugLogging,
    SetupExperiment,
    EnterInitializationMode,
    ExitInitializationMode,
    Terminate,
    Reset,
    GetReal,
    GetInteger,
    GetBoolean,
    GetString,
    SetReal,
    SetInteger,
    SetBoolean,
    SetString,
    FmuState,
    GetDirectionalDerivative,
    EnterEventMode,
    NewDiscreteStates,
    EnterContinuousTimeMode,
    CompletedIntegratorStep,
    SetTime,
    SetContinuousStates,
    GetDerivatives,
    GetEventIndicators,
    GetContinuousStates,
    GetNominalsOfContinuousStates,
    SetRealInputDerivatives,
    GetRealOutputDerivatives,
    DoStep,
    CancelStep,
    GetStatus,
}

impl Function {
    /// The modes the function may be called in.
    #[inline]
    pub fn allowed(self) -> u16 {
        use Function::*;
        match self {
            SetDebugLogging | Reset | FmuState => EVERY,
            SetupExperiment | EnterInitializationMode => any(&[Instantiated]),
            ExitInitializationMode => any(&[Initialization]),
            Terminate => any(&[Event, Continuous, StepComplete, StepFailed]),
            GetReal | GetInteger | GetBoolean | GetString => READ,
            SetReal => any(&[
                Instantiated,
                Initialization,
                Event,
                Continuous,
                StepComplete,
            ]),
            SetInteger | SetBoolean | SetString => {
                any(&[Instantiated, Initialization, Event, StepComplete])
            }
            GetDirectionalDerivative => any(&[
                Initialization,
                Event,
                Continuous,
                StepComplete,
                StepFailed,
                Terminated,
            ]),
            EnterEventMode => any(&[Event, Continuous]),
            NewDiscreteStates | EnterContinuousTimeMode => any(&[Event]),
            CompletedIntegratorStep | SetContinuousStates => any(&[Continuous]),
            SetTime => any(&[Event, Continuous]),
            GetDerivatives | GetEventIndicators | GetContinuousStates => {
                any(&[Initialization, Event, Continuous, Terminated])
            }
            GetNominalsOfContinuousStates => any(&[Instantiated, Event, Continuous, Terminated]),
            SetRealInputDerivatives => any(&[Instantiated, Initialization, StepComplete]),
            GetRealOutputDerivatives => any(&[StepComplete, StepFailed, Terminated]),
            DoStep => any(&[StepComplete]),
            // Never pending: fmi2DoStep is synchronous.
            CancelStep => 0,
            GetStatus => any(&[StepComplete, StepFailed, Terminated]),
        }
    }

    /// The interface the function belongs to (`None`: both).
    #[inline]
    pub fn interface(self) -> Option<Interface> {
        use Function::*;
        match self {
            EnterEventMode
            | NewDiscreteStates
            | EnterContinuousTimeMode
            | CompletedIntegratorStep
            | SetTime
            | SetContinuousStates
            | GetDerivatives
            | GetEventIndicators
            | GetContinuousStates
            | GetNominalsOfContinuousStates => Some(Interface::ModelExchange),
            SetRealInputDerivatives
            | GetRealOutputDerivatives
            | DoStep
            | CancelStep
            | GetStatus => Some(Interface::CoSimulation),
            _ => None,
        }
    }

    /// Whether a call is allowed in `mode` for an instance of `interface`.
    #[inline]
    pub fn permits(self, interface: Interface, mode: Mode) -> bool {
        self.interface().is_none_or(|own| own == interface) && self.allowed() & mode.bit() != 0
    }

    /// Why a call is refused in `mode` for an instance of `interface`, if it is.
    pub fn refusal(self, name: &str, interface: Interface, mode: Mode) -> Option<String> {
        if let Some(own) = self.interface() {
            if own != interface {
                return Some(format!(
                    "{name} is a function of {}; this instance was instantiated for {}",
                    own.name(),
                    interface.name()
                ));
            }
        }
        if self.allowed() & mode.bit() == 0 {
            return Some(format!(
                "{name} may not be called in the instance's present mode: {}",
                mode.describe()
            ));
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn calls_out_of_order_are_refused() {
        let me = Interface::ModelExchange;
        assert!(Function::DoStep.refusal("fmi2DoStep", me, Event).is_some());
        assert!(
            Function::GetDerivatives
                .refusal("fmi2GetDerivatives", me, Instantiated)
                .is_some()
        );
        assert!(
            Function::GetDerivatives
                .refusal("fmi2GetDerivatives", me, Continuous)
                .is_none()
        );
        assert!(Function::Reset.refusal("fmi2Reset", me, Error).is_none());
        assert!(
            Function::SetReal
                .refusal("fmi2SetReal", me, Error)
                .is_some()
        );
        assert!(
            Function::GetReal
                .refusal("fmi2GetReal", me, Error)
                .is_none()
        );
    }
}
