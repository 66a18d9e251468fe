//! "The macro never panics": input outside the supported subset, or not Rust at all, must
//! come back from `differentiate::expand` as `compile_error!` with a message that names
//! the problem. First hand-written cases, one per kind of mistake; then random token soup.

use super::{compile_errors, tokens};
use crate::differentiate::expand;
use proc_macro2::{Delimiter, Group, Literal, Punct, Spacing, TokenStream, TokenTree};
use proptest::prelude::*;
use proptest::sample::select;
use proptest::test_runner::{Config, TestRunner};
use quote::quote;
use std::panic::{AssertUnwindSafe, catch_unwind};

/// One mistake: the attribute arguments and item given to the macro, and a fragment that
/// the error message must contain to count as naming the problem.
struct Case {
    what: &'static str,
    attr: TokenStream,
    item: TokenStream,
    expect: &'static str,
}

/// A case whose mistake is in the body of `f(&self, x: f64, q: &[f64; 3]) -> f64`.
fn in_body(what: &'static str, body: &str, expect: &'static str) -> Case {
    item(
        what,
        &format!("impl Model {{ fn f(&self, x: f64, q: &[f64; 3]) -> f64 {{ {body} }} }}"),
        expect,
    )
}

/// A case given as a whole item.
fn item(what: &'static str, source: &str, expect: &'static str) -> Case {
    Case {
        what,
        attr: TokenStream::new(),
        item: tokens(source),
        expect,
    }
}

/// Run the expansion, turning a panic into an `Err` with its message.
fn expand_caught(attr: TokenStream, item: TokenStream) -> Result<TokenStream, String> {
    catch_unwind(AssertUnwindSafe(|| expand(attr, item))).map_err(|payload| {
        payload
            .downcast_ref::<String>()
            .cloned()
            .or_else(|| payload.downcast_ref::<&str>().map(|s| s.to_string()))
            .unwrap_or_else(|| "(no message)".into())
    })
}

/// Expand every case and report all that panic or whose errors miss the expected
/// fragment, so that one run shows every regression at once.
fn check_all(cases: Vec<Case>) {
    let mut failures = Vec::new();
    for case in cases {
        match expand_caught(case.attr, case.item) {
            Err(panic) => failures.push(format!("{}: panicked: {panic}", case.what)),
            Ok(out) => {
                let errors = compile_errors(&out);
                if !errors.iter().any(|e| e.contains(case.expect)) {
                    failures.push(format!(
                        "{}: expected an error containing {:?}, got {errors:#?}",
                        case.what, case.expect
                    ));
                }
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

#[test]
fn control_flow_outside_the_subset_is_named() {
    check_all(vec![
        in_body(
            "while",
            "let mut s = x; while s > 1.0 { s = s / 2.0; } s",
            "`while` loops are not supported",
        ),
        in_body(
            "loop",
            "let mut s = x; loop { s = s * 0.5; } s",
            "`loop` is not supported",
        ),
        in_body(
            "match on an f64",
            "match x { v => v * 2.0 }",
            "`match` is not supported",
        ),
        in_body(
            "closure",
            "let sq = |t: f64| t * t; sq(x)",
            "closures are not supported",
        ),
        in_body(
            "early return",
            "if x > 0.0 { return x; } -x",
            "`return` is not supported",
        ),
        in_body(
            "break",
            "for i in 0..3 { break; } x",
            "`break` is not supported",
        ),
        in_body(
            "if without else as a value",
            "let y = if x > 0.0 { x }; y",
            "an `if` without `else` cannot produce a value",
        ),
        in_body(
            "missing tail expression",
            "x * 2.0;",
            "but its body evaluates to `()`",
        ),
        in_body(
            "let without initializer",
            "let y: f64; y = x; y",
            "a `let` needs a value",
        ),
        in_body(
            "macro call in a body",
            r#"println!("{}", x); x"#,
            "macros (`println!`) are not supported",
        ),
        in_body(
            "macro in expression position",
            "x + dbg!(x)",
            "macros (`dbg!`) are not supported",
        ),
        in_body(
            "if on a number",
            "if x { 1.0 } else { 2.0 }",
            "an `if` condition must be a comparison",
        ),
        in_body(
            "nested fn",
            "fn g(t: f64) -> f64 { t } x",
            "nested functions are not supported",
        ),
    ]);
}

#[test]
fn assignments_and_names_outside_the_subset_are_named() {
    check_all(vec![
        in_body(
            "assignment to a parameter",
            "self.m = 1.0; x",
            "parameters are read-only",
        ),
        in_body(
            "assignment to an immutable local",
            "let y = x; y = 2.0 * x; y",
            "`y` is not mutable",
        ),
        in_body(
            "assignment to an argument",
            "x += 1.0; x",
            "`x` is not mutable",
        ),
        in_body("unknown local", "x + zeta", "cannot find `zeta` here"),
        in_body("bare self", "let s = self; x", "`self` is not a number"),
        in_body(
            "assignment of a different type",
            "let mut y = x; y = q; y",
            "cannot assign `[f64; 3]` to `y`",
        ),
        in_body(
            "field of a local",
            "let y = x; y.m",
            "field access is only supported on `self`",
        ),
    ]);
}

#[test]
fn loops_and_indices_outside_the_subset_are_named() {
    check_all(vec![
        in_body(
            "loop bound from a parameter",
            "let mut s = 0.0; for i in 0..self.n { s += x; } s",
            "a loop bound must be an integer known at compile time",
        ),
        in_body(
            "loop bound from a constant outside the impl",
            "let mut s = 0.0; for i in 0..N { s += x; } s",
            "define it in the impl",
        ),
        in_body(
            "huge loop bound",
            "let mut s = 0.0; for i in 0..100000000 { s += x; } s",
            "loops are unrolled at compile time",
        ),
        in_body(
            "open loop range",
            "let mut s = 0.0; for i in 0.. { s += x; } s",
            "a loop range needs both bounds",
        ),
        in_body(
            "constant index out of bounds",
            "q[3] * x",
            "index 3 is out of bounds for an array of length 3",
        ),
        in_body(
            "negative index",
            "q[0 - 1] * x",
            "index -1 is out of bounds",
        ),
        in_body(
            "index computed at run time",
            "q[x] * 2.0",
            "an index must be an integer known at compile time",
        ),
        in_body("indexing a number", "x[0]", "only arrays can be indexed"),
        in_body(
            "loop over a number",
            "let mut s = 0.0; for v in x { s += v; } s",
            "a `for` loop must run over a constant range",
        ),
        in_body(
            "array repeat too long",
            "let a = [x; 100000000]; a[0]",
            "must be between 1 and 2^20",
        ),
    ]);
}

#[test]
fn calls_outside_the_subset_are_named() {
    check_all(vec![
        in_body("unknown function", "foo(x)", "unknown function `foo`"),
        in_body(
            "unknown path function",
            "std::process::abort()",
            "unknown function `std::process::abort`",
        ),
        in_body(
            "unknown method",
            "x.frobnicate()",
            "unsupported function `frobnicate`",
        ),
        in_body(
            "helper not in the impl",
            "self.helper(x)",
            "no function `helper` in this impl",
        ),
        in_body(
            "powi with a run-time exponent",
            "let n = 2.0 * x; x.powi(n)",
            "the exponent of `powi` must be an integer known at compile time",
        ),
        in_body(
            "elementary function with too many arguments",
            "x.sin(x)",
            "`sin` takes 0 argument(s) besides the receiver, 1 given",
        ),
        item(
            "recursion through a helper",
            "impl Model {
                fn a(&self, x: f64) -> f64 { self.b(x) + 1.0 }
                fn b(&self, x: f64) -> f64 { self.a(x) * 2.0 }
            }",
            "recursive functions cannot be inlined",
        ),
        item(
            "helper called with the wrong number of arguments",
            "impl Model {
                fn h(&self, a: f64, b: f64) -> f64 { a * b }
                fn f(&self, x: f64) -> f64 { self.h(x) }
            }",
            "`h` takes 2 argument(s) besides `self`, but 1 were given",
        ),
        item(
            "associated function called as a method",
            "impl Model {
                fn h(a: f64) -> f64 { a * a }
                fn f(&self, x: f64) -> f64 { self.h(x) }
            }",
            "call `h` as `Self::h(..)`",
        ),
    ]);
}

#[test]
fn arithmetic_and_literals_outside_the_subset_are_named() {
    check_all(vec![
        in_body(
            "integer times f64",
            "2 * x",
            "this is an integer but the other operand is `f64`",
        ),
        in_body(
            "remainder on f64",
            "x % 2.0",
            "`%` on `f64` is not supported",
        ),
        in_body(
            "f32 literal",
            "x * 2.0f32",
            "`f32` literals are not supported",
        ),
        in_body(
            "f32 integer literal",
            "x * 2f32",
            "`f32` literals are not supported",
        ),
        in_body(
            "string literal",
            r#"let s = "abc"; x"#,
            "only numeric and boolean literals are supported",
        ),
        in_body(
            "integer overflow at compile time",
            "let n = 9223372036854775807 + 1; x",
            "integer overflow",
        ),
        in_body(
            "integer literal too large",
            "let n = 99999999999999999999; x",
            "number too large",
        ),
        in_body(
            "bit operation on f64",
            "x ^ x",
            "this operator is not supported on `f64`",
        ),
        in_body(
            "run-time f64 cast to an integer",
            "let n = x as usize; x",
            "an `f64` computed at run time cannot become an integer",
        ),
        in_body("not on a number", "!x", "`!` cannot be applied to `f64`"),
        in_body(
            "mixed array",
            "let a = [x, 1]; x",
            "array elements must all have the same type",
        ),
        in_body(
            "tuple returned as f64",
            "(x, x)",
            "is declared to return `f64`, but its body evaluates to a tuple of 2 elements",
        ),
    ]);
}

#[test]
fn signatures_outside_the_subset_are_named() {
    check_all(vec![
        item(
            "f32 argument",
            "impl Model { fn f(&self, x: f32) -> f64 { 1.0 } }",
            "unsupported type `f32` (hamel computes in `f64`)",
        ),
        item(
            "&mut argument",
            "impl Model { fn f(&self, x: &mut f64) -> f64 { *x } }",
            "mutable references cannot be differentiated",
        ),
        item(
            "&mut self",
            "impl Model { fn f(&mut self, x: f64) -> f64 { x } }",
            "take `&self`, not `&mut self`",
        ),
        item(
            "generic function",
            "impl Model { fn f<T>(&self, x: f64) -> f64 { x } }",
            "generic functions cannot be differentiated",
        ),
        item(
            "async function",
            "impl Model { async fn f(&self, x: f64) -> f64 { x } }",
            "`async` functions cannot be differentiated",
        ),
        item(
            "tuple return type",
            "impl Model { fn f(&self, x: f64) -> (f64, f64) { (x, x) } }",
            "unsupported type `(f64, f64)`: expected `f64` or a fixed-size array",
        ),
        item(
            "no return type",
            "impl Model { fn f(&self, x: f64) { } }",
            "`f` returns nothing",
        ),
        item(
            "Vec argument",
            "impl Model { fn f(&self, x: Vec<f64>) -> f64 { 0.0 } }",
            "unsupported type `Vec<f64>`",
        ),
        item(
            "array of integers",
            "impl Model { fn f(&self, x: [usize; 2]) -> f64 { 0.0 } }",
            "arrays of integers are not supported",
        ),
        item(
            "array length not an integer",
            "impl Model { fn f(&self, x: [f64; 2.0]) -> f64 { 0.0 } }",
            "an array length must be an integer known at compile time",
        ),
        item(
            "array length a constant the macro cannot read",
            "impl Model { fn f(&self, x: [f64; N]) -> f64 { 0.0 } }",
            "the array length `N` is a constant defined outside the impl block",
        ),
        item(
            "returns a bool",
            "impl Model { fn f(&self, x: f64) -> f64 { x > 0.0 } }",
            "but its body evaluates to `bool`",
        ),
    ]);
}

#[test]
fn items_and_attributes_outside_the_subset_are_named() {
    let valid = quote!(impl Model { fn f(&self, x: f64) -> f64 { x * x } });
    check_all(vec![
        item(
            "trait impl",
            "impl Foo for Bar { fn f(&self, x: f64) -> f64 { x } }",
            "not a trait impl",
        ),
        item("a lone fn", "fn f() {}", "expected `impl`"),
        item("a struct", "struct S;", "expected `impl`"),
        item("nothing at all", "", "expected `impl`"),
        item(
            "garbled body",
            "impl Model { fn f(&self, x: f64) -> f64 { x + } }",
            "expected an expression",
        ),
        item(
            "impl without a type",
            "impl { fn f(&self, x: f64) -> f64 { x } }",
            "expected",
        ),
        Case {
            what: "attribute arguments",
            attr: quote!(foo),
            item: valid.clone(),
            expect: "`#[differentiate]` takes no arguments",
        },
        Case {
            what: "attribute arguments with garbage",
            attr: quote!(= 1, ..),
            item: valid,
            expect: "`#[differentiate]` takes no arguments",
        },
    ]);
}

/// One build should show every independent mistake, not only the first.
#[test]
fn independent_mistakes_are_all_reported() {
    let two_functions = quote! {
        impl Model {
            fn a(&self, x: f64) -> f64 { let mut s = x; while s > 1.0 { s = s / 2.0; } s }
            fn b(&self, x: f64) -> f64 { x % 2.0 }
        }
    };
    let one_function = quote! {
        impl Model {
            fn f(&self, x: f64) -> f64 {
                let y = foo(x);
                let z = 2 * x;
                y + z
            }
        }
    };
    for (item, expected) in [
        (two_functions, ["`while` loops", "`%` on `f64`"]),
        (
            one_function,
            ["unknown function `foo`", "this is an integer"],
        ),
    ] {
        let errors = compile_errors(&expand(TokenStream::new(), item));
        assert_eq!(errors.len(), 2, "{errors:#?}");
        for fragment in expected {
            assert!(
                errors.iter().any(|e| e.contains(fragment)),
                "{fragment:?} not in {errors:#?}"
            );
        }
    }
}

/// Raw identifiers are valid Rust names; `r#type` must not make the macro panic, and the
/// expansion is then error-free.
#[test]
fn raw_identifiers_do_not_panic() {
    let sources = [
        // `format_ident!("{}_OPS", "R#TYPE")` panics: "R#TYPE_OPS" is not a valid Ident.
        "impl Model { fn r#type(&self, x: f64) -> f64 { x * x } }",
        // `syn::Ident::new("r#type", ..)` in `user_args` panics.
        "impl Model { fn f(&self, r#type: f64) -> f64 { r#type * r#type } }",
    ];
    let failures: Vec<String> = sources
        .iter()
        .filter_map(
            |source| match expand_caught(TokenStream::new(), tokens(source)) {
                Err(panic) => Some(format!("{source}: panicked: {panic}")),
                Ok(out) => {
                    let errors = compile_errors(&out);
                    (!errors.is_empty()).then(|| format!("{source}: {errors:?}"))
                }
            },
        )
        .collect();
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

// ---------------------------------------------------------------------------------------
// Token soup: random token sequences must never make the macro panic.

/// A token of the soup, kept as source-level pieces so that failures print readably.
#[derive(Clone, Debug)]
enum Soup {
    Word(&'static str),
    Punct(&'static str),
    /// Source text of a literal.
    Lit(String),
    Group(Delimiter, Vec<Soup>),
}

/// Keywords of the subset and around it, names a body may use, and some it may not.
const WORDS: &[&str] = &[
    "fn", "let", "for", "in", "if", "else", "self", "Self", "impl", "mut", "return", "while",
    "loop", "match", "const", "struct", "as", "pub", "async", "unsafe", "move", "where", "f64",
    "f32", "usize", "i32", "bool", "true", "false", "x", "q", "y", "i", "n", "N", "X", "f", "g",
    "_", "sin", "powi", "powf", "atan2", "mul_add", "sin_cos", "len", "iter", "rev", "std",
    "consts", "PI",
];

/// Punctuation, single and joint.
const PUNCTS: &[&str] = &[
    "+", "-", "*", "/", "%", "=", ";", ":", ",", ".", "&", "!", "<", ">", "|", "#", "?", "@", "..",
    "..=", "::", "->", "=>", "+=", "-=", "*=", "/=", "==", "!=", "<=", ">=", "&&", "||",
];

/// Literals that hit the edges of literal handling.
const ODD_LITERALS: &[&str] = &[
    "1e400",
    "1f32",
    "2f64",
    "3usize",
    "4i32",
    "18446744073709551616",
    "9223372036854775807",
    "0x1F",
    "1_000.5",
    "-1.5",
    "-7",
    "'c'",
    "b'a'",
    "\"text\"",
    "b\"bytes\"",
];

fn literal() -> impl Strategy<Value = String> {
    prop_oneof![
        (0u64..1000).prop_map(|n| Literal::u64_unsuffixed(n).to_string()),
        (0.0f64..1e6).prop_map(|v| Literal::f64_unsuffixed(v).to_string()),
        select(ODD_LITERALS).prop_map(str::to_string),
    ]
}

fn soup_token() -> impl Strategy<Value = Soup> {
    let leaf = prop_oneof![
        4 => select(WORDS).prop_map(Soup::Word),
        4 => select(PUNCTS).prop_map(Soup::Punct),
        2 => literal().prop_map(Soup::Lit),
    ];
    leaf.prop_recursive(3, 40, 6, |inner| {
        let delimiter = select(&[Delimiter::Parenthesis, Delimiter::Bracket, Delimiter::Brace][..]);
        (delimiter, prop::collection::vec(inner, 0..6)).prop_map(|(d, items)| Soup::Group(d, items))
    })
}

fn soup() -> impl Strategy<Value = Vec<Soup>> {
    prop::collection::vec(soup_token(), 0..60)
}

fn to_tokens(soup: &[Soup]) -> TokenStream {
    let mut out = TokenStream::new();
    for token in soup {
        match token {
            Soup::Word(w) => out.extend(tokens(w)),
            Soup::Punct(p) => {
                // Every character but the last is joint, so `..` stays one operator.
                let chars: Vec<char> = p.chars().collect();
                for (i, &c) in chars.iter().enumerate() {
                    let spacing = if i + 1 < chars.len() {
                        Spacing::Joint
                    } else {
                        Spacing::Alone
                    };
                    out.extend([TokenTree::Punct(Punct::new(c, spacing))]);
                }
            }
            Soup::Lit(l) => out.extend(tokens(l)),
            Soup::Group(d, items) => {
                out.extend([TokenTree::Group(Group::new(*d, to_tokens(items)))]);
            }
        }
    }
    out
}

/// Expand and check what can be checked without knowing whether the soup is valid: no
/// panic; an error whenever the item is not even an impl block; and otherwise, when there is
/// no error, output that parses as Rust items.
fn check_soup(attr: TokenStream, item: TokenStream) -> Result<(), TestCaseError> {
    let parses = syn::parse2::<syn::ItemImpl>(item.clone()).is_ok();
    let out = expand_caught(attr.clone(), item.clone()).map_err(|panic| {
        TestCaseError::fail(format!("panicked: {panic}\nattr: {attr}\nitem: {item}"))
    })?;
    let errors = compile_errors(&out);
    if (!parses || !attr.is_empty()) && errors.is_empty() {
        return Err(TestCaseError::fail(format!(
            "invalid item, no error:\n{item}"
        )));
    }
    if errors.is_empty() && syn::parse2::<syn::File>(out.clone()).is_err() {
        return Err(TestCaseError::fail(format!(
            "output is not Rust:\n{item}\n=>\n{out}"
        )));
    }
    Ok(())
}

/// A runner with a fixed seed (the same cases every run) that writes no regression files.
fn runner(full: u32) -> TestRunner {
    TestRunner::new(Config {
        cases: super::fuzz_cases(full),
        failure_persistence: None,
        rng_seed: proptest::test_runner::RngSeed::Fixed(0x5eed_50f0),
        ..Config::default()
    })
}

#[test]
fn token_soup_as_an_item_never_panics() {
    runner(1000)
        .run(&soup(), |soup| {
            check_soup(TokenStream::new(), to_tokens(&soup))
        })
        .unwrap();
}

#[test]
fn token_soup_as_attribute_arguments_never_panics() {
    let item = quote!(impl Model { fn f(&self, x: f64) -> f64 { x } });
    runner(400)
        .run(&soup(), |soup| check_soup(to_tokens(&soup), item.clone()))
        .unwrap();
}

#[test]
fn token_soup_as_a_body_never_panics() {
    runner(1200)
        .run(&soup(), |soup| {
            let body = to_tokens(&soup);
            let item = quote! {
                impl X { fn f(&self, x: f64, q: &[f64; 3]) -> f64 { #body } }
            };
            check_soup(TokenStream::new(), item)
        })
        .unwrap();
}

#[test]
fn token_soup_as_impl_items_never_panics() {
    runner(800)
        .run(&soup(), |soup| {
            let items = to_tokens(&soup);
            check_soup(TokenStream::new(), quote!(impl X { #items }))
        })
        .unwrap();
}

// ---------------------------------------------------------------------------------------
// Garbled models: valid models with a few tokens deleted, repeated, swapped or replaced.
// Random soup rarely even parses; these reach deep into lowering with almost-valid code.

/// Valid models that together use most of the subset.
const MODELS: &[&str] = &[
    "impl Model {
        const N: usize = 3;
        fn helper(&self, a: f64, k: usize) -> f64 { a * (k as f64) }
        fn f(&self, x: f64, q: &[f64; 3]) -> f64 {
            let mut s = 0.0;
            for i in 0..Self::N { s += self.helper(q[i], i) * x.sin(); }
            let (sn, cs) = x.sin_cos();
            if s > 1.0 { s * sn } else { s.powi(2) + cs }
        }
    }",
    "impl Model {
        fn g(&self, q: [f64; 2], v: &[f64; 2]) -> [f64; 2] {
            let [a, b] = q;
            let m = self.m;
            [m * a.cos() * v[0], f64::atan2(b, a) + v[1].exp().ln() - std::f64::consts::PI]
        }
    }",
    "impl Model {
        fn h(&self, x: &[[f64; 2]; 2]) -> f64 {
            let mut t = [0.0; 2];
            for r in 0..2 { for c in (0..=1).rev() { t[r] += x[r][c] * x[c][r]; } }
            t[0].hypot(t[1]).max(x[0][0].mul_add(2.0, -1.0)) / (1.0 + t[0] * t[0]).sqrt()
        }
    }",
    "impl Model {
        const K: f64 = 2.5;
        fn sq(a: f64) -> f64 { a * a }
        fn f(&self, x: f64) -> f64 {
            const C: f64 = 0.5;
            let y = Self::sq(x) * Self::K - C;
            let z = if y < 0.0 && x != 1.0 || !(x >= 2.0) { -y } else { y.abs().cbrt() };
            z.powf(1.5).recip() + x.tanh().asin() - (x / 3.0).acos() * x.signum()
        }
    }",
];

/// A model as a flat list of lexemes: delimiters are lexemes of their own, and joint
/// punctuation stays together (`..`, `+=`), so that joining with spaces re-lexes the same.
fn lexemes(tokens: TokenStream, out: &mut Vec<String>) {
    let mut punct = String::new();
    for tree in tokens {
        match tree {
            TokenTree::Punct(p) => {
                punct.push(p.as_char());
                if p.spacing() == Spacing::Alone {
                    out.push(std::mem::take(&mut punct));
                }
            }
            TokenTree::Group(g) => {
                let (open, close) = match g.delimiter() {
                    Delimiter::Parenthesis => ("(", ")"),
                    Delimiter::Bracket => ("[", "]"),
                    Delimiter::Brace => ("{", "}"),
                    Delimiter::None => ("", ""),
                };
                out.push(open.into());
                lexemes(g.stream(), out);
                out.push(close.into());
            }
            other => out.push(other.to_string()),
        }
    }
}

#[derive(Clone, Debug)]
enum Mutation {
    Delete(usize),
    Repeat(usize),
    Swap(usize),
    Replace(usize, Soup),
    Insert(usize, Soup),
    /// Overwrite one lexeme with another of the same model: keeps the code model-like.
    Transplant(usize, usize),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    let leaf = || {
        prop_oneof![
            select(WORDS).prop_map(Soup::Word),
            select(PUNCTS).prop_map(Soup::Punct),
            literal().prop_map(Soup::Lit),
        ]
    };
    let at = || any::<usize>();
    prop_oneof![
        1 => at().prop_map(Mutation::Delete),
        1 => at().prop_map(Mutation::Repeat),
        1 => at().prop_map(Mutation::Swap),
        1 => (at(), leaf()).prop_map(|(i, s)| Mutation::Replace(i, s)),
        1 => (at(), leaf()).prop_map(|(i, s)| Mutation::Insert(i, s)),
        3 => (at(), at()).prop_map(|(i, j)| Mutation::Transplant(i, j)),
    ]
}

/// Apply the mutations to a model; `None` when the result no longer lexes (unbalanced
/// delimiters), which no macro can ever receive.
fn mutate(model: &str, mutations: &[Mutation]) -> Option<TokenStream> {
    let mut lex = Vec::new();
    lexemes(tokens(model), &mut lex);
    let text = |s: &Soup| to_tokens(std::slice::from_ref(s)).to_string();
    for m in mutations {
        let n = lex.len().max(1);
        match m {
            Mutation::Delete(i) if !lex.is_empty() => {
                lex.remove(i % n);
            }
            Mutation::Repeat(i) if !lex.is_empty() => lex.insert(i % n, lex[i % n].clone()),
            Mutation::Swap(i) if lex.len() > 1 => lex.swap(i % (n - 1), i % (n - 1) + 1),
            Mutation::Replace(i, s) if !lex.is_empty() => lex[i % n] = text(s),
            Mutation::Insert(i, s) => lex.insert(i % n, text(s)),
            Mutation::Transplant(i, j) if !lex.is_empty() => lex[i % n] = lex[j % n].clone(),
            _ => {}
        }
    }
    lex.join(" ").parse().ok()
}

#[test]
fn the_unmutated_models_are_valid() {
    for model in MODELS {
        let errors = compile_errors(&expand(TokenStream::new(), mutate(model, &[]).unwrap()));
        assert!(errors.is_empty(), "{model}: {errors:#?}");
    }
}

#[test]
fn garbled_models_never_panic() {
    let strategy = (select(MODELS), prop::collection::vec(mutation(), 1..3));
    runner(1200)
        .run(&strategy, |(model, mutations)| {
            match mutate(model, &mutations) {
                Some(item) => check_soup(TokenStream::new(), item),
                None => Ok(()),
            }
        })
        .unwrap();
}
