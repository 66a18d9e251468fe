//! What the user wrote: the names in `#[hamel_system(..)]` and the role of each function.

use proc_macro2::{Span, TokenStream};
use quote::ToTokens;
use std::collections::BTreeMap;
use syn::spanned::Spanned;

/// The roles a function of the model can play, each marked by an attribute of that name.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Role {
    /// L(q, q̇)
    Lagrangian,
    /// T(q, q̇)
    KineticEnergy,
    /// V(q)
    PotentialEnergy,
    /// L̃(q, ω), the Lagrangian in quasi-velocities (the paper's eq. 12)
    QuasiLagrangian,
    /// ω¹…ωᵖ(q, q̇), zero on every motion
    Constraints,
    /// ω^{p+1}…ωⁿ(q, q̇), completing the constraints to an invertible ω = A(q) q̇
    QuasiVelocities,
    /// q̇ = B(q) ω, the inverse (optional)
    Velocities,
    /// f(t, q, q̇, u) (optional)
    Forces,
    /// f(q) = 0 or f(t, q) = 0, holonomic constraints (optional); their time derivatives
    /// join the constraint rows
    Holonomic,
    /// The rigid bodies as functions of q (and t): their kinetic energy, and with
    /// `#[gravity]` their potential, are derived
    Bodies,
    /// The gravitational acceleration as a vector, for the bodies' potential energy
    Gravity,
    /// Where bodies roll without slipping: constraint rows from the velocity of the material
    /// point at each contact, and the contacts' heights as holonomic constraints
    Contacts,
    /// y = h(t, q) or h(t, q, speeds), outputs for control (optional): their Lie derivatives
    /// are generated (`control(order = ..)`)
    Outputs,
}

impl Role {
    pub const ALL: [Role; 13] = [
        Role::Lagrangian,
        Role::KineticEnergy,
        Role::PotentialEnergy,
        Role::QuasiLagrangian,
        Role::Constraints,
        Role::QuasiVelocities,
        Role::Velocities,
        Role::Forces,
        Role::Holonomic,
        Role::Bodies,
        Role::Gravity,
        Role::Contacts,
        Role::Outputs,
    ];

    pub fn attribute(self) -> &'static str {
        match self {
            Role::Lagrangian => "lagrangian",
            Role::KineticEnergy => "kinetic_energy",
            Role::PotentialEnergy => "potential_energy",
            Role::QuasiLagrangian => "quasi_lagrangian",
            Role::Constraints => "constraints",
            Role::QuasiVelocities => "quasi_velocities",
            Role::Velocities => "velocities",
            Role::Forces => "forces",
            Role::Holonomic => "holonomic",
            Role::Bodies => "bodies",
            Role::Gravity => "gravity",
            Role::Contacts => "contacts",
            Role::Outputs => "outputs",
        }
    }

    /// Whether the role's function may take the time as a leading argument `t: f64` (the
    /// forces always take it).
    pub fn may_take_time(self) -> bool {
        !matches!(self, Role::Forces)
    }

    /// The role an attribute that is not one was meant to be: `#[quasi_velocity]`,
    /// `#[constraint]`, `#[kinetic]`, `#[bodys]` — a plural or singular of a role's name, its
    /// first word, or two letters from it. rustc would report it as an unknown attribute
    /// beside the macro's "missing role": the macro reports it once, as what it is.
    pub fn misnamed(attr: &syn::Attribute) -> Option<Role> {
        if Role::from_attribute(attr).is_some() {
            return None;
        }
        let segments: Vec<&syn::PathSegment> = attr.path().segments.iter().collect();
        let written = match segments.as_slice() {
            [one] if attr.path().leading_colon.is_none() => one.ident.to_string(),
            [krate, one] if krate.ident == "hamel" => one.ident.to_string(),
            _ => return None,
        };
        let stem = |name: &str| -> String {
            let name = name.to_lowercase();
            if let Some(base) = name.strip_suffix("ies") {
                format!("{base}y")
            } else {
                name.strip_suffix('s').unwrap_or(&name).to_string()
            }
        };
        let mut meant = Role::ALL.into_iter().filter(|role| {
            let name = role.attribute();
            stem(&written) == stem(name)
                || name
                    .strip_prefix(written.as_str())
                    .is_some_and(|rest| rest.starts_with('_'))
                || (written.len() >= 5 && edit_distance(&written, name) <= 2)
        });
        // Only a name that can mean one role (`#[quasi]` could be two).
        match (meant.next(), meant.next()) {
            (Some(role), None) => Some(role),
            _ => None,
        }
    }

    /// The role an attribute marks: `#[kinetic_energy]`, or by the path of its macro in
    /// `hamel`, `#[hamel::kinetic_energy]` (which outside the model says where it belongs).
    fn from_attribute(attr: &syn::Attribute) -> Option<Role> {
        let segments: Vec<&syn::PathSegment> = attr.path().segments.iter().collect();
        let ident = match segments.as_slice() {
            [role] if attr.path().leading_colon.is_none() => &role.ident,
            [krate, role] if krate.ident == "hamel" => &role.ident,
            _ => return None,
        };
        Role::ALL.into_iter().find(|r| ident == r.attribute())
    }

    /// The signature the role's function must have, for messages (all but `#[forces]` may
    /// also take a leading `t: f64`).
    pub fn expected_signature(self) -> &'static str {
        match self {
            Role::Lagrangian | Role::KineticEnergy => {
                "fn(&self, q: &[f64; N], qd: &[f64; N]) -> f64"
            }
            Role::PotentialEnergy => "fn(&self, q: &[f64; N]) -> f64",
            Role::QuasiLagrangian => "fn(&self, q: &[f64; N], w: &[f64; N]) -> f64",
            Role::Constraints => "fn(&self, q: &[f64; N], qd: &[f64; N]) -> [f64; P]",
            Role::QuasiVelocities => "fn(&self, q: &[f64; N], qd: &[f64; N]) -> [f64; N - P]",
            Role::Velocities => "fn(&self, q: &[f64; N], w: &[f64; N]) -> [f64; N]",
            Role::Forces => {
                "fn(&self, t: f64, q: &[f64; N], qd: &[f64; N], u: &[f64; M]) -> [f64; N]"
            }
            Role::Holonomic => "fn(&self, q: &[f64; N]) -> [f64; K]",
            Role::Bodies => "fn(&self, q: &[f64; N]) -> [Body; B]",
            Role::Gravity => "fn(&self) -> Vector3",
            Role::Contacts => "fn(&self, q: &[f64; N]) -> [Contact; C]",
            Role::Outputs => "fn(&self, q: &[f64; N]) -> [f64; R]",
        }
    }
}

/// The most members an indexed group of names (`theta[3]`) may have.
const MAX_GROUP: usize = 1024;

/// An indexed group of names, `theta[3]` for `theta0, theta1, theta2`: its base name, the
/// position of its first member in its list and its length. Its base name, upper-cased, is
/// the index of the first member (`Self::THETA + i`, for loops over the group).
#[derive(Clone)]
pub struct Group {
    pub base: syn::Ident,
    pub start: usize,
    pub len: usize,
}

/// Names given in `#[hamel_system(coordinates(..), speeds(..), inputs(..), constraints(..))]`.
#[derive(Default)]
pub struct Names {
    /// The indexed groups of each list: coordinates, speeds, inputs, constraints.
    pub groups: [Vec<Group>; 4],
    pub coordinates: Option<(Span, Vec<syn::Ident>)>,
    pub speeds: Option<(Span, Vec<syn::Ident>)>,
    pub inputs: Vec<syn::Ident>,
    /// The constraint rows' names: those of `#[constraints]`, then those of `#[holonomic]`
    /// (`None`: `blade0`, the function's name and the row).
    pub constraints: Option<(Span, Vec<syn::Ident>)>,
    /// `inputs(..)` as written, for errors about the inputs as a whole.
    pub inputs_written: Option<TokenStream>,
    /// A list could not be read (its error is reported): that it holds no names, or none
    /// that fit, is no further mistake.
    pub garbled: bool,
    /// `helpers(Wheels, shapes::Frames)`: the sets of shared helpers the roles call.
    pub helpers: Vec<syn::Path>,
    /// `bodies(rear_wheel, frame)`: the names of the bodies `#[bodies]` returns, in order.
    pub bodies: Option<(Span, Vec<syn::Ident>)>,
    /// `units(x = "m", theta = "rad")`: named quantities with their units.
    pub units: Vec<(syn::Ident, syn::LitStr)>,
    /// `outputs(px, py)`: the names of the outputs of `#[outputs]`.
    pub outputs: Option<(Span, Vec<syn::Ident>)>,
    /// `control(order = 2, brackets = 3)`: what control code to generate.
    pub control: Option<ControlKey>,
}

/// `control(order = 2, brackets = 3)` as written: the highest order k of the outputs' Lie
/// derivatives L_f^k h, and the depth of the iterated Lie brackets of the drift and the input
/// fields. Either may be left out.
#[derive(Clone)]
pub struct ControlKey {
    /// The key with its list, for errors about the request as a whole.
    pub written: TokenStream,
    pub order: Option<(usize, Span)>,
    pub brackets: Option<(usize, Span)>,
}

pub const NAME_KEYS: &str = "`coordinates(..)`, `speeds(..)`, `inputs(..)`, `constraints(..)`, \
                             `bodies(..)`, `units(..)`, `helpers(..)`, `outputs(..)` and \
                             `control(..)`";

const KEYS: [&str; 10] = [
    "coordinates",
    "speeds",
    "quasi_velocities",
    "inputs",
    "constraints",
    "bodies",
    "units",
    "helpers",
    "outputs",
    "control",
];

/// Parse the attribute's arguments, collecting every mistake.
pub fn parse_names(attr: TokenStream, errors: &mut Vec<syn::Error>) -> Names {
    let mut names = Names::default();
    if attr.is_empty() {
        return names;
    }
    let parser = syn::meta::parser(|meta| {
        if meta.path.is_ident("helpers") {
            meta.parse_nested_meta(|inner| {
                names.helpers.push(inner.path.clone());
                Ok(())
            })?;
            return Ok(());
        }
        if meta.path.is_ident("units") {
            // A mistake inside the list leaves the other keys to be read (the list's
            // parentheses are consumed before its contents are).
            if let Err(e) = meta.parse_nested_meta(|inner| {
                match parse_unit(&inner)? {
                    Ok(unit) => names.units.push(unit),
                    Err(e) => errors.push(e),
                }
                Ok(())
            }) {
                errors.push(e);
            }
            return Ok(());
        }
        if meta.path.is_ident("control") {
            let key = parse_control(&meta, errors)?;
            if names.control.is_some() {
                errors.push(meta.error("`control` is given twice"));
            }
            names.control = Some(key);
            return Ok(());
        }
        let span = meta.path.span();
        let (list, groups, written) = parse_list(&meta, errors, &mut names.garbled)?;
        // An unknown key is read as the key it most likely meant, so that this one mistake
        // is not followed by "name the coordinates".
        let Some(key) = known_key(&meta.path, errors) else {
            return Ok(());
        };
        let slot = match key.as_str() {
            "coordinates" => {
                names.groups[0] = groups;
                &mut names.coordinates
            }
            "speeds" | "quasi_velocities" => {
                names.groups[1] = groups;
                &mut names.speeds
            }
            "constraints" => {
                names.groups[3] = groups;
                &mut names.constraints
            }
            "bodies" => &mut names.bodies,
            "outputs" => &mut names.outputs,
            _ => {
                names.groups[2] = groups;
                names.inputs = list;
                names.inputs_written = Some(written);
                return Ok(());
            }
        };
        if slot.is_some() {
            errors.push(meta.error(format!("`{key}` is given twice")));
        }
        *slot = Some((span, list));
        Ok(())
    });
    if let Err(e) = syn::parse::Parser::parse2(parser, attr) {
        errors.push(e);
    }
    names
}

/// One entry of `units(x = "m", theta = "rad")`: the outer error where the list cannot be
/// read on, the inner one where only this entry is wrong (a unit that is not a string).
fn parse_unit(
    inner: &syn::meta::ParseNestedMeta<'_>,
) -> syn::Result<syn::Result<(syn::Ident, syn::LitStr)>> {
    const HOW: &str = "write each unit as a name and a string: `units(x = \"m\", theta = \"rad\")`";
    let ident = inner
        .path
        .get_ident()
        .cloned()
        .ok_or_else(|| inner.error(HOW))?;
    if !inner.input.peek(syn::Token![=]) {
        return Err(inner.error(format!("`{ident}` needs its unit: {HOW}")));
    }
    let value: syn::Expr = inner.value()?.parse()?;
    Ok(match value {
        syn::Expr::Lit(syn::ExprLit {
            lit: syn::Lit::Str(unit),
            ..
        }) => Ok((ident, unit)),
        other => Err(syn::Error::new_spanned(other, HOW)),
    })
}

/// `control(order = 2, brackets = 3)`: each entry a known name and a small whole number.
/// A mistake in an entry is reported and the others are read on.
fn parse_control(
    meta: &syn::meta::ParseNestedMeta<'_>,
    errors: &mut Vec<syn::Error>,
) -> syn::Result<ControlKey> {
    const HOW: &str = "write `control(order = 2, brackets = 3)`: `order` is the highest k of the \
                       outputs' Lie derivatives L_f^k h, `brackets` the depth of the iterated Lie \
                       brackets of the drift and the input fields; each is optional";
    let path = &meta.path;
    let group = meta.input.fork().parse::<proc_macro2::Group>().ok();
    let mut key = ControlKey {
        written: quote::quote!(#path #group),
        order: None,
        brackets: None,
    };
    if !meta.input.peek(syn::token::Paren) {
        if meta.input.peek(syn::Token![=]) {
            let _: syn::Token![=] = meta.input.parse()?;
            let _: syn::Expr = meta.input.parse()?;
        }
        errors.push(syn::Error::new_spanned(&key.written, HOW));
        return Ok(key);
    }
    let empty = group.as_ref().is_some_and(|g| g.stream().is_empty());
    if empty {
        meta.input.parse::<proc_macro2::Group>()?;
        return Ok(key);
    }
    let result = meta.parse_nested_meta(|inner| {
        let slot = if inner.path.is_ident("order") {
            &mut key.order
        } else if inner.path.is_ident("brackets") {
            &mut key.brackets
        } else {
            return Err(inner.error(format!(
                "unknown entry `{}`: {HOW}",
                inner.path.to_token_stream()
            )));
        };
        if !inner.input.peek(syn::Token![=]) {
            return Err(inner.error(HOW));
        }
        let value: syn::Expr = inner.value()?.parse()?;
        let read = match &value {
            syn::Expr::Lit(syn::ExprLit {
                lit: syn::Lit::Int(i),
                ..
            }) => i.base10_parse::<usize>().ok(),
            _ => None,
        };
        match read {
            Some(k) => *slot = Some((k, value.span())),
            None => errors.push(syn::Error::new_spanned(
                &value,
                format!("expected a whole number: {HOW}"),
            )),
        }
        Ok(())
    });
    if let Err(e) = result {
        errors.push(e);
    }
    Ok(key)
}

/// The names of one key, `coordinates(x, y, theta)`, and the key with its list as written.
/// `coordinates = [x, y, theta]` is read too, with an error that says how to write it.
fn parse_list(
    meta: &syn::meta::ParseNestedMeta<'_>,
    errors: &mut Vec<syn::Error>,
    garbled: &mut bool,
) -> syn::Result<(Vec<syn::Ident>, Vec<Group>, TokenStream)> {
    let path = &meta.path;
    let mut list = Vec::new();
    let mut groups: Vec<(syn::Ident, usize, usize)> = Vec::new();
    if meta.input.peek(syn::Token![=]) {
        let (list, written) = parse_name_value(meta, errors, garbled)?;
        return Ok((list, Vec::new(), written));
    }
    let group = meta.input.fork().parse::<proc_macro2::Group>().ok();
    let written = quote::quote!(#path #group);
    // An empty list `coordinates()` is no syntax error (it is reported as "no coordinate").
    let empty = matches!(
        &group,
        Some(g) if g.delimiter() == proc_macro2::Delimiter::Parenthesis && g.stream().is_empty()
    );
    let result = if empty {
        meta.input.parse::<proc_macro2::Group>().map(|_| ())
    } else {
        meta.parse_nested_meta(|inner| match inner.path.get_ident() {
            Some(ident) if inner.input.is_empty() || inner.input.peek(syn::Token![,]) => {
                list.push(ident.clone());
                Ok(())
            }
            Some(ident) if inner.input.peek(syn::token::Bracket) => {
                let content;
                syn::bracketed!(content in inner.input);
                let length: syn::LitInt = content.parse()?;
                let len: usize = length.base10_parse()?;
                if len == 0 {
                    return Err(syn::Error::new_spanned(
                        &length,
                        format!(
                            "the indexed group `{ident}[0]` names nothing: a group `{ident}[3]` \
                             stands for `{ident}0, {ident}1, {ident}2`; give it at least one \
                             member, or remove it"
                        ),
                    ));
                }
                if len > MAX_GROUP {
                    return Err(syn::Error::new_spanned(
                        &length,
                        format!("an indexed group has at most {MAX_GROUP} members"),
                    ));
                }
                groups.push((ident.clone(), list.len(), len));
                list.extend(
                    (0..len).map(|i| syn::Ident::new(&format!("{ident}{i}"), ident.span())),
                );
                Ok(())
            }
            _ => Err(inner.error(
                "expected a name (an identifier) or an indexed group of names (`theta[3]`)",
            )),
        })
    };
    if let Err(e) = result {
        errors.push(e);
        *garbled = true;
    }
    let groups = groups
        .into_iter()
        .map(|(base, start, len)| Group { base, start, len })
        .collect();
    Ok((list, groups, written))
}

/// `coordinates = [x, y, theta]`, read with an error that says how to write it.
fn parse_name_value(
    meta: &syn::meta::ParseNestedMeta<'_>,
    errors: &mut Vec<syn::Error>,
    garbled: &mut bool,
) -> syn::Result<(Vec<syn::Ident>, TokenStream)> {
    let path = &meta.path;
    let eq: syn::Token![=] = meta.input.parse()?;
    let value: syn::Expr = meta.input.parse()?;
    let written = quote::quote!(#path #eq #value);
    let idents = match &value {
        syn::Expr::Array(a) => a
            .elems
            .iter()
            .map(|e| match e {
                syn::Expr::Path(p) => p.path.get_ident().cloned(),
                _ => None,
            })
            .collect::<Option<Vec<_>>>(),
        _ => None,
    };
    let shown = match &idents {
        Some(l) if !l.is_empty() => names_of(l),
        _ => "x, y, theta".to_string(),
    };
    errors.push(syn::Error::new_spanned(
        &written,
        format!(
            "write `{}({shown})`: `#[hamel_system]` takes the names in parentheses, not \
             after `=`",
            path.to_token_stream()
        ),
    ));
    *garbled |= idents.is_none();
    Ok((idents.unwrap_or_default(), written))
}

/// The key as written, or the known key it most likely meant (with an error); `None` when
/// it resembles none.
fn known_key(path: &syn::Path, errors: &mut Vec<syn::Error>) -> Option<String> {
    let key = path
        .get_ident()
        .map(ToString::to_string)
        .unwrap_or_default();
    if KEYS.contains(&key.as_str()) {
        return Some(key);
    }
    let known: Vec<String> = KEYS.iter().map(ToString::to_string).collect();
    let guess = crate::engine::lower::closest(&key, &known).cloned();
    let hint = match &guess {
        Some(k) => format!("; did you mean `{k}(..)`?"),
        None => String::new(),
    };
    errors.push(syn::Error::new_spanned(
        path,
        format!(
            "unknown key `{}`{hint} (`#[hamel_system]` on an impl block takes {NAME_KEYS})",
            path.to_token_stream()
        ),
    ));
    guess
}

/// "x, y, theta".
pub fn names_of(idents: &[syn::Ident]) -> String {
    idents
        .iter()
        .map(ToString::to_string)
        .collect::<Vec<_>>()
        .join(", ")
}

/// The length of a type written `[f64; 3]` or `&[f64; 3]`, if it is a literal.
pub fn array_length(ty: &syn::Type) -> Option<usize> {
    match ty {
        syn::Type::Reference(r) => array_length(&r.elem),
        syn::Type::Paren(p) => array_length(&p.elem),
        syn::Type::Group(g) => array_length(&g.elem),
        syn::Type::Array(a) => match &a.len {
            syn::Expr::Lit(syn::ExprLit {
                lit: syn::Lit::Int(i),
                ..
            }) => i.base10_parse().ok(),
            _ => None,
        },
        _ => None,
    }
}

/// The length of a result written `-> [f64; 3]`, if it is a literal.
pub fn written_length(output: &syn::ReturnType) -> Option<usize> {
    match output {
        syn::ReturnType::Type(_, ty) => array_length(ty),
        syn::ReturnType::Default => None,
    }
}

/// A function with a role, and where its role attribute is.
pub struct RoleFn<'a> {
    pub f: &'a syn::ImplItemFn,
    pub attr: &'a syn::Attribute,
    /// `#[holonomic(determines(theta))]`, `#[contacts(determines(theta))]`: the coordinates
    /// the holonomic constraints solve for, as written (empty for the other roles).
    pub determines: Vec<syn::Ident>,
}

/// The roles found in an impl block. Role attributes are removed from the emitted code.
pub struct Roles<'a> {
    pub by_role: BTreeMap<Role, RoleFn<'a>>,
    /// The functions without a role: where a forgotten role attribute may be.
    pub unmarked: Vec<&'a syn::ImplItemFn>,
}

impl<'a> Roles<'a> {
    pub fn find(items: &'a [syn::ImplItem], errors: &mut Vec<syn::Error>) -> Self {
        let mut by_role: BTreeMap<Role, RoleFn<'a>> = BTreeMap::new();
        let mut unmarked = Vec::new();
        for item in items {
            let syn::ImplItem::Fn(f) = item else { continue };
            let marked = f.attrs.iter().any(|a| Role::from_attribute(a).is_some());
            // A misnamed role attribute is reported once, and the function read as the role
            // it was meant to be, so that nothing else is reported for it ("missing role",
            // rustc's unknown attribute, the uses of a model left without its impl).
            let misnamed = (!marked)
                .then(|| {
                    f.attrs
                        .iter()
                        .find_map(|a| Role::misnamed(a).map(|role| (a, role)))
                })
                .flatten();
            if let Some((attr, role)) = misnamed {
                errors.push(syn::Error::new_spanned(
                    attr,
                    format!(
                        "`#[{}]` is not a role of hamel; `#[{}]` is: write `#[{}]` (expected \
                         signature `{}`)",
                        attr.path().to_token_stream().to_string().replace(' ', ""),
                        role.attribute(),
                        role.attribute(),
                        role.expected_signature()
                    ),
                ));
            } else if !marked {
                unmarked.push(f);
            }
            let mut mine: Option<Role> = None;
            for attr in &f.attrs {
                let Some(role) = Role::from_attribute(attr).or_else(|| {
                    misnamed
                        .filter(|(a, _)| std::ptr::eq(*a, attr))
                        .map(|(_, r)| r)
                }) else {
                    continue;
                };
                let determines = if role == Role::Holonomic {
                    holonomic_arguments(role, attr, errors)
                } else if role == Role::Contacts {
                    match attr.meta {
                        syn::Meta::Path(_) => Vec::new(),
                        _ => holonomic_arguments(role, attr, errors),
                    }
                } else {
                    if !matches!(attr.meta, syn::Meta::Path(_)) {
                        errors.push(syn::Error::new_spanned(
                            attr,
                            format!("`#[{}]` takes no arguments", role.attribute()),
                        ));
                    }
                    Vec::new()
                };
                if let Some(other) = mine {
                    errors.push(syn::Error::new_spanned(
                        attr,
                        format!(
                            "`{}` already has the role `#[{}]`: a function plays one role",
                            f.sig.ident,
                            other.attribute()
                        ),
                    ));
                    continue;
                }
                mine = Some(role);
                if let Some(previous) = by_role.get(&role) {
                    errors.push(syn::Error::new_spanned(
                        attr,
                        format!(
                            "a second `#[{}]`: `{}` already has this role",
                            role.attribute(),
                            previous.f.sig.ident
                        ),
                    ));
                    continue;
                }
                by_role.insert(
                    role,
                    RoleFn {
                        f,
                        attr,
                        determines,
                    },
                );
            }
        }
        Roles { by_role, unmarked }
    }

    pub fn get(&self, role: Role) -> Option<&RoleFn<'a>> {
        self.by_role.get(&role)
    }

    /// Roles, but neither an energy nor constraints: the block is a piece of a model whose
    /// other roles are in another impl block (with `#[hamel_system]` too, or it would not be
    /// read), so it is not the model, and it gets no stand-in of the model when it has mistakes:
    /// the other block's would clash with it.
    pub fn is_fragment(&self) -> bool {
        let holds = |roles: &[Role]| roles.iter().any(|r| self.by_role.contains_key(r));
        !self.by_role.is_empty()
            && !holds(&[
                Role::Lagrangian,
                Role::KineticEnergy,
                Role::PotentialEnergy,
                Role::QuasiLagrangian,
                Role::Bodies,
            ])
            && !holds(&[Role::Constraints, Role::Holonomic, Role::Contacts])
    }
}

/// The coordinates named in `#[holonomic(determines(theta, phi))]` or
/// `#[contacts(determines(theta))]` (indexed names such as `theta[2]` refer to one member of
/// a group).
fn holonomic_arguments(
    role: Role,
    attr: &syn::Attribute,
    errors: &mut Vec<syn::Error>,
) -> Vec<syn::Ident> {
    let how = match role {
        Role::Contacts => {
            "`#[contacts(determines(theta))]` names the coordinates that the contacts' heights \
             determine, one per contact whose height varies with the coordinates"
        }
        _ => {
            "`#[holonomic(determines(theta))]` names the coordinates the holonomic \
             constraints determine, one per constraint"
        }
    };
    if matches!(attr.meta, syn::Meta::Path(_)) {
        errors.push(syn::Error::new_spanned(
            attr,
            format!("name the coordinates the constraints solve for: {how}"),
        ));
        return Vec::new();
    }
    let mut names = Vec::new();
    let result = attr.parse_nested_meta(|meta| {
        if !meta.path.is_ident("determines") {
            return Err(meta.error(format!("unknown key: {how}")));
        }
        // `determines()` is no syntax error of the user's: it names nothing.
        let empty = meta
            .input
            .fork()
            .parse::<proc_macro2::Group>()
            .ok()
            .filter(|g| {
                g.delimiter() == proc_macro2::Delimiter::Parenthesis && g.stream().is_empty()
            });
        if let Some(group) = empty {
            meta.input.parse::<proc_macro2::Group>()?;
            return Err(syn::Error::new(
                group.span(),
                format!("`determines()` names no coordinate: {how}"),
            ));
        }
        if !meta.input.peek(syn::token::Paren) {
            return Err(meta.error(format!("`determines` takes a list of coordinates: {how}")));
        }
        meta.parse_nested_meta(|inner| {
            let ident = inner
                .path
                .get_ident()
                .cloned()
                .ok_or_else(|| inner.error("expected a coordinate's name"))?;
            if inner.input.peek(syn::token::Bracket) {
                let content;
                syn::bracketed!(content in inner.input);
                let index: syn::LitInt = content.parse()?;
                let i: usize = index.base10_parse()?;
                names.push(syn::Ident::new(&format!("{ident}{i}"), ident.span()));
            } else {
                names.push(ident);
            }
            Ok(())
        })
    });
    if let Err(e) = result {
        errors.push(e);
    }
    names
}

/// The impl block with the role attributes removed (they are ours, not rustc's), and those
/// misnamed (reported by `Roles::find`). A role
/// function is used by the generated code even when nothing else calls it, so it gets
/// `#[allow(dead_code)]` in their place: a private `fn lagrangian` should not warn.
pub fn strip_role_attributes(imp: &syn::ItemImpl) -> syn::ItemImpl {
    let mut imp = imp.clone();
    for item in &mut imp.items {
        if let syn::ImplItem::Fn(f) = item {
            let before = f.attrs.len();
            f.attrs
                .retain(|a| Role::from_attribute(a).is_none() && Role::misnamed(a).is_none());
            if f.attrs.len() < before {
                f.attrs.push(syn::parse_quote!(#[allow(dead_code)]));
            }
        }
    }
    imp
}

/// The Levenshtein distance between two names (a few letters each: the plain table).
fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut diagonal = row[0];
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let above = row[j + 1];
            row[j + 1] = (above + 1)
                .min(row[j] + 1)
                .min(diagonal + usize::from(ca != *cb));
            diagonal = above;
        }
    }
    row[b.len()]
}

#[cfg(test)]
mod tests {
    use super::parse_names;
    use quote::quote;

    #[test]
    fn name_value_lists_are_read_with_one_error() {
        let mut errors = Vec::new();
        let names = parse_names(quote!(coordinates = [x, y], inputs(u1)), &mut errors);
        assert_eq!(errors.len(), 1);
        assert!(errors[0].to_string().contains("write `coordinates(x, y)`"));
        let list = names.coordinates.map(|(_, l)| l.len());
        assert_eq!(list, Some(2));
        assert!(!names.garbled);
        assert_eq!(names.inputs.len(), 1);

        let mut errors = Vec::new();
        let names = parse_names(quote!(coordinates = 3), &mut errors);
        assert_eq!(errors.len(), 1);
        assert!(names.garbled);
    }

    #[test]
    fn units_and_body_names_are_read_with_one_error_per_mistake() {
        let mut errors = Vec::new();
        let names = parse_names(
            quote!(
                coordinates(x, psi),
                units(x = "m", psi = rad, t = "s"),
                bodies(a, b)
            ),
            &mut errors,
        );
        assert_eq!(errors.len(), 1, "{errors:?}");
        assert!(
            errors[0]
                .to_string()
                .contains("write each unit as a name and a string")
        );
        let units: Vec<(String, String)> = names
            .units
            .iter()
            .map(|(n, u)| (n.to_string(), u.value()))
            .collect();
        assert_eq!(units, [("x".into(), "m".into()), ("t".into(), "s".into())]);
        assert_eq!(names.coordinates.map(|(_, l)| l.len()), Some(2));
        assert_eq!(names.bodies.map(|(_, l)| l.len()), Some(2));

        let mut errors = Vec::new();
        parse_names(quote!(units(x), coordinates(x)), &mut errors);
        assert_eq!(errors.len(), 1, "{errors:?}");
        assert!(errors[0].to_string().contains("`x` needs its unit"));
    }

    #[test]
    fn constraint_names_are_a_list_like_the_others() {
        let mut errors = Vec::new();
        let names = parse_names(
            quote!(coordinates(x, y, theta), constraints(blade, contact[2])),
            &mut errors,
        );
        assert!(errors.is_empty());
        let list: Vec<String> = names
            .constraints
            .map(|(_, l)| l.iter().map(ToString::to_string).collect())
            .unwrap_or_default();
        assert_eq!(list, ["blade", "contact0", "contact1"]);
        assert_eq!(names.groups[3].len(), 1);
        assert_eq!(names.groups[3][0].start, 1);

        let mut errors = Vec::new();
        parse_names(quote!(constraint(blade)), &mut errors);
        assert_eq!(errors.len(), 1);
        assert!(
            errors[0]
                .to_string()
                .contains("did you mean `constraints(..)`")
        );
    }
}
