//! The model behind an object-safe trait: [`ModelObject`] is implemented once, generically,
//! for every exported model ([`Object<S>`]), so that one `#[pyclass]` ([`NativeModel`])
//! serves them all, and the whole solve runs in Rust, monomorphized for the model.

use std::panic::{AssertUnwindSafe, catch_unwind};

use pyo3::prelude::*;

use hamel::{Error, Linearization, Simulation, Trajectory, Vector};

use crate::describe::Description;
use crate::ensemble::{Cases, RowOutputs};
use crate::errors::{panicked, to_py};
use crate::inputs::{InputSpec, Inputs};
use crate::interrupt::{Failure, Watch};
use crate::model::{Hooks, Model};
use crate::settings::{Method, RunSetup};
use crate::study::{StudyResult, StudySpec};

pub use crate::native::{NativeModel, NativeModelType};

/// Everything Python asks of a model, without its type: each method is the generic code for
/// the model's type behind it. Slices are checked for length by the caller
/// ([`NativeModel`]), which knows the names.
pub trait ModelObject: Send + Sync {
    fn description(&self) -> &Description;
    /// The parameters' values, in the order of their names.
    fn parameter_values(&self) -> Vec<f64>;
    /// The same model with some parameters changed.
    fn with_parameters(&self, values: &[(String, f64)]) -> Result<Box<dyn ModelObject>, Error>;
    /// A state by name (`StateBuilder`): the rest zero, the dependent coordinates solved.
    fn state(
        &self,
        t: f64,
        values: &[(String, f64)],
        velocities: Option<&[(String, f64)]>,
    ) -> Result<Vec<f64>, Error>;
    /// A run, the whole solve in Rust with the interpreter released.
    fn simulate(&self, py: Python<'_>, x0: &[f64], setup: &RunSetup) -> PyResult<Trajectory>;
    /// Many runs on every core, one row each, in the order of the cases.
    fn ensemble(
        &self,
        py: Python<'_>,
        cases: &Cases,
        setup: &RunSetup,
        outputs: &RowOutputs,
        threads: Option<usize>,
    ) -> PyResult<hamel::Table>;
    /// A study over a table of cases, in memory or through the study's command line.
    fn study(
        &self,
        py: Python<'_>,
        spec: &StudySpec,
        setup: &RunSetup,
        outputs: &RowOutputs,
    ) -> PyResult<StudyResult>;
    fn linearize(&self, t: f64, x: &[f64], u: &[f64]) -> Result<Linearization, Error>;
    fn rhs(&self, t: f64, x: &[f64], u: &[f64]) -> Result<Vec<f64>, Error>;
    fn energy(&self, t: f64, x: &[f64]) -> Result<f64, Error>;
    fn constraint_forces(&self, t: f64, x: &[f64], u: &[f64]) -> Result<Vec<f64>, Error>;
    /// The outputs y = h(t, x), for a model with `#[outputs]`.
    fn outputs(&self, t: f64, x: &[f64]) -> Option<Vec<f64>>;
    /// The run's 3D scene as an HTML page, for a model with bodies.
    fn scene(
        &self,
        run: &Trajectory,
        show: Option<&[String]>,
        title: Option<&str>,
    ) -> Option<Result<String, String>>;
}

/// A model and what the export macro found out about its type.
pub struct Object<S: Model> {
    pub model: S,
    pub hooks: Hooks<S>,
    pub description: &'static Description,
}

impl<S: Model> Object<S> {
    /// A copy of the model with `values` set (the model has no `Clone`: it is made afresh and
    /// its parameters copied by name).
    pub fn model_with(&self, values: &[(String, f64)]) -> Result<S, Error> {
        let mut model =
            (self.hooks.factory.make)().ok_or_else(|| not_plain(self.description.name))?;
        for name in S::NAMES {
            model.set(name, self.model.get(name).unwrap_or(f64::NAN))?;
        }
        for (name, value) in values {
            model.set(name, *value)?;
        }
        Ok(model)
    }
}

pub fn not_plain(name: &str) -> Error {
    Error::InconsistentModel {
        what: format!(
            "`{name}` has no `Default` and its parameter struct holds more than its parameters, \
             so it cannot be made from Python; implement `Default` for it"
        ),
    }
}

fn vector<V: Vector>(values: &[f64]) -> V {
    V::from_slice(values).unwrap_or_else(V::zeros)
}

impl<S: Model> ModelObject for Object<S> {
    fn description(&self) -> &Description {
        self.description
    }

    fn parameter_values(&self) -> Vec<f64> {
        S::NAMES
            .iter()
            .map(|n| self.model.get(n).unwrap_or(f64::NAN))
            .collect()
    }

    fn with_parameters(&self, values: &[(String, f64)]) -> Result<Box<dyn ModelObject>, Error> {
        Ok(Box::new(Object {
            model: self.model_with(values)?,
            hooks: self.hooks.clone(),
            description: self.description,
        }))
    }

    fn state(
        &self,
        t: f64,
        values: &[(String, f64)],
        velocities: Option<&[(String, f64)]>,
    ) -> Result<Vec<f64>, Error> {
        build_state(&self.model, t, values, velocities).map(|x| x.as_ref().to_vec())
    }

    fn simulate(&self, py: Python<'_>, x0: &[f64], setup: &RunSetup) -> PyResult<Trajectory> {
        let x0: S::State = vector(x0);
        let failure = Failure::default();
        let result = py.detach(|| {
            catch_unwind(AssertUnwindSafe(|| {
                run(&self.model, x0, setup, &failure, Watch::Signals)
            }))
        });
        if let Some(e) = failure.take() {
            return Err(e);
        }
        match result {
            Ok(Ok(trajectory)) => Ok(trajectory),
            Ok(Err(e)) => Err(to_py(&e)),
            Err(payload) => Err(panicked(payload)),
        }
    }

    fn ensemble(
        &self,
        py: Python<'_>,
        cases: &Cases,
        setup: &RunSetup,
        outputs: &RowOutputs,
        threads: Option<usize>,
    ) -> PyResult<hamel::Table> {
        crate::ensemble::run_cases(self, py, cases, setup, outputs, threads)
    }

    fn study(
        &self,
        py: Python<'_>,
        spec: &StudySpec,
        setup: &RunSetup,
        outputs: &RowOutputs,
    ) -> PyResult<StudyResult> {
        crate::study::run_study(self, py, spec, setup, outputs)
    }

    fn linearize(&self, t: f64, x: &[f64], u: &[f64]) -> Result<Linearization, Error> {
        self.model.linearize(t, &vector(x), &vector(u))
    }

    fn rhs(&self, t: f64, x: &[f64], u: &[f64]) -> Result<Vec<f64>, Error> {
        self.model.validate()?;
        let x: S::State = vector(x);
        let mut dx = S::State::zeros();
        self.model
            .rhs(t, &x, &vector(u), &mut dx)
            .map_err(|s| S::singular(s, t, &x))?;
        Ok(dx.as_ref().to_vec())
    }

    fn energy(&self, t: f64, x: &[f64]) -> Result<f64, Error> {
        self.model.validate()?;
        let x: S::State = vector(x);
        self.model.energy(t, &x).map_err(|s| S::singular(s, t, &x))
    }

    fn constraint_forces(&self, t: f64, x: &[f64], u: &[f64]) -> Result<Vec<f64>, Error> {
        let lambda = self.model.constraint_forces(t, &vector(x), &vector(u))?;
        Ok(lambda.as_ref().to_vec())
    }

    fn outputs(&self, t: f64, x: &[f64]) -> Option<Vec<f64>> {
        let hook = self.hooks.outputs.as_ref()?;
        Some((hook.values)(&self.model, t, &vector(x)))
    }

    fn scene(
        &self,
        run: &Trajectory,
        show: Option<&[String]>,
        title: Option<&str>,
    ) -> Option<Result<String, String>> {
        let scene = self.hooks.scene?;
        Some(
            catch_unwind(AssertUnwindSafe(|| scene(&self.model, run, show, title)))
                .unwrap_or_else(|_| Err("drawing the scene panicked".into())),
        )
    }
}

/// A state of `model` by name, through its state builder.
pub fn build_state<S: Model>(
    model: &S,
    t: f64,
    values: &[(String, f64)],
    velocities: Option<&[(String, f64)]>,
) -> Result<S::State, Error> {
    let mut builder = model.state_builder().at_time(t);
    for (name, value) in values {
        builder = builder.set(name, *value);
    }
    if let Some(velocities) = velocities {
        let mut qd = S::Coordinates::zeros();
        for (name, value) in velocities {
            match S::COORDINATES.iter().position(|n| n == name) {
                Some(i) => qd.as_mut()[i] = *value,
                None => {
                    return Err(Error::UnknownName {
                        kind: "coordinate",
                        name: name.clone(),
                        known: S::COORDINATES.join(", "),
                    });
                }
            }
        }
        builder = builder.velocities(&qd);
    }
    builder.build()
}

/// One run of `model` from `x0` with `setup`; `watch` says whether the run looks for Ctrl-C
/// itself (see `Inputs::at`). A Python error kept in `failure` stops it by unwinding: call it
/// inside `catch_unwind`.
pub fn run<S: Model>(
    model: &S,
    x0: S::State,
    setup: &RunSetup,
    failure: &Failure,
    watch: Watch,
) -> Result<Trajectory, Error> {
    let mut sim = Simulation::new(model, x0)
        .start_time(setup.t0)
        .end_time(setup.t_end)
        .sample_interval(setup.dt)
        .record_constraint_forces(setup.lambdas)
        .project_holonomic(setup.project);
    if let Some(n) = setup.max_samples {
        sim = sim.max_samples(n);
    }
    for event in &setup.events {
        sim = sim.event(event.event::<S>(failure));
    }
    // Constant inputs take the runtime's own path for them (checked once; with zero inputs
    // no work integrated), as a Rust program's `run_constant` does: Ctrl-C is then looked for
    // by the progress callback, every 50 ms (`Failure::progress`; a function's inputs look
    // for it themselves, see `Inputs::at`).
    if let InputSpec::Constant(values) = &setup.inputs {
        let u = S::Inputs::from_slice(values).unwrap_or_else(S::Inputs::zeros);
        let sim = sim.on_progress(move |p| failure.progress(watch, p.elapsed));
        return match &setup.method {
            Method::Dopri5(a) => sim.run_constant(&a.dopri5(), u),
            Method::Radau5(a) => sim.run_constant(&a.radau5(), u),
            Method::Rodas5P(a) => sim.run_constant(&a.rodas5p(), u),
            Method::Rodas4(a) => sim.run_constant(&a.rodas4(), u),
            Method::Rk4(f) => sim.run_constant(&f.rk4(), u),
            Method::Midpoint(f) => sim.run_constant(&f.midpoint(), u),
            Method::Gauss(stages, f) => sim.run_constant(&f.gauss(*stages), u),
        };
    }
    let mut inputs = Inputs::<S>::new(&setup.inputs, failure, watch)?;
    let u = move |t: f64, x: &S::State| inputs.at(t, x);
    match &setup.method {
        Method::Dopri5(a) => sim.run(&a.dopri5(), u),
        Method::Radau5(a) => sim.run(&a.radau5(), u),
        Method::Rodas5P(a) => sim.run(&a.rodas5p(), u),
        Method::Rodas4(a) => sim.run(&a.rodas4(), u),
        Method::Rk4(f) => sim.run(&f.rk4(), u),
        Method::Midpoint(f) => sim.run(&f.midpoint(), u),
        Method::Gauss(stages, f) => sim.run(&f.gauss(*stages), u),
    }
}
