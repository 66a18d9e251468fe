//! What the macro notes about a model's geometry for its users (`Mechanism::NOTES`): the
//! contact rows it left out because they repeat others at every configuration, and what the
//! constraint forces of the rows kept then are.
//!
//! A family of rows that are multiples c₀ = 1, c₁, … of one kept row at every configuration
//! constrains one direction of motion: the kept row's multiplier λ is the family's force
//! along it, and how it divides among the contacts is not determined by rigid contacts. The
//! split of least norm, μⱼ = cⱼ λ / Σ cᵢ², is the one the notes give (half each for two
//! wheels on one axle).

use super::spec::Spec;
use crate::system::equations::ContactReading;

/// The notes, with the constraint rows' names as the model has them.
pub fn notes(spec: &Spec<'_>, constraints: &[String]) -> Vec<String> {
    let Some(contacts) = &spec.geometry.contacts else {
        return Vec::new();
    };
    let reading = &contacts.reading;
    let first = spec.written_constraints();
    let describe = |row: usize| describe_row(spec, reading, row);
    let mut notes = Vec::new();
    for (place, &kept) in reading.kept.iter().enumerate() {
        let family: Vec<(usize, f64)> = reading
            .repeats
            .iter()
            .filter_map(|r| r.of.filter(|(of, _)| *of == kept).map(|(_, c)| (r.row, c)))
            .collect();
        if family.is_empty() {
            continue;
        }
        let name = constraints.get(first + place).map_or("?", String::as_str);
        let total: f64 = 1.0 + family.iter().map(|(_, c)| c * c).sum::<f64>();
        let shares: Vec<String> = std::iter::once((kept, 1.0))
            .chain(family.iter().copied())
            .map(|(row, c)| format!("{} to contact {}", share(c / total), row / 2))
            .collect();
        let repeated: Vec<String> = family
            .iter()
            .map(|&(row, c)| {
                let factor = if (c - 1.0).abs() < 1e-9 {
                    String::new()
                } else {
                    format!(" ({} times it)", share(c))
                };
                format!("{}{factor}", describe(row))
            })
            .collect();
        notes.push(format!(
            "{} repeats {} at every configuration and is left out: the constraint force \
             `{name}` is theirs together, and its split of least norm gives {}",
            repeated.join(" and "),
            describe(kept),
            shares.join(", ")
        ));
    }
    for r in reading.repeats.iter().filter(|r| r.of.is_none()) {
        notes.push(format!(
            "{} is a combination of the contact rows before it at every configuration and is \
             left out: the constraint forces of the rows it combines include its share, which \
             rigid contacts do not determine",
            describe(r.row)
        ));
    }
    notes
}

/// "contact 1's (`left_wheel`'s) slip along its heading".
fn describe_row(spec: &Spec<'_>, reading: &ContactReading, row: usize) -> String {
    let contact = row / 2;
    let body = reading
        .bodies
        .get(contact)
        .copied()
        .flatten()
        .and_then(|b| spec.body_names.get(b))
        .map_or_else(String::new, |name| format!(" (`{name}`'s)"));
    let wheel = reading.wheels.get(contact).copied().unwrap_or(false);
    let along = match (wheel, row % 2) {
        (true, 0) => "along its heading",
        (true, _) => "along its axle",
        (false, 0) => "along the surface's x",
        (false, _) => "along the surface's y",
    };
    format!("contact {contact}'s{body} slip {along}")
}

/// A share as a fraction when it is a simple one.
fn share(x: f64) -> String {
    for d in 1..=12u32 {
        let n = x * f64::from(d);
        if (n - n.round()).abs() < 1e-9 {
            let n = n.round() as i64;
            return if d == 1 {
                n.to_string()
            } else {
                format!("{n}/{d}")
            };
        }
    }
    format!("{x:.4}")
}
