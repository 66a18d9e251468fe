//! The macro that exports the FMI 2.0 functions of a model from a crate of type `cdylib`.

/// `fmi2!(Marker, "MobileRobot")`: the functions of FMI 2.0 (Model Exchange and
/// Co-Simulation, unprefixed as a binary FMU's are) for the model of `Marker` (see
/// [`crate::model!`]), exported as the FMU whose model identifier is `"MobileRobot"`. At most
/// one per library: the symbols' names are the standard's. The FMU itself (the library with
/// `modelDescription.xml`) is written by `crate::fmi2::write_fmu` (feature `fmu`).
#[macro_export]
macro_rules! fmi2 {
    ($marker:ty, $identifier:literal) => {
        const _: () = {
            use $crate::fmi2::api;
            use $crate::fmi2::cosim;
            use $crate::fmi2::exchange;
            use $crate::fmi2::modes::Function;
            use $crate::fmi2::types::*;
            type M = $marker;

            #[unsafe(no_mangle)]
            pub extern "C" fn fmi2GetTypesPlatform() -> Text {
                c"default".as_ptr()
            }

            #[unsafe(no_mangle)]
            pub extern "C" fn fmi2GetVersion() -> Text {
                c"2.0".as_ptr()
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SetDebugLogging(
                c: Component,
                on: Boolean,
                n: usize,
                categories: *const Text,
            ) -> Status {
                unsafe { api::set_debug_logging::<M>(c, on, n, categories) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2Instantiate(
                name: Text,
                kind: Integer,
                guid: Text,
                resources: Text,
                functions: *const CallbackFunctions,
                visible: Boolean,
                logging_on: Boolean,
            ) -> Component {
                unsafe {
                    api::instantiate::<M>(
                        $identifier,
                        name,
                        kind,
                        guid,
                        resources,
                        functions,
                        visible,
                        logging_on,
                    )
                }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2FreeInstance(c: Component) {
                unsafe { api::free_instance::<M>(c) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SetupExperiment(
                c: Component,
                tolerance_defined: Boolean,
                tolerance: Real,
                start: Real,
                stop_defined: Boolean,
                stop: Real,
            ) -> Status {
                unsafe {
                    api::setup_experiment::<M>(
                        c,
                        tolerance_defined,
                        tolerance,
                        start,
                        stop_defined,
                        stop,
                    )
                }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2EnterInitializationMode(c: Component) -> Status {
                unsafe { api::enter_initialization_mode::<M>(c) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2ExitInitializationMode(c: Component) -> Status {
                unsafe { api::exit_initialization_mode::<M>(c) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2Terminate(c: Component) -> Status {
                unsafe { api::terminate::<M>(c) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2Reset(c: Component) -> Status {
                unsafe { api::reset::<M>(c) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetReal(
                c: Component,
                vr: *const ValueReference,
                n: usize,
                value: *mut Real,
            ) -> Status {
                unsafe { api::get_real::<M>(c, vr, n, value) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetInteger(
                c: Component,
                vr: *const ValueReference,
                n: usize,
                value: *mut Integer,
            ) -> Status {
                unsafe { api::get_integer::<M>(c, vr, n, value) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetBoolean(
                c: Component,
                vr: *const ValueReference,
                n: usize,
                _value: *mut Boolean,
            ) -> Status {
                unsafe { api::no_variables::<M>(c, Function::GetBoolean, "fmi2GetBoolean", vr, n) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetString(
                c: Component,
                vr: *const ValueReference,
                n: usize,
                _value: *mut Text,
            ) -> Status {
                unsafe { api::no_variables::<M>(c, Function::GetString, "fmi2GetString", vr, n) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SetReal(
                c: Component,
                vr: *const ValueReference,
                n: usize,
                value: *const Real,
            ) -> Status {
                unsafe { api::set_real::<M>(c, vr, n, value) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SetInteger(
                c: Component,
                vr: *const ValueReference,
                n: usize,
                value: *const Integer,
            ) -> Status {
                unsafe { api::set_integer::<M>(c, vr, n, value) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SetBoolean(
                c: Component,
                vr: *const ValueReference,
                n: usize,
                _value: *const Boolean,
            ) -> Status {
                unsafe { api::no_variables::<M>(c, Function::SetBoolean, "fmi2SetBoolean", vr, n) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SetString(
                c: Component,
                vr: *const ValueReference,
                n: usize,
                _value: *const Text,
            ) -> Status {
                unsafe { api::no_variables::<M>(c, Function::SetString, "fmi2SetString", vr, n) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetFMUstate(c: Component, s: *mut FmuState) -> Status {
                unsafe { api::get_fmu_state::<M>(c, s) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SetFMUstate(c: Component, s: FmuState) -> Status {
                unsafe { api::set_fmu_state::<M>(c, s) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2FreeFMUstate(c: Component, s: *mut FmuState) -> Status {
                unsafe { api::free_fmu_state::<M>(c, s) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SerializedFMUstateSize(
                c: Component,
                s: FmuState,
                size: *mut usize,
            ) -> Status {
                unsafe { api::serialized_size::<M>(c, s, size) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SerializeFMUstate(
                c: Component,
                s: FmuState,
                bytes: *mut Byte,
                size: usize,
            ) -> Status {
                unsafe { api::serialize::<M>(c, s, bytes, size) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
                c: Component,
                bytes: *const Byte,
                size: usize,
                s: *mut FmuState,
            ) -> Status {
                unsafe { api::deserialize_fmu_state::<M>(c, bytes, size, s) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetDirectionalDerivative(
                c: Component,
                unknowns: *const ValueReference,
                n_unknowns: usize,
                knowns: *const ValueReference,
                n_knowns: usize,
                seeds: *const Real,
                out: *mut Real,
            ) -> Status {
                unsafe {
                    api::get_directional_derivative::<M>(
                        c,
                        (unknowns, n_unknowns),
                        (knowns, n_knowns),
                        seeds,
                        out,
                    )
                }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2EnterEventMode(c: Component) -> Status {
                unsafe { exchange::enter_event_mode::<M>(c) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2NewDiscreteStates(
                c: Component,
                info: *mut EventInfo,
            ) -> Status {
                unsafe { exchange::new_discrete_states::<M>(c, info) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2EnterContinuousTimeMode(c: Component) -> Status {
                unsafe { exchange::enter_continuous_time_mode::<M>(c) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2CompletedIntegratorStep(
                c: Component,
                _no_set_prior: Boolean,
                enter_event_mode: *mut Boolean,
                terminate_simulation: *mut Boolean,
            ) -> Status {
                unsafe {
                    exchange::completed_integrator_step::<M>(
                        c,
                        enter_event_mode,
                        terminate_simulation,
                    )
                }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SetTime(c: Component, t: Real) -> Status {
                unsafe { exchange::set_time::<M>(c, t) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SetContinuousStates(
                c: Component,
                x: *const Real,
                nx: usize,
            ) -> Status {
                unsafe { exchange::set_continuous_states::<M>(c, x, nx) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetDerivatives(
                c: Component,
                dx: *mut Real,
                nx: usize,
            ) -> Status {
                unsafe { exchange::get_derivatives::<M>(c, dx, nx) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetEventIndicators(
                c: Component,
                z: *mut Real,
                nz: usize,
            ) -> Status {
                unsafe { exchange::get_event_indicators::<M>(c, z, nz) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetContinuousStates(
                c: Component,
                x: *mut Real,
                nx: usize,
            ) -> Status {
                unsafe { exchange::get_continuous_states::<M>(c, x, nx) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetNominalsOfContinuousStates(
                c: Component,
                nominals: *mut Real,
                nx: usize,
            ) -> Status {
                unsafe { exchange::get_nominals::<M>(c, nominals, nx) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SetRealInputDerivatives(
                c: Component,
                _vr: *const ValueReference,
                _n: usize,
                _order: *const Integer,
                _value: *const Real,
            ) -> Status {
                unsafe {
                    cosim::not_offered::<M>(
                        c,
                        Function::SetRealInputDerivatives,
                        "fmi2SetRealInputDerivatives",
                    )
                }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetRealOutputDerivatives(
                c: Component,
                _vr: *const ValueReference,
                _n: usize,
                _order: *const Integer,
                _value: *mut Real,
            ) -> Status {
                unsafe {
                    cosim::not_offered::<M>(
                        c,
                        Function::GetRealOutputDerivatives,
                        "fmi2GetRealOutputDerivatives",
                    )
                }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2DoStep(
                c: Component,
                t: Real,
                h: Real,
                _no_set_prior: Boolean,
            ) -> Status {
                unsafe { cosim::do_step::<M>(c, t, h) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2CancelStep(c: Component) -> Status {
                unsafe { cosim::not_offered::<M>(c, Function::CancelStep, "fmi2CancelStep") }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetStatus(
                c: Component,
                kind: StatusKind,
                _value: *mut Status,
            ) -> Status {
                unsafe { cosim::get_status::<M>(c, "fmi2GetStatus", kind, cosim::Asked::Status) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetRealStatus(
                c: Component,
                kind: StatusKind,
                value: *mut Real,
            ) -> Status {
                unsafe {
                    cosim::get_status::<M>(c, "fmi2GetRealStatus", kind, cosim::Asked::Real(value))
                }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetIntegerStatus(
                c: Component,
                kind: StatusKind,
                _value: *mut Integer,
            ) -> Status {
                unsafe {
                    cosim::get_status::<M>(c, "fmi2GetIntegerStatus", kind, cosim::Asked::Integer)
                }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetBooleanStatus(
                c: Component,
                kind: StatusKind,
                value: *mut Boolean,
            ) -> Status {
                unsafe {
                    cosim::get_status::<M>(
                        c,
                        "fmi2GetBooleanStatus",
                        kind,
                        cosim::Asked::Boolean(value),
                    )
                }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetStringStatus(
                c: Component,
                kind: StatusKind,
                _value: *mut Text,
            ) -> Status {
                unsafe {
                    cosim::get_status::<M>(c, "fmi2GetStringStatus", kind, cosim::Asked::Text)
                }
            }
        };
    };
}
