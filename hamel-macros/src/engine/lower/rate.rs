//! `rate!(expr)`: the time derivative of an expression along the motion,
//! d/dt = Σ q̇ⱼ ∂/∂qⱼ + ∂/∂t, in the body of a role that is read with the velocities (the
//! constraints, say: "the rate of this distance is zero"). A forward tangent of the
//! expression's graph, seeded with the role's own `q̇`. Its kin `angular_velocity!(r)` and
//! `body_rates!(r)` give the angular velocity of a rotation along the motion, in the ground's
//! axes and in the rotated body's own: body rates as quasi-velocities.

use super::geometry::{self, Geo, Point};
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

/// The roles the rate macros may be used in, for messages.
const WHERE: &str = "the roles read with the velocities `qd`: `#[constraints]`, \
     `#[quasi_velocities]`, `#[kinetic_energy]`, `#[lagrangian]` and `#[forces]`";

/// The macros of rates along the motion.
#[derive(Clone, Copy, PartialEq, Eq)]
enum RateMacro {
    /// `rate!(expr)`: the time derivative.
    Rate,
    /// `angular_velocity!(r)`: ω in the ground's axes.
    AngularVelocity,
    /// `body_rates!(r)`: Ω = Rᵀ ω, in the body's own axes.
    BodyRates,
}

impl RateMacro {
    fn name(self) -> &'static str {
        match self {
            RateMacro::Rate => "rate",
            RateMacro::AngularVelocity => "angular_velocity",
            RateMacro::BodyRates => "body_rates",
        }
    }
}

/// Which of hamel's rate macros a macro call is (`rate!`, `hamel::rate!`,
/// `hamel::prelude::body_rates!`).
fn which(mac: &syn::Macro) -> Option<RateMacro> {
    let segments: Vec<String> = mac
        .path
        .segments
        .iter()
        .map(|s| s.ident.to_string())
        .collect();
    let (last, prefix) = segments.split_last()?;
    let prefixed = matches!(
        prefix
            .iter()
            .map(String::as_str)
            .collect::<Vec<_>>()
            .as_slice(),
        [] | ["hamel"] | ["prelude"] | ["hamel", "prelude"]
    );
    [
        RateMacro::Rate,
        RateMacro::AngularVelocity,
        RateMacro::BodyRates,
    ]
    .into_iter()
    .find(|m| prefixed && m.name() == last)
}

/// Whether a macro call is one of hamel's rate macros: `rate!`, `angular_velocity!`,
/// `body_rates!`.
pub fn is_rate(mac: &syn::Macro) -> bool {
    which(mac).is_some()
}

impl Lowerer<'_, '_> {
    /// `rate!(expr)`, `angular_velocity!(r)` or `body_rates!(r)`.
    pub fn rate(&mut self, env: &mut Env, mac: &syn::Macro) -> Value {
        let Some(kind) = which(mac) else {
            return Value::Poison;
        };
        let name = kind.name();
        let depth = self.call_stack.len();
        let context = match (&self.rate_context, depth) {
            (Some(context), 1) => context.clone(),
            (Some(_), _) => {
                return self.error(
                    mac,
                    format!(
                        "`{name}!` may be used directly in the body of a role read with the \
                         velocities, not in a function that a role calls (here `{}`): the \
                         function does not take q̇; move the `{name}!` into the role's body, or \
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
                let what = match kind {
                    RateMacro::Rate => "the time derivative along the motion",
                    _ => "an angular velocity along the motion",
                };
                return self.error(
                    mac,
                    format!(
                        "`{name}!` is {what}, which needs the velocities q̇, and {here}: it may \
                         be used in {WHERE}"
                    ),
                );
            }
        };
        let expr: syn::Expr = match mac.parse_body() {
            Ok(e) => e,
            Err(_) => {
                let example = match kind {
                    RateMacro::Rate => "`rate!(x * x + y * y)`",
                    _ => "of a rotation, `body_rates!(ball.orientation)`",
                };
                return self.error(mac, format!("`{name}!` takes one expression: {example}"));
            }
        };
        let value = self.expr(env, &expr);
        if value.is_poison() {
            return Value::Poison;
        }
        if kind != RateMacro::Rate {
            return self.spin_rate(kind, &expr, value, &context);
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

impl Lowerer<'_, '_> {
    /// `angular_velocity!(r)` or `body_rates!(r)` of the lowered rotation `value`.
    fn spin_rate(
        &mut self,
        kind: RateMacro,
        expr: &syn::Expr,
        value: Value,
        context: &RateContext,
    ) -> Value {
        let name = kind.name();
        let Value::Geo(Geo::Rotation(r)) = value else {
            return self.error(
                expr,
                format!(
                    "`{name}!` takes a `Rotation3` (a body's `orientation`, or a product of \
                     turns); this is {}",
                    value.describe()
                ),
            );
        };
        let reads = self.graph.depends_on(&context.velocities);
        if r.matrix.iter().flatten().any(|n| reads[n.index()]) {
            return self.error(
                expr,
                format!(
                    "this rotation reads the velocities `qd`, and its angular velocity would \
                     need the accelerations: `{name}!` takes a rotation of the coordinates and \
                     the time"
                ),
            );
        }
        let keys: Vec<NodeId> = context.seeds.iter().map(|(k, _)| *k).collect();
        let moving = self.graph.depends_on(&keys);
        let seeds = &context.seeds;
        let omega = geometry::angular_velocity(self.graph, &r, &moving, &mut |g, nodes| {
            diff::tangent(g, nodes, seeds)
        });
        let at = match kind {
            RateMacro::BodyRates => geometry::apply_transposed(self.graph, &r.matrix, omega),
            _ => omega,
        };
        Value::Geo(Geo::Vector(Point::leaf(at)))
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
