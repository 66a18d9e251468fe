//! Calls: the elementary functions of `f64` (`x.sin()`, `f64::atan2(y, x)`) and the other
//! functions of the impl, which are inlined.

use super::value::Value;
use super::{Env, Lowerer};
use crate::engine::graph::{Cmp, Func, Func2};
use quote::ToTokens;
use syn::Expr;

pub const ELEMENTARY: &str = "sin cos sin_cos tan asin acos atan atan2 sinh cosh tanh exp ln log10 \
     sqrt cbrt powi powf hypot recip mul_add abs signum min max";

/// An elementary function by its `f64` method name.
#[derive(Clone, Copy)]
enum Elementary {
    Unary(Func),
    Binary(Func2),
    Recip,
    Powi,
    MulAdd,
    Min,
    Max,
}

impl Elementary {
    fn by_name(name: &str) -> Option<Self> {
        use Elementary::*;
        Some(match name {
            "sin" => Unary(Func::Sin),
            "cos" => Unary(Func::Cos),
            "tan" => Unary(Func::Tan),
            "asin" => Unary(Func::Asin),
            "acos" => Unary(Func::Acos),
            "atan" => Unary(Func::Atan),
            "sinh" => Unary(Func::Sinh),
            "cosh" => Unary(Func::Cosh),
            "tanh" => Unary(Func::Tanh),
            "exp" => Unary(Func::Exp),
            "ln" => Unary(Func::Ln),
            "log10" => Unary(Func::Log10),
            "sqrt" => Unary(Func::Sqrt),
            "cbrt" => Unary(Func::Cbrt),
            "abs" => Unary(Func::Abs),
            "signum" => Unary(Func::Signum),
            "powf" => Binary(Func2::Powf),
            "atan2" => Binary(Func2::Atan2),
            "hypot" => Binary(Func2::Hypot),
            "recip" => Recip,
            "powi" => Powi,
            "mul_add" => MulAdd,
            "min" => Min,
            "max" => Max,
            _ => return None,
        })
    }

    /// Arguments besides the receiver.
    fn arity(&self) -> usize {
        match self {
            Elementary::Unary(_) | Elementary::Recip => 0,
            Elementary::Binary(_) | Elementary::Powi | Elementary::Min | Elementary::Max => 1,
            Elementary::MulAdd => 2,
        }
    }
}

impl<'a> Lowerer<'a, '_> {
    pub fn method_call(&mut self, env: &mut Env, m: &syn::ExprMethodCall) -> Value {
        if let Some(t) = &m.turbofish {
            return self.error(t, "turbofish arguments are not supported here");
        }
        let name = m.method.to_string();
        if matches!(&*m.receiver, Expr::Path(p) if p.path.is_ident("self")) {
            return self.inline(env, &name, true, m.args.iter(), m);
        }
        let receiver = self.expr(env, &m.receiver);
        if name == "len" && m.args.is_empty() {
            return match receiver {
                Value::Array(items) => Value::Int(items.len() as i64),
                Value::Poison => Value::Poison,
                other => self.error(
                    &m.receiver,
                    format!("`len` needs an array, this is {}", other.describe()),
                ),
            };
        }
        let args: Vec<Value> = m.args.iter().map(|a| self.expr(env, a)).collect();
        if let Value::Geo(geo) = receiver {
            return self.geometry_method(geo, m, args);
        }
        self.elementary(&name, receiver, args, m, &m.method)
    }

    pub fn call_expr(&mut self, env: &mut Env, c: &syn::ExprCall) -> Value {
        let Expr::Path(p) = &*c.func else {
            return self.error(&c.func, "only named functions can be called");
        };
        let segments: Vec<String> = p
            .path
            .segments
            .iter()
            .map(|s| s.ident.to_string())
            .collect();
        let segs: Vec<&str> = segments.iter().map(String::as_str).collect();
        if let Some(value) = self.geometry_call(env, &segs, c) {
            return value;
        }
        match segs.as_slice() {
            ["f64", name] | ["std" | "core", "f64", name] => {
                let mut args = c.args.iter();
                let Some(first) = args.next() else {
                    return self.error(
                        c,
                        format!("`f64::{name}` needs its receiver as first argument"),
                    );
                };
                let receiver = self.expr(env, first);
                let rest: Vec<Value> = args.map(|a| self.expr(env, a)).collect();
                let name = name.to_string();
                self.elementary(&name, receiver, rest, c, &p.path)
            }
            ["Self", name] => match self.helper_scope.last().cloned() {
                Some(set) => self.inline_helper(env, &set, name, c),
                None => {
                    let name = name.to_string();
                    self.inline(env, &name, false, c.args.iter(), c)
                }
            },
            // A set of shared helpers by its name or its path (`Wheels::disk`,
            // `shapes::Wheels::disk`): the set is known by its type's name.
            [.., set, name] if self.ctx.helper(set, name).is_some() => {
                let set = set.to_string();
                self.inline_helper(env, &set, name, c)
            }
            [name] => self.unqualified_call(env, name, c),
            _ => {
                let path = segments.join("::");
                let set = segments.len().checked_sub(2).map(|i| segments[i].as_str());
                self.error_once(
                    format!("call {path}"),
                    &c.func,
                    format!(
                        "unknown function `{path}`: the macro differentiates the source of what a \
                         body calls, and it sees only the functions of this impl block, the \
                         elementary functions of `f64` ({ELEMENTARY}), hamel's geometry and \
                         shared helpers; if `{}` holds shared helpers, mark its impl with \
                         `#[hamel::helpers]` and name it in `#[hamel_system(helpers(..))]`",
                        set.unwrap_or("Helpers")
                    ),
                )
            }
        }
    }

    /// A call by a bare name, `name(..)`: never one the macro can inline (those are
    /// `Self::name` or `self.name`); the error says what the name is.
    fn unqualified_call(&mut self, env: &mut Env, name: &str, c: &syn::ExprCall) -> Value {
        match env.get(name).map(|local| local.value.clone()) {
            // A local whose definition was already reported (a closure).
            Some(Value::Poison) => return Value::Poison,
            Some(other) => {
                return self.error(
                    &c.func,
                    format!(
                        "`{name}` is a local holding {}, not a function",
                        other.describe()
                    ),
                );
            }
            None => {}
        }
        let message = match self.ctx.function(name) {
            Some(f) if f.sig.receiver().is_some() => format!(
                "`{name}` is a function of this impl that takes `self`: call it as `self.{name}(..)`"
            ),
            Some(_) => {
                format!("`{name}` is a function of this impl: call it as `Self::{name}(..)`")
            }
            None => format!(
                "unknown function `{name}`: the macro differentiates the source of what a body \
                 calls, and it sees only the functions of this impl block and the elementary \
                 functions of `f64` ({ELEMENTARY}); move `{name}` into this impl and call it as \
                 `Self::{name}(..)`"
            ),
        };
        self.error_once(format!("call {name}"), &c.func, message)
    }

    fn elementary(
        &mut self,
        name: &str,
        receiver: Value,
        args: Vec<Value>,
        call: &dyn ToTokens,
        name_tokens: &dyn ToTokens,
    ) -> Value {
        // The one elementary function with two results (`x.sin_cos()`, `f64::sin_cos(x)`).
        if name == "sin_cos" {
            return match (receiver, args.as_slice()) {
                (Value::Real(x), []) => {
                    let s = self.graph.unary(Func::Sin, x);
                    let c = self.graph.unary(Func::Cos, x);
                    Value::Tuple(vec![Value::Real(s), Value::Real(c)])
                }
                (Value::Poison, _) => Value::Poison,
                (_, [_, ..]) => self.error(
                    call.to_token_stream(),
                    "`sin_cos` takes no argument besides the receiver",
                ),
                (other, []) => self.error(
                    call.to_token_stream(),
                    format!("`sin_cos` needs an `f64`, this is {}", other.describe()),
                ),
            };
        }
        let Some(f) = Elementary::by_name(name) else {
            return self.error(
                name_tokens.to_token_stream(),
                format!(
                    "unsupported function `{name}`: the elementary functions are {ELEMENTARY}; other \
                     functions of this impl are called as `self.{name}(..)`"
                ),
            );
        };
        if args.len() != f.arity() {
            return self.error(
                call.to_token_stream(),
                format!(
                    "`{name}` takes {} argument(s) besides the receiver, {} given",
                    f.arity(),
                    args.len()
                ),
            );
        }
        if receiver.is_poison() || args.iter().any(Value::is_poison) {
            return Value::Poison;
        }
        let Value::Real(x) = receiver else {
            let hint = if matches!(receiver, Value::Int(_)) {
                " (an integer: write a float literal such as `2.0`, or use `as f64`)"
            } else {
                ""
            };
            return self.error(
                call.to_token_stream(),
                format!(
                    "`{name}` needs an `f64` receiver, this is {}{hint}",
                    receiver.describe()
                ),
            );
        };
        let g = &mut *self.graph;
        match (f, args.as_slice()) {
            (Elementary::Unary(func), []) => Value::Real(g.unary(func, x)),
            (Elementary::Recip, []) => {
                let one = g.one();
                Value::Real(g.div(one, x))
            }
            (Elementary::Powi, [Value::Int(n)]) => match i32::try_from(*n) {
                Ok(n) => Value::Real(g.powi(x, n)),
                Err(_) => self.error(
                    call.to_token_stream(),
                    "the exponent of `powi` does not fit in an `i32`",
                ),
            },
            (Elementary::Powi, [other]) => self.error(
                call.to_token_stream(),
                format!(
                    "the exponent of `powi` must be an integer known at compile time, found {}{}",
                    other.describe(),
                    if matches!(other, Value::Real(_)) {
                        " (use `powf` for a real exponent)"
                    } else {
                        ""
                    }
                ),
            ),
            (Elementary::Binary(func), [Value::Real(y)]) => Value::Real(g.binary(func, x, *y)),
            (Elementary::MulAdd, [Value::Real(a), Value::Real(b)]) => {
                // Lowered to x·a + b: the same value up to one rounding, and without the slow
                // software `fma` call on targets that lack the instruction.
                let p = g.mul(x, *a);
                Value::Real(g.add(p, *b))
            }
            (Elementary::Min | Elementary::Max, [Value::Real(y)]) => {
                let op = if matches!(f, Elementary::Min) {
                    Cmp::Lt
                } else {
                    Cmp::Gt
                };
                let c = g.compare(op, x, *y);
                Value::Real(g.select(c, x, *y))
            }
            (_, bad) => {
                let found: Vec<String> = bad.iter().map(Value::describe).collect();
                self.error(
                    call.to_token_stream(),
                    format!("`{name}` takes `f64` arguments, found {}", found.join(", ")),
                )
            }
        }
    }

    /// Inline a call of a shared helper, `Set::name(..)`: in its body `Self` is the set.
    fn inline_helper(&mut self, env: &mut Env, set: &str, name: &str, c: &syn::ExprCall) -> Value {
        let args: Vec<Value> = c.args.iter().map(|a| self.expr(env, a)).collect();
        let f = match self.ctx.helper(set, name) {
            Some(Ok(f)) => f,
            Some(Err(known)) => {
                return self.error_once(
                    format!("call {set}::{name}"),
                    &c.func,
                    format!(
                        "the shared helpers `{set}` have no function `{name}` (they have {})",
                        known
                            .iter()
                            .map(|k| format!("`{k}`"))
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                );
            }
            None => {
                return self.error(
                    &c.func,
                    format!("`Self::{name}` in the helpers `{set}`: no such helper"),
                );
            }
        };
        if args.iter().any(Value::is_poison) {
            return Value::Poison;
        }
        self.helper_scope.push(set.to_string());
        let value = self.call(f, args, c);
        self.helper_scope.pop();
        value
    }

    /// Inline a call of another function of the impl.
    fn inline<'e>(
        &mut self,
        env: &mut Env,
        name: &str,
        with_self: bool,
        args: impl Iterator<Item = &'e Expr>,
        call: &dyn ToTokens,
    ) -> Value {
        let args: Vec<Value> = args.map(|a| self.expr(env, a)).collect();
        let Some(f) = self.ctx.function(name) else {
            let hint = if Elementary::by_name(name).is_some() {
                format!(
                    " (`{name}` is an elementary function: call it on a number, `x.{name}(..)`)"
                )
            } else {
                String::new()
            };
            return self.error_once(
                format!("call self {name}"),
                call.to_token_stream(),
                format!(
                    "no function `{name}` in this impl: the macro can only inline functions defined in \
                     the impl block it annotates{hint}"
                ),
            );
        };
        let takes_self = f.sig.receiver().is_some();
        if takes_self != with_self {
            let how = if takes_self {
                format!("self.{name}(..)")
            } else {
                format!("Self::{name}(..)")
            };
            return self.error(call.to_token_stream(), format!("call `{name}` as `{how}`"));
        }
        if args.iter().any(Value::is_poison) {
            return Value::Poison;
        }
        self.call(f, args, call)
    }
}
