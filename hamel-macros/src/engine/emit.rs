//! Emission: the live part of the graph as straight-line Rust.
//!
//! Every node used more than once becomes a `let`; a node used once is written inline into
//! its user, with parentheses only where Rust's precedence needs them, so the output reads
//! like hand-written code (`let v3 = m0 * v1.cos() + 2.0 * v2;`). Constants are literals and
//! inputs are the expressions the caller bound them to (`q[2]`, `self.m0`). No heap, no
//! runtime AD types, no `unsafe`.

use super::graph::{Cmp, Graph, Node, NodeId};
use crate::engine::hash::HashMap;
use proc_macro2::{Ident, Literal, Span, TokenStream};
use quote::{format_ident, quote};

/// Deepest nesting of an inlined expression before it is bound to a `let` instead.
const MAX_INLINE_DEPTH: usize = 24;
/// Above this many `let`s in a row they are bound in blocks: with full debug info, rustc's
/// code generation overflows its stack on a few thousand sequential `let`s in one function
/// (`tests/ui/tests/at_scale/long_let_sequence.rs` is the regression test).
const MAX_FLAT_LETS: usize = 512;
/// Size of those blocks.
const LETS_PER_BLOCK: usize = 64;

/// `let` statements, flat when there are few; otherwise in blocks that each bind a tuple,
/// `let (v0, v1, ..) = { let v0 = ..; let v1 = ..; (v0, v1, ..) };`, which keeps the
/// nesting of scopes shallow whatever the length.
fn bind_lets(lets: Vec<(Ident, TokenStream)>) -> TokenStream {
    if lets.len() <= MAX_FLAT_LETS {
        return lets
            .into_iter()
            .map(|(name, expr)| quote!(let #name = #expr;))
            .collect();
    }
    lets.chunks(LETS_PER_BLOCK)
        .map(|chunk| {
            let names: Vec<&Ident> = chunk.iter().map(|(n, _)| n).collect();
            let inner = chunk.iter().map(|(name, expr)| quote!(let #name = #expr;));
            quote!(let (#(#names,)*) = { #(#inner)* (#(#names,)*) };)
        })
        .collect()
}

/// The scalar type the emitted code computes in.
#[derive(Clone)]
pub enum Scalar {
    /// Plain `f64`.
    F64,
    /// A type parameter bounded by `hamel::Scalar`, e.g. a dual number: constants are
    /// converted with `Scalar::from_f64`; everything else reads the same as for `f64`.
    Generic(Ident),
}

/// Binding strength of an emitted expression; an operand weaker than its position requires
/// gets parentheses.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Prec {
    Select,
    Or,
    And,
    Compare,
    Sum,
    Product,
    Prefix,
    Atom,
}

/// Straight-line code computing some nodes: `stmts` followed by uses of `value(root)`.
pub struct Code {
    pub stmts: TokenStream,
    refs: HashMap<NodeId, (TokenStream, Prec)>,
}

impl Code {
    /// The expression for a root (a local, a literal or an input expression).
    pub fn value(&self, id: NodeId) -> TokenStream {
        match self.refs.get(&id) {
            Some((tokens, _)) => tokens.clone(),
            None => quote!(::core::compile_error!(
                "hamel internal error: a root was not emitted"
            )),
        }
    }
}

pub struct Emitter<'g> {
    graph: &'g Graph,
    scalar: Scalar,
    inputs: HashMap<NodeId, TokenStream>,
    prefix: String,
}

impl<'g> Emitter<'g> {
    pub fn new(graph: &'g Graph, scalar: Scalar) -> Self {
        Emitter {
            graph,
            scalar,
            inputs: HashMap::default(),
            prefix: "v".into(),
        }
    }

    /// The expression an input node reads; or that an operation node reads instead of
    /// being computed (a value prepared beforehand).
    pub fn bind(&mut self, input: NodeId, tokens: TokenStream) {
        self.inputs.insert(input, tokens);
    }

    /// Straight-line code for `roots`. An input without a binding is an internal error,
    /// reported (never a panic).
    pub fn emit(&self, roots: &[NodeId]) -> syn::Result<Code> {
        let mut stages = self.emit_stages(&[roots])?;
        stages
            .pop()
            .ok_or_else(|| syn::Error::new(Span::call_site(), "hamel internal error: no stage"))
    }

    /// Code in stages, run in order with other code in between (a numeric factorization):
    /// each stage computes what its roots need and was not computed before; a value one
    /// stage computes and a later one uses is kept in a `let`.
    pub fn emit_stages(&self, stages: &[&[NodeId]]) -> syn::Result<Vec<Code>> {
        let g = self.graph;
        let all_roots: Vec<NodeId> = stages.iter().flat_map(|s| s.iter().copied()).collect();
        let mut uses: HashMap<NodeId, usize> = HashMap::default();
        for id in self.cone(&all_roots) {
            for &operand in g.node(id).operands().as_slice() {
                *uses.entry(operand).or_default() += 1;
            }
        }
        for &r in &all_roots {
            *uses.entry(r).or_default() += 2;
        }
        let mut refs: HashMap<NodeId, (TokenStream, Prec)> = HashMap::default();
        // How deeply each inlined expression nests: rustc's parser overflows on expressions
        // thousands of levels deep, so past a bound a single-use node gets a `let` anyway.
        let mut depth: HashMap<NodeId, usize> = HashMap::default();
        let mut counter = 0usize;
        let mut out = Vec::with_capacity(stages.len());
        for roots in stages {
            let mut lets: Vec<(Ident, TokenStream)> = Vec::new();
            for id in self.cone(roots) {
                if refs.contains_key(&id) {
                    continue;
                }
                let node = g.node(id);
                let bound = self.inputs.get(&id);
                let (expr, prec) = match node {
                    _ if bound.is_some() => (bound.cloned().unwrap_or_default(), Prec::Atom),
                    Node::Const(bits) => self.constant(f64::from_bits(bits)),
                    Node::Bool(b) => (quote!(#b), Prec::Atom),
                    Node::Input(slot) => match self.inputs.get(&id) {
                        Some(tokens) => (tokens.clone(), Prec::Atom),
                        None => {
                            return Err(syn::Error::new(
                                Span::call_site(),
                                format!(
                                    "hamel internal error: input `{}` has no binding; please report this",
                                    g.input_label(slot)
                                ),
                            ));
                        }
                    },
                    _ => self.operation(node, &refs),
                };
                let trivial = bound.is_some()
                    || matches!(node, Node::Const(_) | Node::Bool(_) | Node::Input(_));
                let nesting = if trivial {
                    0
                } else {
                    1 + node
                        .operands()
                        .as_slice()
                        .iter()
                        .map(|o| depth.get(o).copied().unwrap_or(0))
                        .max()
                        .unwrap_or(0)
                };
                let single_use = uses.get(&id).copied().unwrap_or(0) <= 1;
                if trivial || (single_use && nesting <= MAX_INLINE_DEPTH) {
                    refs.insert(id, (expr, prec));
                    depth.insert(id, nesting);
                } else {
                    let name = format_ident!("{}{}", self.prefix, counter);
                    counter += 1;
                    lets.push((name.clone(), expr));
                    refs.insert(id, (quote!(#name), Prec::Atom));
                    depth.insert(id, 0);
                }
            }
            out.push(Code {
                stmts: bind_lets(lets),
                refs: refs.clone(),
            });
        }
        Ok(out)
    }

    /// The nodes `roots` need, in topological order, not looking below a bound node: an
    /// operation bound to an expression (a value computed beforehand) is read, not rebuilt.
    fn cone(&self, roots: &[NodeId]) -> Vec<NodeId> {
        self.graph
            .live_set_until(roots, |id| self.inputs.contains_key(&id))
    }

    /// `y` when `id` is 1/y written inline (used once, so not bound to a `let`).
    fn inlined_reciprocal(
        &self,
        id: NodeId,
        refs: &HashMap<NodeId, (TokenStream, Prec)>,
    ) -> Option<NodeId> {
        match self.graph.node(id) {
            Node::Div(one, y)
                if self.graph.is_const(one, 1.0)
                    && !self.inputs.contains_key(&id)
                    && refs.get(&id).is_some_and(|(_, prec)| *prec != Prec::Atom) =>
            {
                Some(y)
            }
            _ => None,
        }
    }

    fn constant(&self, v: f64) -> (TokenStream, Prec) {
        let magnitude = if v.is_nan() {
            quote!(f64::NAN)
        } else if v.is_infinite() {
            quote!(f64::INFINITY)
        } else {
            let lit = Literal::f64_unsuffixed(v.abs());
            quote!(#lit)
        };
        let negative = v.is_sign_negative() && !v.is_nan();
        let scalar = match (&self.scalar, negative) {
            (Scalar::F64, false) => return (magnitude, Prec::Atom),
            (Scalar::F64, true) => return (quote!(-#magnitude), Prec::Prefix),
            (Scalar::Generic(s), false) => quote!(<#s as ::hamel::Scalar>::from_f64(#magnitude)),
            (Scalar::Generic(s), true) => quote!(<#s as ::hamel::Scalar>::from_f64(-#magnitude)),
        };
        (scalar, Prec::Atom)
    }

    fn operation(
        &self,
        node: Node,
        refs: &HashMap<NodeId, (TokenStream, Prec)>,
    ) -> (TokenStream, Prec) {
        // An operand, parenthesized if it binds weaker than `need`.
        let at = |id: NodeId, need: Prec| -> TokenStream {
            match refs.get(&id) {
                Some((tokens, prec)) if *prec >= need => tokens.clone(),
                Some((tokens, _)) => quote!((#tokens)),
                None => quote!(::core::compile_error!(
                    "hamel internal error: operand emitted out of order"
                )),
            }
        };
        // A method receiver must have a known type: `2.0.powf(x)` does not compile, `2f64.powf(x)` does.
        let receiver = |id: NodeId| -> TokenStream {
            match (self.graph.node(id), &self.scalar) {
                (Node::Const(bits), Scalar::F64) if f64::from_bits(bits).is_finite() => {
                    let v = f64::from_bits(bits);
                    let lit = Literal::f64_suffixed(v.abs());
                    if v.is_sign_negative() {
                        quote!((-#lit))
                    } else {
                        quote!(#lit)
                    }
                }
                _ => at(id, Prec::Atom),
            }
        };
        match node {
            Node::Neg(a) => {
                let a = at(a, Prec::Prefix);
                (quote!(-#a), Prec::Prefix)
            }
            Node::Add(a, b) => {
                let (a, b) = (at(a, Prec::Sum), at(b, Prec::Product));
                (quote!(#a + #b), Prec::Sum)
            }
            Node::Sub(a, b) => {
                let (a, b) = (at(a, Prec::Sum), at(b, Prec::Product));
                (quote!(#a - #b), Prec::Sum)
            }
            Node::Mul(a, b) => {
                // x·(1/y) with 1/y used nowhere else is x/y: one division, no product.
                if let Some(y) = self.inlined_reciprocal(b, refs) {
                    let (a, y) = (at(a, Prec::Product), at(y, Prec::Prefix));
                    return (quote!(#a / #y), Prec::Product);
                }
                if let Some(y) = self.inlined_reciprocal(a, refs) {
                    let (b, y) = (at(b, Prec::Product), at(y, Prec::Prefix));
                    return (quote!(#b / #y), Prec::Product);
                }
                let (a, b) = (at(a, Prec::Product), at(b, Prec::Prefix));
                (quote!(#a * #b), Prec::Product)
            }
            Node::Div(a, b) => {
                let (a, b) = (at(a, Prec::Product), at(b, Prec::Prefix));
                (quote!(#a / #b), Prec::Product)
            }
            Node::Unary(f, a) => {
                let a = receiver(a);
                let m = format_ident!("{}", f.method_name());
                (quote!(#a.#m()), Prec::Atom)
            }
            Node::Powi(a, n) => {
                let a = receiver(a);
                let n = Literal::i32_unsuffixed(n);
                (quote!(#a.powi(#n)), Prec::Atom)
            }
            Node::Binary(f, a, b) => {
                let (a, b) = (receiver(a), at(b, Prec::Select));
                let m = format_ident!("{}", f.method_name());
                (quote!(#a.#m(#b)), Prec::Atom)
            }
            Node::Select(c, a, b) => {
                let (c, a, b) = (
                    at(c, Prec::Select),
                    at(a, Prec::Select),
                    at(b, Prec::Select),
                );
                (quote!(if #c { #a } else { #b }), Prec::Select)
            }
            Node::Compare(op, a, b) => {
                let (a, b) = (at(a, Prec::Sum), at(b, Prec::Sum));
                let op = match op {
                    Cmp::Lt => quote!(<),
                    Cmp::Le => quote!(<=),
                    Cmp::Gt => quote!(>),
                    Cmp::Ge => quote!(>=),
                    Cmp::Eq => quote!(==),
                    Cmp::Ne => quote!(!=),
                };
                (quote!(#a #op #b), Prec::Compare)
            }
            Node::And(a, b) => {
                let (a, b) = (at(a, Prec::And), at(b, Prec::Compare));
                (quote!(#a && #b), Prec::And)
            }
            Node::Or(a, b) => {
                let (a, b) = (at(a, Prec::Or), at(b, Prec::And));
                (quote!(#a || #b), Prec::Or)
            }
            Node::Not(a) => {
                let a = at(a, Prec::Prefix);
                (quote!(!#a), Prec::Prefix)
            }
            Node::Const(_) | Node::Input(_) | Node::Bool(_) => (
                quote!(::core::compile_error!(
                    "hamel internal error: leaf emitted as operation"
                )),
                Prec::Atom,
            ),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::engine::graph::Func;

    #[test]
    fn shared_nodes_become_lets_and_single_uses_inline() {
        let mut g = Graph::new();
        let x = g.new_input("x");
        let y = g.new_input("y");
        let s = g.unary(Func::Sin, x); // used twice
        let a = g.mul(s, y);
        let b = g.add(s, a);
        let two = g.constant(2.0);
        let c = g.sub(b, two);
        let mut e = Emitter::new(&g, Scalar::F64);
        e.bind(x, quote!(q[0]));
        e.bind(y, quote!(q[1]));
        let code = e.emit(&[c]).unwrap();
        let text = format!("{} => {}", code.stmts, code.value(c));
        assert_eq!(
            text,
            "let v0 = q [0] . sin () ; let v1 = v0 + q [1] * v0 - 2.0 ; => v1"
        );
    }

    /// x·(1/y) is written x / y when 1/y is used once; shared, 1/y is one `let` and the
    /// products multiply by it.
    #[test]
    fn a_reciprocal_used_once_is_a_division() {
        let mut g = Graph::new();
        let (x, y, z) = (g.new_input("x"), g.new_input("y"), g.new_input("z"));
        let sum = g.add(y, z);
        let one = g.one();
        let reciprocal = g.div(one, sum);
        let once = g.mul(x, reciprocal);
        let mut e = Emitter::new(&g, Scalar::F64);
        for (id, t) in [(x, quote!(a)), (y, quote!(b)), (z, quote!(c))] {
            e.bind(id, t);
        }
        let code = e.emit(&[once]).unwrap();
        let text = format!("{} => {}", code.stmts, code.value(once));
        assert_eq!(text, "let v0 = a / (b + c) ; => v0");
        let twice = g.mul(z, reciprocal);
        let mut e = Emitter::new(&g, Scalar::F64);
        for (id, t) in [(x, quote!(a)), (y, quote!(b)), (z, quote!(c))] {
            e.bind(id, t);
        }
        let code = e.emit(&[once, twice]).unwrap();
        let text = format!(
            "{} => {}, {}",
            code.stmts,
            code.value(once),
            code.value(twice)
        );
        assert_eq!(
            text,
            "let v0 = 1.0 / (b + c) ; let v1 = a * v0 ; let v2 = c * v0 ; => v1, v2"
        );
    }

    #[test]
    fn precedence_is_respected() {
        let mut g = Graph::new();
        let x = g.new_input("x");
        let y = g.new_input("y");
        let z = g.new_input("z");
        let s = g.add(y, z);
        let p = g.mul(x, s); // x * (y + z)
        let d = g.sub(x, s); // x - (y + z)
        let n = g.neg(s); // -(y + z)
        let m = g.unary(Func::Cos, n); // cos(-(y+z)) folds to cos(y+z)
        let mut e = Emitter::new(&g, Scalar::F64);
        for (id, t) in [(x, quote!(a)), (y, quote!(b)), (z, quote!(c))] {
            e.bind(id, t);
        }
        let code = e.emit(&[p, d, m]).unwrap();
        let text = code.stmts.to_string();
        assert!(text.contains("a * v0"), "{text}");
        assert!(text.contains("a - v0"), "{text}");
        assert!(text.contains("v0 . cos ()"), "{text}");
    }

    #[test]
    fn unbound_input_is_an_error_not_a_panic() {
        let mut g = Graph::new();
        let x = g.new_input("x");
        let e = Emitter::new(&g, Scalar::F64);
        assert!(e.emit(&[x]).is_err());
    }
}
