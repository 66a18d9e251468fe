//! What a Rust expression of the supported subset evaluates to while it is being lowered.

use super::geometry::{Geo, GeoKind};
use crate::engine::graph::{Graph, NodeId};

/// The compile-time image of a Rust value.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    /// An `f64`, as a graph node.
    Real(NodeId),
    /// A `bool` (a comparison), as a boolean graph node.
    Bool(NodeId),
    /// An integer known at compile time: loop counters, indices, `powi` exponents.
    Int(i64),
    /// A fixed-size array `[T; N]`.
    Array(Vec<Value>),
    /// A tuple, for destructuring only (`let (s, c) = x.sin_cos();`).
    Tuple(Vec<Value>),
    /// `()`, the value of statements.
    Unit,
    /// A value of hamel's geometry vocabulary (`Vector3`, `Rotation3`, `Body`…).
    Geo(Geo),
    /// Stands in for a value whose expression already produced an error, so that one mistake
    /// is reported once and lowering can go on to find the next independent one.
    Poison,
}

impl Value {
    /// How the value reads in a message: "`f64`", "`[f64; 3]`"...
    pub fn describe(&self) -> String {
        match self {
            Value::Real(_) => "`f64`".into(),
            Value::Bool(_) => "`bool`".into(),
            Value::Int(_) => "an integer".into(),
            Value::Array(items) => match items.first() {
                Some(first) => format!(
                    "`[{}; {}]`",
                    first.describe().trim_matches('`'),
                    items.len()
                ),
                None => "an empty array".into(),
            },
            Value::Tuple(items) => format!("a tuple of {} elements", items.len()),
            Value::Unit => "`()` (no value)".into(),
            Value::Geo(g) => format!("`{}`", g.kind().name()),
            Value::Poison => "an erroneous value".into(),
        }
    }

    pub fn is_poison(&self) -> bool {
        match self {
            Value::Poison => true,
            Value::Array(items) | Value::Tuple(items) => items.iter().any(Value::is_poison),
            _ => false,
        }
    }

    /// All real nodes in row-major order, or `None` if the value is not made of reals.
    pub fn flatten(&self) -> Option<Vec<NodeId>> {
        let mut out = Vec::new();
        self.flatten_into(&mut out).then_some(out)
    }

    fn flatten_into(&self, out: &mut Vec<NodeId>) -> bool {
        match self {
            Value::Real(id) => {
                out.push(*id);
                true
            }
            Value::Array(items) => items.iter().all(|v| v.flatten_into(out)),
            Value::Geo(g) => {
                g.flatten_into(out);
                true
            }
            _ => false,
        }
    }
}

/// The type of an argument or result, as far as lowering cares.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Shape {
    Real,
    Int,
    Array(usize, Box<Shape>),
    /// A type of hamel's geometry vocabulary.
    Geo(GeoKind),
}

impl Shape {
    /// Number of reals in a value of this shape.
    pub fn len(&self) -> usize {
        match self {
            Shape::Real => 1,
            Shape::Int => 0,
            Shape::Array(n, inner) => n * inner.len(),
            Shape::Geo(kind) => kind.len(),
        }
    }

    pub fn describe(&self) -> String {
        match self {
            Shape::Real => "`f64`".into(),
            Shape::Int => "an integer".into(),
            Shape::Array(n, inner) => format!("`[{}; {n}]`", inner.describe().trim_matches('`')),
            Shape::Geo(kind) => format!("`{}`", kind.name()),
        }
    }

    /// Whether `value` has this shape (poison fits anything: its error is already reported).
    pub fn admits(&self, value: &Value) -> bool {
        match (self, value) {
            (_, Value::Poison) => true,
            (Shape::Real, Value::Real(_)) | (Shape::Int, Value::Int(_)) => true,
            (Shape::Array(n, inner), Value::Array(items)) => {
                items.len() == *n && items.iter().all(|v| inner.admits(v))
            }
            (Shape::Geo(kind), Value::Geo(g)) => g.kind() == *kind,
            _ => false,
        }
    }

    /// A value of this shape made of fresh graph inputs, labelled `name[i][j]`; also returns
    /// the inputs in row-major order. Integers cannot be inputs.
    pub fn fresh_inputs(&self, graph: &mut Graph, name: &str) -> Option<(Value, Vec<NodeId>)> {
        let mut nodes = Vec::new();
        let value = self.fresh_into(graph, name, &mut nodes)?;
        Some((value, nodes))
    }

    fn fresh_into(&self, graph: &mut Graph, name: &str, nodes: &mut Vec<NodeId>) -> Option<Value> {
        match self {
            Shape::Real => {
                let id = graph.new_input(name);
                nodes.push(id);
                Some(Value::Real(id))
            }
            Shape::Int => None,
            Shape::Geo(kind) => {
                let parts: Vec<NodeId> = (0..kind.len())
                    .map(|i| graph.new_input(format!("{name}.{i}")))
                    .collect();
                nodes.extend(&parts);
                Some(Value::Geo(Geo::from_nodes(*kind, &parts)))
            }
            Shape::Array(n, inner) => (0..*n)
                .map(|i| inner.fresh_into(graph, &format!("{name}[{i}]"), nodes))
                .collect::<Option<Vec<_>>>()
                .map(Value::Array),
        }
    }
}
