//! Each role's signature against what the role needs: the arguments' number, order and
//! shapes, the result, and whether the function takes the time.

use super::{count, error_at_output};
use crate::engine::hash::HashSet;
use crate::engine::lower::geometry::GeoKind;
use crate::engine::lower::{Arg, Lowerer, Shape};
use crate::system::model::{Role, RoleFn, Roles, names_of, written_length};
use quote::ToTokens;
use syn::ext::IdentExt;

/// What each role's signature must be, for the messages about unsupported types in it: with
/// `p` the constraint rows once the contacts are read, or from the lengths as written.
pub(super) fn record_expected_signatures(
    roles: &Roles<'_>,
    n: usize,
    m: usize,
    p: Option<usize>,
    lowerer: &mut Lowerer<'_, '_>,
) {
    let p_total = p.or_else(|| written_rows(roles)).filter(|&p| p < n);
    for (role, rf) in &roles.by_role {
        let timed = takes_time(*role, rf.f, n, m, p_total);
        let (args, out) = expected_of(*role, rf.f, (n, m, p_total), timed);
        let name = rf.f.sig.ident.to_string();
        lowerer
            .signature_hints
            .insert(name.clone(), render(*role, &args, out.as_ref()));
        lowerer.expected_arguments.insert(name, args);
    }
}

/// Every constraint row, as the role functions' result types say (before they are
/// checked): the constraints', two per rolling contact, the holonomic constraints' and the
/// contacts' heights.
pub fn written_rows(roles: &Roles<'_>) -> Option<usize> {
    let written = |role: Role| roles.get(role).map(|rf| written_length(&rf.f.sig.output));
    let contacts = roles.get(Role::Contacts);
    let constraints = match (written(Role::Constraints), contacts) {
        (Some(p), _) => p?,
        (None, Some(_)) => 0,
        (None, None) => return None,
    };
    let rolling = match written(Role::Contacts) {
        Some(c) => 2 * c?,
        None => 0,
    };
    let holonomic = written(Role::Holonomic).unwrap_or(Some(0))?;
    let heights = contacts.map_or(0, |c| c.determines.len());
    Some(constraints + rolling + holonomic + heights)
}

/// The signature of every role present: the functions that take the time, and the optional
/// roles left out of the model because their signature is wrong (their error stands, and
/// the rest of the model is still checked). A required role with a wrong signature clears
/// `ok`.
pub(super) fn check_signatures(
    roles: &Roles<'_>,
    (n, m, p): (usize, usize, Option<usize>),
    coordinates: &[syn::Ident],
    inputs: &[syn::Ident],
    lowerer: &mut Lowerer<'_, '_>,
    ok: &mut bool,
) -> (HashSet<String>, Vec<Role>) {
    let mut dropped = Vec::new();
    let mut timed = HashSet::default();
    for (role, rf) in &roles.by_role {
        let takes = takes_time(*role, rf.f, n, m, p);
        let fits = check_signature(
            *role,
            rf,
            &expected_of(*role, rf.f, (n, m, p), takes),
            lowerer,
            (coordinates, inputs),
            p,
        );
        if takes && *role != Role::Forces {
            timed.insert(rf.f.sig.ident.to_string());
        }
        if !fits {
            lowerer.mark_faulty(rf.f.sig.ident.to_string());
            match role {
                Role::Velocities | Role::Forces | Role::Outputs => dropped.push(*role),
                _ => *ok = false,
            }
        }
    }
    (timed, dropped)
}

/// Whether a role function takes the time first: one argument more than the role needs,
/// and the role may take it (`fn(&self, t: f64, q: &[f64; N], qd: &[f64; N])`). A `t` of
/// the wrong type or in the wrong place is then reported by the signature check.
pub(super) fn takes_time(
    role: Role,
    f: &syn::ImplItemFn,
    n: usize,
    m: usize,
    p: Option<usize>,
) -> bool {
    if role == Role::Forces {
        return true;
    }
    let typed: Vec<&syn::PatType> = typed_arguments(f);
    // One argument too many, and one of them is the time: named `t`, or a scalar `f64`.
    let is_time = |pt: &&syn::PatType| {
        argument_name(&pt.pat).is_some_and(|name| name == "t")
            || matches!(&*pt.ty, syn::Type::Path(ty) if ty.path.is_ident("f64"))
    };
    // The outputs take one or two arguments besides the time: the time is the first.
    if role == Role::Outputs {
        return typed.first().is_some_and(is_time);
    }
    role.may_take_time()
        && typed.len() == expected(role, n, m, p, false).0.len() + 1
        && typed.iter().any(is_time)
}

/// The arguments after `&self`, as written.
fn typed_arguments(f: &syn::ImplItemFn) -> Vec<&syn::PatType> {
    f.sig
        .inputs
        .iter()
        .filter_map(|a| match a {
            syn::FnArg::Typed(pt) => Some(pt),
            syn::FnArg::Receiver(_) => None,
        })
        .collect()
}

/// [`expected`] for the function `f` as written: the outputs read the configuration alone,
/// `h(q)`, or the speeds too, `h(q, speeds)`, as the function's arguments say.
pub(super) fn expected_of(
    role: Role,
    f: &syn::ImplItemFn,
    (n, m, p): (usize, usize, Option<usize>),
    timed: bool,
) -> (Vec<(&'static str, Shape)>, Option<Shape>) {
    let (mut args, out) = expected(role, n, m, p, timed);
    let besides_time = typed_arguments(f).len() - usize::from(timed);
    if role == Role::Outputs && besides_time == 2 {
        let free = p.map_or(Shape::Real, |p| {
            Shape::Array(n.saturating_sub(p), Box::new(Shape::Real))
        });
        args.push(("speeds", free));
    }
    (args, out)
}

/// What a role's function must take and return (`p`: the number of constraint rows, the
/// holonomic ones' included, when known; `timed`: the function takes the time first).
pub(super) fn expected(
    role: Role,
    n: usize,
    m: usize,
    p: Option<usize>,
    timed: bool,
) -> (Vec<(&'static str, Shape)>, Option<Shape>) {
    let real_array = |len: usize| Shape::Array(len, Box::new(Shape::Real));
    let q = ("q", real_array(n));
    let qd = ("qd", real_array(n));
    let w = ("w", real_array(n));
    let (mut args, out) = match role {
        Role::Lagrangian | Role::KineticEnergy => (vec![q, qd], Some(Shape::Real)),
        Role::PotentialEnergy => (vec![q], Some(Shape::Real)),
        Role::QuasiLagrangian => (vec![q, w], Some(Shape::Real)),
        Role::Constraints => (vec![q, qd], None),
        Role::QuasiVelocities => (vec![q, qd], p.map(|p| real_array(n - p))),
        Role::Velocities => (vec![q, w], Some(real_array(n))),
        Role::Holonomic | Role::Bodies | Role::Contacts | Role::Outputs => (vec![q], None),
        Role::Gravity => (vec![], Some(Shape::Geo(GeoKind::Vector))),
        Role::Forces => {
            return (
                vec![("t", Shape::Real), q, qd, ("u", real_array(m))],
                Some(real_array(n)),
            );
        }
    };
    if timed {
        args.insert(0, ("t", Shape::Real));
    }
    (args, out)
}

/// Compare a role function's signature with what its role needs (`expected`: its arguments
/// and result; `names`: the coordinates and inputs).
pub(super) fn check_signature(
    role: Role,
    rf: &RoleFn<'_>,
    expected: &(Vec<(&str, Shape)>, Option<Shape>),
    lowerer: &mut Lowerer<'_, '_>,
    names: (&[syn::Ident], &[syn::Ident]),
    p: Option<usize>,
) -> bool {
    let (expected, output) = (&expected.0, expected.1.as_ref());
    let (coordinates, inputs) = names;
    let f = rf.f;
    let Some(sig) = lowerer.signature(f) else {
        return false;
    };
    let rendered = render(role, expected, output);
    if sig.args.len() != expected.len() {
        lowerer.push_error(syn::Error::new_spanned(
            &f.sig.inputs,
            format!(
                "`#[{}]` takes {} besides `&self`, this function takes {}: expected \
                 `{rendered}`{}",
                role.attribute(),
                count(expected.len(), "argument"),
                sig.args.len(),
                why_these_arguments(role)
            ),
        ));
        return false;
    }
    if let Some(e) = misplaced(role, &sig.args, expected, &rendered) {
        lowerer.push_error(e);
        return false;
    }
    let mut ok = true;
    for (arg, (name, shape)) in sig.args.iter().zip(expected) {
        if arg.shape != *shape {
            let why = match shape {
                Shape::Array(_, _) if *name == "u" && inputs.is_empty() => {
                    "one per input, and the model declares none (name them in \
                     `#[hamel_system(inputs(..))]`)"
                        .to_string()
                }
                Shape::Array(..) if *name == "u" => {
                    format!("one per input ({})", names_of(inputs))
                }
                Shape::Array(..) if *name == "speeds" => {
                    "one per free quasi-velocity (the state's speeds)".to_string()
                }
                Shape::Array(..) => format!("one per coordinate ({})", names_of(coordinates)),
                _ => "the time".to_string(),
            };
            lowerer.push_error(syn::Error::new_spanned(
                &arg.ty,
                format!(
                    "argument `{}` of `#[{}]` must be {}, {why}; found {}. Expected `{rendered}`",
                    arg.pat.to_token_stream(),
                    role.attribute(),
                    shape.describe(),
                    arg.shape.describe()
                ),
            ));
            ok = false;
        }
    }
    if let (Some(want), Some(got)) = (output, &sig.output)
        && want != got
    {
        lowerer.push_error(error_at_output(
            f,
            wrong_output(role, want, got, coordinates, p),
        ));
        ok = false;
    }
    ok && sig.output.is_some()
}

/// Why a role takes the arguments it does, for the message about their number.
fn why_these_arguments(role: Role) -> &'static str {
    match role {
        Role::Holonomic => {
            "; a holonomic constraint f(q) = 0 depends on the configuration (and, with a \
             leading `t: f64`, the time) only: the macro derives its velocity row"
        }
        Role::Bodies => {
            "; a body's pose (its centre and orientation) is a function of the configuration \
             (and, with a leading `t: f64`, the time) only: the macro derives its velocity and \
             angular velocity"
        }
        Role::Contacts => {
            "; where a body touches the ground is a function of the configuration (and, with \
             a leading `t: f64`, the time) only: the macro derives the velocity of the body's \
             material point there"
        }
        Role::Gravity => " (or with a leading `t: f64`): gravity is a vector of the parameters",
        Role::Forces => "",
        Role::Outputs => {
            " (or with a leading `t: f64`), or `fn(&self, q: &[f64; N], speeds: &[f64; N - P]) \
             -> [f64; R]` for outputs of the speeds too"
        }
        _ => " (or with a leading `t: f64`)",
    }
}

/// A role function returns `got` where `want` is needed.
fn wrong_output(
    role: Role,
    want: &Shape,
    got: &Shape,
    coordinates: &[syn::Ident],
    p: Option<usize>,
) -> String {
    let (attribute, want, got) = (role.attribute(), want.describe(), got.describe());
    match (role, p) {
        (Role::QuasiVelocities, Some(p)) => format!(
            "`#[{attribute}]` must return {want}, found {got}: with {} and {}, {} complete the \
             constraints to ω = A(q)·qd",
            count(coordinates.len(), "coordinate"),
            count(p, "constraint"),
            count(coordinates.len() - p, "quasi-velocity"),
        ),
        (Role::Velocities | Role::Forces, _) => format!(
            "`#[{attribute}]` must return {want}, one per coordinate ({}); found {got}",
            names_of(coordinates)
        ),
        _ => format!("`#[{attribute}]` must return {want}, found {got}"),
    }
}

/// The name an argument is written with, without the leading underscores that only silence
/// "unused" warnings: `_q` is `q`. `None` for a pattern that is not a plain name.
pub fn argument_name(pat: &syn::Pat) -> Option<String> {
    match pat {
        syn::Pat::Ident(p) => Some(
            p.ident
                .unraw()
                .to_string()
                .trim_start_matches('_')
                .to_string(),
        ),
        _ => None,
    }
}

/// Arguments named as other arguments of the role (`fn(&self, qd, q)`): the names would say
/// one thing and the positions another, so the order is an error (other names, `config`,
/// `vel`, are the user's choice). One error for the whole list, at the first misplaced one.
pub(super) fn misplaced(
    role: Role,
    args: &[Arg],
    expected: &[(&str, Shape)],
    rendered: &str,
) -> Option<syn::Error> {
    let swaps: Vec<(&Arg, &str)> = args
        .iter()
        .zip(expected)
        .filter_map(|(arg, (place, _))| {
            let name = argument_name(&arg.pat)?;
            let other = expected.iter().any(|(e, _)| *e == name);
            (other && name != *place).then_some((arg, *place))
        })
        .collect();
    let (first, place) = swaps.first()?;
    let rest: Vec<String> = swaps[1..]
        .iter()
        .map(|(arg, place)| {
            format!(
                " and `{}` in the place of `{place}`",
                arg.pat.to_token_stream()
            )
        })
        .collect();
    Some(syn::Error::new_spanned(
        &first.pat,
        format!(
            "argument `{}` is in the place of `{place}`{}: `#[{}]` takes `{rendered}`; put the \
             arguments in this order",
            first.pat.to_token_stream(),
            rest.concat(),
            role.attribute()
        ),
    ))
}

pub(super) fn render(role: Role, args: &[(&str, Shape)], output: Option<&Shape>) -> String {
    let args: Vec<String> = args
        .iter()
        .map(|(n, s)| match s {
            Shape::Real => format!("{n}: f64"),
            other => format!("{n}: &{}", other.describe().trim_matches('`')),
        })
        .collect();
    let unknown = match role {
        Role::Holonomic => "[f64; K]",
        Role::Bodies => "[Body; B]",
        Role::Contacts => "[Contact; C]",
        Role::Outputs => "[f64; R]",
        _ => "[f64; P]",
    };
    let out = output.map_or_else(
        || unknown.to_string(),
        |s| s.describe().trim_matches('`').to_string(),
    );
    if args.is_empty() {
        return format!("fn(&self) -> {out}");
    }
    format!("fn(&self, {}) -> {out}", args.join(", "))
}
