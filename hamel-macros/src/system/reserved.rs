//! Names a model's coordinates, speeds and inputs may not have: they are already taken by the
//! columns a trajectory adds to the state's, or, upper-cased into index constants
//! (`Model::THETA`), by the constants of `HamelSystem` and `Parameters`, which `Model::N`
//! would then hide. The one table of them. A constraint's name has an index constant too,
//! but its column is `lambda_<name>`, which no other column can be (the prefix is reserved
//! to them): only the constants restrict it.

/// Columns of a trajectory beside the state's, and columns that upcoming features add.
const COLUMNS: [(&str, &str); 3] = [
    ("t", "the time"),
    ("energy", "the energy"),
    ("energy_balance", "the energy balance"),
];

/// Prefixes of columns that trajectories add, one per constraint.
const COLUMN_PREFIXES: [(&str, &str); 1] = [("lambda_", "the constraint forces")];

/// Associated constants of `HamelSystem` and `Parameters`.
const CONSTANTS: [(&str, &str, &str); 11] = [
    ("N", "HamelSystem", "the number of coordinates"),
    ("P", "HamelSystem", "the number of constraints"),
    ("M", "HamelSystem", "the number of inputs"),
    ("STATE", "HamelSystem", "the names of the state"),
    ("COORDINATES", "HamelSystem", "the names of the coordinates"),
    ("SPEEDS", "HamelSystem", "the names of the speeds"),
    ("INPUTS", "HamelSystem", "the names of the inputs"),
    ("CONSTRAINTS", "HamelSystem", "the names of the constraints"),
    (
        "PREPARED_LEN",
        "HamelSystem",
        "the number of values the right-hand side prepares",
    ),
    ("NAMES", "Parameters", "the names of the parameters"),
    ("DOCS", "Parameters", "the parameters' doc comments"),
];

/// Why `name` (as written, without `r#`) cannot name a coordinate, speed or input, if it
/// cannot.
pub fn clash(name: &str) -> Option<String> {
    if let Some((_, what)) = COLUMNS.iter().find(|(column, _)| *column == name) {
        return Some(format!(
            "trajectories have a column `{name}` ({what}) beside the state's"
        ));
    }
    if let Some((prefix, what)) = COLUMN_PREFIXES.iter().find(|(p, _)| name.starts_with(p)) {
        return Some(format!(
            "trajectories have columns `{prefix}..` ({what}) beside the state's"
        ));
    }
    constant_clash(name)
}

/// Why `name` (as written, without `r#`) cannot name a constraint, if it cannot: its index
/// constant would hide a constant of the traits.
pub fn constant_clash(name: &str) -> Option<String> {
    let upper = name.to_uppercase();
    CONSTANTS
        .iter()
        .find(|(constant, ..)| *constant == upper)
        .map(|(constant, owner, what)| {
            format!(
                "its index constant `Self::{constant}` would hide `{owner}::{constant}` ({what})"
            )
        })
}

#[cfg(test)]
mod tests {
    use super::{clash, constant_clash};

    #[test]
    fn reserved_names() {
        for name in [
            "t",
            "energy",
            "energy_balance",
            "lambda_1",
            "n",
            "P",
            "state",
            "docs",
        ] {
            assert!(clash(name).is_some(), "{name}");
        }
        for name in ["x", "theta", "T", "energy2", "lambda", "omega", "p1"] {
            assert!(clash(name).is_none(), "{name}");
        }
        for name in ["t", "energy", "lambda_1", "blade"] {
            assert!(constant_clash(name).is_none(), "{name}");
        }
        for name in ["n", "Constraints", "docs"] {
            assert!(constant_clash(name).is_some(), "{name}");
        }
    }
}
