//! Expressions: literals, names, parameters, indexing, operators, casts, assignments.

use super::value::Value;
use super::{Env, Lowerer};
use crate::engine::graph::Cmp;
use quote::ToTokens;
use syn::{BinOp, Expr, UnOp};

/// A one-line summary of the subset, appended to "not supported" errors.
pub const SUBSET: &str = "supported are `f64` arithmetic (`+ - * /`, unary `-`), comparisons in `if`/`else`, \
     `let`/`let mut` with `=`, `+=`, `-=`, `*=`, `/=`, arrays `[a, b]` indexed by constants, \
     `for i in 0..N` with a constant `N`, the elementary functions of `f64`, and calls of other \
     functions of this impl";

/// Constants of `std::f64::consts`, which fold at compile time.
fn math_constant(name: &str) -> Option<f64> {
    use std::f64::consts as c;
    Some(match name {
        "PI" => c::PI,
        "TAU" => c::TAU,
        "E" => c::E,
        "SQRT_2" => c::SQRT_2,
        "FRAC_1_SQRT_2" => c::FRAC_1_SQRT_2,
        "FRAC_PI_2" => c::FRAC_PI_2,
        "FRAC_PI_3" => c::FRAC_PI_3,
        "FRAC_PI_4" => c::FRAC_PI_4,
        "FRAC_PI_6" => c::FRAC_PI_6,
        "FRAC_PI_8" => c::FRAC_PI_8,
        "FRAC_1_PI" => c::FRAC_1_PI,
        "FRAC_2_PI" => c::FRAC_2_PI,
        "FRAC_2_SQRT_PI" => c::FRAC_2_SQRT_PI,
        "LN_2" => c::LN_2,
        "LN_10" => c::LN_10,
        "LOG2_E" => c::LOG2_E,
        "LOG10_E" => c::LOG10_E,
        "LOG2_10" => c::LOG2_10,
        "LOG10_2" => c::LOG10_2,
        _ => return None,
    })
}

/// Associated constants of `f64` itself (`f64::EPSILON`).
fn f64_constant(name: &str) -> Option<f64> {
    Some(match name {
        "EPSILON" => f64::EPSILON,
        "MAX" => f64::MAX,
        "MIN" => f64::MIN,
        "MIN_POSITIVE" => f64::MIN_POSITIVE,
        "INFINITY" => f64::INFINITY,
        "NEG_INFINITY" => f64::NEG_INFINITY,
        _ => return None,
    })
}

fn is_constant_name(name: &str) -> bool {
    name.chars().any(|c| c.is_ascii_uppercase())
        && name
            .chars()
            .all(|c| c.is_ascii_uppercase() || c.is_ascii_digit() || c == '_')
}

impl<'a> Lowerer<'a, '_> {
    pub fn expr(&mut self, env: &mut Env, e: &Expr) -> Value {
        let before = self.graph.len();
        let value = self.expr_inner(env, e);
        self.note(&value, before, e);
        value
    }

    fn expr_inner(&mut self, env: &mut Env, e: &Expr) -> Value {
        match e {
            Expr::Lit(l) => self.literal(&l.lit),
            Expr::Path(p) => self.path(env, p),
            Expr::Field(f) => self.field(env, f),
            Expr::Index(i) => self.index(env, i),
            Expr::Binary(b) => self.binary(env, b),
            Expr::Unary(u) => self.unary_expr(env, u),
            Expr::Paren(p) => self.expr(env, &p.expr),
            Expr::Group(g) => self.expr(env, &g.expr),
            Expr::Block(b) => {
                if let Some(label) = &b.label {
                    return self.error(label, "labelled blocks are not supported");
                }
                self.block(env, &b.block)
            }
            Expr::Array(a) => self.array(env, a),
            Expr::Repeat(r) => self.repeat(env, r),
            Expr::MethodCall(m) => self.method_call(env, m),
            Expr::Call(c) => self.call_expr(env, c),
            Expr::Cast(c) => self.cast(env, c),
            Expr::If(i) => self.if_expr(env, i),
            Expr::ForLoop(f) => self.for_loop(env, f),
            Expr::Assign(a) => {
                let value = self.expr(env, &a.right);
                self.assign(env, &a.left, value);
                Value::Unit
            }
            Expr::Reference(r) => {
                if let Some(m) = &r.mutability {
                    return self.error(m, "mutable references are not supported: bodies are pure functions");
                }
                self.expr(env, &r.expr)
            }
            Expr::While(w) => self.error(
                w.while_token,
                "`while` loops are not supported: the number of iterations must be known at compile \
                 time; use `for i in 0..N` with a constant `N`",
            ),
            Expr::Loop(l) => self.error(
                l.loop_token,
                "`loop` is not supported: the number of iterations must be known at compile time; \
                 use `for i in 0..N` with a constant `N`",
            ),
            Expr::Match(m) => self.error(
                m.match_token,
                "`match` is not supported: branch with `if`/`else` on a comparison instead",
            ),
            Expr::Closure(c) => self.error(
                c,
                "closures are not supported: write the helper as a function of this impl and call it \
                 as `self.helper(..)`",
            ),
            Expr::Return(r) => self.error(
                r.return_token,
                "`return` is not supported: a body's result is its final expression (leave out the \
                 `return` and the semicolon)",
            ),
            Expr::Break(b) => self.error(
                b.break_token,
                "`break` is not supported: loops are unrolled at compile time and run every iteration",
            ),
            Expr::Continue(c) => self.error(
                c.continue_token,
                "`continue` is not supported: loops are unrolled at compile time; use `if` inside the loop",
            ),
            Expr::Macro(m) if super::rate::is_rate(&m.mac) => self.rate(env, &m.mac),
            Expr::Macro(m) => self.error(
                m,
                format!(
                    "macros (`{}!`) are not supported in a differentiated body",
                    m.mac.path.to_token_stream()
                ),
            ),
            Expr::Tuple(t) => {
                let items: Vec<Value> = t.elems.iter().map(|e| self.expr(env, e)).collect();
                if items.is_empty() { Value::Unit } else { Value::Tuple(items) }
            }
            Expr::Range(r) => self.error(r, "a range is only supported as the bound of a `for` loop"),
            Expr::Let(l) => self.error(l, "`if let` is not supported: use a comparison"),
            Expr::Unsafe(u) => self.error(u.unsafe_token, "`unsafe` is not supported in a differentiated body"),
            other => self.error(other, format!("this expression is not supported: {SUBSET}")),
        }
    }

    fn literal(&mut self, lit: &syn::Lit) -> Value {
        match lit {
            syn::Lit::Float(f) => match f.suffix() {
                "" | "f64" => match f.base10_parse::<f64>() {
                    Ok(v) => Value::Real(self.graph.constant(v)),
                    Err(e) => {
                        self.push_error(e);
                        Value::Poison
                    }
                },
                s => self.error(
                    f,
                    format!("`{s}` literals are not supported: hamel computes in `f64`"),
                ),
            },
            syn::Lit::Int(i) => match i.suffix() {
                "f64" => match i.base10_parse::<f64>() {
                    Ok(v) => Value::Real(self.graph.constant(v)),
                    Err(e) => {
                        self.push_error(e);
                        Value::Poison
                    }
                },
                "f32" => self.error(
                    i,
                    "`f32` literals are not supported: hamel computes in `f64`",
                ),
                _ => match i.base10_parse::<i64>() {
                    Ok(v) => Value::Int(v),
                    Err(e) => {
                        self.push_error(e);
                        Value::Poison
                    }
                },
            },
            syn::Lit::Bool(b) => Value::Bool(self.graph.boolean(b.value)),
            other => self.error(other, "only numeric and boolean literals are supported"),
        }
    }

    fn path(&mut self, env: &mut Env, p: &syn::ExprPath) -> Value {
        if p.qself.is_some() {
            return self.error(p, "qualified paths `<T as Trait>::..` are not supported");
        }
        let segments: Vec<String> = p
            .path
            .segments
            .iter()
            .map(|s| s.ident.to_string())
            .collect();
        if p.path.segments.iter().any(|s| !s.arguments.is_none()) {
            return self.error(p, "generic arguments are not supported here");
        }
        let segs: Vec<&str> = segments.iter().map(String::as_str).collect();
        let last = *segs.last().unwrap_or(&"");
        match segs.as_slice() {
            [name] => {
                if let Some(local) = env.get(name) {
                    return local.value.clone();
                }
                if *name == "self" {
                    return self.error(
                        p,
                        "`self` is not a number: read parameters as `self.field` and call helpers as `self.helper(..)`",
                    );
                }
                if is_constant_name(name) {
                    // A constant from outside the impl (or an imported `PI`): the generated code
                    // reads it by the same path, so rustc resolves it exactly as in the user's code.
                    return self.external(p.to_token_stream(), name.to_string());
                }
                let value = self.error(
                    p,
                    format!(
                        "cannot find `{name}` here: a body sees its arguments, its `let` locals, \
                         `self.field` parameters and constants"
                    ),
                );
                env.bind(name.to_string(), Value::Poison, true);
                value
            }
            ["Self", name] => match (self.ctx.constant(name), self.ctx.generated_index(name)) {
                (Some(c), _) => self.assoc_const(name, c),
                (None, Some(index)) => Value::Int(index),
                (None, None) => self.external(p.to_token_stream(), format!("Self::{name}")),
            },
            ["std" | "core", "f64", "consts", name]
            | ["f64", "consts", name]
            | ["consts", name] => match math_constant(name) {
                Some(v) => Value::Real(self.graph.constant(v)),
                None => self.error(
                    p,
                    format!("`{name}` is not a constant of `std::f64::consts`"),
                ),
            },
            ["std" | "core", "f64", name] | ["f64", name] => match f64_constant(name) {
                Some(v) => Value::Real(self.graph.constant(v)),
                None => self.error(p, format!("`f64::{name}` is not supported here")),
            },
            _ if is_constant_name(last) => {
                let key = segments.join("::");
                self.external(p.to_token_stream(), key)
            }
            _ => self.error(
                p,
                format!("unsupported path `{}`: {SUBSET}", segments.join("::")),
            ),
        }
    }

    /// A value read from outside the body: becomes a graph input bound to `tokens`.
    fn external(&mut self, tokens: proc_macro2::TokenStream, name: String) -> Value {
        let node = self.externals.get_or_insert(self.graph, name, tokens);
        Value::Real(node)
    }

    fn assoc_const(&mut self, name: &str, c: &'a syn::ImplItemConst) -> Value {
        if let Some(v) = self.const_cache.get(name) {
            return v.clone();
        }
        if self.const_stack.iter().any(|n| n == name) {
            return self.error(
                &c.ident,
                format!("the constant `Self::{name}` is defined in terms of itself"),
            );
        }
        self.const_stack.push(name.to_string());
        let shape = self.shape_of(&c.ty);
        let value = self.expr(&mut Env::default(), &c.expr);
        self.const_stack.pop();
        let value = match shape {
            Some(shape) if !shape.admits(&value) => self.error(
                &c.expr,
                format!(
                    "`Self::{name}` is declared {} but its value is {}",
                    shape.describe(),
                    value.describe()
                ),
            ),
            Some(_) => value,
            None => Value::Poison,
        };
        self.const_cache.insert(name.to_string(), value.clone());
        value
    }

    fn field(&mut self, env: &mut Env, f: &syn::ExprField) -> Value {
        let is_self = matches!(&*f.base, Expr::Path(p) if p.path.is_ident("self"));
        if !is_self {
            let base = self.expr(env, &f.base);
            if let Some(value) = self.geometry_field(&base, f) {
                return value;
            }
            return match (base, &f.member) {
                (Value::Tuple(items), syn::Member::Unnamed(i)) => match items.get(i.index as usize) {
                    Some(v) => v.clone(),
                    None => self.error(&f.member, format!("this tuple has {} elements", items.len())),
                },
                (Value::Poison, _) => Value::Poison,
                _ => self.error(
                    f,
                    "field access is only supported on `self` (the model's parameters, `self.field`) \
                     and on tuples (`t.0`)",
                ),
            };
        }
        let name = match &f.member {
            syn::Member::Named(id) => format!("self.{id}"),
            syn::Member::Unnamed(i) => format!("self.{}", i.index),
        };
        self.external(f.to_token_stream(), name)
    }

    fn index(&mut self, env: &mut Env, i: &syn::ExprIndex) -> Value {
        if let Expr::Field(f) = &*i.expr
            && matches!(&*f.base, Expr::Path(p) if p.path.is_ident("self"))
        {
            return self.parameter_entry(env, f, i);
        }
        let base = self.expr(env, &i.expr);
        let index = self.expr(env, &i.index);
        match (base, index) {
            (Value::Poison, _) | (_, Value::Poison) => Value::Poison,
            (Value::Geo(geo), index) => self.geometry_index(geo, index, i),
            (Value::Array(items), Value::Int(k)) => {
                match usize::try_from(k).ok().and_then(|k| items.get(k)) {
                    Some(v) => v.clone(),
                    None => self.error(
                        i,
                        format!(
                            "index {k} is out of bounds for an array of length {}",
                            items.len()
                        ),
                    ),
                }
            }
            (Value::Array(_), other) => {
                let message = self.index_message(env, &i.index, &other);
                self.error(&i.index, message)
            }
            (other, _) => self.error(
                &i.expr,
                format!("only arrays can be indexed, this is {}", other.describe()),
            ),
        }
    }

    /// An entry of an array parameter, `self.m[i]` with `i` known at compile time: one
    /// external value, read as `self.m[2]` with the user's spans, so that an index out of
    /// the array's range is rustc's error at the user's code (the struct's length is not
    /// known here).
    fn parameter_entry(&mut self, env: &mut Env, f: &syn::ExprField, i: &syn::ExprIndex) -> Value {
        let syn::Member::Named(member) = &f.member else {
            return self.error(f, "parameters are named fields: `self.mass`, `self.m[i]`");
        };
        match self.expr(env, &i.index) {
            Value::Poison => Value::Poison,
            Value::Int(k) if k >= 0 => {
                let span = syn::spanned::Spanned::span(&i.index);
                let largest = self
                    .parameter_arrays
                    .entry(member.to_string())
                    .or_insert((k as usize, span));
                if k as usize > largest.0 {
                    *largest = (k as usize, span);
                }
                let mut index = proc_macro2::Literal::usize_unsuffixed(k as usize);
                index.set_span(span);
                let base = &f.base;
                let tokens = quote::quote!(#base.#member[#index]);
                self.external(tokens, format!("self.{member}[{k}]"))
            }
            other => {
                let message = self.index_message(env, &i.index, &other);
                self.error(&i.index, message)
            }
        }
    }

    /// Why an index is not an integer known at compile time; an unknown name gets a
    /// suggestion among the constants the macro knows.
    fn index_message(&self, env: &Env, index: &Expr, value: &Value) -> String {
        let generic = format!(
            "an index must be an integer known at compile time (a literal, a loop counter or a \
             constant), found {}",
            value.describe()
        );
        let Expr::Path(p) = index else {
            return generic;
        };
        let segments: Vec<String> = p
            .path
            .segments
            .iter()
            .map(|s| s.ident.to_string())
            .collect();
        let name = match segments.as_slice() {
            [s, name] if s == "Self" => name.clone(),
            // A bare name that is no local: a constant from outside the impl.
            [name] if env.get(name).is_none() && is_constant_name(name) => name.clone(),
            _ => return generic,
        };
        let written = segments.join("::");
        let known = self.ctx.generated_names();
        if known.contains(&name) {
            return format!("write `Self::{name}`: the index constants belong to the model");
        }
        if known.is_empty() {
            return format!(
                "`{written}` is not an integer constant of this impl: an index must be known at \
                 compile time; define it in the impl, `const {name}: usize = ..;`, and write \
                 `Self::{name}`"
            );
        }
        let list: Vec<String> = known.iter().map(|k| format!("`Self::{k}`")).collect();
        let hint = match closest(&name, known) {
            Some(k) => format!("; did you mean `Self::{k}`?"),
            None => String::new(),
        };
        format!(
            "`{written}` is not a coordinate, speed or input of this model{hint} (the index \
             constants are the names in `#[hamel_system(..)]` in upper case: {})",
            list.join(", ")
        )
    }

    fn binary(&mut self, env: &mut Env, b: &syn::ExprBinary) -> Value {
        let compound = match b.op {
            BinOp::AddAssign(_) => Some(BinOp::Add(Default::default())),
            BinOp::SubAssign(_) => Some(BinOp::Sub(Default::default())),
            BinOp::MulAssign(_) => Some(BinOp::Mul(Default::default())),
            BinOp::DivAssign(_) => Some(BinOp::Div(Default::default())),
            BinOp::RemAssign(_)
            | BinOp::BitXorAssign(_)
            | BinOp::BitAndAssign(_)
            | BinOp::BitOrAssign(_)
            | BinOp::ShlAssign(_)
            | BinOp::ShrAssign(_) => {
                return self.error(b.op, "only `=`, `+=`, `-=`, `*=` and `/=` are supported");
            }
            _ => None,
        };
        if let Some(op) = compound {
            let current = self.expr(env, &b.left);
            let rhs = self.expr(env, &b.right);
            let value = self.arith(&op, current, rhs, b);
            self.assign(env, &b.left, value);
            return Value::Unit;
        }
        let left = self.expr(env, &b.left);
        let right = self.expr(env, &b.right);
        self.arith(&b.op, left, right, b)
    }

    /// Apply a binary operator to two values (arithmetic, comparison or logic).
    fn arith(&mut self, op: &BinOp, left: Value, right: Value, at: &syn::ExprBinary) -> Value {
        if left.is_poison() || right.is_poison() {
            return Value::Poison;
        }
        if let Some(value) = self.geometry_arith(op, &left, &right, at) {
            return value;
        }
        let g = &mut *self.graph;
        let cmp = match op {
            BinOp::Lt(_) => Some(Cmp::Lt),
            BinOp::Le(_) => Some(Cmp::Le),
            BinOp::Gt(_) => Some(Cmp::Gt),
            BinOp::Ge(_) => Some(Cmp::Ge),
            BinOp::Eq(_) => Some(Cmp::Eq),
            BinOp::Ne(_) => Some(Cmp::Ne),
            _ => None,
        };
        match (left, right) {
            (Value::Poison, _) | (_, Value::Poison) => Value::Poison,
            (Value::Real(a), Value::Real(c)) => match (op, cmp) {
                (_, Some(cmp)) => Value::Bool(g.compare(cmp, a, c)),
                (BinOp::Add(_), _) => Value::Real(g.add(a, c)),
                (BinOp::Sub(_), _) => Value::Real(g.sub(a, c)),
                (BinOp::Mul(_), _) => Value::Real(g.mul(a, c)),
                (BinOp::Div(_), _) => Value::Real(g.div(a, c)),
                (BinOp::Rem(_), _) => self.error(op, "`%` on `f64` is not supported"),
                _ => self.error(op, "this operator is not supported on `f64`"),
            },
            (Value::Int(a), Value::Int(c)) => {
                if let Some(cmp) = cmp {
                    let truth = cmp.apply(a as f64, c as f64);
                    return Value::Bool(g.boolean(truth));
                }
                let result = match op {
                    BinOp::Add(_) => a.checked_add(c),
                    BinOp::Sub(_) => a.checked_sub(c),
                    BinOp::Mul(_) => a.checked_mul(c),
                    BinOp::Div(_) => a.checked_div(c),
                    BinOp::Rem(_) => a.checked_rem(c),
                    _ => return self.error(op, "this operator is not supported on integers"),
                };
                match result {
                    Some(v) => Value::Int(v),
                    None => self.error(
                        at,
                        "integer overflow or division by zero in a compile-time expression",
                    ),
                }
            }
            (Value::Bool(a), Value::Bool(c)) => match op {
                BinOp::And(_) => Value::Bool(g.and(a, c)),
                BinOp::Or(_) => Value::Bool(g.or(a, c)),
                BinOp::Eq(_) | BinOp::Ne(_) => {
                    let both = g.and(a, c);
                    let na = g.not(a);
                    let nc = g.not(c);
                    let neither = g.and(na, nc);
                    let equal = g.or(both, neither);
                    Value::Bool(if matches!(op, BinOp::Eq(_)) {
                        equal
                    } else {
                        g.not(equal)
                    })
                }
                _ => self.error(
                    op,
                    "on `bool`, only `&&`, `||`, `==` and `!=` are supported",
                ),
            },
            (l @ (Value::Real(_) | Value::Int(_)), Value::Real(_) | Value::Int(_)) => {
                let int_side = if matches!(l, Value::Int(_)) {
                    &at.left
                } else {
                    &at.right
                };
                self.error(
                    int_side,
                    "this is an integer but the other operand is `f64`: write a float literal such as \
                     `2.0`, or convert with `as f64`",
                )
            }
            (l, r) => self.error(
                at,
                format!(
                    "this operator cannot combine {} and {}",
                    l.describe(),
                    r.describe()
                ),
            ),
        }
    }

    fn unary_expr(&mut self, env: &mut Env, u: &syn::ExprUnary) -> Value {
        let value = self.expr(env, &u.expr);
        match (&u.op, value) {
            (_, Value::Poison) => Value::Poison,
            (UnOp::Deref(_), v) => v,
            (UnOp::Neg(_), Value::Real(a)) => Value::Real(self.graph.neg(a)),
            (UnOp::Neg(_), Value::Geo(geo)) => self.geometry_neg(geo, u),
            (UnOp::Neg(_), Value::Int(a)) => match a.checked_neg() {
                Some(v) => Value::Int(v),
                None => self.error(u, "integer overflow"),
            },
            (UnOp::Not(_), Value::Bool(a)) => Value::Bool(self.graph.not(a)),
            (op, v) => self.error(
                u,
                format!(
                    "`{}` cannot be applied to {}",
                    op.to_token_stream(),
                    v.describe()
                ),
            ),
        }
    }

    fn array(&mut self, env: &mut Env, a: &syn::ExprArray) -> Value {
        let items: Vec<Value> = a.elems.iter().map(|e| self.expr(env, e)).collect();
        if items.iter().any(Value::is_poison) {
            return Value::Poison;
        }
        if items.is_empty() {
            return self.error(a, "empty arrays are not supported");
        }
        let first = items[0].describe();
        if let Some((i, odd)) = items
            .iter()
            .enumerate()
            .find(|(_, v)| v.describe() != first)
        {
            let at = a
                .elems
                .iter()
                .nth(i)
                .map(|e| e.to_token_stream())
                .unwrap_or_else(|| a.to_token_stream());
            return self.error(
                at,
                format!(
                    "array elements must all have the same type: {first} and {}",
                    odd.describe()
                ),
            );
        }
        Value::Array(items)
    }

    fn repeat(&mut self, env: &mut Env, r: &syn::ExprRepeat) -> Value {
        let item = self.expr(env, &r.expr);
        let Some(n) = self.const_int(&r.len, "the length of `[value; N]`") else {
            return Value::Poison;
        };
        match usize::try_from(n) {
            Ok(n) if n > 0 && n <= super::types::MAX_ARRAY_ELEMENTS => Value::Array(vec![item; n]),
            _ => self.error(
                &r.len,
                "the length of `[value; N]` must be between 1 and 2^20",
            ),
        }
    }

    fn cast(&mut self, env: &mut Env, c: &syn::ExprCast) -> Value {
        let value = self.expr(env, &c.expr);
        let target = c.ty.to_token_stream().to_string();
        let integer_target = matches!(
            target.as_str(),
            "usize" | "isize" | "u8" | "u16" | "u32" | "u64" | "i8" | "i16" | "i32" | "i64"
        );
        match (value, target.as_str()) {
            (Value::Poison, _) => Value::Poison,
            (Value::Int(n), "f64") => Value::Real(self.graph.constant(n as f64)),
            (v @ Value::Real(_), "f64") => v,
            (v @ Value::Int(_), _) if integer_target => v,
            (Value::Real(_), _) if integer_target => self.error(
                c,
                "an `f64` computed at run time cannot become an integer: indices and loop bounds must \
                 be known at compile time",
            ),
            (v, _) => self.error(c, format!("cannot cast {} to `{target}`", v.describe())),
        }
    }

    /// Store `value` into a mutable local, or an element of one.
    pub fn assign(&mut self, env: &mut Env, target: &Expr, value: Value) {
        let mut indices = Vec::new();
        let mut base = target;
        loop {
            match base {
                Expr::Index(i) => {
                    indices.push(&*i.index);
                    base = &i.expr;
                }
                Expr::Paren(p) => base = &p.expr,
                _ => break,
            }
        }
        indices.reverse();
        let name = match base {
            Expr::Path(p) if p.path.get_ident().is_some() => p.path.segments[0].ident.to_string(),
            Expr::Field(f) if matches!(&*f.base, Expr::Path(p) if p.path.is_ident("self")) => {
                let field = f.member.to_token_stream().to_string();
                self.error(
                    target,
                    format!(
                        "parameters are read-only in the model's functions: copy `self.{field}` \
                         into a local first, `let mut {field} = self.{field};`"
                    ),
                );
                return;
            }
            _ => {
                self.error(
                    target,
                    "only `let mut` locals (or their elements) can be assigned to",
                );
                return;
            }
        };
        let mut positions = Vec::new();
        for index in indices {
            match self.expr(env, index) {
                Value::Int(k) => positions.push((k, index)),
                Value::Poison => return,
                other => {
                    self.error(
                        index,
                        format!(
                            "an index must be an integer known at compile time, found {}",
                            other.describe()
                        ),
                    );
                    return;
                }
            }
        }
        let Some(local) = env.get(&name) else {
            self.error(base, format!("cannot find `{name}` here"));
            return;
        };
        if !local.mutable {
            self.error(
                base,
                format!(
                    "`{name}` is not mutable: declare it `let mut {name}` (arguments are read-only; \
                     copy one into a local with `let mut {name} = *{name};`)"
                ),
            );
            return;
        }
        let mut whole = local.value.clone();
        let mut slot = &mut whole;
        for (k, at) in positions {
            let len = match slot {
                Value::Array(items) => items.len(),
                Value::Poison => return,
                other => {
                    let msg = format!("{} cannot be indexed", other.describe());
                    self.error(at, msg);
                    return;
                }
            };
            match (usize::try_from(k).ok().filter(|&k| k < len), slot) {
                (Some(k), Value::Array(items)) => slot = &mut items[k],
                _ => {
                    self.error(
                        at,
                        format!("index {k} is out of bounds for an array of length {len}"),
                    );
                    return;
                }
            }
        }
        if !same_kind(slot, &value) {
            let msg = format!(
                "cannot assign {} to `{name}`, which holds {}",
                value.describe(),
                slot.describe()
            );
            self.error(target, msg);
            return;
        }
        *slot = value;
        if let Some(local) = env.get_mut(&name) {
            local.value = whole;
        }
    }
}

/// The candidate closest to `name`, if it is close enough to be a typo (edit distance with
/// transpositions, at most a third of the name's length, at least one).
pub fn closest<'c>(name: &str, candidates: &'c [String]) -> Option<&'c String> {
    let distance = |a: &str, b: &str| {
        let (a, b): (Vec<char>, Vec<char>) = (a.chars().collect(), b.chars().collect());
        let mut d = vec![vec![0usize; b.len() + 1]; a.len() + 1];
        for (i, row) in d.iter_mut().enumerate() {
            row[0] = i;
        }
        d[0] = (0..=b.len()).collect();
        for i in 1..=a.len() {
            for j in 1..=b.len() {
                let cost = usize::from(a[i - 1] != b[j - 1]);
                let mut best = (d[i - 1][j] + 1)
                    .min(d[i][j - 1] + 1)
                    .min(d[i - 1][j - 1] + cost);
                if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                    best = best.min(d[i - 2][j - 2] + 1);
                }
                d[i][j] = best;
            }
        }
        d[a.len()][b.len()]
    };
    let limit = (name.chars().count() / 3).max(1);
    candidates
        .iter()
        .map(|c| (distance(name, c), c))
        .filter(|&(d, _)| d <= limit)
        .min_by_key(|&(d, _)| d)
        .map(|(_, c)| c)
}

/// Whether a value may replace another in an assignment.
fn same_kind(old: &Value, new: &Value) -> bool {
    match (old, new) {
        (Value::Poison, _) | (_, Value::Poison) => true,
        (Value::Real(_), Value::Real(_))
        | (Value::Int(_), Value::Int(_))
        | (Value::Bool(_), Value::Bool(_)) => true,
        (Value::Array(a), Value::Array(b)) | (Value::Tuple(a), Value::Tuple(b)) => {
            a.len() == b.len() && a.iter().zip(b).all(|(x, y)| same_kind(x, y))
        }
        (Value::Geo(a), Value::Geo(b)) => a.kind() == b.kind(),
        _ => false,
    }
}
