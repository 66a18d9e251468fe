//! Units for axis labels: [`Units`], a lookup from the names of quantities — a model's
//! coordinates, speeds, inputs, time and energy, its parameters, or any name given — to
//! their units.

use hamel_runtime::{HamelSystem, Parameters};

/// Where axis labels find units: the names of quantities and their units.
///
/// [`Units::of`] reads what a model states: the units of its coordinates, speeds, inputs,
/// `t` and `energy` from `#[hamel_system(units(..))]` ([`HamelSystem::unit`]), and its
/// parameters' from their doc comments (`/// trail (m)`, [`Parameters::parameter_unit`]).
/// [`Units::with`] adds or overrides a name, for quantities a model does not know (a speed
/// computed from its state, an eigenvalue). A name found nowhere has no unit, and its label
/// is the bare name: nothing is guessed.
///
/// [`Panel::units`](super::Panel::units) labels the axes of a trajectory's panels with
/// them; [`Units::label`] gives any other label.
///
/// ```
/// use hamel::models::WhippleBicycle;
/// use hamel::plot::Units;
///
/// let units = Units::of::<WhippleBicycle>().with("v", "m/s");
/// assert_eq!(units.label("trail c", "c"), "trail c (m)"); // from `/// trail (m)`
/// assert_eq!(units.label("forward speed v", "v"), "forward speed v (m/s)");
/// assert_eq!(units.unit("no such quantity"), None);
/// assert_eq!(units.label("no such quantity", "no such quantity"), "no such quantity");
/// ```
#[derive(Clone, Default)]
pub struct Units {
    /// The model's quantities ([`HamelSystem::unit`]).
    system: Option<fn(&str) -> Option<&'static str>>,
    /// The model's parameters ([`Parameters::parameter_unit`]).
    parameters: Option<fn(&str) -> Option<&'static str>>,
    /// Names given with [`Units::with`], the latest last.
    given: Vec<(String, String)>,
}

impl core::fmt::Debug for Units {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Units")
            .field("model", &self.system.is_some())
            .field("parameters", &self.parameters.is_some())
            .field("given", &self.given)
            .finish()
    }
}

impl Units {
    /// No units: every label is its bare name until [`Units::with`] adds some.
    pub fn new() -> Units {
        Units::default()
    }

    /// The units model `S` states: its quantities' ([`HamelSystem::unit`]: coordinates,
    /// speeds, inputs, `t`, `energy` and `energy_balance`) and its parameters'
    /// ([`Parameters::parameter_unit`]), the quantities' first where a name is both.
    pub fn of<S: HamelSystem>() -> Units {
        Units {
            system: Some(S::unit),
            parameters: Some(S::parameter_unit),
            given: Vec::new(),
        }
    }

    /// The units of the parameters `P` documents ([`Parameters::parameter_unit`]), for a
    /// study over them.
    pub fn of_parameters<P: Parameters>() -> Units {
        Units {
            system: None,
            parameters: Some(P::parameter_unit),
            given: Vec::new(),
        }
    }

    /// The same units, with `name` in `unit` (over what the model states).
    pub fn with(mut self, name: &str, unit: &str) -> Units {
        self.given.push((name.to_string(), unit.to_string()));
        self
    }

    /// The unit of the quantity `name`: the last one [`Units::with`] gave, or the model's.
    pub fn unit(&self, name: &str) -> Option<&str> {
        self.given
            .iter()
            .rev()
            .find(|(n, _)| n == name)
            .map(|(_, u)| u.as_str())
            .or_else(|| self.system.and_then(|f| f(name)))
            .or_else(|| self.parameters.and_then(|f| f(name)))
    }

    /// `text` followed by the unit of `name` in parentheses, `"trail c (m)"`, or `text`
    /// alone when `name` has no unit.
    pub fn label(&self, text: &str, name: &str) -> String {
        match self.unit(name) {
            Some(unit) => format!("{text} ({unit})"),
            None => text.to_string(),
        }
    }

    /// The label of an axis showing the quantities `names` under the label `text`: `text
    /// (unit)` when they share one unit; when `text` lists them (`"v, omega"`) and their
    /// units differ, each with its own, `"v (m/s), omega (rad/s)"`; otherwise `text`.
    pub(crate) fn axis_label(&self, text: &str, names: &[String]) -> String {
        let units: Vec<Option<&str>> = names.iter().map(|n| self.unit(n)).collect();
        match units.first() {
            Some(Some(first)) if units.iter().all(|u| u == &Some(*first)) => {
                format!("{text} ({first})")
            }
            Some(_) if text == names.join(", ") => names
                .iter()
                .zip(&units)
                .map(|(name, unit)| match unit {
                    Some(unit) => format!("{name} ({unit})"),
                    None => name.clone(),
                })
                .collect::<Vec<_>>()
                .join(", "),
            _ => text.to_string(),
        }
    }
}
