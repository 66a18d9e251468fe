//! Differentiation by source transformation on the graph.
//!
//! Both sweeps add ordinary nodes to the same hash-consed graph, so derivative code shares
//! subexpressions with the function value and with each other, and a derivative of a
//! derivative is just another sweep. Nothing here runs at simulation time: the nodes are
//! emitted as straight-line Rust.
//!
//! * `tangent` — forward mode: the directional derivative F'(x)·ẋ for seed tangents ẋ.
//! * `adjoint` — reverse mode: the weighted gradient w̄ᵀF'(x), the cheap gradient.
//! * second order by composition: `hessian` (forward over reverse) and `bidirectional`
//!   (forward over forward), the paper's eqs. (9)–(11).
//!
//! `Select` (an `if` in the user's code) evaluates both branches. Its tangent is the select of
//! the branch tangents, which never mixes branches. In reverse mode the adjoint flowing into
//! an untaken branch is zero, but zero times a non-finite local partial (√x at x < 0 in the
//! branch an `if x > 0.0` guards against) would still be NaN; so every node that lives only
//! under some branches gets a *guard*, the condition under which it is used, and its adjoint
//! contributions are selected by that guard.

use super::graph::{Func, Func2, Graph, Node, NodeId};
use crate::engine::hash::HashMap;

/// ∂node/∂(its operand number `which`), as a node.
fn partial(g: &mut Graph, id: NodeId, which: usize) -> NodeId {
    let node = g.node(id);
    match node {
        Node::Neg(_) => g.constant(-1.0),
        Node::Add(..) => g.one(),
        Node::Sub(..) => g.constant(if which == 0 { 1.0 } else { -1.0 }),
        Node::Mul(a, b) => {
            if which == 0 {
                b
            } else {
                a
            }
        }
        Node::Div(_, b) => {
            let one = g.one();
            let r = g.div(one, b);
            if which == 0 {
                r
            } else {
                // −a/b² = −y·(1/b)
                let yr = g.mul(id, r);
                g.neg(yr)
            }
        }
        Node::Unary(f, a) => unary_partial(g, f, a, id),
        Node::Powi(a, n) => {
            let p = g.powi(a, n - 1);
            let k = g.constant(f64::from(n));
            g.mul(k, p)
        }
        Node::Binary(f, a, b) => binary_partial(g, f, a, b, id, which),
        Node::Select(..)
        | Node::Const(_)
        | Node::Input(_)
        | Node::Bool(_)
        | Node::Compare(..)
        | Node::And(..)
        | Node::Or(..)
        | Node::Not(_) => g.zero(),
    }
}

fn unary_partial(g: &mut Graph, f: Func, a: NodeId, y: NodeId) -> NodeId {
    let one = g.one();
    match f {
        Func::Sin => g.unary(Func::Cos, a),
        Func::Cos => {
            let s = g.unary(Func::Sin, a);
            g.neg(s)
        }
        // 1 + tan² reuses the value instead of computing cos again.
        Func::Tan => {
            let y2 = g.mul(y, y);
            g.add(one, y2)
        }
        Func::Asin | Func::Acos => {
            let a2 = g.mul(a, a);
            let d = g.sub(one, a2);
            let s = g.unary(Func::Sqrt, d);
            let r = g.div(one, s);
            if f == Func::Asin { r } else { g.neg(r) }
        }
        Func::Atan => {
            let a2 = g.mul(a, a);
            let d = g.add(one, a2);
            g.div(one, d)
        }
        Func::Sinh => g.unary(Func::Cosh, a),
        Func::Cosh => g.unary(Func::Sinh, a),
        // 1/cosh², not 1 − tanh²: the latter loses all relative accuracy as tanh → ±1.
        Func::Tanh => {
            let c = g.unary(Func::Cosh, a);
            let c2 = g.mul(c, c);
            g.div(one, c2)
        }
        Func::Exp => y,
        Func::Ln => g.div(one, a),
        Func::Log10 => {
            let k = g.constant(std::f64::consts::LN_10);
            let d = g.mul(a, k);
            g.div(one, d)
        }
        // 1/(2√a) = 0.5/y
        Func::Sqrt => {
            let half = g.constant(0.5);
            g.div(half, y)
        }
        // 1/(3·∛a²) = (1/3)/y²
        Func::Cbrt => {
            let third = g.constant(1.0 / 3.0);
            let y2 = g.mul(y, y);
            g.div(third, y2)
        }
        Func::Abs => g.unary(Func::Signum, a),
        Func::Signum => g.zero(),
    }
}

fn binary_partial(
    g: &mut Graph,
    f: Func2,
    a: NodeId,
    b: NodeId,
    y: NodeId,
    which: usize,
) -> NodeId {
    match f {
        Func2::Powf => {
            if which == 0 {
                // b·a^(b−1)
                let one = g.one();
                let e = g.sub(b, one);
                let p = g.binary(Func2::Powf, a, e);
                g.mul(b, p)
            } else {
                // y·ln a
                let l = g.unary(Func::Ln, a);
                g.mul(y, l)
            }
        }
        // atan2(a, b): ∂a = b/(a²+b²), ∂b = −a/(a²+b²)
        Func2::Atan2 => {
            let a2 = g.mul(a, a);
            let b2 = g.mul(b, b);
            let r2 = g.add(a2, b2);
            if which == 0 {
                g.div(b, r2)
            } else {
                let q = g.div(a, r2);
                g.neg(q)
            }
        }
        // hypot(a, b) = y: ∂a = a/y, ∂b = b/y
        Func2::Hypot => g.div(if which == 0 { a } else { b }, y),
    }
}

/// Forward mode. `seeds` gives the tangent of some input nodes (any node, typically a fresh
/// input or a constant); every other input has tangent zero. Returns the tangent of each
/// root. The seeds must not depend on the seeded inputs themselves.
pub fn tangent(g: &mut Graph, roots: &[NodeId], seeds: &[(NodeId, NodeId)]) -> Vec<NodeId> {
    let live = g.live_set(roots);
    let mut dot: HashMap<NodeId, NodeId> =
        HashMap::with_capacity_and_hasher(live.len(), Default::default());
    for &(input, seed) in seeds {
        if !g.is_zero(seed) {
            dot.insert(input, seed);
        }
    }
    for id in live {
        if dot.contains_key(&id) {
            continue; // a seeded input
        }
        let node = g.node(id);
        let t = match node {
            Node::Select(c, a, b) => {
                let (ta, tb) = (dot.get(&a).copied(), dot.get(&b).copied());
                if ta.is_none() && tb.is_none() {
                    None
                } else {
                    let zero = g.zero();
                    Some(g.select(c, ta.unwrap_or(zero), tb.unwrap_or(zero)))
                }
            }
            _ => {
                let ops = node.operands();
                let mut terms = Vec::new();
                for (which, operand) in ops.as_slice().iter().enumerate() {
                    if let Some(&t) = dot.get(operand) {
                        let p = partial(g, id, which);
                        terms.push(g.mul(p, t));
                    }
                }
                (!terms.is_empty()).then(|| g.sum(&terms))
            }
        };
        if let Some(t) = t.filter(|t| !g.is_zero(*t)) {
            dot.insert(id, t);
        }
    }
    roots
        .iter()
        .map(|r| match dot.get(r) {
            Some(&t) => t,
            None => g.zero(),
        })
        .collect()
}

/// Reverse mode. Returns, for each node of `wrt`, the derivative of Σᵢ weightᵢ·rootᵢ with
/// respect to it. The weights must not depend on `wrt`.
pub fn adjoint(g: &mut Graph, roots: &[NodeId], weights: &[NodeId], wrt: &[NodeId]) -> Vec<NodeId> {
    let active = g.depends_on(wrt);
    let live: Vec<NodeId> = g
        .live_set(roots)
        .into_iter()
        .filter(|id| active[id.index()])
        .collect();
    let guards = guards(g, roots, &live);

    let mut contributions: HashMap<NodeId, Vec<NodeId>> = HashMap::default();
    for (&root, &weight) in roots.iter().zip(weights) {
        if active[root.index()] && !g.is_zero(weight) {
            contributions.entry(root).or_default().push(weight);
        }
    }
    let mut result: HashMap<NodeId, NodeId> = HashMap::default();
    for &id in live.iter().rev() {
        let Some(terms) = contributions.remove(&id) else {
            continue;
        };
        let bar = g.sum(&terms);
        if g.is_zero(bar) {
            continue;
        }
        let node = g.node(id);
        if let Node::Input(_) = node {
            result.insert(id, bar);
            continue;
        }
        if let Node::Select(c, a, b) = node {
            let zero = g.zero();
            if active[a.index()] {
                let t = g.select(c, bar, zero);
                contributions.entry(a).or_default().push(t);
            }
            if active[b.index()] {
                let t = g.select(c, zero, bar);
                contributions.entry(b).or_default().push(t);
            }
            continue;
        }
        let guard = guards.get(&id).copied();
        for (which, &operand) in node.operands().as_slice().iter().enumerate() {
            if !active[operand.index()] {
                continue;
            }
            let p = partial(g, id, which);
            let mut t = g.mul(bar, p);
            if let Some(guard) = guard {
                let zero = g.zero();
                t = g.select(guard, t, zero);
            }
            if !g.is_zero(t) {
                contributions.entry(operand).or_default().push(t);
            }
        }
    }
    wrt.iter()
        .map(|w| match result.get(w) {
            Some(&r) => r,
            None => g.zero(),
        })
        .collect()
}

/// The condition under which each node of `live` is used, for nodes that are not always
/// used (only those appear in the map). Computed from the roots down: a node is used when
/// any of its users is, and a `Select` uses its branches only under their condition.
fn guards(g: &mut Graph, roots: &[NodeId], live: &[NodeId]) -> HashMap<NodeId, NodeId> {
    let mut guard: HashMap<NodeId, NodeId> = HashMap::default();
    let truth = g.boolean(true);
    for &r in roots {
        guard.insert(r, truth);
    }
    for &id in live.iter().rev() {
        let Some(&mine) = guard.get(&id) else {
            continue;
        };
        let node = g.node(id);
        let mut reach = |g: &mut Graph, child: NodeId, edge: NodeId| {
            let when = g.and(mine, edge);
            let merged = match guard.get(&child) {
                Some(&old) => g.or(old, when),
                None => when,
            };
            guard.insert(child, merged);
        };
        match node {
            Node::Select(c, a, b) => {
                reach(g, a, c);
                let not_c = g.not(c);
                reach(g, b, not_c);
            }
            _ if node.is_bool() => {}
            _ => {
                for &child in node.operands().as_slice() {
                    reach(g, child, truth);
                }
            }
        }
    }
    guard.retain(|_, gd| g.bool_value(*gd) != Some(true));
    guard
}

/// Hessian of Σᵢ wᵢ·rootᵢ: `rows × cols` block of second derivatives, forward over reverse.
/// `rows` and `cols` are input nodes.
pub fn hessian(
    g: &mut Graph,
    roots: &[NodeId],
    weights: &[NodeId],
    rows: &[NodeId],
    cols: &[NodeId],
) -> Vec<Vec<NodeId>> {
    let gradient = adjoint(g, roots, weights, rows);
    let one = g.one();
    let columns: Vec<Vec<NodeId>> = cols
        .iter()
        .map(|&c| tangent(g, &gradient, &[(c, one)]))
        .collect();
    (0..rows.len())
        .map(|i| columns.iter().map(|col| col[i]).collect())
        .collect()
}

/// Bidirectional second derivative F''(x)[u, v] (the paper's eq. 10), forward over forward.
/// The directions must not depend on the inputs they seed.
pub fn bidirectional(
    g: &mut Graph,
    roots: &[NodeId],
    u: &[(NodeId, NodeId)],
    v: &[(NodeId, NodeId)],
) -> Vec<NodeId> {
    let first = tangent(g, roots, v);
    tangent(g, &first, u)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::engine::graph::Cmp;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-13 * (1.0 + a.abs().max(b.abs()))
    }

    #[test]
    fn product_rule_forward_and_reverse() {
        let mut g = Graph::new();
        let x = g.new_input("x");
        let y = g.new_input("y");
        let s = g.unary(Func::Sin, x);
        let f = g.mul(s, y); // sin(x)·y
        let one = g.one();
        let dx = tangent(&mut g, &[f], &[(x, one)])[0];
        let grad = adjoint(&mut g, &[f], &[one], &[x, y]);
        let vals = g.evaluate(&[dx, grad[0], grad[1]], &[0.7, 1.9]);
        assert!(close(vals[0], 0.7f64.cos() * 1.9));
        assert!(close(vals[1], 0.7f64.cos() * 1.9));
        assert!(close(vals[2], 0.7f64.sin()));
    }

    #[test]
    fn hessian_of_quadratic_form_is_constant() {
        let mut g = Graph::new();
        let x = g.new_input("x");
        let y = g.new_input("y");
        let xx = g.mul(x, x);
        let xy = g.mul(x, y);
        let three = g.constant(3.0);
        let t = g.mul(three, xy);
        let f = g.add(xx, t); // x² + 3xy
        let one = g.one();
        let h = hessian(&mut g, &[f], &[one], &[x, y], &[x, y]);
        let consts: Vec<Option<f64>> = h.iter().flatten().map(|&n| g.const_value(n)).collect();
        assert_eq!(consts, vec![Some(2.0), Some(3.0), Some(3.0), Some(0.0)]);
    }

    #[test]
    fn untaken_branch_does_not_poison_the_gradient() {
        // f(x) = if x > 0 { √x } else { 0 } at x = −1: √−1 is NaN in the untaken branch.
        let mut g = Graph::new();
        let x = g.new_input("x");
        let zero = g.zero();
        let c = g.compare(Cmp::Gt, x, zero);
        let r = g.unary(Func::Sqrt, x);
        let f = g.select(c, r, zero);
        let one = g.one();
        let grad = adjoint(&mut g, &[f], &[one], &[x])[0];
        let h = hessian(&mut g, &[f], &[one], &[x], &[x])[0][0];
        let at_minus = g.evaluate(&[grad, h], &[-1.0]);
        assert_eq!(at_minus, vec![0.0, 0.0]);
        let at_four = g.evaluate(&[grad, h], &[4.0]);
        assert!(close(at_four[0], 0.25));
        assert!(close(at_four[1], -1.0 / 32.0));
    }

    #[test]
    fn bidirectional_matches_mixed_partial() {
        // f = sin(x·y): ∂²f/∂x∂y = cos(xy) − xy·sin(xy)
        let mut g = Graph::new();
        let x = g.new_input("x");
        let y = g.new_input("y");
        let p = g.mul(x, y);
        let f = g.unary(Func::Sin, p);
        let one = g.one();
        let d = bidirectional(&mut g, &[f], &[(x, one)], &[(y, one)])[0];
        let (xv, yv) = (0.4, -1.3);
        let v = g.evaluate(&[d], &[xv, yv])[0];
        let xy: f64 = xv * yv;
        assert!(close(v, xy.cos() - xy * xy.sin()));
    }
}
