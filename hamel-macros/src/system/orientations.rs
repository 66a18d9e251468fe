//! Orientations of three turns about fixed axes by coordinates (Euler or Tait–Bryan angles,
//! `Rotation3::about_y(q[2]) * Rotation3::about_z(q[3]) * Rotation3::about_y(q[4])`), as the
//! impl block writes them: at run time, a singularity met where one of them is at its own
//! (two turns about one axis) is reported as that, with the quaternion orientation as the
//! remedy (`hamel::geometry::at_singular_orientation`), where the message of a singular
//! velocity transformation alone suggested other quasi-velocities.

use proc_macro2::TokenStream;
use quote::quote;
use syn::visit::Visit;

/// One such orientation: its axes (0 = x, 1 = y, 2 = z), the coordinates' indices, and how
/// it reads by the coordinates' names.
struct ThreeTurns {
    axes: [usize; 3],
    coordinates: [usize; 3],
    written: String,
}

/// A turn: `about_x(q[i])` or `from_axis_angle(&Vector3::x(), q[i])`, as (axis, i).
fn turn(e: &syn::Expr, n: usize) -> Option<(usize, usize)> {
    let syn::Expr::Call(call) = strip(e) else {
        return None;
    };
    let syn::Expr::Path(f) = &*call.func else {
        return None;
    };
    let name = f.path.segments.last()?.ident.to_string();
    let axis = |name: &str| match name {
        "x" | "about_x" => Some(0),
        "y" | "about_y" => Some(1),
        "z" | "about_z" => Some(2),
        _ => None,
    };
    let args: Vec<&syn::Expr> = call.args.iter().collect();
    let (axis, angle) = match (name.as_str(), args.as_slice()) {
        (about, [angle]) => (axis(about)?, *angle),
        ("from_axis_angle", [direction, angle]) => {
            let syn::Expr::Call(unit) = strip(direction) else {
                return None;
            };
            let syn::Expr::Path(p) = &*unit.func else {
                return None;
            };
            (axis(&p.path.segments.last()?.ident.to_string())?, *angle)
        }
        _ => return None,
    };
    let syn::Expr::Index(index) = strip(angle) else {
        return None;
    };
    let syn::Expr::Lit(syn::ExprLit {
        lit: syn::Lit::Int(i),
        ..
    }) = strip(&index.index)
    else {
        return None;
    };
    let i: usize = i.base10_parse().ok()?;
    (i < n).then_some((axis, i))
}

/// `e` without parentheses and references.
fn strip(e: &syn::Expr) -> &syn::Expr {
    match e {
        syn::Expr::Paren(p) => strip(&p.expr),
        syn::Expr::Reference(r) => strip(&r.expr),
        _ => e,
    }
}

/// The factors of a product `a * b * c`, left to right.
fn factors<'e>(e: &'e syn::Expr, into: &mut Vec<&'e syn::Expr>) {
    match strip(e) {
        syn::Expr::Binary(b) if matches!(b.op, syn::BinOp::Mul(_)) => {
            factors(&b.left, into);
            factors(&b.right, into);
        }
        other => into.push(other),
    }
}

/// The turns of a product, left to right: each factor's (axis, coordinate), `None` for a
/// factor that is no turn by a coordinate.
type Turns = Vec<Option<(usize, usize)>>;

/// Every three consecutive turns by coordinates in the products of the impl block's
/// functions, through the `let` bindings of a function (`let heading = about_z(q[2]) *
/// about_x(q[3]);` then `heading * about_y(q[4])`, as the catalogue's rolling disk writes
/// it).
struct Finder<'c> {
    coordinates: &'c [syn::Ident],
    found: Vec<ThreeTurns>,
    /// The turns bound to each name so far in the function being read.
    bound: Vec<(String, Turns)>,
}

impl Finder<'_> {
    /// The turns of `e`, a product or a single factor, a bound name standing for its turns.
    fn turns(&self, e: &syn::Expr) -> Turns {
        let mut all = Vec::new();
        factors(e, &mut all);
        let n = self.coordinates.len();
        all.iter()
            .flat_map(|f| match (turn(f, n), strip(f)) {
                (Some(t), _) => vec![Some(t)],
                (None, syn::Expr::Path(p)) if p.path.segments.len() == 1 => {
                    let name = p.path.segments[0].ident.to_string();
                    let bound = self.bound.iter().rev().find(|(b, _)| *b == name);
                    bound.map_or_else(|| vec![None], |(_, turns)| turns.clone())
                }
                _ => vec![None],
            })
            .collect()
    }
}

impl<'ast> Visit<'ast> for Finder<'_> {
    fn visit_impl_item_fn(&mut self, f: &'ast syn::ImplItemFn) {
        self.bound.clear();
        syn::visit::visit_impl_item_fn(self, f);
        self.bound.clear();
    }

    fn visit_local(&mut self, local: &'ast syn::Local) {
        syn::visit::visit_local(self, local);
        // `let name = …` or `let name: Rotation3 = …`.
        let pattern = match &local.pat {
            syn::Pat::Type(typed) => &*typed.pat,
            other => other,
        };
        let (syn::Pat::Ident(name), Some(init)) = (pattern, &local.init) else {
            return;
        };
        // Bound whatever it is: a later `let` of the same name shadows an earlier one of
        // turns, and its turns (none, if it is no product of turns) replace theirs.
        let turns = self.turns(&init.expr);
        self.bound.push((name.ident.to_string(), turns));
    }

    fn visit_expr_binary(&mut self, b: &'ast syn::ExprBinary) {
        if !matches!(b.op, syn::BinOp::Mul(_)) {
            return syn::visit::visit_expr_binary(self, b);
        }
        let mut turns = self.turns(&b.left);
        turns.extend(self.turns(&b.right));
        for window in turns.windows(3) {
            if let [Some(a), Some(b), Some(c)] = window {
                let axes = [a.0, b.0, c.0];
                let coordinates = [a.1, b.1, c.1];
                let name = |(axis, i): (usize, usize)| {
                    format!("about_{}({})", ["x", "y", "z"][axis], self.coordinates[i])
                };
                let written = [*a, *b, *c].map(name).join(" * ");
                if !self.found.iter().any(|t| t.written == written) {
                    self.found.push(ThreeTurns {
                        axes,
                        coordinates,
                        written,
                    });
                }
            }
        }
        // The factors themselves (a turn's argument) hold no further products of turns.
    }
}

/// `HamelSystem::singular` for a model whose impl block orients a body by three turns about
/// fixed axes by coordinates; `None` when it has none.
pub fn singular(imp: &syn::ItemImpl, coordinates: &[syn::Ident]) -> Option<TokenStream> {
    let mut finder = Finder {
        coordinates,
        found: Vec::new(),
        bound: Vec::new(),
    };
    finder.visit_item_impl(imp);
    if finder.found.is_empty() {
        return None;
    }
    let turns = finder.found.iter().map(|t| {
        let axes = t.axes;
        let angles = t.coordinates.map(|i| quote!(x[#i]));
        let written = &t.written;
        quote! {
            ::hamel::geometry::ThreeTurns {
                axes: [#(#axes),*],
                angles: [#(#angles),*],
                written: #written,
            }
        }
    });
    Some(quote! {
        let error = s.at(
            t,
            <Self as ::hamel::HamelSystem>::named_state(x),
            <Self as ::hamel::HamelSystem>::COORDINATES,
            <Self as ::hamel::HamelSystem>::SPEEDS,
        );
        ::hamel::geometry::at_singular_orientation(error, &[#(#turns),*])
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn three_turns_by_coordinates_are_found_and_nothing_else() {
        let coordinates: Vec<syn::Ident> = ["x", "y", "alpha", "beta", "gamma"]
            .iter()
            .map(|n| syn::Ident::new(n, proc_macro2::Span::call_site()))
            .collect();
        let imp: syn::ItemImpl = syn::parse_quote! {
            impl Ball {
                fn bodies(&self, q: &[f64; 5]) -> [Body; 1] {
                    let r = Rotation3::about_y(q[2]) * Rotation3::about_z(q[3]) * Rotation3::about_y(q[4]);
                    let s = Rotation3::about_z(self.a) * Rotation3::about_x(q[3]) * Rotation3::about_y(q[4]);
                    let u = Rotation3::about_z(q[2]) * Rotation3::about_x(q[3]);
                    [Body::new(self.m, i, c, r)]
                }
            }
        };
        let tokens = singular(&imp, &coordinates).unwrap().to_string();
        assert!(
            tokens.contains("about_y(alpha) * about_z(beta) * about_y(gamma)"),
            "{tokens}"
        );
        assert_eq!(tokens.matches("ThreeTurns").count(), 1, "{tokens}");
    }

    /// The catalogue's rolling disk turns by two coordinates in a `let`, then by the third
    /// (before, only a product of three turns written out was found: its singularity kept
    /// the message of a singular mass matrix). A name bound in another function, bound to
    /// something else, or shadowed by a `let` of something else, is no turn.
    #[test]
    fn turns_are_followed_through_let_bindings() {
        let coordinates: Vec<syn::Ident> = ["x", "y", "psi", "phi", "theta"]
            .iter()
            .map(|n| syn::Ident::new(n, proc_macro2::Span::call_site()))
            .collect();
        let imp: syn::ItemImpl = syn::parse_quote! {
            impl Disk {
                fn bodies(&self, q: &[f64; 5]) -> [Body; 1] {
                    let heading: Rotation3 = Rotation3::about_z(q[2]) * Rotation3::about_x(q[3]);
                    let centre = heading * Vector3::new(0.0, 0.0, self.r);
                    [Body::new(self.m, i, centre, heading * Rotation3::about_y(q[4]))]
                }
                fn other(&self, q: &[f64; 5]) -> Rotation3 {
                    let centre = Rotation3::about_z(self.a);
                    heading * Rotation3::about_y(q[4]) * Rotation3::about_x(q[3]) * centre
                }
                fn shadowed(&self, q: &[f64; 5]) -> Rotation3 {
                    let tilt = Rotation3::about_y(q[4]) * Rotation3::about_x(q[3]);
                    let tilt = Rotation3::about_x(self.a);
                    Rotation3::about_z(q[2]) * tilt
                }
            }
        };
        let tokens = singular(&imp, &coordinates).unwrap().to_string();
        assert!(
            tokens.contains("about_z(psi) * about_x(phi) * about_y(theta)"),
            "{tokens}"
        );
        assert_eq!(tokens.matches("ThreeTurns").count(), 1, "{tokens}");
    }
}
