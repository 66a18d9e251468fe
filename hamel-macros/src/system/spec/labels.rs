//! What names and units a model gives for display only: the bodies' names
//! (`bodies(rear_wheel, ..)`) and the units of its named quantities (`units(x = "m", ..)`).
//! Neither changes the equations, so a mistake here is reported without stopping them.

use super::count;
use crate::engine::hash::HashSet;
use crate::engine::lower::{Lowerer, closest};
use crate::system::model::Names;
use syn::ext::IdentExt;

/// The names scenes and pictures give the bodies of `#[bodies]` (which returns `bodies`
/// bodies, when it has a readable signature): those of `bodies(..)`, one per body, or
/// `body0`, `body1`, … by default.
pub(super) fn body_names(
    names: &Names,
    bodies: Option<(&syn::ImplItemFn, usize)>,
    lowerer: &mut Lowerer<'_, '_>,
) -> Vec<String> {
    let default = |b: usize| (0..b).map(|i| format!("body{i}")).collect();
    let Some((span, list)) = &names.bodies else {
        return bodies.map_or_else(Vec::new, |(_, b)| default(b));
    };
    let Some((f, b)) = bodies else {
        lowerer.push_error(syn::Error::new(
            *span,
            "`bodies(..)` names the bodies a `#[bodies]` function returns, and this model has \
             none: remove `bodies(..)`, or state the bodies with `#[bodies]`",
        ));
        return Vec::new();
    };
    if list.len() != b && !names.garbled {
        lowerer.push_error(syn::Error::new(
            *span,
            format!(
                "{} for {}: `{}` (`#[bodies]`) returns {}; name one per body, in order",
                count(list.len(), "body name"),
                count(b, "body"),
                f.sig.ident,
                count(b, "body"),
            ),
        ));
        return default(b);
    }
    let mut seen = HashSet::default();
    for ident in list {
        if !seen.insert(ident.unraw().to_string()) {
            lowerer.push_error(syn::Error::new_spanned(
                ident,
                format!("the body name `{ident}` is given twice: name each body once"),
            ));
        }
    }
    list.iter().map(|i| i.unraw().to_string()).collect()
}

/// The units of `units(..)`, each checked to name a coordinate, a speed, an input, `t` or
/// `energy`, once, with a unit that is not empty. The base name of an indexed group
/// (`theta` of `theta[3]`) gives every member its unit.
pub(super) fn units(
    names: &Names,
    quantities: [&[syn::Ident]; 3],
    lowerer: &mut Lowerer<'_, '_>,
) -> Vec<(String, String)> {
    let mut known: Vec<String> = quantities
        .iter()
        .flat_map(|list| list.iter().map(|i| i.unraw().to_string()))
        .collect();
    known.extend(["t".to_string(), "energy".to_string()]);
    // Groups of coordinates, speeds and inputs, by their base names.
    known.extend(
        names.groups[..3]
            .iter()
            .flatten()
            .map(|g| g.base.unraw().to_string()),
    );
    let mut seen = HashSet::default();
    let mut units = Vec::new();
    for (ident, unit) in &names.units {
        let name = ident.unraw().to_string();
        if !known.contains(&name) {
            let hint = closest(&name, &known)
                .map(|k| format!("; did you mean `{k}`?"))
                .unwrap_or_default();
            lowerer.push_error(syn::Error::new_spanned(
                ident,
                format!(
                    "`{name}` in `units(..)` is none of the model's quantities{hint} (units are \
                     given for the coordinates, speeds and inputs, `t` and `energy`)"
                ),
            ));
        } else if !seen.insert(name.clone()) {
            lowerer.push_error(syn::Error::new_spanned(
                ident,
                format!("the unit of `{name}` is given twice"),
            ));
        } else if unit.value().trim().is_empty() {
            lowerer.push_error(syn::Error::new_spanned(
                unit,
                format!("an empty unit: give `{name}` its unit, or leave it out of `units(..)`"),
            ));
        } else {
            let unit = unit.value().trim().to_string();
            match group_members(names, &name) {
                Some(members) => units.extend(members.into_iter().map(|m| (m, unit.clone()))),
                None => units.push((name, unit)),
            }
        }
    }
    units
}

/// The members of the indexed group of coordinates, speeds or inputs called `base`
/// (`theta0`, `theta1`, … of `theta[3]`).
fn group_members(names: &Names, base: &str) -> Option<Vec<String>> {
    let group = names.groups[..3]
        .iter()
        .flatten()
        .find(|g| g.base.unraw() == base)?;
    Some((0..group.len).map(|i| format!("{base}{i}")).collect())
}
