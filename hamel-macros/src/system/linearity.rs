//! Is a row affine in the velocities, A(q, t)·v + a(q, t)? Decided on the graph,
//! structurally, so that the error can point at the subexpression that breaks it.

use crate::engine::graph::{Graph, Node, NodeId};
use crate::engine::hash::HashMap;

/// How a node depends on the velocity inputs.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Class {
    /// The constant zero.
    Zero,
    /// Independent of the velocities (and not known to be zero).
    Free,
    /// Σ c_j(q)·v_j: linear and homogeneous.
    Linear,
    /// Σ c_j(q)·v_j + a(q): linear plus a part without velocities.
    Affine,
    /// Anything else; carries the node where linearity broke and why.
    Broken(NodeId, Why),
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Why {
    Product,
    Quotient,
    Function,
    Condition,
}

/// The verdict on one row.
pub enum Verdict {
    /// Σ c_j(q)·v_j.
    Linear,
    /// Σ c_j(q)·v_j + a(q), with a part that is not known to be zero.
    Affine,
    /// The row is the constant zero.
    Zero,
    /// The row does not depend on the velocities.
    Independent,
    /// The row is not linear: where, and why.
    Broken(NodeId, Why),
}

impl Class {
    /// Whether the value varies with the velocities.
    fn has_velocity(self) -> bool {
        matches!(self, Class::Linear | Class::Affine)
    }
}

/// The class of a sum (or of a select, whose branches are summands of a sort).
fn sum(a: Class, b: Class) -> Class {
    match (a, b) {
        (b @ Class::Broken(..), _) | (_, b @ Class::Broken(..)) => b,
        (Class::Zero, x) | (x, Class::Zero) => x,
        (Class::Free, Class::Free) => Class::Free,
        (Class::Linear, Class::Linear) => Class::Linear,
        _ => Class::Affine,
    }
}

pub fn classify(g: &Graph, root: NodeId, velocities: &[NodeId]) -> Verdict {
    let mut class: HashMap<NodeId, Class> = HashMap::default();
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
                Node::Add(a, b) | Node::Sub(a, b) => sum(c(a), c(b)),
                Node::Mul(a, b) => match (c(a), c(b)) {
                    (b @ Class::Broken(..), _) | (_, b @ Class::Broken(..)) => b,
                    (Class::Zero, _) | (_, Class::Zero) => Class::Zero,
                    (x, y) if x.has_velocity() && y.has_velocity() => {
                        Class::Broken(id, Why::Product)
                    }
                    (x, Class::Free) | (Class::Free, x) => x,
                    _ => Class::Free,
                },
                Node::Div(a, b) => match (c(a), c(b)) {
                    (b @ Class::Broken(..), _) | (_, b @ Class::Broken(..)) => b,
                    (_, y) if y.has_velocity() => Class::Broken(id, Why::Quotient),
                    (x, _) => x,
                },
                Node::Select(cond, a, b) => match (c(cond), c(a), c(b)) {
                    (Class::Broken(..), ..) => Class::Broken(id, Why::Condition),
                    (x, ..) if x.has_velocity() => Class::Broken(id, Why::Condition),
                    (_, b @ Class::Broken(..), _) | (_, _, b @ Class::Broken(..)) => b,
                    // Per configuration one branch is taken: the select of two affine
                    // functions is affine (A and a are selects themselves).
                    (_, x, y) => sum(x, y),
                },
                Node::Compare(_, a, b) | Node::And(a, b) | Node::Or(a, b) => match (c(a), c(b)) {
                    (b @ Class::Broken(..), _) | (_, b @ Class::Broken(..)) => b,
                    (x, y) if x.has_velocity() || y.has_velocity() => Class::Linear,
                    _ => Class::Free,
                },
                Node::Not(a) => c(a),
                Node::Unary(_, a) | Node::Powi(a, _) => match c(a) {
                    b @ Class::Broken(..) => b,
                    x if x.has_velocity() => Class::Broken(id, Why::Function),
                    x => x,
                },
                Node::Binary(_, a, b) => match (c(a), c(b)) {
                    (b @ Class::Broken(..), _) | (_, b @ Class::Broken(..)) => b,
                    (x, y) if x.has_velocity() || y.has_velocity() => {
                        Class::Broken(id, Why::Function)
                    }
                    _ => Class::Free,
                },
            }
        };
        class.insert(id, result);
    }
    match class.get(&root).copied().unwrap_or(Class::Free) {
        Class::Linear => Verdict::Linear,
        Class::Affine => Verdict::Affine,
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
        assert!(matches!(classify(&g, aff, &[v]), Verdict::Affine));
        let scaled = g.mul(aff, s);
        assert!(matches!(classify(&g, scaled, &[v]), Verdict::Affine));
        let squared = g.mul(aff, lin);
        assert!(matches!(
            classify(&g, squared, &[v]),
            Verdict::Broken(at, Why::Product) if at == squared
        ));
        assert!(matches!(classify(&g, s, &[v]), Verdict::Independent));
        let z = g.zero();
        assert!(matches!(classify(&g, z, &[v]), Verdict::Zero));
    }
}
