//! Co-Simulation: `fmi2DoStep` integrates the model over the communication step with one of
//! hamel's integrators (`hamel.integrator`; Dormand–Prince by default), the inputs held
//! constant over it. Each step ends exactly on the communication point (the integrator's
//! last step is shortened to it, nothing is interpolated), at the importer's tolerance or
//! rtol 1e-9, atol 1e-12; the next communication step starts with the largest step the last
//! one took, so that a run of many short communication steps does not choose its first step
//! afresh each time.

use super::api::{call, write_one};
use super::instance::{Instance, Outcome, Refusal, State};
use super::logger::Category;
use super::modes::{Function, Mode};
use super::types::*;
use super::variables::INTEGRATORS;
use crate::model::Model;
use hamel_runtime::integrate::{Control, Observer, Ode, StepView};
use hamel_runtime::{
    DormandPrince, Error, GaussLegendre, HamelSystem, ImplicitMidpoint, Integrator, NamedValues,
    Radau5, Rk4,
};

/// The reduced ODE with constant inputs, as a hamel simulation integrates it: the prepared
/// right-hand side, the exact Jacobian (dual numbers) for the implicit methods, the state
/// named in messages.
struct StepOde<'a, S: HamelSystem> {
    system: &'a S,
    prepared: &'a [f64],
    u: S::Inputs,
}

impl<S: HamelSystem> Ode for StepOde<'_, S> {
    type State = S::State;

    fn rhs(&mut self, t: f64, x: &S::State, dx: &mut S::State) -> Result<(), Error> {
        self.system
            .rhs_prepared(self.prepared, t, x, &self.u, dx)
            .map_err(|s| S::singular(s, t, x))
    }

    fn jacobian(&mut self, t: f64, x: &S::State, jacobian: &mut [f64]) -> Result<bool, Error> {
        let (a, _) = self
            .system
            .jacobian(t, x, &self.u)
            .map_err(|s| S::singular(s, t, x))?;
        jacobian.copy_from_slice(a.as_ref());
        Ok(true)
    }

    fn describe(&self, x: &S::State) -> NamedValues {
        S::named_state(x)
    }
}

/// Keeps the end of the communication step and the largest step taken.
struct End<V> {
    x: Option<V>,
    largest: f64,
}

impl<V: Copy> Observer<V> for End<V> {
    fn sample(&mut self, _t: f64, x: &V) -> Result<Control, Error> {
        self.x = Some(*x);
        Ok(Control::Continue)
    }

    fn watches_steps(&self) -> bool {
        true
    }

    fn step(&mut self, step: &StepView<'_, V>) -> Result<Control, Error> {
        self.largest = self.largest.max(step.t1 - step.t);
        Ok(Control::Continue)
    }
}

/// One integration from (t, x) to t + h with `integrator`.
fn integrate<S: HamelSystem, I: Integrator>(
    integrator: &I,
    ode: &mut StepOde<'_, S>,
    (t, x): (f64, &S::State),
    end: f64,
) -> Result<(S::State, f64), Error> {
    let mut observer = End {
        x: None,
        largest: 0.0,
    };
    integrator.integrate_observed(ode, t, x, &[end], &mut observer)?;
    let x1 = observer.x.unwrap_or(*x);
    Ok((x1, observer.largest))
}

impl<M: Model> Instance<M> {
    /// `fmi2DoStep(currentCommunicationPoint = t, communicationStepSize = h)`.
    pub fn do_step(&mut self, t: f64, h: f64) -> Outcome {
        if !(t.is_finite() && h.is_finite()) {
            return Err(Refusal::error(format!(
                "the communication point {t} and step {h} must be finite numbers"
            )));
        }
        if h <= 0.0 {
            return Err(Refusal::error(format!(
                "the communication step {h} must be positive"
            )));
        }
        // The importer's clock and this instance's agree to rounding (a sum of steps).
        let slack = 1e-9 * h.max(f64::EPSILON * t.abs());
        if (t - self.t).abs() > slack.max(8.0 * f64::EPSILON * self.t.abs()) {
            return Err(Refusal::error(format!(
                "the communication point is {t}, but the instance is at t = {} (the last \
                 communication point plus its step)",
                self.t
            )));
        }
        let end = t + h;
        if let Some(stop) = self.experiment.stop {
            if end > stop + 1e-9 * h {
                return Err(Refusal::error(format!(
                    "the step from {t} by {h} ends after the stop time {stop} given to \
                     fmi2SetupExperiment"
                )));
            }
        }
        match self.integrate_to(t, end) {
            Ok((x1, largest)) => {
                self.x = x1;
                self.t = end;
                self.stepping.initial_step = (largest > 0.0).then_some(largest);
                Ok(())
            }
            Err(e) => {
                // The state stays at the communication point, where the step started.
                self.t = t;
                self.stepping.last_successful_time = t;
                self.stepping.terminated = true;
                self.mode = Mode::StepFailed;
                Err(Refusal::discard(format!(
                    "the step from t = {t} to {end} failed: {e}"
                )))
            }
        }
    }

    /// x(end) from x(t) with the chosen integrator.
    fn integrate_to(&self, t: f64, end: f64) -> Result<(State<M>, f64), String> {
        let mut ode = StepOde::<M::System> {
            system: &self.system,
            prepared: &self.prepared,
            u: self.u,
        };
        let (rtol, atol) = self.tolerances();
        let start = (t, &self.x);
        let first = self.stepping.initial_step.map(|h| h.min(end - t));
        let (x1, largest) = match INTEGRATORS[self.method].0 {
            "dopri5" => {
                let mut dp = DormandPrince::new(rtol, atol);
                dp.initial_step = first;
                integrate(&dp, &mut ode, start, end)
            }
            "radau5" => {
                let mut radau = Radau5::new(rtol, atol);
                radau.initial_step = first;
                integrate(&radau, &mut ode, start, end)
            }
            "rk4" => integrate(&Rk4::new(self.step), &mut ode, start, end),
            "gauss2" => integrate(&GaussLegendre::new(2, self.step), &mut ode, start, end),
            "gauss3" => integrate(&GaussLegendre::new(3, self.step), &mut ode, start, end),
            _ => integrate(&ImplicitMidpoint::new(self.step), &mut ode, start, end),
        }
        .map_err(|e| e.to_string())?;
        if x1.as_ref().iter().any(|v| !v.is_finite()) {
            return Err(format!(
                "the state reached is not finite: {}",
                M::System::named_state(&x1)
            ));
        }
        Ok((x1, largest))
    }

    /// `fmi2Terminate` for both interfaces.
    pub fn terminate(&mut self) {
        self.mode = Mode::Terminated;
        self.log(
            Status::Ok,
            Category::Events,
            &format!("terminated at t = {}", self.t),
        );
    }
}

/// `fmi2DoStep`.
///
/// # Safety
/// `c` is null or an instance of `M` not yet freed.
pub unsafe fn do_step<M: Model>(c: Component, t: Real, h: Real) -> Status {
    // SAFETY: the caller's contract.
    unsafe { call::<M>(c, Function::DoStep, "fmi2DoStep", |inst| inst.do_step(t, h)) }
}

/// `fmi2SetRealInputDerivatives`, `fmi2GetRealOutputDerivatives` and `fmi2CancelStep`: not
/// offered (`canInterpolateInputs="false"`, `maxOutputDerivativeOrder="0"`, `fmi2DoStep` never
/// returns `fmi2Pending`).
///
/// # Safety
/// `c` as above.
pub unsafe fn not_offered<M: Model>(c: Component, function: Function, name: &str) -> Status {
    let why = match function {
        Function::SetRealInputDerivatives => {
            "the FMU holds its inputs constant over a step (canInterpolateInputs=\"false\")"
        }
        Function::GetRealOutputDerivatives => {
            "the FMU gives no derivatives of its outputs (maxOutputDerivativeOrder=\"0\")"
        }
        _ => "fmi2DoStep never returns fmi2Pending: there is no step to cancel",
    };
    // SAFETY: the caller's contract.
    unsafe { call::<M>(c, function, name, |_| Err(Refusal::error(why))) }
}

/// Which `fmi2Get*Status` is called, with the pointer of its answer: the last successful
/// time (Real) and whether the model cannot go on (Boolean) are answered, after an
/// `fmi2DoStep` that returned `fmi2Discard` as at any other time; the other questions concern
/// asynchronous steps, which this FMU does not take (`fmi2Discard`, as the standard says).
pub enum Asked {
    Status,
    Real(*mut Real),
    Integer,
    Boolean(*mut Boolean),
    Text,
}

/// `fmi2GetStatus`, `fmi2GetRealStatus`, …
///
/// # Safety
/// `c` as above; the pointer in `asked` null or writable.
pub unsafe fn get_status<M: Model>(
    c: Component,
    name: &str,
    kind: StatusKind,
    asked: Asked,
) -> Status {
    // SAFETY: the caller's contract.
    unsafe {
        call::<M>(c, Function::GetStatus, name, |inst| match (kind, asked) {
            (LAST_SUCCESSFUL_TIME, Asked::Real(value)) => {
                *write_one(value, "value")? = if inst.mode == Mode::StepFailed {
                    inst.stepping.last_successful_time
                } else {
                    inst.t
                };
                Ok(())
            }
            (TERMINATED, Asked::Boolean(value)) => {
                *write_one(value, "value")? = if inst.stepping.terminated {
                    TRUE
                } else {
                    FALSE
                };
                Ok(())
            }
            _ => Err(Refusal::discard(format!(
                "status kind {kind} is not answered by {name}: fmi2DoStep never returns \
                 fmi2Pending (fmi2GetRealStatus answers fmi2LastSuccessfulTime, \
                 fmi2GetBooleanStatus fmi2Terminated)"
            ))),
        })
    }
}
