//! The C types of FMI 2.0 (`fmi2TypesPlatform.h`, `fmi2FunctionTypes.h`), as the standard
//! defines them for the "default" platform: `fmi2Real` is `double`, `fmi2Integer` and
//! `fmi2Boolean` are `int`, `fmi2ValueReference` is `unsigned int`, strings are `const char*`.

use core::ffi::{c_char, c_int, c_uint, c_void};

pub type Component = *mut c_void;
pub type ComponentEnvironment = *mut c_void;
pub type FmuState = *mut c_void;
pub type ValueReference = c_uint;
pub type Real = f64;
pub type Integer = c_int;
pub type Boolean = c_int;
pub type Text = *const c_char;
pub type Byte = c_char;

pub const TRUE: Boolean = 1;
pub const FALSE: Boolean = 0;

/// `fmi2Status`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Status {
    Ok = 0,
    Warning = 1,
    Discard = 2,
    Error = 3,
    Fatal = 4,
    Pending = 5,
}

impl Status {
    /// The standard's name, for messages.
    pub fn name(self) -> &'static str {
        match self {
            Status::Ok => "fmi2OK",
            Status::Warning => "fmi2Warning",
            Status::Discard => "fmi2Discard",
            Status::Error => "fmi2Error",
            Status::Fatal => "fmi2Fatal",
            Status::Pending => "fmi2Pending",
        }
    }
}

/// `fmi2Type`: which interface an instance serves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interface {
    ModelExchange,
    CoSimulation,
}

impl Interface {
    /// From `fmi2Type` (0: Model Exchange, 1: Co-Simulation); `None` for anything else.
    pub fn from_c(value: c_int) -> Option<Interface> {
        match value {
            0 => Some(Interface::ModelExchange),
            1 => Some(Interface::CoSimulation),
            _ => None,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Interface::ModelExchange => "Model Exchange",
            Interface::CoSimulation => "Co-Simulation",
        }
    }
}

/// `fmi2StatusKind`, the question of `fmi2Get*Status`.
pub type StatusKind = c_int;
pub const DO_STEP_STATUS: StatusKind = 0;
pub const PENDING_STATUS: StatusKind = 1;
pub const LAST_SUCCESSFUL_TIME: StatusKind = 2;
pub const TERMINATED: StatusKind = 3;

/// `fmi2CallbackLogger`: `(environment, instanceName, status, category, message, ...)`. The
/// message is a printf format; this FMU formats its messages itself and passes them with
/// every `%` doubled and no further arguments.
pub type Logger = unsafe extern "C" fn(ComponentEnvironment, Text, Status, Text, Text, ...);

/// `fmi2CallbackFunctions`. The memory functions are not used: the FMU allocates with Rust's
/// allocator (`canNotUseMemoryManagementFunctions="true"`).
#[repr(C)]
pub struct CallbackFunctions {
    pub logger: Option<Logger>,
    pub allocate_memory: Option<unsafe extern "C" fn(usize, usize) -> *mut c_void>,
    pub free_memory: Option<unsafe extern "C" fn(*mut c_void)>,
    pub step_finished: Option<unsafe extern "C" fn(ComponentEnvironment, Status)>,
    pub component_environment: ComponentEnvironment,
}

/// `fmi2EventInfo`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct EventInfo {
    pub new_discrete_states_needed: Boolean,
    pub terminate_simulation: Boolean,
    pub nominals_of_continuous_states_changed: Boolean,
    pub values_of_continuous_states_changed: Boolean,
    pub next_event_time_defined: Boolean,
    pub next_event_time: Real,
}
