//! A model's description for Python: the names of its parameters, coordinates, speeds,
//! inputs, outputs, constraints and bodies, and their units, read from the traits the macro
//! implements (nothing is parsed again).

use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::model::{Hooks, Model};

/// Everything static about a model type.
pub struct Description {
    /// The model's type name (`MobileRobot`).
    pub name: &'static str,
    /// The parameter struct's doc comment (`Parameters::DOC`), empty where there is none.
    pub doc: &'static str,
    pub parameters: &'static [&'static str],
    pub parameter_docs: &'static [&'static str],
    pub parameter_units: Vec<Option<&'static str>>,
    /// The parameters' defaults, for a model with `Default`.
    pub defaults: Option<Vec<f64>>,
    pub coordinates: &'static [&'static str],
    pub speeds: &'static [&'static str],
    pub inputs: &'static [&'static str],
    pub constraints: &'static [&'static str],
    pub state: &'static [&'static str],
    pub outputs: &'static [&'static str],
    /// The coordinates the holonomic constraints determine.
    pub dependent: Vec<&'static str>,
    /// Units of the named quantities (coordinates, speeds, inputs, `t`, `energy`).
    pub units: &'static [(&'static str, &'static str)],
    pub conservative: bool,
    pub reversible: bool,
    /// Whether the model has bodies to draw (`scene`).
    pub has_scene: bool,
}

impl Description {
    pub fn of<S: Model>(name: &'static str, hooks: &Hooks<S>) -> Description {
        let defaults = if hooks.factory.defaults {
            (hooks.factory.make)().map(|m| {
                S::NAMES
                    .iter()
                    .map(|n| m.get(n).unwrap_or(f64::NAN))
                    .collect()
            })
        } else {
            None
        };
        Description {
            name,
            doc: S::DOC,
            parameters: S::NAMES,
            parameter_docs: S::DOCS,
            parameter_units: S::NAMES.iter().map(|n| S::parameter_unit(n)).collect(),
            defaults,
            coordinates: S::COORDINATES,
            speeds: S::SPEEDS,
            inputs: S::INPUTS,
            constraints: S::CONSTRAINTS,
            state: S::STATE,
            outputs: hooks.outputs.as_ref().map_or(&[], |o| o.names),
            dependent: S::DEPENDENT.iter().map(|&i| S::COORDINATES[i]).collect(),
            units: S::UNITS,
            conservative: S::CONSERVATIVE,
            reversible: S::REVERSIBLE,
            has_scene: hooks.scene.is_some(),
        }
    }

    /// The description as a Python dictionary (what `hamel.Model` reads once per class).
    pub fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        d.set_item("name", self.name)?;
        d.set_item("doc", self.doc)?;
        d.set_item("parameters", self.parameters.to_vec())?;
        d.set_item("parameter_docs", self.parameter_docs.to_vec())?;
        d.set_item("parameter_units", self.parameter_units.clone())?;
        d.set_item("defaults", self.defaults.clone())?;
        d.set_item("coordinates", self.coordinates.to_vec())?;
        d.set_item("speeds", self.speeds.to_vec())?;
        d.set_item("inputs", self.inputs.to_vec())?;
        d.set_item("constraints", self.constraints.to_vec())?;
        d.set_item("state", self.state.to_vec())?;
        d.set_item("outputs", self.outputs.to_vec())?;
        d.set_item("dependent", self.dependent.clone())?;
        let units = PyDict::new(py);
        for (name, unit) in self.units {
            units.set_item(*name, *unit)?;
        }
        d.set_item("units", units)?;
        d.set_item("conservative", self.conservative)?;
        d.set_item("reversible", self.reversible)?;
        d.set_item("has_scene", self.has_scene)?;
        Ok(d)
    }
}
