//! A run's settings as Python gives them: the integrator by name with its settings, the span
//! and sampling, and what is recorded. Mistakes are `ValueError`s that name the argument.

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use hamel::{DormandPrince, GaussLegendre, ImplicitMidpoint, Radau5, Rk4, Rodas4, Rodas5P};

use crate::events::EventSpec;
use crate::inputs::InputSpec;

/// The integrators, by the names `method=` takes (the robot example's `--integrator`).
pub const METHODS: [&str; 8] = [
    "dopri5", "rk4", "midpoint", "gauss2", "gauss3", "radau5", "rodas5p", "rodas4",
];

/// The adaptive methods among them: they take tolerances, not a step.
const ADAPTIVE: [&str; 4] = ["dopri5", "radau5", "rodas5p", "rodas4"];

/// An integrator with its settings.
#[derive(Clone, Debug)]
pub enum Method {
    Dopri5(Adaptive),
    Radau5(Adaptive),
    Rodas5P(Adaptive),
    Rodas4(Adaptive),
    Rk4(Fixed),
    Midpoint(Fixed),
    Gauss(usize, Fixed),
}

/// The settings of an adaptive method.
#[derive(Clone, Debug)]
pub struct Adaptive {
    pub rtol: f64,
    pub atol: f64,
    pub max_steps: Option<usize>,
    pub max_step: Option<f64>,
    pub initial_step: Option<f64>,
    pub min_step: Option<f64>,
}

/// The settings of a fixed-step method.
#[derive(Clone, Debug)]
pub struct Fixed {
    pub step: f64,
    pub max_steps: Option<usize>,
}

/// An adaptive method made with `new(rtol, atol)`, its optional settings applied (the
/// adaptive integrators share these builder methods).
macro_rules! adaptive {
    ($settings:expr, $method:ident) => {{
        let a = $settings;
        let mut m = $method::new(a.rtol, a.atol);
        if let Some(n) = a.max_steps {
            m = m.with_max_steps(n);
        }
        if let Some(h) = a.max_step {
            m = m.with_max_step(h);
        }
        if let Some(h) = a.initial_step {
            m = m.with_initial_step(h);
        }
        if let Some(r) = a.min_step {
            m = m.with_min_step(r);
        }
        m
    }};
}

impl Adaptive {
    pub fn dopri5(&self) -> DormandPrince {
        adaptive!(self, DormandPrince)
    }

    pub fn radau5(&self) -> Radau5 {
        adaptive!(self, Radau5)
    }

    pub fn rodas5p(&self) -> Rodas5P {
        adaptive!(self, Rodas5P)
    }

    pub fn rodas4(&self) -> Rodas4 {
        adaptive!(self, Rodas4)
    }
}

impl Fixed {
    pub fn rk4(&self) -> Rk4 {
        let m = Rk4::new(self.step);
        match self.max_steps {
            Some(n) => m.with_max_steps(n),
            None => m,
        }
    }

    pub fn midpoint(&self) -> ImplicitMidpoint {
        let m = ImplicitMidpoint::new(self.step);
        match self.max_steps {
            Some(n) => m.with_max_steps(n),
            None => m,
        }
    }

    pub fn gauss(&self, stages: usize) -> GaussLegendre {
        let m = GaussLegendre::new(stages, self.step);
        match self.max_steps {
            Some(n) => m.with_max_steps(n),
            None => m,
        }
    }
}

/// The integrator's settings as given to `simulate` (each `None` when not given).
pub struct MethodArgs<'a> {
    pub method: &'a str,
    pub rtol: Option<f64>,
    pub atol: Option<f64>,
    pub step: Option<f64>,
    pub max_steps: Option<usize>,
    pub max_step: Option<f64>,
    pub initial_step: Option<f64>,
    pub min_step: Option<f64>,
    /// The sample interval: a fixed-step method's step when none is given.
    pub dt: f64,
}

impl MethodArgs<'_> {
    /// The method, or a `ValueError` for an unknown name or a setting the method has not.
    pub fn method(&self) -> PyResult<Method> {
        let adaptive = ADAPTIVE.contains(&self.method);
        let refuse = |name: &str, given: bool| -> PyResult<()> {
            if given {
                let kind = if adaptive {
                    "an adaptive"
                } else {
                    "a fixed-step"
                };
                Err(PyValueError::new_err(format!(
                    "{name}: the method `{}` is {kind} method and has no `{name}` (dopri5, \
                     radau5, rodas5p and rodas4 take rtol, atol, max_step, initial_step, \
                     min_step; rk4, midpoint, gauss2 and gauss3 take step; all take max_steps)",
                    self.method
                )))
            } else {
                Ok(())
            }
        };
        if adaptive {
            refuse("step", self.step.is_some())?;
            let a = Adaptive {
                rtol: self.rtol.unwrap_or(1e-9),
                atol: self.atol.unwrap_or(1e-12),
                max_steps: self.max_steps,
                max_step: self.max_step,
                initial_step: self.initial_step,
                min_step: self.min_step,
            };
            return Ok(match self.method {
                "dopri5" => Method::Dopri5(a),
                "radau5" => Method::Radau5(a),
                "rodas5p" => Method::Rodas5P(a),
                _ => Method::Rodas4(a),
            });
        }
        if !METHODS.contains(&self.method) {
            return Err(PyValueError::new_err(format!(
                "method: unknown integrator `{}`; the integrators are {}",
                self.method,
                METHODS.join(", ")
            )));
        }
        refuse("rtol", self.rtol.is_some())?;
        refuse("atol", self.atol.is_some())?;
        refuse("max_step", self.max_step.is_some())?;
        refuse("initial_step", self.initial_step.is_some())?;
        refuse("min_step", self.min_step.is_some())?;
        let f = Fixed {
            step: self.step.unwrap_or(self.dt),
            max_steps: self.max_steps,
        };
        Ok(match self.method {
            "rk4" => Method::Rk4(f),
            "midpoint" => Method::Midpoint(f),
            "gauss2" => Method::Gauss(2, f),
            _ => Method::Gauss(3, f),
        })
    }
}

/// Everything a run needs besides the model and its initial state.
pub struct RunSetup {
    pub t0: f64,
    pub t_end: f64,
    pub dt: f64,
    pub method: Method,
    pub inputs: InputSpec,
    pub events: Vec<EventSpec>,
    /// Record the constraint forces (`lambda_<constraint>` columns).
    pub lambdas: bool,
    /// Keep the holonomic constraints to rounding.
    pub project: bool,
    pub max_samples: Option<u64>,
}
