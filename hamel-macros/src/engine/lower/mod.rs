//! Lowering: the body of an ordinary Rust function over `f64` becomes graph nodes.
//!
//! The lowering is an abstract interpreter of the supported subset: locals map to graph
//! values, `for` loops over constant ranges are unrolled, calls of other functions of the
//! same impl are inlined, `if` becomes a `Select` (or, when its condition is known at compile
//! time, only the taken branch is lowered). What is outside the subset is reported with the
//! span of the offending piece; lowering then continues with a poison value so that one build
//! reports every independent mistake.
//!
//! Split by job: `value.rs` (what an expression evaluates to), `env.rs` (locals and scopes),
//! `expr.rs` (expressions), `stmt.rs` (statements, loops, branches), `call.rs` (elementary
//! functions and inlined calls), `types.rs` (signatures and their shapes).

mod call;
mod env;
mod expr;
pub mod geometry;
mod rate;
mod span;
mod stmt;
mod types;
mod value;

pub use env::Env;
pub use expr::closest;
pub use rate::{RateContext, uses_rate};
pub use types::{Arg, Signature, render_type};
pub use value::{Shape, Value};

use crate::engine::graph::{Graph, NodeId};
use crate::engine::hash::{HashMap, HashSet};
use proc_macro2::TokenStream;
use quote::ToTokens;
use std::fmt::Display;

/// Ceiling on the total number of unrolled loop iterations in one expansion.
pub const MAX_UNROLLED_ITERATIONS: usize = 200_000;
/// Ceiling on the depth of inlined calls.
const MAX_CALL_DEPTH: usize = 64;

/// The functions and associated constants of the impl block being expanded: what a body may
/// call (`self.helper(..)`, `Self::helper(..)`) and read (`Self::N`).
pub struct ImplContext<'a> {
    fns: HashMap<String, &'a syn::ImplItemFn>,
    consts: HashMap<String, &'a syn::ImplItemConst>,
    /// Integer constants the expansion itself defines (`Self::ALPHA`, a coordinate's index).
    generated: HashMap<String, i64>,
    /// Their names in the order they were defined, for messages.
    generated_names: Vec<String>,
    /// Shared helpers (`#[hamel::helpers]`): their functions by the set's name and their own.
    helpers: HashMap<String, HashMap<String, &'a syn::ImplItemFn>>,
}

impl<'a> ImplContext<'a> {
    pub fn new(items: impl IntoIterator<Item = &'a syn::ImplItem>) -> Self {
        let mut fns = HashMap::default();
        let mut consts = HashMap::default();
        for item in items {
            match item {
                syn::ImplItem::Fn(f) => {
                    fns.insert(f.sig.ident.to_string(), f);
                }
                syn::ImplItem::Const(c) => {
                    consts.insert(c.ident.to_string(), c);
                }
                _ => {}
            }
        }
        ImplContext {
            fns,
            consts,
            generated: HashMap::default(),
            generated_names: Vec::new(),
            helpers: HashMap::default(),
        }
    }

    /// Make the functions of a set of shared helpers known, as `Set::name(..)`.
    pub fn add_helpers(&mut self, set: String, items: impl IntoIterator<Item = &'a syn::ImplItem>) {
        let fns = items.into_iter().filter_map(|item| match item {
            syn::ImplItem::Fn(f) => Some((f.sig.ident.to_string(), f)),
            _ => None,
        });
        self.helpers.entry(set).or_default().extend(fns);
    }

    /// The helper `name` of the set `set`: `Ok` with the function, `Err` with the set's
    /// functions (sorted) when it has no such one, `None` when there is no such set.
    fn helper(&self, set: &str, name: &str) -> Option<Result<&'a syn::ImplItemFn, Vec<String>>> {
        let fns = self.helpers.get(set)?;
        Some(fns.get(name).copied().ok_or_else(|| {
            let mut names: Vec<String> = fns.keys().cloned().collect();
            names.sort();
            names
        }))
    }

    /// Make `Self::name` an integer constant known to bodies.
    pub fn define_index(&mut self, name: String, value: i64) {
        if self.generated.insert(name.clone(), value).is_none() {
            self.generated_names.push(name);
        }
    }

    /// The names of the index constants the expansion defines, in order.
    pub fn generated_names(&self) -> &[String] {
        &self.generated_names
    }

    fn generated_index(&self, name: &str) -> Option<i64> {
        self.generated.get(name).copied()
    }

    pub fn function(&self, name: &str) -> Option<&'a syn::ImplItemFn> {
        self.fns.get(name).copied()
    }

    fn constant(&self, name: &str) -> Option<&'a syn::ImplItemConst> {
        self.consts.get(name).copied()
    }
}

/// A value the generated code reads from outside the body: a parameter `self.field`, or a
/// constant defined outside the impl. Each becomes one graph input; `tokens` is the Rust
/// expression that reads it, spanned at the user's first use so that rustc's own errors
/// (no such field, wrong type) point at the user's code.
#[derive(Clone)]
pub struct External {
    pub node: NodeId,
    pub tokens: TokenStream,
}

#[derive(Clone, Default)]
pub struct Externals {
    pub items: Vec<External>,
    by_name: HashMap<String, usize>,
}

impl Externals {
    fn get_or_insert(&mut self, graph: &mut Graph, name: String, tokens: TokenStream) -> NodeId {
        if let Some(&i) = self.by_name.get(&name) {
            return self.items[i].node;
        }
        let node = graph.new_input(name.clone());
        self.by_name.insert(name, self.items.len());
        self.items.push(External { node, tokens });
        node
    }

    /// The input of the external read as `name` (`"self.m0"`, `"G"`), if the body reads it.
    #[cfg(test)]
    pub fn node(&self, name: &str) -> Option<NodeId> {
        self.by_name.get(name).map(|&i| self.items[i].node)
    }
}

/// The lowering state for one expansion: several functions may be lowered into the same
/// graph with the same lowerer (their parameters then share inputs).
pub struct Lowerer<'a, 'g> {
    pub graph: &'g mut Graph,
    ctx: &'a ImplContext<'a>,
    pub externals: Externals,
    errors: Vec<syn::Error>,
    call_stack: Vec<String>,
    const_cache: HashMap<String, Value>,
    const_stack: Vec<String>,
    unrolled: usize,
    reported_budget: bool,
    /// Constants outside the impl block already reported as array lengths: one mistake,
    /// one error, however many signatures repeat it.
    reported_lengths: crate::engine::hash::HashSet<String>,
    /// Functions whose signature or body had an error (by name): the error fallback stubs
    /// their bodies, so that rustc does not report the same mistake a second time.
    faulty: HashSet<String>,
    /// Functions whose bodies have been lowered (by name).
    lowered: HashSet<String>,
    /// Mistakes reported once per expansion however often they occur (an unknown function).
    reported_once: HashSet<String>,
    /// Mistakes met so far, counting those reported once but met again: a body that met one
    /// has no value to draw verdicts from.
    mistakes: usize,
    /// The signature a function must have, by name (the role functions of a model): type
    /// errors in its signature say what is expected there.
    pub signature_hints: HashMap<String, String>,
    /// The arguments a function must take, named as in its role's signature (`q`, `qd`), by
    /// function name (the role functions of a model): a body checked on its own is checked
    /// on these, not on a mistaken signature.
    pub expected_arguments: HashMap<String, Vec<(&'static str, Shape)>>,
    /// The entries of array parameters the bodies read: for each field, the largest index
    /// and where it is written. The macro cannot see the struct, so the generated code
    /// checks these against the arrays' lengths (a pattern rustc checks in `cargo check`).
    pub parameter_arrays: std::collections::BTreeMap<String, (usize, proc_macro2::Span)>,
    current_signature: Option<String>,
    /// Set while a role read with the velocities is lowered: where `rate!` has a meaning.
    pub rate_context: Option<RateContext>,
    /// The sets of the shared helpers being inlined, innermost last: their `Self::name(..)`
    /// is a function of the set.
    helper_scope: Vec<String>,
}

impl<'a, 'g> Lowerer<'a, 'g> {
    pub fn new(graph: &'g mut Graph, ctx: &'a ImplContext<'a>) -> Self {
        Lowerer {
            graph,
            ctx,
            externals: Externals::default(),
            errors: Vec::new(),
            call_stack: Vec::new(),
            const_cache: HashMap::default(),
            const_stack: Vec::new(),
            unrolled: 0,
            reported_budget: false,
            reported_lengths: crate::engine::hash::HashSet::default(),
            faulty: HashSet::default(),
            lowered: HashSet::default(),
            reported_once: HashSet::default(),
            mistakes: 0,
            signature_hints: HashMap::default(),
            expected_arguments: HashMap::default(),
            parameter_arrays: std::collections::BTreeMap::new(),
            current_signature: None,
            rate_context: None,
            helper_scope: Vec::new(),
        }
    }

    /// Record an error at the span of `tokens`; returns poison to stand in for the value.
    pub fn error(&mut self, tokens: impl ToTokens, message: impl Display) -> Value {
        self.push_error(syn::Error::new_spanned(tokens, message));
        Value::Poison
    }

    /// Record an error only the first time `key` is seen (one report per mistake, not one per
    /// occurrence); returns poison either way.
    fn error_once(&mut self, key: String, tokens: impl ToTokens, message: impl Display) -> Value {
        if self.reported_once.insert(key) {
            self.error(tokens, message);
        } else {
            self.mistakes += 1;
            if let Some(name) = self.call_stack.last() {
                self.faulty.insert(name.clone());
            }
        }
        Value::Poison
    }

    pub fn push_error(&mut self, error: syn::Error) {
        // An error while a body is lowered lies in that body (the innermost call).
        if let Some(name) = self.call_stack.last() {
            self.faulty.insert(name.clone());
        }
        self.mistakes += 1;
        self.errors.push(error);
    }

    /// Whether `Self::name` is a constant of the impl block or of the expansion.
    pub fn knows_constant(&self, name: &str) -> bool {
        self.ctx.constant(name).is_some() || self.ctx.generated_index(name).is_some()
    }

    /// A mistake already reported (the same one met again): it fails the body it is in
    /// without a second error.
    pub fn note_repeated_mistake(&mut self) {
        if let Some(name) = self.call_stack.last() {
            self.faulty.insert(name.clone());
        }
    }

    /// Whether any error has been recorded so far.
    pub fn has_errors(&self) -> bool {
        !self.errors.is_empty()
    }

    /// Note that the function `name` has a mistake reported elsewhere (its signature does not
    /// fit its role): the error fallback leaves its body out too.
    pub fn mark_faulty(&mut self, name: String) {
        self.faulty.insert(name);
    }

    /// The functions whose signature or body had an error.
    pub fn faulty_functions(&self) -> &HashSet<String> {
        &self.faulty
    }

    /// Whether the body of the function `name` has been lowered.
    pub fn was_lowered(&self, name: &str) -> bool {
        self.lowered.contains(name)
    }

    /// All errors so far, combined into one (or `Ok` if there were none). The same message at
    /// the same place is kept once, however many times it was found (a function lowered
    /// twice, a signature checked twice).
    pub fn take_errors(&mut self) -> syn::Result<()> {
        let mut seen = HashSet::default();
        let mut errors = std::mem::take(&mut self.errors)
            .into_iter()
            .flatten()
            .filter(|e| seen.insert((format!("{:?}", e.span()), e.to_string())));
        match errors.next() {
            None => Ok(()),
            Some(mut first) => {
                for e in errors {
                    first.combine(e);
                }
                Err(first)
            }
        }
    }

    /// Lower a call of `f` with the given argument values (one per typed argument; the
    /// receiver is implicit). `call_site` is what errors about the call itself point at.
    pub fn call(
        &mut self,
        f: &'a syn::ImplItemFn,
        args: Vec<Value>,
        call_site: &dyn ToTokens,
    ) -> Value {
        self.call_checked(f, args, call_site, true)
    }

    /// Lower a function's body on arguments of the shapes its role needs, whatever its
    /// signature says (a mistaken signature is reported elsewhere): what the body would do
    /// once the signature is fixed.
    pub fn check_body(&mut self, f: &'a syn::ImplItemFn, args: Vec<Value>) -> Value {
        // Checked as the role it is: a role read with the velocities may take `rate!` (without
        // its context, correct `body_rates!` code was reported beside the real mistake).
        self.rate_context = self.rate_context_for(f, &args);
        let value = self.call_checked(f, args, &f.sig.ident, false);
        self.rate_context = None;
        value
    }

    fn call_checked(
        &mut self,
        f: &'a syn::ImplItemFn,
        args: Vec<Value>,
        call_site: &dyn ToTokens,
        check_args: bool,
    ) -> Value {
        let name = f.sig.ident.to_string();
        if self.call_stack.contains(&name) {
            return self.error(
                call_site.to_token_stream(),
                format!(
                    "`{name}` calls itself (through {}): recursive functions cannot be inlined; \
                     rewrite the recursion as a `for` loop with a constant bound",
                    self.call_stack.join(" → ")
                ),
            );
        }
        if self.call_stack.len() >= MAX_CALL_DEPTH {
            return self.error(
                call_site.to_token_stream(),
                format!("calls nested more than {MAX_CALL_DEPTH} deep cannot be inlined"),
            );
        }
        let Some(signature) = self.signature(f) else {
            return Value::Poison;
        };
        if signature.args.len() != args.len() {
            let message = match self.helper_scope.last() {
                Some(set) => format!(
                    "the shared helper `{set}::{name}` takes {} argument(s), but {} were given",
                    signature.args.len(),
                    args.len()
                ),
                None => format!(
                    "`{name}` takes {} argument(s) besides `self`, but {} were given",
                    signature.args.len(),
                    args.len()
                ),
            };
            return self.error(call_site.to_token_stream(), message);
        }
        let mut env = Env::default();
        env.push();
        for (arg, value) in signature.args.iter().zip(args) {
            if check_args && !arg.shape.admits(&value) {
                self.error(
                    call_site.to_token_stream(),
                    format!(
                        "argument `{}` of `{name}` is {}, but {} was given",
                        arg.pat.to_token_stream(),
                        arg.shape.describe(),
                        value.describe()
                    ),
                );
                continue;
            }
            self.bind_pattern(&mut env, &arg.pat, value, false);
        }
        self.lowered.insert(name.clone());
        self.call_stack.push(name);
        let mistakes = self.mistakes;
        let result = self.block(&mut env, &f.block);
        self.call_stack.pop();
        // After a mistake the body's value is not what the user meant (a `loop` that was
        // skipped leaves a local at its initial value): drawing a verdict from it, such as
        // "does not depend on the velocities", would add a false error to the true one.
        if self.mistakes > mistakes {
            return Value::Poison;
        }
        self.check_result(f, signature.output.as_ref(), result)
    }

    /// The body's value, if it has the declared type (else an error at the body's tail).
    fn check_result(
        &mut self,
        f: &syn::ImplItemFn,
        output: Option<&Shape>,
        result: Value,
    ) -> Value {
        let Some(shape) = output.filter(|shape| !shape.admits(&result)) else {
            return result;
        };
        let tail = f
            .block
            .stmts
            .last()
            .map(|s| s.to_token_stream())
            .unwrap_or_else(|| f.block.to_token_stream());
        self.error(
            tail,
            format!(
                "`{}` is declared to return {}, but its body evaluates to {}",
                f.sig.ident,
                shape.describe(),
                result.describe()
            ),
        );
        self.faulty.insert(f.sig.ident.to_string());
        Value::Poison
    }

    /// Lower a role function of the model: errors about the call point at its name. A role
    /// read with the velocities (its arguments named `q` and `qd`) may take `rate!` of its
    /// expressions.
    pub fn call_role(&mut self, f: &'a syn::ImplItemFn, args: Vec<Value>) -> Value {
        self.rate_context = self.rate_context_for(f, &args);
        let value = self.call(f, args, &f.sig.ident);
        self.rate_context = None;
        value
    }

    /// The coordinates, velocities and time among a role's arguments, by the names its role
    /// gives them.
    fn rate_context_for(&mut self, f: &syn::ImplItemFn, args: &[Value]) -> Option<RateContext> {
        let expected = self.expected_arguments.get(&f.sig.ident.to_string())?;
        let at = |name: &str| {
            let i = expected.iter().position(|(n, _)| *n == name)?;
            args.get(i)?.flatten()
        };
        let (q, qd) = (at("q")?, at("qd")?);
        let t = match at("t").as_deref() {
            Some([t]) => Some(*t),
            _ => None,
        };
        let mut seeds: Vec<(NodeId, NodeId)> = q.iter().copied().zip(qd.iter().copied()).collect();
        if let Some(t) = t {
            let one = self.graph.one();
            seeds.push((t, one));
        }
        Some(RateContext {
            seeds,
            velocities: qd,
        })
    }

    /// Count unrolled iterations against the budget; false (with an error) when exhausted.
    fn spend_iterations(&mut self, count: usize, at: &dyn ToTokens) -> bool {
        self.unrolled = self.unrolled.saturating_add(count);
        if self.unrolled > MAX_UNROLLED_ITERATIONS || self.graph.too_large() {
            if !self.reported_budget {
                self.reported_budget = true;
                self.error(
                    at.to_token_stream(),
                    format!(
                        "this loop unrolls into more than the {MAX_UNROLLED_ITERATIONS} iterations \
                         (or {} graph nodes) a model may have; loops are unrolled at compile time, \
                         so their bounds must be small constants",
                        crate::engine::graph::MAX_NODES
                    ),
                );
            }
            return false;
        }
        true
    }

    /// Note the source of a freshly created real node, and of the fresh nodes below it that
    /// no inner expression claimed (those the graph's normal forms create: in `-a * b` the
    /// product `a * b` under the negation), so that an error about any of them can point
    /// at the smallest expression that made it.
    fn note(&mut self, value: &Value, before: usize, e: &syn::Expr) {
        let Value::Real(id) = value else { return };
        if id.index() < before || self.graph.span(*id).is_some() {
            return;
        }
        let range = span::expr_range(e);
        let mut stack = vec![*id];
        while let Some(id) = stack.pop() {
            if id.index() < before || self.graph.span(id).is_some() {
                continue;
            }
            self.graph.note_span(id, range);
            stack.extend_from_slice(self.graph.node(id).operands().as_slice());
        }
    }
}
