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

/// Every three consecutive turns by coordinates in the products of the impl block's
/// functions.
struct Finder<'c> {
    coordinates: &'c [syn::Ident],
    found: Vec<ThreeTurns>,
}

impl<'ast> Visit<'ast> for Finder<'_> {
    fn visit_expr_binary(&mut self, b: &'ast syn::ExprBinary) {
        if !matches!(b.op, syn::BinOp::Mul(_)) {
            return syn::visit::visit_expr_binary(self, b);
        }
        let mut all = Vec::new();
        factors(&b.left, &mut all);
        factors(&b.right, &mut all);
        let n = self.coordinates.len();
        let turns: Vec<Option<(usize, usize)>> = all.iter().map(|f| turn(f, n)).collect();
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
}
