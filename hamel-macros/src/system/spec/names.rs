//! The names of the coordinates, speeds, inputs and constraint rows: how many, that they
//! are distinct and not reserved, and that declared inputs are read.

use super::rows::ModelShape;
use super::signatures::{expected, render};
use super::{count, fail};
use crate::engine::hash::{HashMap, HashSet};
use crate::engine::lower::Lowerer;
use crate::system::model::{Group, Names, Role, Roles, names_of};
use crate::system::reserved;
use proc_macro2::TokenStream;
use quote::format_ident;
use syn::ext::IdentExt;

/// Inputs are read by the forces only: without `#[forces]` they would be silently ignored.
pub(super) fn check_inputs_are_read(
    names: &Names,
    roles: &Roles<'_>,
    n: usize,
    lowerer: &mut Lowerer<'_, '_>,
) {
    if let Some(written) = &names.inputs_written
        && !names.inputs.is_empty()
        && roles.get(Role::Forces).is_none()
    {
        let (args, out) = expected(Role::Forces, n, names.inputs.len(), None, true);
        let (declared, them) = match names.inputs.as_slice() {
            [one] => (format!("the input `{one}` is declared"), "it"),
            all => (format!("the inputs {} are declared", names_of(all)), "them"),
        };
        lowerer.push_error(syn::Error::new_spanned(
            written,
            format!(
                "{declared}, but the model has no `#[forces]` to read {them}, so {them} would \
                 be ignored: add a `#[forces]` function `{}` that uses `u`, or remove \
                 `inputs(..)`",
                render(Role::Forces, &args, out.as_ref())
            ),
        ));
    }
}

/// Names of the speeds: given, or w{p+1}…w{n} as in the paper. A mistake in the names is
/// reported, but does not stop the model from being checked.
pub(super) fn speed_names(
    written: Option<(proc_macro2::Span, Vec<syn::Ident>)>,
    garbled: bool,
    n: usize,
    p: Option<usize>,
    lowerer: &mut Lowerer<'_, '_>,
) -> Vec<syn::Ident> {
    match (written, p) {
        // A list that could not be read is reported already, and its length means nothing.
        (Some((span, list)), Some(p)) if list.len() != n - p && !garbled => {
            lowerer.push_error(syn::Error::new(
                span,
                format!(
                    "{} for {} ({} − {}): name one speed per quasi-velocity",
                    count(list.len(), "speed name"),
                    count(n - p, "quasi-velocity"),
                    count(n, "coordinate"),
                    count(p, "constraint"),
                ),
            ));
            list
        }
        (Some((_, list)), _) => list,
        (None, Some(p)) => (p + 1..=n).map(|k| format_ident!("w{}", k)).collect(),
        (None, None) => Vec::new(),
    }
}

/// The constraint rows of a model, for the message about naming them.
pub(super) struct Rows<'a> {
    pub(super) constraints: Option<&'a syn::ImplItemFn>,
    /// The rolling contacts: their function, how many, how many rows they keep and how many
    /// heights are holonomic.
    pub(super) contacts: Option<(&'a syn::ImplItemFn, usize, usize, usize)>,
    /// Every nonholonomic row: the constraints' and two per contact.
    pub(super) nonholonomic: usize,
    pub(super) holonomic: Option<&'a syn::ImplItemFn>,
    /// The rows of `#[holonomic]`.
    pub(super) k: usize,
}

/// Names of the constraint rows, when `constraints(..)` gives them: one per row (`rows`, when
/// the rows could be counted), the nonholonomic ones first. A wrong count is reported, but
/// does not stop the model from being checked.
pub(super) fn constraint_names(
    names: &Names,
    rows: Option<Rows<'_>>,
    lowerer: &mut Lowerer<'_, '_>,
) -> Option<Vec<syn::Ident>> {
    let (span, list) = names.constraints.clone()?;
    let Some(rows) = rows else {
        return Some(list);
    };
    let heights = rows.contacts.map_or(0, |(_, _, _, h)| h);
    let p = rows.nonholonomic + rows.k + heights;
    // A list that could not be read is reported already, and its length means nothing.
    if list.len() != p && !names.garbled && rows.contacts.is_some() {
        lowerer.push_error(syn::Error::new(
            span,
            format!(
                "{} for {}: {}; name one per row, in this order",
                count(list.len(), "constraint name"),
                count(p, "constraint row"),
                row_sources(&rows)
            ),
        ));
    } else if list.len() != p && !names.garbled {
        let rows_of = |f: Option<&syn::ImplItemFn>, role: Role, rows: usize| {
            let what = count(rows, "row");
            match f {
                Some(f) => format!(
                    "`{}` (`#[{}]`) returns {what}",
                    f.sig.ident,
                    role.attribute()
                ),
                None => format!("`#[{}]` returns {what}", role.attribute()),
            }
        };
        let constraints = rows_of(rows.constraints, Role::Constraints, rows.nonholonomic);
        let first = rows.constraints.map_or_else(
            || "`#[constraints]`".to_string(),
            |f| format!("`{}`", f.sig.ident),
        );
        let given = match rows.holonomic {
            Some(h) => format!(
                "{constraints} and {}; name one per row, in order, those of {first} first",
                rows_of(Some(h), Role::Holonomic, rows.k)
            ),
            None => format!("{constraints}; name one per row, in order"),
        };
        lowerer.push_error(syn::Error::new(
            span,
            format!(
                "{} for {}: {given}",
                count(list.len(), "constraint name"),
                count(p, "constraint row"),
            ),
        ));
    }
    Some(list)
}

/// Where the constraint rows of a model with rolling contacts come from, in their order.
fn row_sources(rows: &Rows<'_>) -> String {
    let mut parts = Vec::new();
    let contact_rows = rows.contacts.map_or(0, |(_, _, kept, _)| kept);
    if let Some(f) = rows.constraints {
        let written = count(rows.nonholonomic - contact_rows, "row");
        parts.push(format!(
            "`{}` (`#[constraints]`) returns {written}",
            f.sig.ident
        ));
    }
    if let Some((f, c, kept, _)) = rows.contacts {
        let left_out = match 2 * c - kept {
            0 => String::new(),
            r => format!(", less {} that repeat the others", count(r, "row")),
        };
        parts.push(format!(
            "`{}` (`#[contacts]`) gives {} (two per contact, the slip along the surface{left_out})",
            f.sig.ident,
            count(kept, "row")
        ));
    }
    if let Some(h) = rows.holonomic {
        parts.push(format!(
            "`{}` (`#[holonomic]`) returns {}",
            h.sig.ident,
            count(rows.k, "row")
        ));
    }
    if let Some((f, _, _, h)) = rows.contacts.filter(|(_, _, _, h)| *h > 0) {
        parts.push(format!(
            "then {} of `{}`, one per coordinate in `determines(..)`",
            count(h, "height"),
            f.sig.ident
        ));
    }
    parts.join(", ")
}

/// The coordinates' names; an error when there are none (unless the list could not be read,
/// which is reported already).
pub(super) fn coordinate_names(
    written: Option<(proc_macro2::Span, Vec<syn::Ident>)>,
    garbled: bool,
    lowerer: &mut Lowerer<'_, '_>,
    at: &TokenStream,
    ok: &mut bool,
) -> Vec<syn::Ident> {
    let error = match written {
        Some((_, list)) if !list.is_empty() => return list,
        _ if garbled => {
            *ok = false;
            return Vec::new();
        }
        Some((span, _)) => syn::Error::new(span, "a model needs at least one coordinate"),
        None => syn::Error::new_spanned(
            at,
            "name the generalized coordinates: `#[hamel_system(coordinates(x, y, theta))]` \
             (the names appear in accessors, `Debug` output and CSV headers)",
        ),
    };
    fail(lowerer, ok, error);
    Vec::new()
}

/// What each list of names holds, in the order of the lists given to `check_names`.
pub(super) const KINDS: [&str; 4] = ["coordinate", "speed", "input", "constraint"];

/// Each name must have an upper-case form that is an identifier (its index constant), be
/// distinct from the others, and not be reserved. `lists`: the coordinates, speeds, inputs
/// and constraints. A constraint's column is `lambda_<name>`, which no other column can be
/// (the `lambda_` prefix is reserved): its name need only be distinct, and not hide a
/// constant.
pub(super) fn check_names(lists: [&[syn::Ident]; 4], lowerer: &mut Lowerer<'_, '_>, ok: &mut bool) {
    let mut seen: HashMap<String, (&syn::Ident, &str)> = HashMap::default();
    let named = lists
        .into_iter()
        .zip(KINDS)
        .flat_map(|(list, kind)| list.iter().map(move |ident| (ident, kind)));
    for (ident, kind) in named {
        let upper = ident.unraw().to_string().to_uppercase();
        if syn::parse_str::<syn::Ident>(&upper).is_err() {
            fail(
                lowerer,
                ok,
                syn::Error::new(
                    ident.span(),
                    format!(
                        "the name `{ident}` has no upper-case form that is an identifier (`{upper}`), \
                         which its index constant needs: choose another name"
                    ),
                ),
            );
        }
        let plain = ident.unraw().to_string();
        let reserved = if kind == "constraint" {
            reserved::constant_clash(&plain)
        } else {
            reserved::clash(&plain)
        };
        if let Some(why) = reserved {
            lowerer.push_error(syn::Error::new(
                ident.span(),
                format!("the name `{ident}` is reserved: {why}; choose another name"),
            ));
        }
        if let Some((first, first_kind)) = seen.insert(upper.clone(), (ident, kind)) {
            let already = if first.unraw() == ident.unraw() {
                format!("already the name of {}", a(first_kind))
            } else {
                format!("`{first}`, {}, has the same upper case", a(first_kind))
            };
            lowerer.push_error(syn::Error::new(
                ident.span(),
                format!(
                    "duplicate name `{ident}` ({already}): coordinates, speeds, inputs and \
                     constraints need distinct names (also in upper case, which names their \
                     index constants, `Self::{upper}`)"
                ),
            ));
        }
    }
}

/// The base name of an indexed group names a constant too (`Self::THETA`, its first index):
/// it must clash with no other name's constant and not be reserved. (`lists` as for
/// `check_names`.)
pub(super) fn check_group_names(
    groups: &[Vec<Group>; 4],
    lists: [&[syn::Ident]; 4],
    lowerer: &mut Lowerer<'_, '_>,
) {
    let upper = |i: &syn::Ident| i.unraw().to_string().to_uppercase();
    let mut taken: HashSet<String> = lists.iter().copied().flatten().map(upper).collect();
    for (group, kind) in groups
        .iter()
        .zip(KINDS)
        .flat_map(|(groups, kind)| groups.iter().map(move |g| (g, kind)))
    {
        let name = upper(&group.base);
        let base = group.base.unraw().to_string();
        let reserved = if kind == "constraint" {
            reserved::constant_clash(&base)
        } else {
            reserved::clash(&base)
        };
        if let Some(why) = reserved {
            lowerer.push_error(syn::Error::new(
                group.base.span(),
                format!(
                    "the group name `{}` is reserved: {why}; choose another name",
                    group.base
                ),
            ));
        } else if !taken.insert(name.clone()) {
            lowerer.push_error(syn::Error::new(
                group.base.span(),
                format!(
                    "the group `{base}[{len}]` names the constant `Self::{name}` (the index of \
                     `{base}0`), which another name already has: choose distinct names",
                    base = group.base,
                    len = group.len
                ),
            ));
        }
    }
}

/// "a coordinate", "an input".
fn a(kind: &str) -> String {
    if kind.starts_with(['a', 'e', 'i', 'o', 'u']) {
        format!("an {kind}")
    } else {
        format!("a {kind}")
    }
}

/// The constraint rows' names, and every list of names checked for clashes and reserved
/// words.
pub(super) fn check_all_names(
    names: &Names,
    shape: &ModelShape<'_, '_>,
    (coordinates, speeds): (&[syn::Ident], &[syn::Ident]),
    roles: &Roles<'_>,
    lowerer: &mut Lowerer<'_, '_>,
    ok: &mut bool,
) -> Option<Vec<syn::Ident>> {
    let (kept, heights) = shape.contact_rows();
    // (A failed `#[holonomic]` leaves the rows uncounted: `p` is `None`.)
    let rows = shape.p.map(|p| Rows {
        constraints: shape.constraints.map(|c| c.f),
        contacts: shape.contacts.map(|(c, count)| (c.f, count, kept, heights)),
        nonholonomic: p - shape.k,
        holonomic: shape.holonomic.map(|h| h.f),
        k: shape.k - heights,
    });
    let constraint_names = constraint_names(names, rows, lowerer);
    let lists = [
        coordinates,
        speeds,
        &names.inputs,
        constraint_names.as_deref().unwrap_or_default(),
    ];
    check_names(lists, lowerer, ok);
    check_group_names(&names.groups, lists, lowerer);
    check_inputs_are_read(names, roles, coordinates.len(), lowerer);
    constraint_names
}
