//! The expression graph: a hash-consed DAG in SSA form.
//!
//! Every node is created through a constructor that first simplifies (constant folding and
//! algebraic identities) and then interns the node, so a common subexpression exists exactly
//! once and the node ids are a topological order (children always precede parents). The
//! differentiation passes in `diff.rs` add their nodes to the same graph, which is how a
//! derivative shares `cos(x)` with the function value that already needed it.
//!
//! The graph holds real-valued nodes and boolean nodes (comparisons and their combinations,
//! used only as the condition of a `Select`). Booleans are never differentiated.

use crate::engine::hash::HashMap;
use proc_macro2::Span;

/// The first and last token of a piece of source: what `syn::Error::new_spanned` underlines.
/// (`Span::join` is nightly-only, so a range is kept as its two ends.)
#[derive(Clone, Copy, Debug)]
pub struct SpanRange {
    pub start: Span,
    pub end: Span,
}

impl SpanRange {
    pub fn error(self, message: impl std::fmt::Display) -> syn::Error {
        let a = proc_macro2::Ident::new("start", self.start);
        let b = proc_macro2::Ident::new("end", self.end);
        syn::Error::new_spanned(quote::quote!(#a #b), message)
    }
}

/// Index of a node; ids grow in creation order, so children have smaller ids than parents.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct NodeId(u32);

impl NodeId {
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// Elementary functions of one real argument.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Func {
    Sin,
    Cos,
    Tan,
    Asin,
    Acos,
    Atan,
    Sinh,
    Cosh,
    Tanh,
    Exp,
    Ln,
    Log10,
    Sqrt,
    Cbrt,
    Abs,
    Signum,
}

impl Func {
    /// Whether f(0) = 0 (and so f of a zero is zero).
    pub fn odd_through_zero(self) -> bool {
        matches!(
            self,
            Func::Sin
                | Func::Tan
                | Func::Asin
                | Func::Atan
                | Func::Sinh
                | Func::Tanh
                | Func::Sqrt
                | Func::Cbrt
                | Func::Abs
                | Func::Signum
        )
    }

    pub fn apply(self, x: f64) -> f64 {
        match self {
            Func::Sin => x.sin(),
            Func::Cos => x.cos(),
            Func::Tan => x.tan(),
            Func::Asin => x.asin(),
            Func::Acos => x.acos(),
            Func::Atan => x.atan(),
            Func::Sinh => x.sinh(),
            Func::Cosh => x.cosh(),
            Func::Tanh => x.tanh(),
            Func::Exp => x.exp(),
            Func::Ln => x.ln(),
            Func::Log10 => x.log10(),
            Func::Sqrt => x.sqrt(),
            Func::Cbrt => x.cbrt(),
            Func::Abs => x.abs(),
            Func::Signum => x.signum(),
        }
    }

    /// The `f64` method that computes this function.
    pub fn method_name(self) -> &'static str {
        match self {
            Func::Sin => "sin",
            Func::Cos => "cos",
            Func::Tan => "tan",
            Func::Asin => "asin",
            Func::Acos => "acos",
            Func::Atan => "atan",
            Func::Sinh => "sinh",
            Func::Cosh => "cosh",
            Func::Tanh => "tanh",
            Func::Exp => "exp",
            Func::Ln => "ln",
            Func::Log10 => "log10",
            Func::Sqrt => "sqrt",
            Func::Cbrt => "cbrt",
            Func::Abs => "abs",
            Func::Signum => "signum",
        }
    }
}

/// Elementary functions of two real arguments, in `f64` method order (`a.atan2(b)`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Func2 {
    Powf,
    Atan2,
    Hypot,
}

impl Func2 {
    pub fn apply(self, a: f64, b: f64) -> f64 {
        match self {
            Func2::Powf => a.powf(b),
            Func2::Atan2 => a.atan2(b),
            Func2::Hypot => a.hypot(b),
        }
    }

    pub fn method_name(self) -> &'static str {
        match self {
            Func2::Powf => "powf",
            Func2::Atan2 => "atan2",
            Func2::Hypot => "hypot",
        }
    }
}

/// Comparison operators on reals.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Cmp {
    Lt,
    Le,
    Gt,
    Ge,
    Eq,
    Ne,
}

impl Cmp {
    pub fn apply(self, a: f64, b: f64) -> bool {
        match self {
            Cmp::Lt => a < b,
            Cmp::Le => a <= b,
            Cmp::Gt => a > b,
            Cmp::Ge => a >= b,
            Cmp::Eq => a == b,
            Cmp::Ne => a != b,
        }
    }
}

/// One node. Real constants are stored by their bit pattern so that they can be hashed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Node {
    Const(u64),
    /// An input slot: an argument element, a parameter, a seed direction... The caller that
    /// created the slot knows what it stands for; the graph only knows its number.
    Input(u32),
    Neg(NodeId),
    Add(NodeId, NodeId),
    Sub(NodeId, NodeId),
    Mul(NodeId, NodeId),
    Div(NodeId, NodeId),
    Unary(Func, NodeId),
    Powi(NodeId, i32),
    Binary(Func2, NodeId, NodeId),
    /// `if cond { then } else { otherwise }`, all three evaluated (branch-free).
    Select(NodeId, NodeId, NodeId),
    // Boolean-valued nodes.
    Bool(bool),
    Compare(Cmp, NodeId, NodeId),
    And(NodeId, NodeId),
    Or(NodeId, NodeId),
    Not(NodeId),
}

impl Node {
    pub fn is_bool(&self) -> bool {
        matches!(
            self,
            Node::Bool(_) | Node::Compare(..) | Node::And(..) | Node::Or(..) | Node::Not(_)
        )
    }

    /// The nodes this node reads, in operand order.
    pub fn operands(&self) -> Operands {
        match *self {
            Node::Const(_) | Node::Input(_) | Node::Bool(_) => Operands::new(&[]),
            Node::Neg(a) | Node::Unary(_, a) | Node::Powi(a, _) | Node::Not(a) => {
                Operands::new(&[a])
            }
            Node::Add(a, b)
            | Node::Sub(a, b)
            | Node::Mul(a, b)
            | Node::Div(a, b)
            | Node::Binary(_, a, b)
            | Node::Compare(_, a, b)
            | Node::And(a, b)
            | Node::Or(a, b) => Operands::new(&[a, b]),
            Node::Select(c, a, b) => Operands::new(&[c, a, b]),
        }
    }
}

/// Up to three operands without allocating.
#[derive(Clone, Copy)]
pub struct Operands {
    ids: [NodeId; 3],
    len: usize,
}

impl Operands {
    fn new(ids: &[NodeId]) -> Self {
        let mut all = [NodeId(0); 3];
        all[..ids.len()].copy_from_slice(ids);
        Operands {
            ids: all,
            len: ids.len(),
        }
    }

    pub fn as_slice(&self) -> &[NodeId] {
        &self.ids[..self.len]
    }
}

/// Ceiling on the graph size: unrolling a loop with a huge bound must end in an error that
/// names the problem, not in an exhausted machine.
pub const MAX_NODES: usize = 2_000_000;

#[derive(Default)]
pub struct Graph {
    nodes: Vec<Node>,
    spans: Vec<Option<SpanRange>>,
    interned: HashMap<Node, NodeId>,
    input_labels: Vec<String>,
}

impl Graph {
    pub fn new() -> Self {
        Self::default()
    }

    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// The node with this index (`0..len()`).
    pub(super) fn id_at(&self, index: usize) -> NodeId {
        NodeId(index as u32)
    }

    pub fn node(&self, id: NodeId) -> Node {
        self.nodes[id.index()]
    }

    /// The source of the expression that first created this node, if any.
    pub fn span(&self, id: NodeId) -> Option<SpanRange> {
        self.spans[id.index()]
    }

    /// Record where a node came from (the first span recorded wins).
    pub fn note_span(&mut self, id: NodeId, span: SpanRange) {
        let slot = &mut self.spans[id.index()];
        if slot.is_none() {
            *slot = Some(span);
        }
    }

    pub fn too_large(&self) -> bool {
        self.nodes.len() > MAX_NODES
    }

    pub fn input_label(&self, slot: u32) -> &str {
        &self.input_labels[slot as usize]
    }

    pub fn input_count(&self) -> usize {
        self.input_labels.len()
    }

    #[cfg(test)]
    pub fn input_slot(&self, id: NodeId) -> Option<u32> {
        match self.node(id) {
            Node::Input(slot) => Some(slot),
            _ => None,
        }
    }

    /// A new, distinct input. `label` is for debugging and generated comments only.
    pub fn new_input(&mut self, label: impl Into<String>) -> NodeId {
        let slot = self.input_labels.len() as u32;
        self.input_labels.push(label.into());
        self.intern(Node::Input(slot))
    }

    pub fn constant(&mut self, value: f64) -> NodeId {
        self.intern(Node::Const(value.to_bits()))
    }

    pub fn const_value(&self, id: NodeId) -> Option<f64> {
        match self.node(id) {
            Node::Const(bits) => Some(f64::from_bits(bits)),
            _ => None,
        }
    }

    pub fn is_const(&self, id: NodeId, value: f64) -> bool {
        self.const_value(id) == Some(value)
    }

    pub fn is_zero(&self, id: NodeId) -> bool {
        self.is_const(id, 0.0)
    }

    pub fn zero(&mut self) -> NodeId {
        self.constant(0.0)
    }

    pub fn one(&mut self) -> NodeId {
        self.constant(1.0)
    }

    pub fn boolean(&mut self, value: bool) -> NodeId {
        self.intern(Node::Bool(value))
    }

    pub fn bool_value(&self, id: NodeId) -> Option<bool> {
        match self.node(id) {
            Node::Bool(b) => Some(b),
            _ => None,
        }
    }

    pub(super) fn intern(&mut self, node: Node) -> NodeId {
        if let Some(&id) = self.interned.get(&node) {
            return id;
        }
        let id = NodeId(self.nodes.len() as u32);
        self.nodes.push(node);
        self.spans.push(None);
        self.interned.insert(node, id);
        id
    }

    /// Operands of commutative operations in a canonical order, so `a*b` and `b*a` meet.
    fn ordered(a: NodeId, b: NodeId) -> (NodeId, NodeId) {
        if a <= b { (a, b) } else { (b, a) }
    }

    pub fn neg(&mut self, a: NodeId) -> NodeId {
        match self.node(a) {
            Node::Const(bits) => self.constant(-f64::from_bits(bits)),
            Node::Neg(inner) => inner,
            Node::Sub(x, y) => self.sub(y, x),
            // A product with a constant in front takes the sign into its constant.
            Node::Mul(k, x) if self.const_value(k).is_some() => {
                let c = -self.const_value(k).unwrap_or(1.0);
                self.scale_by(c, x)
            }
            _ => self.intern(Node::Neg(a)),
        }
    }

    pub fn add(&mut self, a: NodeId, b: NodeId) -> NodeId {
        if let (Some(x), Some(y)) = (self.const_value(a), self.const_value(b)) {
            return self.constant(x + y);
        }
        if self.is_zero(a) {
            return b;
        }
        if self.is_zero(b) {
            return a;
        }
        if let Some(normal) = self.normal_sum(a, b, 1.0) {
            return normal;
        }
        if let Some(factored) = self.common_factor(a, b, false) {
            return factored;
        }
        if let Node::Neg(y) = self.node(b) {
            return self.intern(Node::Sub(a, y));
        }
        // a + (−k)·y is a − k·y.
        if let Some((k, y)) = self.leading_constant(b)
            && k < 0.0
        {
            let positive = self.scale_by(-k, y);
            return self.intern(Node::Sub(a, positive));
        }
        if let Node::Neg(x) = self.node(a) {
            return self.intern(Node::Sub(b, x));
        }
        let (a, b) = Self::ordered(a, b);
        self.intern(Node::Add(a, b))
    }

    pub fn sub(&mut self, a: NodeId, b: NodeId) -> NodeId {
        if let (Some(x), Some(y)) = (self.const_value(a), self.const_value(b)) {
            return self.constant(x - y);
        }
        if self.is_zero(b) {
            return a;
        }
        if self.is_zero(a) {
            return self.neg(b);
        }
        if a == b {
            return self.zero();
        }
        if let Some(normal) = self.normal_sum(a, b, -1.0) {
            return normal;
        }
        if let Some(factored) = self.common_factor(a, b, true) {
            return factored;
        }
        if let Node::Neg(y) = self.node(b) {
            let (a, y) = Self::ordered(a, y);
            return self.intern(Node::Add(a, y));
        }
        self.intern(Node::Sub(a, b))
    }

    pub fn mul(&mut self, a: NodeId, b: NodeId) -> NodeId {
        if let (Some(x), Some(y)) = (self.const_value(a), self.const_value(b)) {
            return self.constant(x * y);
        }
        // x·0 = 0 is the usual AD convention: it drops the IEEE subtlety 0·∞ = NaN, which
        // would otherwise turn every structurally zero derivative into live code.
        if self.is_zero(a) || self.is_zero(b) {
            return self.zero();
        }
        if self.is_const(a, 1.0) {
            return b;
        }
        if self.is_const(b, 1.0) {
            return a;
        }
        if self.is_const(a, -1.0) {
            return self.neg(b);
        }
        if self.is_const(b, -1.0) {
            return self.neg(a);
        }
        // Pull negations out so that −x·y and x·(−y) share one node.
        match (self.node(a), self.node(b)) {
            (Node::Neg(x), Node::Neg(y)) => return self.mul(x, y),
            (Node::Neg(x), _) => {
                let p = self.mul(x, b);
                return self.neg(p);
            }
            (_, Node::Neg(y)) => {
                let p = self.mul(a, y);
                return self.neg(p);
            }
            _ => {}
        }
        // Constants in front, folded together: 2·(0.5·x) is x, and x·(2·y) is 2·(x·y).
        if let Some(c) = self.const_value(b) {
            return self.scale_by(c, a);
        }
        if let Some(c) = self.const_value(a) {
            return self.scale_by(c, b);
        }
        if let Some(c) = self.cancelled_product(a, b, false) {
            return c;
        }
        if let Some((k, y)) = self.leading_constant(b) {
            let p = self.mul(a, y);
            return self.scale_by(k, p);
        }
        if let Some((k, x)) = self.leading_constant(a) {
            let p = self.mul(x, b);
            return self.scale_by(k, p);
        }
        let (a, b) = Self::ordered(a, b);
        self.intern(Node::Mul(a, b))
    }

    /// `(k, y)` when `x` is `k·y` with a constant `k`.
    fn leading_constant(&self, x: NodeId) -> Option<(f64, NodeId)> {
        match self.node(x) {
            Node::Mul(k, y) => self.const_value(k).map(|kv| (kv, y)),
            _ => None,
        }
    }

    /// k·x ± k·y as k·(x ± y): one multiplication instead of two.
    fn common_factor(&mut self, a: NodeId, b: NodeId, subtract: bool) -> Option<NodeId> {
        let (ka, x) = self.leading_constant(a)?;
        let (kb, y) = self.leading_constant(b)?;
        if ka != kb {
            return None;
        }
        let inner = if subtract {
            self.sub(x, y)
        } else {
            self.add(x, y)
        };
        Some(self.scale_by(ka, inner))
    }

    /// c·x with the constant in front, merged with a constant already in front of x.
    fn scale_by(&mut self, c: f64, x: NodeId) -> NodeId {
        if let Node::Mul(k, y) = self.node(x)
            && let Some(kv) = self.const_value(k)
        {
            let product = c * kv;
            let k = self.constant(product);
            return self.mul(k, y);
        }
        let k = self.constant(c);
        self.intern(Node::Mul(k, x))
    }

    pub fn div(&mut self, a: NodeId, b: NodeId) -> NodeId {
        if let (Some(x), Some(y)) = (self.const_value(a), self.const_value(b)) {
            return self.constant(x / y);
        }
        if self.is_zero(a) {
            return self.zero();
        }
        if self.is_const(b, 1.0) {
            return a;
        }
        if self.is_const(b, -1.0) {
            return self.neg(a);
        }
        match (self.node(a), self.node(b)) {
            (Node::Neg(x), Node::Neg(y)) => return self.div(x, y),
            (Node::Neg(x), _) => {
                let q = self.div(x, b);
                return self.neg(q);
            }
            (_, Node::Neg(y)) => {
                let q = self.div(a, y);
                return self.neg(q);
            }
            _ => {}
        }
        if let Some(c) = self.cancelled_product(a, b, true) {
            return c;
        }
        // A constant in the numerator goes in front, as in products: 0.5·b/r and −0.5·b/r
        // are then multiples of one node b/r.
        if let Some((k, x)) = self.leading_constant(a) {
            let q = self.div(x, b);
            return self.scale_by(k, q);
        }
        self.intern(Node::Div(a, b))
    }

    pub fn unary(&mut self, f: Func, a: NodeId) -> NodeId {
        if let Some(x) = self.const_value(a) {
            return self.constant(f.apply(x));
        }
        match (f, self.node(a)) {
            // Odd and even symmetries keep negations outside, where `mul` can cancel them.
            (
                Func::Sin | Func::Tan | Func::Asin | Func::Atan | Func::Sinh | Func::Tanh,
                Node::Neg(x),
            )
            | (Func::Cbrt, Node::Neg(x)) => {
                let inner = self.unary(f, x);
                self.neg(inner)
            }
            (Func::Cos | Func::Cosh | Func::Abs, Node::Neg(x)) => self.unary(f, x),
            (Func::Abs, Node::Unary(Func::Abs, _)) => a,
            _ => self.intern(Node::Unary(f, a)),
        }
    }

    pub fn powi(&mut self, a: NodeId, n: i32) -> NodeId {
        if let Some(x) = self.const_value(a) {
            return self.constant(x.powi(n));
        }
        match n {
            0 => self.one(),
            1 => a,
            -1 => {
                let one = self.one();
                self.div(one, a)
            }
            _ => self.intern(Node::Powi(a, n)),
        }
    }

    pub fn binary(&mut self, f: Func2, a: NodeId, b: NodeId) -> NodeId {
        if let (Some(x), Some(y)) = (self.const_value(a), self.const_value(b)) {
            return self.constant(f.apply(x, y));
        }
        if f == Func2::Powf
            && let Some(y) = self.const_value(b)
        {
            if y == 1.0 {
                return a;
            }
            if y == 0.0 {
                return self.one();
            }
        }
        self.intern(Node::Binary(f, a, b))
    }

    pub fn select(&mut self, cond: NodeId, then: NodeId, otherwise: NodeId) -> NodeId {
        if let Some(c) = self.bool_value(cond) {
            return if c { then } else { otherwise };
        }
        if then == otherwise {
            return then;
        }
        self.intern(Node::Select(cond, then, otherwise))
    }

    pub fn compare(&mut self, op: Cmp, a: NodeId, b: NodeId) -> NodeId {
        if let (Some(x), Some(y)) = (self.const_value(a), self.const_value(b)) {
            return self.boolean(op.apply(x, y));
        }
        self.intern(Node::Compare(op, a, b))
    }

    pub fn and(&mut self, a: NodeId, b: NodeId) -> NodeId {
        match (self.bool_value(a), self.bool_value(b)) {
            (Some(false), _) | (_, Some(false)) => self.boolean(false),
            (Some(true), _) => b,
            (_, Some(true)) => a,
            _ if a == b => a,
            _ => {
                let (a, b) = Self::ordered(a, b);
                self.intern(Node::And(a, b))
            }
        }
    }

    pub fn or(&mut self, a: NodeId, b: NodeId) -> NodeId {
        match (self.bool_value(a), self.bool_value(b)) {
            (Some(true), _) | (_, Some(true)) => self.boolean(true),
            (Some(false), _) => b,
            (_, Some(false)) => a,
            _ if a == b => a,
            _ => {
                let (a, b) = Self::ordered(a, b);
                self.intern(Node::Or(a, b))
            }
        }
    }

    pub fn not(&mut self, a: NodeId) -> NodeId {
        match self.node(a) {
            Node::Bool(b) => self.boolean(!b),
            Node::Not(inner) => inner,
            _ => self.intern(Node::Not(a)),
        }
    }

    /// Sum of many terms, added pairwise so that the dependency chain stays short.
    pub fn sum(&mut self, terms: &[NodeId]) -> NodeId {
        match terms {
            [] => self.zero(),
            [only] => *only,
            _ => {
                let (left, right) = terms.split_at(terms.len() / 2);
                let l = self.sum(left);
                let r = self.sum(right);
                self.add(l, r)
            }
        }
    }

    /// Rebuild the cone of `roots` with some inputs replaced by other nodes. Simplification
    /// runs again on the way, so substituting zeros prunes the terms they multiply.
    pub fn substitute(
        &mut self,
        roots: &[NodeId],
        replace: &HashMap<NodeId, NodeId>,
    ) -> Vec<NodeId> {
        let live = self.live_set(roots);
        let mut image: HashMap<NodeId, NodeId> = HashMap::default();
        for id in live {
            let new = if let Some(&r) = replace.get(&id) {
                r
            } else {
                let m = |x: NodeId| image[&x];
                match self.node(id) {
                    Node::Const(_) | Node::Input(_) | Node::Bool(_) => id,
                    Node::Neg(a) => self.neg(m(a)),
                    Node::Add(a, b) => self.add(m(a), m(b)),
                    Node::Sub(a, b) => self.sub(m(a), m(b)),
                    Node::Mul(a, b) => self.mul(m(a), m(b)),
                    Node::Div(a, b) => self.div(m(a), m(b)),
                    Node::Unary(f, a) => self.unary(f, m(a)),
                    Node::Powi(a, n) => self.powi(m(a), n),
                    Node::Binary(f, a, b) => self.binary(f, m(a), m(b)),
                    Node::Select(c, a, b) => self.select(m(c), m(a), m(b)),
                    Node::Compare(op, a, b) => self.compare(op, m(a), m(b)),
                    Node::And(a, b) => self.and(m(a), m(b)),
                    Node::Or(a, b) => self.or(m(a), m(b)),
                    Node::Not(a) => self.not(m(a)),
                }
            };
            if let Some(span) = self.span(id) {
                self.note_span(new, span);
            }
            image.insert(id, new);
        }
        roots.iter().map(|r| image[r]).collect()
    }

    /// Every node reachable from `roots`, in increasing id order (a topological order).
    /// Beyond clearing one flag per node, the cost is that of the cone, not of the graph:
    /// the macro asks for many small cones of a graph of up to millions of nodes.
    pub fn live_set(&self, roots: &[NodeId]) -> Vec<NodeId> {
        self.live_set_until(roots, |_| false)
    }

    /// [`Self::live_set`], not looking below the nodes where `stop` holds (they are in it).
    pub fn live_set_until(&self, roots: &[NodeId], stop: impl Fn(NodeId) -> bool) -> Vec<NodeId> {
        let mut seen = vec![false; self.nodes.len()];
        let mut live = Vec::new();
        let mut stack: Vec<NodeId> = roots.to_vec();
        while let Some(id) = stack.pop() {
            if !std::mem::replace(&mut seen[id.index()], true) {
                live.push(id);
                if !stop(id) {
                    stack.extend_from_slice(self.node(id).operands().as_slice());
                }
            }
        }
        live.sort_unstable();
        live
    }

    /// For every node, whether it depends on any of the given input nodes.
    pub fn depends_on(&self, inputs: &[NodeId]) -> Vec<bool> {
        let mut active = vec![false; self.nodes.len()];
        for &i in inputs {
            active[i.index()] = true;
        }
        for (i, node) in self.nodes.iter().enumerate() {
            if !active[i] {
                active[i] = node.operands().as_slice().iter().any(|o| active[o.index()]);
            }
        }
        active
    }

    /// Which nodes are zero whenever every node of `zero` (inputs) is, whatever the other
    /// inputs: a sound, incomplete reading of the expressions (a product with a zero factor, a
    /// sum or select of zeros, an odd function of zero, a quotient of zero), in one forward
    /// pass (operands come before their users), no recursion however deep the graph. A
    /// quotient by zero, or a product with an infinite factor, would make the value NaN; the
    /// generated code's checks report those where it computes them.
    pub fn vanishes_with(&self, zero: &[NodeId]) -> Vec<bool> {
        let mut vanishes = vec![false; self.nodes.len()];
        for &i in zero {
            vanishes[i.index()] = true;
        }
        for (i, node) in self.nodes.iter().enumerate() {
            let z = |x: NodeId| vanishes[x.index()];
            vanishes[i] = vanishes[i]
                || match *node {
                    Node::Const(bits) => f64::from_bits(bits) == 0.0,
                    Node::Neg(a) => z(a),
                    Node::Add(a, b) | Node::Sub(a, b) => z(a) && z(b),
                    Node::Mul(a, b) => z(a) || z(b),
                    Node::Div(a, _) => z(a),
                    Node::Powi(a, n) => n > 0 && z(a),
                    Node::Unary(f, a) => f.odd_through_zero() && z(a),
                    Node::Select(_, a, b) => z(a) && z(b),
                    _ => false,
                };
        }
        vanishes
    }

    /// Evaluate every node below `roots` for given input values (indexed by slot). Booleans
    /// evaluate to 1.0 / 0.0. An interpreter for tests and for the macro's own sanity checks
    /// of a model (a closed-form inverse is checked at sample points); simulations run the
    /// emitted Rust, never this.
    pub fn evaluate(&self, roots: &[NodeId], inputs: &[f64]) -> Vec<f64> {
        let mut value = vec![f64::NAN; self.nodes.len()];
        for id in self.live_set(roots) {
            let v = |x: NodeId| value[x.index()];
            let b = |x: f64| if x != 0.0 { 1.0 } else { 0.0 };
            value[id.index()] = match self.node(id) {
                Node::Const(bits) => f64::from_bits(bits),
                Node::Input(slot) => inputs.get(slot as usize).copied().unwrap_or(f64::NAN),
                Node::Neg(a) => -v(a),
                Node::Add(a, c) => v(a) + v(c),
                Node::Sub(a, c) => v(a) - v(c),
                Node::Mul(a, c) => v(a) * v(c),
                Node::Div(a, c) => v(a) / v(c),
                Node::Unary(f, a) => f.apply(v(a)),
                Node::Powi(a, n) => v(a).powi(n),
                Node::Binary(f, a, c) => f.apply(v(a), v(c)),
                Node::Select(c, a, e) => {
                    if v(c) != 0.0 {
                        v(a)
                    } else {
                        v(e)
                    }
                }
                Node::Bool(x) => b(if x { 1.0 } else { 0.0 }),
                Node::Compare(op, a, c) => b(if op.apply(v(a), v(c)) { 1.0 } else { 0.0 }),
                Node::And(a, c) => b(v(a) * v(c)),
                Node::Or(a, c) => b(v(a) + v(c)),
                Node::Not(a) => b(if v(a) != 0.0 { 0.0 } else { 1.0 }),
            };
        }
        roots.iter().map(|r| value[r.index()]).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn common_subexpressions_are_shared() {
        let mut g = Graph::new();
        let x = g.new_input("x");
        let y = g.new_input("y");
        let a = g.mul(x, y);
        let b = g.mul(y, x);
        assert_eq!(a, b);
        let s1 = g.unary(Func::Sin, a);
        let s2 = g.unary(Func::Sin, b);
        assert_eq!(s1, s2);
    }

    #[test]
    fn identities_simplify() {
        let mut g = Graph::new();
        let x = g.new_input("x");
        let zero = g.zero();
        let one = g.one();
        assert_eq!(g.mul(x, zero), zero);
        assert_eq!(g.mul(one, x), x);
        assert_eq!(g.add(x, zero), x);
        assert_eq!(g.sub(x, zero), x);
        let n = g.neg(x);
        assert_eq!(g.neg(n), x);
        assert_eq!(g.sub(x, x), zero);
        assert_eq!(g.div(x, one), x);
        assert_eq!(g.powi(x, 1), x);
        assert_eq!(g.powi(x, 0), one);
        // x + (−y) becomes x − y
        let y = g.new_input("y");
        let ny = g.neg(y);
        let s = g.add(x, ny);
        assert_eq!(g.node(s), Node::Sub(x, y));
    }

    #[test]
    fn constants_fold() {
        let mut g = Graph::new();
        let two = g.constant(2.0);
        let three = g.constant(3.0);
        let p = g.mul(two, three);
        assert_eq!(g.const_value(p), Some(6.0));
        let s = g.unary(Func::Sqrt, p);
        assert_eq!(g.const_value(s), Some(6f64.sqrt()));
        let c = g.compare(Cmp::Lt, two, three);
        assert_eq!(g.bool_value(c), Some(true));
        let x = g.new_input("x");
        assert_eq!(g.select(c, x, two), x);
    }

    #[test]
    fn substitution_resimplifies() {
        let mut g = Graph::new();
        let x = g.new_input("x");
        let y = g.new_input("y");
        let p = g.mul(x, y);
        let s = g.unary(Func::Sin, p);
        let e = g.add(s, x);
        let zero = g.zero();
        let out = g.substitute(&[e], &[(y, zero)].into_iter().collect());
        // sin(x·0) + x = sin(0) + x = x
        assert_eq!(out[0], x);
    }

    #[test]
    fn evaluation_matches_f64() {
        let mut g = Graph::new();
        let x = g.new_input("x");
        let y = g.new_input("y");
        let a = g.binary(Func2::Atan2, y, x);
        let h = g.binary(Func2::Hypot, x, y);
        let r = g.mul(a, h);
        let v = g.evaluate(&[r], &[0.3, -1.2]);
        assert_eq!(v[0], (-1.2f64).atan2(0.3) * 0.3f64.hypot(-1.2));
    }
}
