//! What control code the model asks for: `#[outputs]`, `outputs(..)` and
//! `control(order = .., brackets = ..)`, checked against each other. A model that asks for
//! none gets none, and its expansion is what it was without them.

use super::error_at_output;
use crate::engine::lower::{Lowerer, Shape};
use crate::system::model::{ControlKey, Names, Role, Roles, names_of};
use quote::format_ident;
use syn::ext::IdentExt;

/// The highest order of Lie derivatives, and the deepest brackets, a model may ask for: each
/// level is a tangent sweep of the one before, and the generated code grows with it.
pub const MOST_ORDER: usize = 4;
pub const MOST_DEPTH: usize = 4;
/// The most brackets a model may ask for: (m + 1)(m + 2)/2 … grow as (m + 1)^depth.
pub const MOST_BRACKETS: usize = 256;

/// The outputs y = h(t, q) or h(t, q, speeds) and their names.
pub struct Outputs<'a> {
    pub f: &'a syn::ImplItemFn,
    pub names: Vec<String>,
    /// `fn(&self, q, speeds)`: the outputs read the speeds too.
    pub reads_speeds: bool,
}

/// The control code a model asks for.
pub struct ControlRequest<'a> {
    pub outputs: Option<Outputs<'a>>,
    /// L_f^k h for k = 0 … order, and L_g L_f^k h for k < order (0 without outputs).
    pub order: usize,
    /// Iterated Lie brackets of the drift and the input fields, to this depth (0: none).
    pub brackets: usize,
}

/// How many right-nested brackets [X₁, [X₂, … [X_{L−1}, X_L]]] of `generators` fields there
/// are of depth 1 … `depth` whose innermost pair is ordered (the others are its negatives or
/// zero).
pub fn bracket_count(generators: usize, depth: usize) -> usize {
    let pairs = generators * generators.saturating_sub(1) / 2;
    (0..depth).map(|d| pairs * generators.pow(d as u32)).sum()
}

/// The request, or `None` when the model asks for no control code. Mistakes are reported
/// (the rest of the model is still checked and built, so that one build finds them all).
pub(super) fn request<'a>(
    names: &Names,
    roles: &Roles<'a>,
    dropped: &[Role],
    (n, m, p): (usize, usize, Option<usize>),
    lowerer: &mut Lowerer<'a, '_>,
) -> Option<ControlRequest<'a>> {
    let role = roles.get(Role::Outputs);
    if role.is_none() && names.control.is_none() && names.outputs.is_none() {
        return None;
    }
    if let (None, Some((span, _))) = (role, &names.outputs) {
        lowerer.push_error(syn::Error::new(
            *span,
            "`outputs(..)` names the outputs of an `#[outputs]` function, and the model has \
             none: add `#[outputs] fn name(&self, q: &[f64; N]) -> [f64; R]`, or remove \
             `outputs(..)`",
        ));
    }
    let key = names.control.clone().unwrap_or(ControlKey {
        written: proc_macro2::TokenStream::new(),
        order: None,
        brackets: None,
    });
    let order = order(&key, role.is_some(), lowerer);
    let brackets = brackets(&key, m, lowerer);
    let outputs = role
        .filter(|_| !dropped.contains(&Role::Outputs))
        .and_then(|rf| outputs(rf.f, names, (n, p), lowerer));
    Some(ControlRequest {
        outputs,
        order,
        brackets,
    })
}

/// `order = k`: 2 where it is not given and there are outputs (the relative degree of an
/// output of the configuration that the inputs act on through the accelerations).
fn order(key: &ControlKey, outputs: bool, lowerer: &mut Lowerer<'_, '_>) -> usize {
    match (key.order, outputs) {
        (None, true) => 2,
        (None, false) => 0,
        (Some((_, span)), false) => {
            lowerer.push_error(syn::Error::new(
                span,
                "`order` asks for the Lie derivatives of outputs, and the model has none: add \
                 `#[outputs] fn name(&self, q: &[f64; N]) -> [f64; R]`, or remove `order`",
            ));
            0
        }
        (Some((k, span)), true) if k == 0 || k > MOST_ORDER => {
            lowerer.push_error(syn::Error::new(
                span,
                format!(
                    "`order = {k}`: the Lie derivatives L_f^k h are generated for k = 1 … \
                     {MOST_ORDER} (each order is a tangent sweep of the one before)"
                ),
            ));
            2
        }
        (Some((k, _)), true) => k,
    }
}

/// `brackets = d`, at most `MOST_DEPTH` deep and `MOST_BRACKETS` in number.
fn brackets(key: &ControlKey, m: usize, lowerer: &mut Lowerer<'_, '_>) -> usize {
    let Some((depth, span)) = key.brackets else {
        return 0;
    };
    let count = bracket_count(m + 1, depth);
    if depth > MOST_DEPTH {
        lowerer.push_error(syn::Error::new(
            span,
            format!(
                "`brackets = {depth}`: iterated Lie brackets are generated to a depth of at most \
                 {MOST_DEPTH} (each level is a tangent sweep of the one before)"
            ),
        ));
        return 0;
    }
    if count > MOST_BRACKETS {
        lowerer.push_error(syn::Error::new(
            span,
            format!(
                "`brackets = {depth}` with {m} inputs is {count} brackets, more than \
                 {MOST_BRACKETS}: ask for a smaller depth"
            ),
        ));
        return 0;
    }
    depth
}

/// The outputs' function: its result an array of reals, one per name of `outputs(..)` (or
/// named `y0`, `y1`, …).
fn outputs<'a>(
    f: &'a syn::ImplItemFn,
    names: &Names,
    (n, p): (usize, Option<usize>),
    lowerer: &mut Lowerer<'a, '_>,
) -> Option<Outputs<'a>> {
    let sig = lowerer.signature(f)?;
    let reads_speeds = sig.args.len() - usize::from(timed(&sig.args)) == 2;
    let count = match &sig.output {
        Some(Shape::Array(r, inner)) if **inner == Shape::Real && *r > 0 => *r,
        other => {
            let found = other
                .as_ref()
                .map_or("no array".to_string(), Shape::describe);
            lowerer.push_error(error_at_output(
                f,
                format!(
                    "`#[outputs]` must return `[f64; R]`, one value per output (R ≥ 1); found \
                     {found}"
                ),
            ));
            return None;
        }
    };
    if reads_speeds && p.is_none_or(|p| p >= n) {
        return None;
    }
    let names = match &names.outputs {
        Some((span, list)) if list.len() != count => {
            lowerer.push_error(syn::Error::new(
                *span,
                format!(
                    "`outputs({})` names {} and `{}` returns {count} values: name one output \
                     per value, in order",
                    names_of(list),
                    list.len(),
                    f.sig.ident
                ),
            ));
            return None;
        }
        Some((_, list)) => distinct(list, lowerer)?,
        None => (0..count).map(|i| format_ident!("y{}", i)).collect(),
    };
    Some(Outputs {
        f,
        names: names.iter().map(|i| i.unraw().to_string()).collect(),
        reads_speeds,
    })
}

/// Whether the first argument is the time (a scalar).
fn timed(args: &[crate::engine::lower::Arg]) -> bool {
    args.first().is_some_and(|a| a.shape == Shape::Real)
}

/// The output names, each once.
fn distinct(list: &[syn::Ident], lowerer: &mut Lowerer<'_, '_>) -> Option<Vec<syn::Ident>> {
    for (i, name) in list.iter().enumerate() {
        if list[..i].iter().any(|other| other == name) {
            lowerer.push_error(syn::Error::new(
                name.span(),
                format!(
                    "the output `{name}` is named twice in `outputs({})`: each output needs a \
                     name of its own",
                    names_of(list)
                ),
            ));
            return None;
        }
    }
    Some(list.to_vec())
}

#[cfg(test)]
mod tests {
    use super::bracket_count;

    #[test]
    fn brackets_are_counted_by_depth() {
        // f, g1, g2: [f, g1], [f, g2], [g1, g2]; then each bracketed once more by f, g1, g2.
        assert_eq!(bracket_count(3, 1), 3);
        assert_eq!(bracket_count(3, 2), 3 + 9);
        assert_eq!(bracket_count(3, 3), 3 + 9 + 27);
        assert_eq!(bracket_count(1, 4), 0);
    }
}
