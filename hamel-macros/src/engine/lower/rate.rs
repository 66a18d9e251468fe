//! `rate!(expr)`: the time derivative of an expression along the motion,
//! d/dt = Σ q̇ⱼ ∂/∂qⱼ + ∂/∂t, in the body of a role that is read with the velocities (the
//! constraints, say: "the rate of this distance is zero"). A forward tangent of the
//! expression's graph, seeded with the role's own `q̇`.

use super::geometry::{Geo, Point};
use super::value::Value;
use super::{Env, Lowerer};
use crate::engine::diff;
use crate::engine::graph::NodeId;

/// Where `rate!` has a meaning: the body of the role function being lowered, with its
/// coordinates, velocities and time.
#[derive(Clone)]
pub struct RateContext {
    /// q → q̇ and t → 1.
    pub seeds: Vec<(NodeId, NodeId)>,
    /// The velocities, which the expression must not read (its rate would need the
    /// accelerations).
    pub velocities: Vec<NodeId>,
}

/// The roles `rate!` may be used in, for messages.
const WHERE: &str = "the roles read with the velocities `qd`: `#[constraints]`, \
     `#[quasi_velocities]`, `#[kinetic_energy]`, `#[lagrangian]` and `#[forces]`";

/// Whether a macro call is hamel's `rate!` (`rate!`, `hamel::rate!`).
pub fn is_rate(mac: &syn::Macro) -> bool {
    let segments: Vec<String> = mac
        .path
        .segments
        .iter()
        .map(|s| s.ident.to_string())
        .collect();
    matches!(
        segments
            .iter()
            .map(String::as_str)
            .collect::<Vec<_>>()
            .as_slice(),
        ["rate"] | ["hamel", "rate"] | ["prelude", "rate"] | ["hamel", "prelude", "rate"]
    )
}

impl Lowerer<'_, '_> {
    /// `rate!(expr)`.
    pub fn rate(&mut self, env: &mut Env, mac: &syn::Macro) -> Value {
        let depth = self.call_stack.len();
        let context = match (&self.rate_context, depth) {
            (Some(context), 1) => context.clone(),
            (Some(_), _) => {
                return self.error(
                    mac,
                    format!(
                        "`rate!` may be used directly in the body of a role read with the \
                         velocities, not in a function that a role calls (here `{}`): the \
                         function does not take q̇; move the `rate!` into the role's body, or \
                         give the function the rate as an argument",
                        self.call_stack.last().map_or("", String::as_str)
                    ),
                );
            }
            (None, _) => {
                let here = match self.call_stack.first() {
                    Some(role) => format!("`{role}` is not read with the velocities"),
                    None => "this expression is not in a role's body".to_string(),
                };
                return self.error(
                    mac,
                    format!(
                        "`rate!` is the time derivative along the motion, which needs the \
                         velocities q̇, and {here}: it may be used in {WHERE}"
                    ),
                );
            }
        };
        let expr: syn::Expr = match mac.parse_body() {
            Ok(e) => e,
            Err(_) => {
                return self.error(mac, "`rate!` takes one expression: `rate!(x * x + y * y)`");
            }
        };
        let value = self.expr(env, &expr);
        if value.is_poison() {
            return Value::Poison;
        }
        let Some(nodes) = value.flatten() else {
            return self.error(
                &expr,
                format!(
                    "`rate!` takes an `f64`, an array of them or a `Vector3`; this is {}",
                    value.describe()
                ),
            );
        };
        if let Value::Geo(geo) = &value
            && !matches!(geo, Geo::Vector(_))
        {
            return self.error(
                &expr,
                format!(
                    "`rate!` of a `{}` is not one of the vocabulary's values: take the rate of \
                     an `f64`, an array of them or a `Vector3`",
                    geo.kind().name()
                ),
            );
        }
        let reads = self.graph.depends_on(&context.velocities);
        if nodes.iter().any(|n| reads[n.index()]) {
            return self.error(
                &expr,
                "this expression reads the velocities `qd`, and its rate would need the \
                 accelerations: `rate!` differentiates functions of the coordinates and the \
                 time",
            );
        }
        let rates = diff::tangent(self.graph, &nodes, &context.seeds);
        rebuild(&value, &mut rates.into_iter())
    }
}

/// A value of the shape of `like` from reals in its flattened order.
fn rebuild(like: &Value, reals: &mut impl Iterator<Item = NodeId>) -> Value {
    match like {
        Value::Real(_) => reals.next().map_or(Value::Poison, Value::Real),
        Value::Array(items) => Value::Array(items.iter().map(|i| rebuild(i, reals)).collect()),
        Value::Geo(Geo::Vector(_)) => match (reals.next(), reals.next(), reals.next()) {
            (Some(x), Some(y), Some(z)) => Value::Geo(Geo::Vector(Point::leaf([x, y, z]))),
            _ => Value::Poison,
        },
        _ => Value::Poison,
    }
}

/// Whether a function's body uses `rate!` anywhere.
pub fn uses_rate(f: &syn::ImplItemFn) -> bool {
    struct Find(bool);
    impl<'ast> syn::visit::Visit<'ast> for Find {
        fn visit_macro(&mut self, m: &'ast syn::Macro) {
            self.0 |= is_rate(m);
        }
    }
    let mut find = Find(false);
    syn::visit::Visit::visit_block(&mut find, &f.block);
    find.0
}
