//! Is a row linear and homogeneous in the velocities? Decided on the graph, structurally,
//! so that the error can point at the subexpression that breaks linearity.

use crate::engine::graph::{Graph, Node, NodeId};
use std::collections::HashMap;

/// How a node depends on the velocity inputs.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Class {
    /// The constant zero.
    Zero,
    /// Independent of the velocities (and not known to be zero).
    Free,
    /// Σ c_j(q)·v_j: linear and homogeneous.
    Linear,
    /// Anything else; carries the node where linearity broke and why.
    Broken(NodeId, Why),
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Why {
    Product,
    Quotient,
    Function,
    Affine,
    Condition,
}

/// The verdict on one row.
pub enum Verdict {
    Linear,
    /// The row is the constant zero.
    Zero,
    /// The row does not depend on the velocities.
    Independent,
    /// The row is not linear: where, and why.
    Broken(NodeId, Why),
}

pub fn classify(g: &Graph, root: NodeId, velocities: &[NodeId]) -> Verdict {
    let mut class: HashMap<NodeId, Class> = HashMap::new();
    for id in g.live_set(&[root]) {
        let c = |x: NodeId| class.get(&x).copied().unwrap_or(Class::Free);
        let node = g.node(id);
        let result = if velocities.contains(&id) {
            Class::Linear
        } else {
            match node {
                Node::Const(_) if g.is_zero(id) => Class::Zero,
                Node::Const(_) | Node::Input(_) | Node::Bool(_) => Class::Free,
                Node::Neg(a) => c(a),
                Node::Add(a, b) | Node::Sub(a, b) => match (c(a), c(b)) {
                    (b @ Class::Broken(..), _) | (_, b @ Class::Broken(..)) => b,
                    (Class::Zero, x) | (x, Class::Zero) => x,
                    (Class::Free, Class::Free) => Class::Free,
                    (Class::Linear, Class::Linear) => Class::Linear,
                    _ => Class::Broken(id, Why::Affine),
                },
                Node::Mul(a, b) => match (c(a), c(b)) {
                    (b @ Class::Broken(..), _) | (_, b @ Class::Broken(..)) => b,
                    (Class::Zero, _) | (_, Class::Zero) => Class::Zero,
                    (Class::Linear, Class::Linear) => Class::Broken(id, Why::Product),
                    (Class::Linear, _) | (_, Class::Linear) => Class::Linear,
                    _ => Class::Free,
                },
                Node::Div(a, b) => match (c(a), c(b)) {
                    (b @ Class::Broken(..), _) | (_, b @ Class::Broken(..)) => b,
                    (_, Class::Linear) => Class::Broken(id, Why::Quotient),
                    (x, _) => x,
                },
                Node::Select(cond, a, b) => match (c(cond), c(a), c(b)) {
                    (Class::Broken(..), ..) | (Class::Linear, ..) => {
                        Class::Broken(id, Why::Condition)
                    }
                    (_, b @ Class::Broken(..), _) | (_, _, b @ Class::Broken(..)) => b,
                    (_, Class::Zero, x) | (_, x, Class::Zero) => x,
                    (_, x, y) if x == y => x,
                    _ => Class::Broken(id, Why::Affine),
                },
                Node::Compare(_, a, b) | Node::And(a, b) | Node::Or(a, b) => match (c(a), c(b)) {
                    (b @ Class::Broken(..), _) | (_, b @ Class::Broken(..)) => b,
                    (Class::Linear, _) | (_, Class::Linear) => Class::Linear,
                    _ => Class::Free,
                },
                Node::Not(a) => c(a),
                Node::Unary(_, a) | Node::Powi(a, _) => match c(a) {
                    b @ Class::Broken(..) => b,
                    Class::Linear => Class::Broken(id, Why::Function),
                    x => x,
                },
                Node::Binary(_, a, b) => match (c(a), c(b)) {
                    (b @ Class::Broken(..), _) | (_, b @ Class::Broken(..)) => b,
                    (Class::Linear, _) | (_, Class::Linear) => Class::Broken(id, Why::Function),
                    _ => Class::Free,
                },
            }
        };
        class.insert(id, result);
    }
    match class.get(&root).copied().unwrap_or(Class::Free) {
        Class::Linear => Verdict::Linear,
        Class::Zero => Verdict::Zero,
        Class::Free => Verdict::Independent,
        Class::Broken(at, why) => Verdict::Broken(at, why),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::engine::graph::Func;

    #[test]
    fn verdicts() {
        let mut g = Graph::new();
        let q = g.new_input("q");
        let v = g.new_input("v");
        let s = g.unary(Func::Sin, q);
        let lin = g.mul(s, v);
        assert!(matches!(classify(&g, lin, &[v]), Verdict::Linear));
        let sq = g.mul(v, v);
        assert!(matches!(classify(&g, sq, &[v]), Verdict::Broken(at, Why::Product) if at == sq));
        let sv = g.unary(Func::Sin, v);
        let e = g.add(lin, sv);
        assert!(matches!(classify(&g, e, &[v]), Verdict::Broken(at, Why::Function) if at == sv));
        let aff = g.add(lin, s);
        assert!(matches!(
            classify(&g, aff, &[v]),
            Verdict::Broken(_, Why::Affine)
        ));
        assert!(matches!(classify(&g, s, &[v]), Verdict::Independent));
        let z = g.zero();
        assert!(matches!(classify(&g, z, &[v]), Verdict::Zero));
    }
}
