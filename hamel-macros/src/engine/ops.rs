//! Operation counts of emitted code: the measure behind the cheap-gradient check.

use super::graph::{Graph, Node, NodeId};

/// How many operations the code for some roots performs, by kind. Constants and inputs
/// are free; every other live node is one operation.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct OpCount {
    /// `+`, `-` and negation.
    pub add: usize,
    pub mul: usize,
    pub div: usize,
    /// Elementary functions (`sin`, `sqrt`, `powi`, `atan2`, ...).
    pub func: usize,
    /// Selects, comparisons and boolean logic (from `if`).
    pub branch: usize,
}

impl OpCount {
    pub fn total(&self) -> usize {
        self.add + self.mul + self.div + self.func + self.branch
    }
}

pub fn count(graph: &Graph, roots: &[NodeId]) -> OpCount {
    let mut c = OpCount::default();
    for id in graph.live_set(roots) {
        match graph.node(id) {
            Node::Const(_) | Node::Input(_) | Node::Bool(_) => {}
            Node::Neg(_) | Node::Add(..) | Node::Sub(..) => c.add += 1,
            Node::Mul(..) => c.mul += 1,
            Node::Div(..) => c.div += 1,
            Node::Unary(..) | Node::Powi(..) | Node::Binary(..) => c.func += 1,
            Node::Select(..) | Node::Compare(..) | Node::And(..) | Node::Or(..) | Node::Not(_) => {
                c.branch += 1
            }
        }
    }
    c
}
