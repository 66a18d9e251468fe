//! Sums in normal form, so that the graph sees cancellations.
//!
//! Derivative code is full of terms that cancel only up to association: the γ terms of
//! Hamel's equations produce `sin·(cos·ω) − cos·(sin·ω)`, the kinematics `(a + b − c) −
//! (a − b − c)`, rotations `m·sin²x + m·cos²x`. Hash-consing alone cannot see these.
//!
//! A sum is flattened into coefficient·term pairs, and terms are compared by the multiset of
//! their factors, so `sin·(cos·ω)` and `cos·(sin·ω)` are recognized as the same term without
//! restructuring either product (restructuring products would lose shared sub-products such
//! as `m·l`). When flattening merges or cancels terms, combines constants, or finds
//! `P·sin²x + P·cos²x`, the sum is rebuilt from what is left; when nothing merges it stays the
//! binary node it was, which keeps shared partial sums shared.
//!
//! A quotient's divisor counts as a reciprocal factor (the node `1/r`), so that `0.5·b/r`
//! and `−0.5·b/r` are multiples of one term and `r·(b/r)` loses its `r` and `1/r`. Where the
//! flat terms show nothing, products with a sum among their factors are distributed once
//! and looked at again (the rotation of a closed-form inverse cancels only there), and the
//! result is kept only if it is simpler.
//!
//! Flattening stops at a small number of pieces: this is a local simplification, not a
//! computer-algebra system, and its cost stays bounded per node.

use super::graph::{Func, Graph, Node, NodeId};

/// Most terms a sum is flattened into before normalization gives up on it.
const MAX_TERMS: usize = 16;
/// Most factors a term is flattened into when comparing terms.
const MAX_FACTORS: usize = 16;

/// Operations the merged terms take as a sum (as `Graph::sum_cost` counts them), a
/// coefficient other than ±1 one more.
fn merged_cost(terms: &[Term]) -> usize {
    let products: usize = terms
        .iter()
        .map(|t| t.factors.len().saturating_sub(1) + usize::from(t.weight().abs() != 1.0))
        .sum();
    products + terms.len().saturating_sub(1)
}

/// A product `scale · rest · (Σ terms + Σ constants)` split at one of its factors that is a sum.
struct SplitProduct {
    scale: f64,
    rest: NodeId,
    terms: Vec<(f64, NodeId)>,
    constants: Vec<f64>,
}

/// One term of a flattened sum: `coefficient · node`, where `node` is the product of
/// `factors` (sorted ids) times its own constant `scale`.
struct Term {
    coefficient: f64,
    node: NodeId,
    factors: Vec<NodeId>,
    scale: f64,
}

impl Term {
    /// The value of the term as a multiple of the bare product of its factors.
    fn weight(&self) -> f64 {
        self.coefficient * self.scale
    }
}

impl Graph {
    /// `a + sign·b` in normal form when flattening finds something to simplify, else `None`.
    /// When the flat terms show nothing, the terms that are a factor times a short sum
    /// (`m·(a + b) − m·(a − b)`, `s·(s·m₀ + 2 s·m_w) + c·(c·m₀ + …)`) are distributed once and
    /// looked at again; the sum is rebuilt only if that finds a cancellation.
    pub(super) fn normal_sum(&mut self, a: NodeId, b: NodeId, sign: f64) -> Option<NodeId> {
        let mut raw = Vec::new();
        let mut constants = Vec::new();
        if !self.collect_terms(a, 1.0, &mut raw, &mut constants)
            || !self.collect_terms(b, sign, &mut raw, &mut constants)
        {
            return None;
        }
        if let Some((terms, constant)) = self.merged(&raw, &constants) {
            return Some(self.rebuild_sum(&terms, constant));
        }
        // Products with a sum as a factor of their own (x·(p ± q)), distributed; kept if
        // anything merges, as the products' other factors stay the nodes they are.
        if let Some(expanded) = self.distributed(&raw, false)
            && let Some((terms, constant)) = self.merged(&expanded, &constants)
        {
            return Some(self.rebuild_sum(&terms, constant));
        }
        // Then sums deeper in the products (x·(m·(p ± q))): the rest of each product is
        // rebuilt as a new node, so distributing pays only where it removes operations even
        // if the inner sums cost nothing (being shared with other uses). That is where a
        // rotation cancels through them: sin·(m·(c·a + s·b)) − cos·(m·(s·a − c·b)) = m·b.
        if !self.deep_expansion_merges(&raw) {
            return None;
        }
        let expanded = self.distributed(&raw, true)?;
        let (terms, constant) = self.merged(&expanded, &constants)?;
        (merged_cost(&terms) < self.sum_cost(&raw)).then(|| self.rebuild_sum(&terms, constant))
    }

    /// Whether distributing the products of `raw` down to a sum among their factors gives
    /// two terms with the same factors, or a sin² and a cos² term that meet: read off the
    /// factor lists, before any node of the expansion is built (most sums have neither,
    /// and building their expansions to find out cost more than the rest of the macro).
    fn deep_expansion_merges(&mut self, raw: &[(f64, NodeId)]) -> bool {
        let mut lists: Vec<(f64, Vec<NodeId>)> = Vec::new();
        for &(c, node) in raw {
            let mut factors = Vec::new();
            let mut scale = 1.0;
            if !self.factors(node, false, &mut factors, &mut scale) {
                lists.push((c, vec![node]));
                continue;
            }
            let Some(at) = factors.iter().position(|&f| self.is_sum(f)) else {
                factors.sort_unstable();
                lists.push((c * scale, factors));
                continue;
            };
            let sum = factors.remove(at);
            let mut inner = Vec::new();
            let mut constants = Vec::new();
            if !self.collect_terms(sum, 1.0, &mut inner, &mut constants) {
                return false;
            }
            for (ci, t) in inner {
                let mut term = factors.clone();
                let mut t_scale = 1.0;
                if !self.factors(t, false, &mut term, &mut t_scale) {
                    return false;
                }
                self.cancel_reciprocals(&mut term);
                term.sort_unstable();
                lists.push((c * scale * ci * t_scale, term));
            }
            for k in constants {
                let mut term = factors.clone();
                term.sort_unstable();
                lists.push((c * scale * k, term));
            }
            if lists.len() > MAX_TERMS {
                return false;
            }
        }
        let mut sorted: Vec<&Vec<NodeId>> = lists.iter().map(|(_, l)| l).collect();
        sorted.sort_unstable();
        if sorted.windows(2).any(|w| w[0] == w[1]) {
            return true;
        }
        // sin²x·P against cos²x·P of the same weight: only lists with a square of each.
        let squares = |l: &[NodeId], f: Func| {
            l.windows(2)
                .any(|w| w[0] == w[1] && matches!(self.node(w[0]), Node::Unary(g, _) if g == f))
        };
        let sines: Vec<&(f64, Vec<NodeId>)> = lists
            .iter()
            .filter(|(_, l)| squares(l, Func::Sin))
            .collect();
        let cosines: Vec<&(f64, Vec<NodeId>)> = lists
            .iter()
            .filter(|(_, l)| squares(l, Func::Cos))
            .collect();
        sines.iter().any(|(ws, a)| {
            cosines
                .iter()
                .any(|(wc, b)| ws == wc && self.sin_cos_pair(a, b).is_some())
        })
    }

    /// Operations a sum of `raw` terms takes: one per factor of each product beyond the
    /// first, one per term beyond the first; a factor that is a sum counts as one.
    fn sum_cost(&mut self, raw: &[(f64, NodeId)]) -> usize {
        let mut cost = raw.len().saturating_sub(1);
        for &(_, node) in raw {
            let mut factors = Vec::new();
            let mut scale = 1.0;
            cost += if self.factors(node, false, &mut factors, &mut scale) {
                factors.len().saturating_sub(1)
            } else {
                MAX_FACTORS
            };
        }
        cost
    }

    /// The raw terms with every product that has a short sum among its factors
    /// (`x·(p ± q)`, `x·(m·(p ± q))`) written as `x·p ± x·q`; `None` if there is none, or the
    /// result would be too long.
    fn distributed(&mut self, raw: &[(f64, NodeId)], deep: bool) -> Option<Vec<(f64, NodeId)>> {
        let mut out = Vec::with_capacity(raw.len() * 2);
        let mut any = false;
        for &(c, node) in raw {
            match self.split_at_sum(node, deep) {
                Some(split) => {
                    any = true;
                    let weight = c * split.scale;
                    for (ci, t) in split.terms {
                        let product = self.mul(split.rest, t);
                        out.push((weight * ci, product));
                    }
                    for k in split.constants {
                        out.push((weight * k, split.rest));
                    }
                }
                None => out.push((c, node)),
            }
            if out.len() > MAX_TERMS {
                return None;
            }
        }
        any.then_some(out)
    }

    /// A product with a sum among its factors, as scale · rest · (Σ terms + Σ constants).
    fn split_at_sum(&mut self, node: NodeId, deep: bool) -> Option<SplitProduct> {
        if !matches!(self.node(node), Node::Mul(..)) {
            return None;
        }
        let mut factors = Vec::new();
        let mut scale = 1.0;
        if !self.factors(node, false, &mut factors, &mut scale) {
            return None;
        }
        // x·(p ± q) as written: x stays the node it is (shared with its other uses).
        if let Node::Mul(x, y) = self.node(node) {
            let direct = if self.is_sum(y) {
                Some((x, y))
            } else if self.is_sum(x) {
                Some((y, x))
            } else {
                None
            };
            if let Some((rest, sum)) = direct {
                let mut terms = Vec::new();
                let mut constants = Vec::new();
                return self
                    .collect_terms(sum, 1.0, &mut terms, &mut constants)
                    .then_some(SplitProduct {
                        scale: 1.0,
                        rest,
                        terms,
                        constants,
                    });
            }
        }
        if !deep {
            return None;
        }
        let at = factors.iter().position(|&f| self.is_sum(f))?;
        let sum = factors.remove(at);
        let mut terms = Vec::new();
        let mut constants = Vec::new();
        if !self.collect_terms(sum, 1.0, &mut terms, &mut constants) {
            return None;
        }
        let mut rest = self.one();
        for f in factors {
            rest = self.mul(rest, f);
        }
        Some(SplitProduct {
            scale,
            rest,
            terms,
            constants,
        })
    }

    fn is_sum(&self, id: NodeId) -> bool {
        matches!(self.node(id), Node::Add(..) | Node::Sub(..))
    }

    /// The terms and constant of `raw` + `constants` in normal form, if merging, cancelling,
    /// folding constants or sin² + cos² simplified anything.
    fn merged(&mut self, raw: &[(f64, NodeId)], constants: &[f64]) -> Option<(Vec<Term>, f64)> {
        let count = raw.len();
        let mut terms: Vec<Term> = Vec::with_capacity(count);
        for &(coefficient, node) in raw {
            let mut factors = Vec::new();
            let mut scale = 1.0;
            if self.factors(node, false, &mut factors, &mut scale) {
                self.cancel_reciprocals(&mut factors);
            } else {
                factors = vec![node];
                scale = 1.0;
            }
            factors.sort_unstable();
            match terms.iter_mut().find(|t| t.factors == factors) {
                Some(t) => t.coefficient += coefficient * scale / t.scale,
                None => terms.push(Term {
                    coefficient,
                    node,
                    factors,
                    scale,
                }),
            }
        }
        terms.retain(|t| t.coefficient != 0.0);
        // Folded from +0.0: x − x is +0.0 in IEEE arithmetic (an empty `f64` sum is −0.0).
        let mut constant: f64 = constants.iter().fold(0.0, |acc, c| acc + c);
        let pythagoras = self.pythagoras(&mut terms, &mut constant);
        if terms.len() == count && constants.len() <= 1 && !pythagoras {
            return None;
        }
        Some((terms, constant))
    }

    pub(super) fn collect_terms(
        &self,
        id: NodeId,
        c: f64,
        terms: &mut Vec<(f64, NodeId)>,
        constants: &mut Vec<f64>,
    ) -> bool {
        match self.node(id) {
            Node::Add(a, b) => {
                self.collect_terms(a, c, terms, constants)
                    && self.collect_terms(b, c, terms, constants)
            }
            Node::Sub(a, b) => {
                self.collect_terms(a, c, terms, constants)
                    && self.collect_terms(b, -c, terms, constants)
            }
            Node::Neg(a) => self.collect_terms(a, -c, terms, constants),
            Node::Const(bits) => {
                constants.push(c * f64::from_bits(bits));
                true
            }
            // The constant in front belongs to the coefficient (keeps rebuilt signs right).
            Node::Mul(k, x) if self.const_value(k).is_some() => {
                terms.push((c * self.const_value(k).unwrap_or(1.0), x));
                terms.len() <= MAX_TERMS
            }
            _ => {
                terms.push((c, id));
                terms.len() <= MAX_TERMS
            }
        }
    }

    /// A product (or quotient, `divide`) in which a factor meets its reciprocal
    /// (`(1/b)·(b·x)`, `(b·x)/b`), with those two cancelled; `None` when nothing cancels (the
    /// product is then built as usual).
    pub(super) fn cancelled_product(
        &mut self,
        a: NodeId,
        b: NodeId,
        divide: bool,
    ) -> Option<NodeId> {
        let mut up = Vec::new();
        let mut down = Vec::new();
        let mut coefficient = 1.0;
        if !self.monomial(a, false, &mut up, &mut down, &mut coefficient)
            || !self.monomial(b, divide, &mut up, &mut down, &mut coefficient)
        {
            return None;
        }
        let mut cancelled = false;
        let mut i = 0;
        while i < up.len() {
            if let Some(j) = down.iter().position(|&d| d == up[i]) {
                up.remove(i);
                down.remove(j);
                cancelled = true;
            } else {
                i += 1;
            }
        }
        if !cancelled {
            return None;
        }
        up.sort_unstable();
        down.sort_unstable();
        let mut numerator = self.constant(coefficient);
        for &f in &up {
            numerator = self.mul(numerator, f);
        }
        let mut result = numerator;
        for &f in &down {
            result = self.div(result, f);
        }
        Some(result)
    }

    /// Factors of a product or quotient: `up` multiply, `down` divide.
    fn monomial(
        &self,
        id: NodeId,
        inverted: bool,
        up: &mut Vec<NodeId>,
        down: &mut Vec<NodeId>,
        c: &mut f64,
    ) -> bool {
        match self.node(id) {
            Node::Mul(x, y) => {
                self.monomial(x, inverted, up, down, c) && self.monomial(y, inverted, up, down, c)
            }
            Node::Div(x, y) => {
                self.monomial(x, inverted, up, down, c) && self.monomial(y, !inverted, up, down, c)
            }
            Node::Neg(x) => {
                *c = -*c;
                self.monomial(x, inverted, up, down, c)
            }
            Node::Const(bits) => {
                let v = f64::from_bits(bits);
                *c = if inverted { *c / v } else { *c * v };
                true
            }
            _ => {
                if inverted {
                    down.push(id)
                } else {
                    up.push(id)
                }
                up.len() + down.len() <= MAX_FACTORS
            }
        }
    }

    /// The non-constant factors of a product or quotient and its constant part, divisors
    /// as reciprocal factors (`1/r`, the node `Div(1, r)`): so that `0.5·b/r` and
    /// `(−0.5·b)/r`, or `x·(b/r)` and `(x·b)/r`, are seen as the same term.
    pub(super) fn factors(
        &mut self,
        id: NodeId,
        inverted: bool,
        factors: &mut Vec<NodeId>,
        scale: &mut f64,
    ) -> bool {
        match self.node(id) {
            Node::Mul(a, b) => {
                self.factors(a, inverted, factors, scale)
                    && self.factors(b, inverted, factors, scale)
            }
            Node::Div(a, b) => {
                self.factors(a, inverted, factors, scale)
                    && self.factors(b, !inverted, factors, scale)
            }
            Node::Neg(a) => {
                *scale = -*scale;
                self.factors(a, inverted, factors, scale)
            }
            Node::Const(bits) => {
                let v = f64::from_bits(bits);
                *scale = if inverted { *scale / v } else { *scale * v };
                true
            }
            Node::Powi(x, 2) => {
                let f = self.factor(x, inverted);
                factors.extend([f, f]);
                factors.len() <= MAX_FACTORS
            }
            _ => {
                let f = self.factor(id, inverted);
                factors.push(f);
                factors.len() <= MAX_FACTORS
            }
        }
    }

    /// Removes each factor `x` together with a factor `1/x`: the term `r·(b/r)·x` is `b·x`.
    pub(super) fn cancel_reciprocals(&self, factors: &mut Vec<NodeId>) {
        let mut i = 0;
        while i < factors.len() {
            let partner = match self.node(factors[i]) {
                Node::Div(one, x) if self.is_const(one, 1.0) => {
                    factors.iter().position(|&f| f == x)
                }
                _ => None,
            };
            match partner {
                Some(j) => {
                    let (first, second) = if i < j { (i, j) } else { (j, i) };
                    factors.remove(second);
                    factors.remove(first);
                    i = 0;
                }
                None => i += 1,
            }
        }
    }

    /// `x`, or its reciprocal `Div(1, x)` (the node `div(1, x)` builds).
    fn factor(&mut self, x: NodeId, inverted: bool) -> NodeId {
        if inverted {
            let one = self.one();
            self.intern(Node::Div(one, x))
        } else {
            x
        }
    }

    /// Replace w·P·sin²x + w·P·cos²x by w·P. Returns whether it did.
    fn pythagoras(&mut self, terms: &mut Vec<Term>, constant: &mut f64) -> bool {
        let mut found = false;
        'search: loop {
            for i in 0..terms.len() {
                for (j, other) in terms.iter().enumerate() {
                    if i == j || terms[i].weight() != other.weight() {
                        continue;
                    }
                    if let Some(rest) = self.sin_cos_pair(&terms[i].factors, &other.factors) {
                        let weight = terms[i].weight();
                        let (first, second) = if i < j { (i, j) } else { (j, i) };
                        terms.remove(second);
                        terms.remove(first);
                        if rest.is_empty() {
                            *constant += weight;
                        } else {
                            let mut node = rest[0];
                            for &f in &rest[1..] {
                                node = self.mul(node, f);
                            }
                            terms.push(Term {
                                coefficient: weight,
                                node,
                                factors: rest,
                                scale: 1.0,
                            });
                        }
                        found = true;
                        continue 'search;
                    }
                }
            }
            return found;
        }
    }

    /// If `a` = P·sin²x and `b` = P·cos²x (sorted factor lists), return P.
    fn sin_cos_pair(&self, a: &[NodeId], b: &[NodeId]) -> Option<Vec<NodeId>> {
        let squares = |factors: &[NodeId], f: Func| -> Vec<(NodeId, NodeId)> {
            factors
                .windows(2)
                .filter(|w| w[0] == w[1])
                .filter_map(|w| match self.node(w[0]) {
                    Node::Unary(g, arg) if g == f => Some((w[0], arg)),
                    _ => None,
                })
                .collect()
        };
        for (sin, arg) in squares(a, Func::Sin) {
            for (cos, arg2) in squares(b, Func::Cos) {
                if arg != arg2 {
                    continue;
                }
                let without = |factors: &[NodeId], x: NodeId| -> Vec<NodeId> {
                    let mut v = factors.to_vec();
                    for _ in 0..2 {
                        if let Some(p) = v.iter().position(|&f| f == x) {
                            v.remove(p);
                        }
                    }
                    v
                };
                let rest = without(a, sin);
                if rest == without(b, cos) {
                    return Some(rest);
                }
            }
        }
        None
    }

    /// Σ cᵢ·tᵢ + constant as a left-deep chain: positive terms first, then the negative ones
    /// subtracted, the constant last. Built with `add`/`sub`, so the local rules (a common
    /// factor of two terms) still apply to what merging left; the terms are already merged,
    /// so the flattening inside finds nothing more and the recursion ends.
    fn rebuild_sum(&mut self, terms: &[Term], constant: f64) -> NodeId {
        let mut positive: Option<NodeId> = None;
        let mut negative: Option<NodeId> = None;
        for t in terms {
            let magnitude = self.times(t.coefficient.abs(), t.node);
            let slot = if t.coefficient > 0.0 {
                &mut positive
            } else {
                &mut negative
            };
            *slot = Some(match *slot {
                None => magnitude,
                Some(acc) => self.add(acc, magnitude),
            });
        }
        let body = match (positive, negative) {
            (Some(p), Some(n)) => Some(self.sub(p, n)),
            (Some(p), None) => Some(p),
            (None, Some(n)) => Some(self.neg(n)),
            (None, None) => None,
        };
        match body {
            None => self.constant(constant),
            Some(b) if constant == 0.0 => b,
            Some(b) if constant > 0.0 => {
                let k = self.constant(constant);
                self.plain_add(b, k)
            }
            Some(b) => {
                let k = self.constant(-constant);
                self.intern(Node::Sub(b, k))
            }
        }
    }

    fn plain_add(&mut self, a: NodeId, b: NodeId) -> NodeId {
        let (x, y) = if a <= b { (a, b) } else { (b, a) };
        self.intern(Node::Add(x, y))
    }

    /// c·x for c > 0, through `mul` (which folds constants in front).
    fn times(&mut self, c: f64, x: NodeId) -> NodeId {
        if c == 1.0 {
            return x;
        }
        let k = self.constant(c);
        self.mul(k, x)
    }
}

#[cfg(test)]
mod tests {
    use crate::engine::graph::{Func, Graph, Node, NodeId};

    #[test]
    fn terms_meet_whatever_the_association_of_their_products() {
        let mut g = Graph::new();
        let s = g.new_input("s");
        let c = g.new_input("c");
        let w = g.new_input("w");
        let cw = g.mul(c, w);
        let sw = g.mul(s, w);
        let a = g.mul(s, cw);
        let b = g.mul(c, sw);
        let d = g.sub(a, b);
        assert!(g.is_zero(d));
        let two = g.constant(2.0);
        let half = g.constant(0.5);
        let t = g.mul(two, s);
        let u = g.mul(half, t);
        assert_eq!(u, s);
    }

    #[test]
    fn sums_cancel_and_combine() {
        let mut g = Graph::new();
        let a = g.new_input("a");
        let b = g.new_input("b");
        let c = g.new_input("c");
        let ab = g.add(a, b);
        let p = g.sub(ab, c); // a + b − c
        let amb = g.sub(a, b);
        let q = g.sub(amb, c); // a − b − c
        let d = g.sub(p, q); // 2b
        let v = g.evaluate(&[d], &[1.0, 3.0, 5.0]);
        assert_eq!(v, vec![6.0]);
        assert_eq!(crate::engine::ops::count(&g, &[d]).total(), 1);
    }

    #[test]
    fn pythagoras_with_common_factors() {
        let mut g = Graph::new();
        let x = g.new_input("x");
        let m = g.new_input("m");
        let w = g.new_input("w");
        let s = g.unary(Func::Sin, x);
        let c = g.unary(Func::Cos, x);
        let s2 = g.mul(s, s);
        let c2 = g.mul(c, c);
        let sum = g.add(s2, c2);
        assert_eq!(g.const_value(sum), Some(1.0));
        // m·w·sin²x + (w·cos x)·(m·cos x) = m·w
        let ms2 = g.mul(m, s2);
        let a = g.mul(w, ms2);
        let wc = g.mul(w, c);
        let mc = g.mul(m, c);
        let b = g.mul(wc, mc);
        let total = g.add(a, b);
        let mw = g.mul(m, w);
        assert_eq!(total, mw);
        // Different weights stay.
        let other = g.add(ms2, c2);
        assert!(g.const_value(other).is_none());
    }

    /// What only distributing a factor over a short sum shows: m·(a + b) − m·(a − b) = 2·m·b,
    /// and sin x·(sin x·m + 2·sin x·w) + cos x·(cos x·m + 2·cos x·w) = m + 2·w, the robot's
    /// composed kinetic energy; a product with nothing to cancel keeps its shape.
    #[test]
    fn distributing_a_factor_finds_cancellations() {
        let mut g = Graph::new();
        let (x, m, w) = (g.new_input("x"), g.new_input("m"), g.new_input("w"));
        let (a, b) = (g.new_input("a"), g.new_input("b"));
        let (sum, difference) = (g.add(a, b), g.sub(a, b));
        let (left, right) = (g.mul(m, sum), g.mul(m, difference));
        let total = g.sub(left, right);
        let values = [0.3, 1.7, -0.4, 2.5, 0.9];
        let got = g.evaluate(&[total], &values)[0];
        assert!((got - 2.0 * 1.7 * 0.9).abs() < 1e-15, "{got}");
        assert!(!matches!(g.node(total), Node::Sub(..)), "not reduced");

        let (s, c) = (g.unary(Func::Sin, x), g.unary(Func::Cos, x));
        let two = g.constant(2.0);
        let inner = |g: &mut Graph, f: NodeId| {
            let fm = g.mul(f, m);
            let fw = g.mul(f, w);
            let twice = g.mul(two, fw);
            let sum = g.add(fm, twice);
            g.mul(f, sum)
        };
        let (ps, pc) = (inner(&mut g, s), inner(&mut g, c));
        let kinetic = g.add(ps, pc);
        let expected = {
            let twice = g.mul(two, w);
            g.add(m, twice)
        };
        let (got, want) = {
            let v = g.evaluate(&[kinetic, expected], &values);
            (v[0], v[1])
        };
        assert!((got - want).abs() < 1e-15);
        let ops = crate::engine::ops::count(&g, &[kinetic]).total();
        assert!(ops <= 3, "m + 2·w takes {ops} operations");

        // (a + b)·w + m: nothing cancels, the product stays as written.
        let product = g.mul(sum, w);
        let plain = g.add(product, m);
        assert!(
            matches!(g.node(plain), Node::Add(p, q) if [p, q] == [product, m] || [p, q] == [m, product])
        );
    }

    /// Quotients meet as multiples of one term: 0.5·b/r − (−0.5·b/r) = b/r, and
    /// r·(b/r) + x − b = x, whatever the association of the products and quotients.
    #[test]
    fn quotients_merge_as_reciprocal_factors() {
        let mut g = Graph::new();
        let (b, r, x) = (g.new_input("b"), g.new_input("r"), g.new_input("x"));
        let (half, minus_half) = (g.constant(0.5), g.constant(-0.5));
        let hb = g.mul(half, b);
        let up = g.div(hb, r);
        let mhb = g.mul(minus_half, b);
        let down = g.div(mhb, r);
        let difference = g.sub(up, down);
        let quotient = g.div(b, r);
        assert_eq!(difference, quotient);

        let rb = g.mul(r, quotient);
        let sum = g.add(rb, x);
        let rest = g.sub(sum, b);
        assert_eq!(rest, x);
    }

    /// A rotation through a shared factor cancels only when the products are distributed
    /// down to their sums: sin·(m·(c·a + s·b)) − cos·(m·(s·a − c·b)) = m·b. A deeper sum that
    /// cancels nothing stays as written.
    #[test]
    fn rotations_cancel_through_factored_sums() {
        let mut g = Graph::new();
        let (angle, m, a, b) = (
            g.new_input("angle"),
            g.new_input("m"),
            g.new_input("a"),
            g.new_input("b"),
        );
        let (s, c) = (g.unary(Func::Sin, angle), g.unary(Func::Cos, angle));
        let (ca, sb, sa, cb) = (g.mul(c, a), g.mul(s, b), g.mul(s, a), g.mul(c, b));
        let (first, second) = (g.add(ca, sb), g.sub(sa, cb));
        let (mf, ms) = (g.mul(m, first), g.mul(m, second));
        let (left, right) = (g.mul(s, mf), g.mul(c, ms));
        let total = g.sub(left, right);
        let mb = g.mul(m, b);
        assert_eq!(total, mb);

        let other = g.mul(a, ms);
        let plain = g.add(left, other);
        assert!(matches!(g.node(plain), Node::Add(..)));
        assert!(g.node(plain).operands().as_slice().contains(&left));
    }

    #[test]
    fn unmerged_sums_keep_their_shape() {
        let mut g = Graph::new();
        let a = g.new_input("a");
        let b = g.new_input("b");
        let c = g.new_input("c");
        let ab = g.add(a, b);
        let abc = g.add(ab, c);
        assert!(g.node(abc).operands().as_slice().contains(&ab));
    }
}
