//! Statements and control flow: blocks, `let`, `const`, `for` (unrolled) and `if` (a select,
//! or the taken branch alone when the condition is known at compile time).

use super::value::Value;
use super::{Env, Lowerer};
use quote::ToTokens;
use syn::{Expr, Pat, Stmt};

impl<'a> Lowerer<'a, '_> {
    /// A block in a scope of its own; its value is its final expression (or `()`).
    pub fn block(&mut self, env: &mut Env, block: &syn::Block) -> Value {
        env.push();
        let mut result = Value::Unit;
        let count = block.stmts.len();
        for (i, stmt) in block.stmts.iter().enumerate() {
            let value = self.stmt(env, stmt);
            let is_tail = i + 1 == count && matches!(stmt, Stmt::Expr(_, None));
            if is_tail {
                result = value;
            }
        }
        env.pop();
        result
    }

    fn stmt(&mut self, env: &mut Env, stmt: &Stmt) -> Value {
        match stmt {
            Stmt::Local(local) => {
                let Some(init) = &local.init else {
                    return self.error(
                        local,
                        "a `let` needs a value here (`let x = 0.0;`): deferred initialization is not supported",
                    );
                };
                if let Some((else_token, _)) = &init.diverge {
                    return self.error(else_token, "`let ... else` is not supported");
                }
                let value = self.expr(env, &init.expr);
                self.bind_pattern(env, &local.pat, value, false);
                Value::Unit
            }
            Stmt::Item(syn::Item::Const(c)) => {
                let shape = self.shape_of(&c.ty);
                let value = self.expr(env, &c.expr);
                let value = match shape {
                    Some(shape) if !shape.admits(&value) => self.error(
                        &c.expr,
                        format!("`{}` is declared {} but its value is {}", c.ident, shape.describe(), value.describe()),
                    ),
                    Some(_) => value,
                    None => Value::Poison,
                };
                env.bind(c.ident.to_string(), value, false);
                Value::Unit
            }
            Stmt::Item(syn::Item::Fn(f)) => self.error(
                &f.sig,
                "nested functions are not supported: make it a function of this impl and call it as `self.name(..)`",
            ),
            Stmt::Item(syn::Item::Use(u)) => self.error(
                u,
                "`use` inside a differentiated body is not supported: put it at module level",
            ),
            Stmt::Item(item) => self.error(item, "only `const` items are supported inside a differentiated body"),
            Stmt::Expr(e, _) => self.expr(env, e),
            Stmt::Macro(m) if super::rate::is_rate(&m.mac) => self.rate(env, &m.mac),
            Stmt::Macro(m) => self.error(
                m,
                format!(
                    "macros (`{}!`) are not supported in a differentiated body",
                    m.mac.path.to_token_stream()
                ),
            ),
        }
    }

    /// Bind the names of a pattern (`x`, `mut x`, `x: f64`, `_`, `[a, b, c]`, `&x`).
    pub fn bind_pattern(&mut self, env: &mut Env, pat: &Pat, value: Value, mutable: bool) {
        match pat {
            Pat::Ident(p) => {
                if let Some(r) = &p.by_ref {
                    self.error(r, "`ref` bindings are not supported");
                } else if let Some((at, _)) = &p.subpat {
                    self.error(at, "`@` patterns are not supported");
                } else {
                    env.bind(
                        p.ident.to_string(),
                        value,
                        mutable || p.mutability.is_some(),
                    );
                }
            }
            Pat::Type(p) => {
                if let Some(shape) = self.shape_of(&p.ty) {
                    if shape.admits(&value) {
                        self.bind_pattern(env, &p.pat, value, mutable);
                    } else {
                        self.error(
                            &p.ty,
                            format!(
                                "declared {} but the value is {}",
                                shape.describe(),
                                value.describe()
                            ),
                        );
                        self.bind_pattern(env, &p.pat, Value::Poison, mutable);
                    }
                } else {
                    self.bind_pattern(env, &p.pat, Value::Poison, mutable);
                }
            }
            Pat::Wild(_) => {}
            Pat::Reference(r) => self.bind_pattern(env, &r.pat, value, mutable),
            Pat::Paren(p) => self.bind_pattern(env, &p.pat, value, mutable),
            Pat::Tuple(t) => {
                let items = match value {
                    Value::Tuple(items) if items.len() == t.elems.len() => items,
                    Value::Poison => vec![Value::Poison; t.elems.len()],
                    other => {
                        self.error(
                            t,
                            format!(
                                "this pattern takes a tuple of {} elements, the value is {}",
                                t.elems.len(),
                                other.describe()
                            ),
                        );
                        vec![Value::Poison; t.elems.len()]
                    }
                };
                for (p, v) in t.elems.iter().zip(items) {
                    self.bind_pattern(env, p, v, mutable);
                }
            }
            Pat::Slice(s) => {
                let items = match value {
                    Value::Array(items) if items.len() == s.elems.len() => items,
                    Value::Poison => vec![Value::Poison; s.elems.len()],
                    other => {
                        self.error(
                            s,
                            format!(
                                "this pattern takes an array of {} elements, the value is {}",
                                s.elems.len(),
                                other.describe()
                            ),
                        );
                        vec![Value::Poison; s.elems.len()]
                    }
                };
                for (p, v) in s.elems.iter().zip(items) {
                    self.bind_pattern(env, p, v, mutable);
                }
            }
            other => {
                self.error(
                    other,
                    "unsupported pattern: use a name, `mut name`, `_`, an array pattern `[a, b, c]` \
                     or a tuple pattern `(a, b)`",
                );
                poison_names(env, other);
            }
        }
    }

    pub fn for_loop(&mut self, env: &mut Env, f: &syn::ExprForLoop) -> Value {
        let Some(items) = self.loop_items(env, &f.expr) else {
            // Lower the body once anyway, with the counter poisoned, to report its errors too.
            env.push();
            self.bind_pattern(env, &f.pat, Value::Poison, false);
            self.block(env, &f.body);
            env.pop();
            return Value::Unit;
        };
        if !self.spend_iterations(items.len(), &f.expr) {
            return Value::Poison;
        }
        for item in items {
            env.push();
            self.bind_pattern(env, &f.pat, item, false);
            let before = self.error_count();
            self.block(env, &f.body);
            env.pop();
            // One report per mistake, not one per iteration.
            if self.error_count() > before {
                break;
            }
        }
        Value::Unit
    }

    /// What a `for` loop iterates over: a constant range (optionally `.rev()`), or the
    /// elements of an array (`arr`, `&arr`, `arr.iter()`).
    fn loop_items(&mut self, env: &mut Env, iterable: &Expr) -> Option<Vec<Value>> {
        match iterable {
            Expr::Paren(p) => self.loop_items(env, &p.expr),
            Expr::Range(r) => {
                let (Some(start), Some(end)) = (&r.start, &r.end) else {
                    self.error(r, "a loop range needs both bounds, as in `0..N`");
                    return None;
                };
                let start = self.loop_bound(env, start)?;
                let end = self.loop_bound(env, end)?;
                let end = match r.limits {
                    syn::RangeLimits::HalfOpen(_) => end,
                    syn::RangeLimits::Closed(_) => end.checked_add(1)?,
                };
                let count = usize::try_from(end.saturating_sub(start)).unwrap_or(0);
                if count > super::MAX_UNROLLED_ITERATIONS {
                    self.spend_iterations(count, r);
                    return None;
                }
                Some((start..end).map(Value::Int).collect())
            }
            Expr::MethodCall(m) if m.method == "rev" && m.args.is_empty() => {
                let mut items = self.loop_items(env, &m.receiver)?;
                items.reverse();
                Some(items)
            }
            Expr::MethodCall(m)
                if (m.method == "iter" || m.method == "into_iter") && m.args.is_empty() =>
            {
                self.loop_items(env, &m.receiver)
            }
            other => match self.expr(env, other) {
                Value::Array(items) => Some(items),
                Value::Poison => None,
                v => {
                    self.error(
                        other,
                        format!(
                            "a `for` loop must run over a constant range `0..N` or an array, this is {}",
                            v.describe()
                        ),
                    );
                    None
                }
            },
        }
    }

    fn loop_bound(&mut self, env: &mut Env, e: &Expr) -> Option<i64> {
        match self.expr(env, e) {
            Value::Int(n) => Some(n),
            Value::Poison => None,
            other => {
                let is_parameter = matches!(e, Expr::Field(f) if matches!(&*f.base, Expr::Path(p) if p.path.is_ident("self")));
                let hint = if matches!(e, Expr::Path(p) if p.path.get_ident().is_some()) {
                    " (a constant defined outside this impl is invisible to the macro: define it in \
                     the impl, `const N: usize = 5;`, and write `Self::N`)"
                } else if is_parameter {
                    " (a parameter is an `f64` read at run time, but loops are unrolled at compile \
                     time: use a literal or a constant of the impl, `const N: usize = 5;` and \
                     `0..Self::N`)"
                } else {
                    ""
                };
                self.error(
                    e,
                    format!(
                        "a loop bound must be an integer known at compile time, found {}{hint}",
                        other.describe()
                    ),
                );
                None
            }
        }
    }

    pub fn if_expr(&mut self, env: &mut Env, i: &syn::ExprIf) -> Value {
        let cond = self.expr(env, &i.cond);
        let cond = match cond {
            Value::Bool(c) => Some(c),
            Value::Poison => None,
            other => {
                self.error(
                    &i.cond,
                    format!(
                        "an `if` condition must be a comparison, found {}",
                        other.describe()
                    ),
                );
                None
            }
        };
        // Known at compile time (a loop counter, a constant): lower the taken branch only, so
        // the other may index out of bounds for this iteration without harm.
        if let Some(known) = cond.and_then(|c| self.graph.bool_value(c)) {
            return if known {
                self.block(env, &i.then_branch)
            } else {
                match &i.else_branch {
                    Some((_, e)) => self.expr(env, e),
                    None => Value::Unit,
                }
            };
        }
        let depth = env.depth();
        let mut then_env = env.clone();
        let then_value = self.block(&mut then_env, &i.then_branch);
        let mut else_env = env.clone();
        let else_value = match &i.else_branch {
            Some((_, e)) => self.expr(&mut else_env, e),
            None => Value::Unit,
        };
        let Some(c) = cond else {
            return Value::Poison;
        };
        for (level, name) in env.bindings(depth) {
            let (Some(a), Some(b)) = (then_env.at(level, &name), else_env.at(level, &name)) else {
                continue;
            };
            // Both branches may have changed the local, to the same value or not: an `if`
            // whose branches both do `y += x` still updates `y`.
            let merged = if a.value == b.value {
                a.value.clone()
            } else {
                self.merge(c, a.value.clone(), b.value.clone(), i, &name)
            };
            env.set_at(level, &name, merged);
        }
        self.merge(c, then_value, else_value, i, "the value of this `if`")
    }

    /// Join the values of the two branches of an `if` at run time.
    fn merge(
        &mut self,
        c: crate::engine::graph::NodeId,
        a: Value,
        b: Value,
        at: &syn::ExprIf,
        what: &str,
    ) -> Value {
        match (a, b) {
            (Value::Poison, _) | (_, Value::Poison) => Value::Poison,
            (Value::Real(x), Value::Real(y)) => Value::Real(self.graph.select(c, x, y)),
            (Value::Bool(x), Value::Bool(y)) => {
                let g = &mut *self.graph;
                let then = g.and(c, x);
                let nc = g.not(c);
                let otherwise = g.and(nc, y);
                Value::Bool(g.or(then, otherwise))
            }
            (Value::Int(x), Value::Int(y)) if x == y => Value::Int(x),
            (Value::Int(_), Value::Int(_)) => self.error(
                &at.cond,
                format!(
                    "`{what}` is an integer that would depend on a condition known only at run time; \
                     integers (indices, loop bounds) must be known at compile time"
                ),
            ),
            (Value::Array(x), Value::Array(y)) if x.len() == y.len() => Value::Array(
                x.into_iter()
                    .zip(y)
                    .map(|(p, q)| self.merge(c, p, q, at, what))
                    .collect(),
            ),
            (Value::Tuple(x), Value::Tuple(y)) if x.len() == y.len() => Value::Tuple(
                x.into_iter()
                    .zip(y)
                    .map(|(p, q)| self.merge(c, p, q, at, what))
                    .collect(),
            ),
            (Value::Geo(x), Value::Geo(y)) if x.kind() == y.kind() => {
                match x.select(self.graph, c, y) {
                    Some(geo) => Value::Geo(geo),
                    None => Value::Poison,
                }
            }
            (Value::Unit, Value::Unit) => Value::Unit,
            (Value::Unit, other) | (other, Value::Unit) if at.else_branch.is_none() => self.error(
                at,
                format!(
                    "an `if` without `else` cannot produce a value ({}); add an `else` branch",
                    other.describe()
                ),
            ),
            (x, y) => self.error(
                at,
                format!(
                    "the branches of this `if` give different types for {what}: {} and {}",
                    x.describe(),
                    y.describe()
                ),
            ),
        }
    }

    fn error_count(&self) -> usize {
        self.errors.len()
    }
}

/// Bind every name of a pattern that could not be lowered to poison, so that its uses do not
/// report "cannot find" on top of the real mistake.
fn poison_names(env: &mut Env, pat: &Pat) {
    struct Names<'e>(&'e mut Env);
    impl<'ast> syn::visit::Visit<'ast> for Names<'_> {
        fn visit_pat_ident(&mut self, p: &'ast syn::PatIdent) {
            self.0.bind(p.ident.to_string(), Value::Poison, true);
        }
    }
    syn::visit::Visit::visit_pat(&mut Names(env), pat);
}
