//! Values with names, for messages: `x = 0.1, y = -2, alpha = 0.3`.

use crate::error::Num;
use core::fmt;

/// Named values, as they appear in error messages and `Debug` output: `Display` writes each
/// value with four significant digits ([`Num`]: `t = 2.669`, `x = 1e300`), as a person reads a
/// message; `Debug` writes the exact values, for diagnostics that compare them.
#[derive(Clone, PartialEq)]
pub struct NamedValues(pub Vec<(String, f64)>);

impl NamedValues {
    /// The values paired with the names, in order (the shorter list sets the length).
    pub fn new(names: &[&str], values: &[f64]) -> Self {
        NamedValues(
            names
                .iter()
                .zip(values)
                .map(|(n, v)| ((*n).to_string(), *v))
                .collect(),
        )
    }

    /// The value named `name`, exact.
    pub fn get(&self, name: &str) -> Option<f64> {
        self.0.iter().find(|(n, _)| n == name).map(|(_, v)| *v)
    }
}

impl fmt::Display for NamedValues {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, (name, value)) in self.0.iter().enumerate() {
            if i > 0 {
                f.write_str(", ")?;
            }
            write!(f, "{name} = {}", Num(*value))?;
        }
        Ok(())
    }
}

impl fmt::Debug for NamedValues {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut map = f.debug_map();
        for (name, value) in &self.0 {
            map.entry(&format_args!("{name}"), value);
        }
        map.finish()
    }
}
