//! A last pass over finished expressions: the factors the terms of a sum share, taken out
//! of it, the most shared first (a greedy Horner scheme in many variables).
//! `2·x₇·(x₅ cos α·sin α·J_x − x₅ sin α·cos α·J_z) + 2·sin α·l·m₀·l·cos α·x₅·x₇` becomes
//! `2·x₅·x₇·sin α·cos α·(J_x − J_z + l·l·m₀)`. The parameters of each term are multiplied into
//! one factor and the terms of parameters alone added into one, so that they form values
//! prepared once. It runs once the equations are complete, on what the right-hand side
//! computes: during construction a factored sum would hide its terms from later
//! cancellations.

use super::graph::{Graph, Node, NodeId};
use crate::engine::hash::HashMap;

impl Graph {
    /// `roots` rebuilt with every sum in Horner form; `varying` are the inputs that are not
    /// parameters. The rest of each node as it is (no other simplification runs again).
    pub fn factored(&mut self, roots: &[NodeId], varying: &[NodeId]) -> Vec<NodeId> {
        let mut active = self.depends_on(varying);
        let mut image: HashMap<NodeId, NodeId> = HashMap::default();
        for id in self.live_set(roots) {
            let node = self.node(id);
            let m = |x: NodeId| image.get(&x).copied().unwrap_or(x);
            let rebuilt = match node {
                Node::Neg(a) => Node::Neg(m(a)),
                Node::Add(a, b) => Node::Add(m(a), m(b)),
                Node::Sub(a, b) => Node::Sub(m(a), m(b)),
                Node::Mul(a, b) => Node::Mul(m(a), m(b)),
                Node::Div(a, b) => Node::Div(m(a), m(b)),
                Node::Unary(f, a) => Node::Unary(f, m(a)),
                Node::Powi(a, n) => Node::Powi(m(a), n),
                Node::Binary(f, a, b) => Node::Binary(f, m(a), m(b)),
                Node::Select(c, a, b) => Node::Select(m(c), m(a), m(b)),
                Node::Compare(op, a, b) => Node::Compare(op, m(a), m(b)),
                Node::And(a, b) => Node::And(m(a), m(b)),
                Node::Or(a, b) => Node::Or(m(a), m(b)),
                Node::Not(a) => Node::Not(m(a)),
                Node::Const(_) | Node::Input(_) | Node::Bool(_) => node,
            };
            let new = self.intern(rebuilt);
            let new = match rebuilt {
                Node::Add(..) | Node::Sub(..) => {
                    self.common_factor_out(new, &mut active).unwrap_or(new)
                }
                Node::Div(..) => self.divided_by_parameters(new, &mut active).unwrap_or(new),
                _ => new,
            };
            image.insert(id, new);
        }
        roots.iter().map(|r| image[r]).collect()
    }

    /// The sum `id` with its terms merged (k·(a + b) flattened into them) and rebuilt by
    /// taking out, again and again, the factor the most terms have: Horner's scheme for
    /// many variables, greedy. `None` if the sum cannot be flattened.
    fn common_factor_out(&mut self, id: NodeId, active: &mut Vec<bool>) -> Option<NodeId> {
        let mut raw = Vec::new();
        if !self.flat_terms(id, 1.0, &mut raw) || raw.len() < 2 {
            return None;
        }
        let mut terms: Vec<(f64, Vec<NodeId>)> = Vec::with_capacity(raw.len());
        for (c, t) in raw {
            let (c, factors) = match self.node(t) {
                Node::Const(bits) => (c * f64::from_bits(bits), Vec::new()),
                _ => {
                    let mut factors = Vec::new();
                    let mut scale = 1.0;
                    if !self.factors(t, false, &mut factors, &mut scale) {
                        return None;
                    }
                    self.cancel_reciprocals(&mut factors);
                    (c * scale, self.parameters_grouped(factors, active))
                }
            };
            match terms.iter_mut().find(|(_, f)| *f == factors) {
                Some((w, _)) => *w += c,
                None => terms.push((c, factors)),
            }
        }
        terms.retain(|(c, _)| *c != 0.0);
        self.extend_activity(active);
        // The terms of parameters alone, as one: a sum prepared once.
        let (fixed, mut terms): (Vec<_>, Vec<_>) = terms
            .into_iter()
            .partition(|(_, factors)| factors.iter().all(|f| !active[f.index()]));
        if fixed.len() > 1 {
            let items = self.signed_products(fixed);
            terms.push((1.0, vec![self.plain_sum(&items)]));
        } else {
            terms.extend(fixed);
        }
        Some(self.horner(terms))
    }

    /// x·p/q with q and p parameters alone, as x·(p/q): a product by a value prepared
    /// once instead of a division at every call (`r·(φ₁ − φ₂)/b` is `(φ₁ − φ₂)·(r/b)`).
    fn divided_by_parameters(&mut self, id: NodeId, active: &mut Vec<bool>) -> Option<NodeId> {
        let Node::Div(a, b) = self.node(id) else {
            return None;
        };
        self.extend_activity(active);
        if active[b.index()] || !active[a.index()] {
            return None;
        }
        let mut factors = Vec::new();
        let mut scale = 1.0;
        if !self.factors(a, false, &mut factors, &mut scale) {
            factors = vec![a];
            scale = 1.0;
        }
        let (fixed, varying): (Vec<NodeId>, Vec<NodeId>) =
            factors.into_iter().partition(|f| !active[f.index()]);
        let mut numerator = self.plain_product(&fixed);
        if scale != 1.0 {
            let k = self.constant(scale);
            numerator = self.intern(Node::Mul(k, numerator));
        }
        let quotient = self.intern(Node::Div(numerator, b));
        let rest = self.plain_product(&varying);
        Some(self.intern(Node::Mul(rest, quotient)))
    }

    /// A term's factors, sorted, with those that depend on the parameters alone multiplied
    /// into one factor: `l·m₀` of `x₅·l·m₀` is then one value, prepared once and taken out of
    /// a sum as one factor.
    fn parameters_grouped(&mut self, factors: Vec<NodeId>, active: &mut Vec<bool>) -> Vec<NodeId> {
        self.extend_activity(active);
        let (mut fixed, mut varying): (Vec<NodeId>, Vec<NodeId>) =
            factors.into_iter().partition(|f| !active[f.index()]);
        fixed.sort_unstable();
        if !fixed.is_empty() {
            varying.push(self.plain_product(&fixed));
        }
        varying.sort_unstable();
        varying
    }

    /// Σ cᵢ·tᵢ flattened through sums, negations and constant multiples of sums.
    fn flat_terms(&self, id: NodeId, c: f64, out: &mut Vec<(f64, NodeId)>) -> bool {
        match self.node(id) {
            Node::Add(a, b) => self.flat_terms(a, c, out) && self.flat_terms(b, c, out),
            Node::Sub(a, b) => self.flat_terms(a, c, out) && self.flat_terms(b, -c, out),
            Node::Neg(a) => self.flat_terms(a, -c, out),
            Node::Mul(k, x)
                if self.const_value(k).is_some()
                    && matches!(self.node(x), Node::Add(..) | Node::Sub(..)) =>
            {
                self.flat_terms(x, c * self.const_value(k).unwrap_or(1.0), out)
            }
            _ => {
                out.push((c, id));
                out.len() <= 64
            }
        }
    }

    /// Σ cᵢ·Πfᵢ with the factor most terms share taken out first, recursively.
    fn horner(&mut self, terms: Vec<(f64, Vec<NodeId>)>) -> NodeId {
        if terms.is_empty() {
            return self.zero();
        }
        let mut counts: HashMap<NodeId, usize> = HashMap::default();
        for (_, factors) in &terms {
            let mut seen = factors.clone();
            seen.dedup();
            for f in seen {
                *counts.entry(f).or_default() += 1;
            }
        }
        let best = counts
            .into_iter()
            .filter(|&(_, n)| n >= 2)
            .max_by_key(|&(f, n)| (n, std::cmp::Reverse(f)));
        let Some((f, _)) = best else {
            let items = self.signed_products(terms);
            return self.plain_sum(&items);
        };
        let (mut with, without): (Vec<_>, Vec<_>) = terms
            .into_iter()
            .partition(|(_, factors)| factors.contains(&f));
        for (_, factors) in &mut with {
            if let Some(at) = factors.iter().position(|&g| g == f) {
                factors.remove(at);
            }
        }
        let inner = self.horner(with);
        let grouped = self.intern(Node::Mul(f, inner));
        if without.is_empty() {
            return grouped;
        }
        let rest = self.horner(without);
        self.intern(Node::Add(grouped, rest))
    }

    /// `active` (whether a node depends on the varying inputs) extended to the nodes built
    /// since: each depends on them if an operand does.
    fn extend_activity(&self, active: &mut Vec<bool>) {
        for i in active.len()..self.len() {
            let id = self.id_at(i);
            let varying = self
                .node(id)
                .operands()
                .as_slice()
                .iter()
                .any(|o| active[o.index()]);
            active.push(varying);
        }
    }

    /// Each cᵢ·Πfᵢ as its sign and magnitude |cᵢ|·Πfᵢ.
    fn signed_products(&mut self, terms: Vec<(f64, Vec<NodeId>)>) -> Vec<(bool, NodeId)> {
        terms
            .into_iter()
            .map(|(c, factors)| {
                let product = self.plain_product(&factors);
                let magnitude = if c.abs() == 1.0 {
                    product
                } else if factors.is_empty() {
                    self.constant(c.abs())
                } else {
                    let k = self.constant(c.abs());
                    self.intern(Node::Mul(k, product))
                };
                (c < 0.0, magnitude)
            })
            .collect()
    }

    /// Σ ±xᵢ: the positive ones added, the negative ones subtracted.
    fn plain_sum(&mut self, items: &[(bool, NodeId)]) -> NodeId {
        let mut acc: Option<NodeId> = None;
        let mut pending = Vec::new();
        for &(negative, x) in items {
            match (acc, negative) {
                (None, false) => acc = Some(x),
                (None, true) => pending.push(x),
                (Some(a), false) => acc = Some(self.intern(Node::Add(a, x))),
                (Some(a), true) => acc = Some(self.intern(Node::Sub(a, x))),
            }
        }
        let mut pending = pending.into_iter();
        let mut acc = match (acc, pending.next()) {
            (Some(a), Some(first)) => self.intern(Node::Sub(a, first)),
            (Some(a), None) => a,
            (None, Some(first)) => self.intern(Node::Neg(first)),
            (None, None) => self.zero(),
        };
        for x in pending {
            acc = self.intern(Node::Sub(acc, x));
        }
        acc
    }

    /// The product of `factors` as written (1 for none), without simplification.
    fn plain_product(&mut self, factors: &[NodeId]) -> NodeId {
        let mut iter = factors.iter().copied();
        let Some(first) = iter.next() else {
            return self.one();
        };
        iter.fold(first, |acc, f| self.intern(Node::Mul(acc, f)))
    }
}

#[cfg(test)]
mod tests {
    use crate::engine::graph::{Func, Graph};
    use crate::engine::ops;

    /// r·(x − y)/b with r and b parameters is (x − y)·(r/b): a product by a prepared
    /// quotient, the same value.
    #[test]
    fn a_division_by_parameters_is_a_product() {
        let mut g = Graph::new();
        let (x, y, r, b) = (
            g.new_input("x"),
            g.new_input("y"),
            g.new_input("r"),
            g.new_input("b"),
        );
        let difference = g.sub(x, y);
        let scaled = g.mul(r, difference);
        let angle = g.div(scaled, b);
        let rewritten = g.factored(&[angle], &[x, y])[0];
        assert!(matches!(
            g.node(rewritten),
            crate::engine::graph::Node::Mul(..)
        ));
        let values = [0.9, -0.4, 0.3, 1.7];
        let v = g.evaluate(&[angle, rewritten], &values);
        assert!((v[0] - v[1]).abs() <= 1e-15 * v[0].abs(), "{v:?}");
        // Divided by something that varies, it stays a division.
        let by_state = g.div(r, x);
        let kept = g.factored(&[by_state], &[x, y])[0];
        assert_eq!(kept, by_state);
    }

    /// 2·x·y·sin a·cos a·J − 2·x·y·cos a·sin a·K + 2·sin a·l·m·l·cos a·x·y, with x, y, a
    /// varying, is 2·x·y·sin a·cos a·(J − K + l·m·l): the same value with fewer
    /// operations, and the parameters J, K, l, m together in one sum.
    #[test]
    fn common_factors_come_out_of_sums() {
        let mut g = Graph::new();
        let (x, y, a) = (g.new_input("x"), g.new_input("y"), g.new_input("a"));
        let (j, k, l, m) = (
            g.new_input("J"),
            g.new_input("K"),
            g.new_input("l"),
            g.new_input("m"),
        );
        let (s, c) = (g.unary(Func::Sin, a), g.unary(Func::Cos, a));
        let two = g.constant(2.0);
        let product = |g: &mut Graph, factors: &[_]| {
            factors[1..]
                .iter()
                .fold(factors[0], |acc, &f| g.mul(acc, f))
        };
        let first = product(&mut g, &[two, x, y, s, c, j]);
        let second = product(&mut g, &[two, x, y, c, s, k]);
        let third = product(&mut g, &[two, s, l, m, l, c, x, y]);
        let difference = g.sub(first, second);
        let sum = g.add(difference, third);
        let factored = g.factored(&[sum], &[x, y, a])[0];
        let values = [0.7, -1.3, 0.4, 2.0, 0.5, 1.1, 3.0];
        let (before, after) = {
            let v = g.evaluate(&[sum, factored], &values);
            (v[0], v[1])
        };
        assert!(
            (before - after).abs() <= 1e-14 * before.abs(),
            "{before} {after}"
        );
        let (n_before, n_after) = (
            ops::count(&g, &[sum]).total(),
            ops::count(&g, &[factored]).total(),
        );
        assert!(
            n_after < n_before,
            "{n_after} operations against {n_before}"
        );
        // The parameters form one sum that no varying input reaches.
        let active = g.depends_on(&[x, y, a]);
        let live = g.live_set(&[factored]);
        let parameter_sums = live
            .iter()
            .filter(|&&id| {
                !active[id.index()]
                    && matches!(
                        g.node(id),
                        crate::engine::graph::Node::Add(..) | crate::engine::graph::Node::Sub(..)
                    )
            })
            .count();
        assert!(parameter_sums >= 1);
    }
}
