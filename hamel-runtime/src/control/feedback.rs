//! A controller as a run's input function: u = k(t, x), which may fail (a singular
//! decoupling matrix, a reference of the wrong shape), and a run that says why.

use core::cell::RefCell;

use crate::error::Error;
use crate::integrate::Integrator;
use crate::simulation::Simulation;
use crate::sink::Sink;
use crate::system::HamelSystem;
use crate::trajectory::{Summary, Trajectory};
use crate::vector::Vector;

/// A feedback law u = k(t, x) for a system `S`: what [`Simulation::run_controlled`] calls at
/// every evaluation of the right-hand side and at every sample. A closure
/// `|t, x| -> Result<S::Inputs, Error>` is one.
pub trait Controller<S: HamelSystem> {
    /// The inputs at time `t` in state `x`, or why there are none.
    fn control(&self, t: f64, x: &S::State) -> Result<S::Inputs, Error>;
}

impl<S, F> Controller<S> for F
where
    S: HamelSystem,
    F: Fn(f64, &S::State) -> Result<S::Inputs, Error>,
{
    fn control(&self, t: f64, x: &S::State) -> Result<S::Inputs, Error> {
        self(t, x)
    }
}

impl<S: HamelSystem> Simulation<'_, S> {
    /// Runs with the inputs of a controller, u = k(t, x), as [`Simulation::run`] does with an
    /// input function: with the events, the output columns and the monitors of any run, the
    /// inputs recorded at the samples. A controller that fails ends the run with its error
    /// (which names the time and the state), the first it returned.
    pub fn run_controlled<I: Integrator, C: Controller<S>>(
        &self,
        integrator: &I,
        controller: &C,
    ) -> Result<Trajectory, Error> {
        let failure = RefCell::new(None);
        let run = self.run(integrator, |t, x| inputs_or_nan(controller, t, x, &failure));
        match failure.into_inner() {
            Some(e) => Err(e),
            None => run,
        }
    }

    /// [`Simulation::run_controlled`], streaming the samples to `sink` as
    /// [`Simulation::stream`] does.
    pub fn stream_controlled<I: Integrator, C: Controller<S>>(
        &self,
        integrator: &I,
        controller: &C,
        sink: &mut dyn Sink,
    ) -> Result<Summary, Error> {
        let failure = RefCell::new(None);
        let run = self.stream(
            integrator,
            |t, x| inputs_or_nan(controller, t, x, &failure),
            sink,
        );
        match failure.into_inner() {
            Some(e) => Err(e),
            None => run,
        }
    }
}

/// The controller's inputs; where it fails, inputs that are not numbers, which end the run
/// at once (every evaluation checks its inputs), its error kept to be returned instead.
fn inputs_or_nan<S: HamelSystem, C: Controller<S>>(
    controller: &C,
    t: f64,
    x: &S::State,
    failure: &RefCell<Option<Error>>,
) -> S::Inputs {
    match controller.control(t, x) {
        Ok(u) => u,
        Err(e) => {
            failure.borrow_mut().get_or_insert(e);
            let mut u = S::Inputs::zeros();
            u.as_mut().fill(f64::NAN);
            u
        }
    }
}
