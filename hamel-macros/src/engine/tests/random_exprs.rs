//! Random expression trees, differentiated by the engine and checked against hyper-dual
//! numbers evaluated on the same tree.
//!
//! Each case is a function `f(&self, x: &[f64; 3]) -> f64` over `x[0]`, `x[1]`, `x[2]`, the
//! parameter `self.p` and constants, built from `+ - * /`, unary `-`, the elementary
//! functions, `if`/`else` and `let` (with compound assignments). The tree is rendered to
//! Rust, lowered by the engine, and differentiated four ways: the gradient (`adjoint`), a
//! directional derivative (`tangent`), the 3×3 Hessian (`hessian`) and a bidirectional
//! second derivative (`bidirectional`), all evaluated by `Graph::evaluate` at a random point.
//! The test evaluates the same tree itself, in plain `f64` and in `HyperDual<f64>`, and the
//! results must agree to 1e-12, norm-wise relative per derivative object.
//!
//! Arguments stay in their functions' domains by construction (`Expr::positive` and friends),
//! so a case is only skipped where the reference overflows (non-finite, or beyond 1e12).
//!
//! Some results are ill-conditioned: a derivative that is a sum of terms cancelling to (near)
//! zero, such as the Hessian of `x.hypot(x)`, is known to no better than the rounding error of
//! its terms, so any two correct f64 computations may differ by more than 1e-12 of the
//! result. The reference therefore also carries, for every entry, the magnitude of the terms
//! it is made of (`Reference::m`). A case that misses the tolerance is ill-conditioned rather
//! than wrong only when its terms are much larger than its result and it still agrees to 1e-12
//! of those terms; such cases are counted and printed, and must stay rare.

use crate::engine::diff;
use crate::engine::graph::{Graph, NodeId};
use crate::engine::lower::{ImplContext, Lowerer, Value};
use num_dual::{DualNum, HyperDual64};
use proptest::prelude::*;
use proptest::sample::select;
use proptest::test_runner::{Config, RngSeed, TestCaseError, TestRunner};
use std::cell::Cell;
use std::fmt::Write;
use std::ops::{Add, Div, Mul, Neg, Sub};

// ---------------------------------------------------------------------------------------
// The trees.

#[derive(Clone, Copy, Debug, PartialEq)]
enum Arith {
    Add,
    Sub,
    Mul,
    Div,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Unary {
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
    Recip,
    Abs,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Binary {
    Atan2,
    Hypot,
    Powf,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Compare {
    Lt,
    Le,
    Gt,
    Ge,
}

#[derive(Clone, Debug)]
enum Expr {
    /// `x[i]`
    X(usize),
    /// `self.p`
    P,
    /// A `let` local, by number modulo the locals in scope (`x[k % 3]` when there are none),
    /// so that any tree is valid wherever it lands.
    Local(usize),
    Const(f64),
    Neg(Box<Expr>),
    Arith(Arith, Box<Expr>, Box<Expr>),
    Unary(Unary, Box<Expr>),
    /// `a.f(b)`, or `f64::f(a, b)` when the flag is set.
    Binary(Binary, Box<Expr>, Box<Expr>, bool),
    Powi(Box<Expr>, i32),
    MulAdd(Box<Expr>, Box<Expr>, Box<Expr>),
    /// `if a op b { then } else { otherwise }`
    If(Compare, Box<Expr>, Box<Expr>, Box<Expr>, Box<Expr>),
}

/// Constructors that keep every argument in its function's domain.
impl Expr {
    fn constant(c: f64) -> Box<Expr> {
        Box::new(Expr::Const(c))
    }

    fn arith(op: Arith, a: Expr, b: Expr, square: bool) -> Expr {
        let b = if op == Arith::Div {
            Expr::positive(b, square)
        } else {
            b
        };
        Expr::Arith(op, Box::new(a), Box::new(b))
    }

    /// A positive value made from any expression: `1.0 + e * e` or `e.abs() + 0.5`.
    fn positive(e: Expr, square: bool) -> Expr {
        if square {
            let e2 = Expr::Arith(Arith::Mul, Box::new(e.clone()), Box::new(e));
            Expr::Arith(Arith::Add, Expr::constant(1.0), Box::new(e2))
        } else {
            let abs = Expr::Unary(Unary::Abs, Box::new(e));
            Expr::Arith(Arith::Add, Box::new(abs), Expr::constant(0.5))
        }
    }

    /// `e.atan() * k`: any value squeezed into (−1.571·k, 1.571·k).
    fn squeezed(e: Expr, k: f64) -> Expr {
        let atan = Expr::Unary(Unary::Atan, Box::new(e));
        Expr::Arith(Arith::Mul, Box::new(atan), Expr::constant(k))
    }

    fn unary(f: Unary, e: Expr, square: bool) -> Expr {
        let arg = match f {
            // tan on (−0.95, 0.95), far from its poles.
            Unary::Tan => Expr::squeezed(e, 0.6),
            // asin and acos on (−0.9, 0.9), away from their infinite slopes at ±1.
            Unary::Asin | Unary::Acos => Expr::squeezed(e, 0.57),
            Unary::Ln | Unary::Log10 | Unary::Sqrt | Unary::Cbrt | Unary::Recip => {
                Expr::positive(e, square)
            }
            _ => e,
        };
        Expr::Unary(f, Box::new(arg))
    }

    fn binary(f: Binary, a: Expr, b: Expr, square: bool, path: bool) -> Expr {
        let a = if f == Binary::Powf {
            Expr::positive(a, square)
        } else {
            a
        };
        Expr::Binary(f, Box::new(a), Box::new(b), path)
    }

    fn powi(e: Expr, n: i32, square: bool) -> Expr {
        let e = if n < 0 { Expr::positive(e, square) } else { e };
        Expr::Powi(Box::new(e), n)
    }
}

/// A statement before the tail expression.
#[derive(Clone, Debug)]
enum Stmt {
    /// `let mut t{n} = e;`
    Let(Expr),
    /// `t{k} op= e;` on an existing local (nothing when there is none yet).
    Update(usize, Arith, Expr),
}

#[derive(Clone, Debug)]
struct Body {
    stmts: Vec<Stmt>,
    tail: Expr,
}

// ---------------------------------------------------------------------------------------
// Strategies.

fn constant() -> impl Strategy<Value = f64> {
    prop_oneof![
        select(&[0.0, 1.0, -1.0, 2.0, 0.5, -0.5, 3.0][..]),
        -3.0..3.0f64,
    ]
}

fn leaf() -> impl Strategy<Value = Expr> {
    prop_oneof![
        4 => (0..3usize).prop_map(Expr::X),
        1 => Just(Expr::P),
        1 => (0..4usize).prop_map(Expr::Local),
        2 => constant().prop_map(Expr::Const),
    ]
}

const UNARY: [Unary; 16] = [
    Unary::Sin,
    Unary::Cos,
    Unary::Tan,
    Unary::Asin,
    Unary::Acos,
    Unary::Atan,
    Unary::Sinh,
    Unary::Cosh,
    Unary::Tanh,
    Unary::Exp,
    Unary::Ln,
    Unary::Log10,
    Unary::Sqrt,
    Unary::Cbrt,
    Unary::Recip,
    Unary::Abs,
];
const ARITH: [Arith; 4] = [Arith::Add, Arith::Sub, Arith::Mul, Arith::Div];

/// Trees of depth ≤ 5 (not counting the domain guards around arguments).
fn expr() -> impl Strategy<Value = Expr> {
    leaf().prop_recursive(5, 24, 3, |e| {
        let binary = select(&[Binary::Atan2, Binary::Hypot, Binary::Powf][..]);
        let compare = select(&[Compare::Lt, Compare::Le, Compare::Gt, Compare::Ge][..]);
        let b = any::<bool>;
        let boxed = |e: Expr| Box::new(e);
        prop_oneof![
            1 => e.clone().prop_map(move |a| Expr::Neg(boxed(a))),
            6 => (select(&ARITH[..]), e.clone(), e.clone(), b())
                .prop_map(|(op, a, c, s)| Expr::arith(op, a, c, s)),
            6 => (select(&UNARY[..]), e.clone(), b()).prop_map(|(f, a, s)| Expr::unary(f, a, s)),
            2 => (binary, e.clone(), e.clone(), b(), b())
                .prop_map(|(f, a, c, s, path)| Expr::binary(f, a, c, s, path)),
            1 => (e.clone(), -3..=4i32, b()).prop_map(|(a, n, s)| Expr::powi(a, n, s)),
            1 => (e.clone(), e.clone(), e.clone())
                .prop_map(move |(a, c, d)| Expr::MulAdd(boxed(a), boxed(c), boxed(d))),
            1 => (compare, e.clone(), e.clone(), e.clone(), e).prop_map(move |(op, a, c, t, o)| {
                Expr::If(op, boxed(a), boxed(c), boxed(t), boxed(o))
            }),
        ]
    })
}

fn stmt() -> impl Strategy<Value = Stmt> {
    prop_oneof![
        2 => expr().prop_map(Stmt::Let),
        1 => (0..4usize, select(&ARITH[..]), expr(), any::<bool>()).prop_map(|(k, op, e, s)| {
            let e = if op == Arith::Div { Expr::positive(e, s) } else { e };
            Stmt::Update(k, op, e)
        }),
    ]
}

fn body() -> impl Strategy<Value = Body> {
    (prop::collection::vec(stmt(), 0..3), expr()).prop_map(|(stmts, tail)| Body { stmts, tail })
}

/// Where the derivatives are evaluated, and the directions of the directional ones.
#[derive(Clone, Debug)]
struct Point {
    x: [f64; 3],
    p: f64,
    dir: [f64; 3],
    u: [f64; 3],
    v: [f64; 3],
}

fn point() -> impl Strategy<Value = Point> {
    let coordinates = || prop::array::uniform3(-2.0..2.0f64);
    let direction = || prop::array::uniform3(-1.0..1.0f64);
    (
        coordinates(),
        -2.0..2.0f64,
        direction(),
        direction(),
        direction(),
    )
        .prop_map(|(x, p, dir, u, v)| Point { x, p, dir, u, v })
}

// ---------------------------------------------------------------------------------------
// Rendering to Rust. Every compound expression is parenthesized, so precedence never
// depends on the tree's shape.

impl Unary {
    fn name(self) -> &'static str {
        match self {
            Unary::Sin => "sin",
            Unary::Cos => "cos",
            Unary::Tan => "tan",
            Unary::Asin => "asin",
            Unary::Acos => "acos",
            Unary::Atan => "atan",
            Unary::Sinh => "sinh",
            Unary::Cosh => "cosh",
            Unary::Tanh => "tanh",
            Unary::Exp => "exp",
            Unary::Ln => "ln",
            Unary::Log10 => "log10",
            Unary::Sqrt => "sqrt",
            Unary::Cbrt => "cbrt",
            Unary::Recip => "recip",
            Unary::Abs => "abs",
        }
    }
}

impl Binary {
    fn name(self) -> &'static str {
        match self {
            Binary::Atan2 => "atan2",
            Binary::Hypot => "hypot",
            Binary::Powf => "powf",
        }
    }
}

impl Arith {
    fn symbol(self) -> &'static str {
        match self {
            Arith::Add => "+",
            Arith::Sub => "-",
            Arith::Mul => "*",
            Arith::Div => "/",
        }
    }
}

impl Compare {
    fn symbol(self) -> &'static str {
        match self {
            Compare::Lt => "<",
            Compare::Le => "<=",
            Compare::Gt => ">",
            Compare::Ge => ">=",
        }
    }

    fn holds(self, a: f64, b: f64) -> bool {
        match self {
            Compare::Lt => a < b,
            Compare::Le => a <= b,
            Compare::Gt => a > b,
            Compare::Ge => a >= b,
        }
    }
}

/// `e` as Rust source, with `locals` locals `t0, t1, ..` in scope.
fn render(e: &Expr, locals: usize) -> String {
    let r = |e: &Expr| render(e, locals);
    match e {
        Expr::X(i) => format!("x[{i}]"),
        Expr::P => "self.p".into(),
        Expr::Local(k) if locals == 0 => format!("x[{}]", k % 3),
        Expr::Local(k) => format!("t{}", k % locals),
        // `{:?}` always writes a float literal (`1.0`, `1e-7`), never an integer.
        Expr::Const(c) => format!("({c:?})"),
        Expr::Neg(a) => format!("(-{})", r(a)),
        Expr::Arith(op, a, b) => format!("({} {} {})", r(a), op.symbol(), r(b)),
        Expr::Unary(f, a) => format!("{}.{}()", r(a), f.name()),
        Expr::Binary(f, a, b, false) => format!("{}.{}({})", r(a), f.name(), r(b)),
        Expr::Binary(f, a, b, true) => format!("f64::{}({}, {})", f.name(), r(a), r(b)),
        Expr::Powi(a, n) => format!("{}.powi({n})", r(a)),
        Expr::MulAdd(a, b, c) => format!("{}.mul_add({}, {})", r(a), r(b), r(c)),
        Expr::If(op, a, b, t, o) => format!(
            "(if {} {} {} {{ {} }} else {{ {} }})",
            r(a),
            op.symbol(),
            r(b),
            r(t),
            r(o)
        ),
    }
}

/// The whole impl block.
fn render_model(body: &Body) -> String {
    let mut src = String::from("impl Model {\n    fn f(&self, x: &[f64; 3]) -> f64 {\n");
    let mut locals = 0;
    for stmt in &body.stmts {
        match stmt {
            Stmt::Let(e) => {
                let _ = writeln!(src, "        let mut t{locals} = {};", render(e, locals));
                locals += 1;
            }
            Stmt::Update(..) if locals == 0 => {}
            Stmt::Update(k, op, e) => {
                let (t, op, e) = (k % locals, op.symbol(), render(e, locals));
                let _ = writeln!(src, "        t{t} {op}= {e};");
            }
        }
    }
    let _ = write!(src, "        {}\n    }}\n}}", render(&body.tail, locals));
    src
}

// ---------------------------------------------------------------------------------------
// The test's own evaluation of a tree: over `f64` with Rust's semantics, and over
// `Reference` (hyper-dual numbers with the magnitudes of their terms).

trait Scalar:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    fn constant(c: f64) -> Self;
    fn value(self) -> f64;
    fn unary(self, f: Unary) -> Self;
    fn binary(self, f: Binary, b: Self) -> Self;
    fn powi(self, n: i32) -> Self;
    fn mul_add(self, a: Self, b: Self) -> Self;
}

impl Scalar for f64 {
    fn constant(c: f64) -> Self {
        c
    }

    fn value(self) -> f64 {
        self
    }

    fn unary(self, f: Unary) -> Self {
        match f {
            Unary::Sin => self.sin(),
            Unary::Cos => self.cos(),
            Unary::Tan => self.tan(),
            Unary::Asin => self.asin(),
            Unary::Acos => self.acos(),
            Unary::Atan => self.atan(),
            Unary::Sinh => self.sinh(),
            Unary::Cosh => self.cosh(),
            Unary::Tanh => self.tanh(),
            Unary::Exp => self.exp(),
            Unary::Ln => self.ln(),
            Unary::Log10 => self.log10(),
            Unary::Sqrt => self.sqrt(),
            Unary::Cbrt => self.cbrt(),
            Unary::Recip => self.recip(),
            Unary::Abs => self.abs(),
        }
    }

    fn binary(self, f: Binary, b: Self) -> Self {
        match f {
            Binary::Atan2 => self.atan2(b),
            Binary::Hypot => self.hypot(b),
            Binary::Powf => self.powf(b),
        }
    }

    fn powi(self, n: i32) -> Self {
        f64::powi(self, n)
    }

    /// Rust's `mul_add`: fused, one rounding.
    fn mul_add(self, a: Self, b: Self) -> Self {
        f64::mul_add(self, a, b)
    }
}

/// [f, f', f''] of an elementary function at `x`, written independently of the engine's
/// formulas and in forms without cancellation (tanh' = 1/cosh², not 1 − tanh²).
fn unary_derivatives(f: Unary, x: f64) -> [f64; 3] {
    match f {
        Unary::Sin => [x.sin(), x.cos(), -x.sin()],
        Unary::Cos => [x.cos(), -x.sin(), -x.cos()],
        Unary::Tan => {
            let (t, sec2) = (x.tan(), x.cos().powi(-2));
            [t, sec2, 2.0 * t * sec2]
        }
        Unary::Asin | Unary::Acos => {
            let d = 1.0 - x * x;
            let sign = if f == Unary::Asin { 1.0 } else { -1.0 };
            let value = if f == Unary::Asin { x.asin() } else { x.acos() };
            [value, sign / d.sqrt(), sign * x / (d * d.sqrt())]
        }
        Unary::Atan => {
            let d = 1.0 + x * x;
            [x.atan(), 1.0 / d, -2.0 * x / (d * d)]
        }
        Unary::Sinh => [x.sinh(), x.cosh(), x.sinh()],
        Unary::Cosh => [x.cosh(), x.sinh(), x.cosh()],
        Unary::Tanh => {
            let (t, sech2) = (x.tanh(), x.cosh().powi(-2));
            [t, sech2, -2.0 * t * sech2]
        }
        Unary::Exp => [x.exp(); 3],
        Unary::Ln => [x.ln(), 1.0 / x, -1.0 / (x * x)],
        Unary::Log10 => {
            let l = std::f64::consts::LN_10;
            [x.log10(), 1.0 / (x * l), -1.0 / (x * x * l)]
        }
        Unary::Sqrt => {
            let s = x.sqrt();
            [s, 0.5 / s, -0.25 / (s * x)]
        }
        Unary::Cbrt => {
            let c = x.cbrt();
            [c, c / (3.0 * x), -2.0 * c / (9.0 * x * x)]
        }
        Unary::Recip => [1.0 / x, -1.0 / (x * x), 2.0 / (x * x * x)],
        Unary::Abs => [x.abs(), x.signum(), 0.0],
    }
}

/// Value, gradient and Hessian of a two-argument function at (a, b): the function by its
/// value, [f_a, f_b] and [f_aa, f_ab, f_bb].
type Derivatives2 = (f64, [f64; 2], [f64; 3]);

/// The derivatives of a two-argument function at (a, b), and the magnitudes of its second
/// derivatives as a chain rule composes them. Differentiating a first partial such as
/// ∂hypot/∂a = a/h gives 1/h − a²/h³, which cancels where a ≈ h; forward-over-reverse
/// and hyper-dual evaluation both compute it that way, so the cancellation belongs to the
/// problem, and its magnitude is 1/h + a²/h³, not |b²/h³|.
fn binary_derivatives(f: Binary, a: f64, b: f64) -> (Derivatives2, [f64; 3]) {
    match f {
        Binary::Atan2 => {
            let r2 = a * a + b * b;
            let r4 = r2 * r2;
            let hessian = [-2.0 * a * b / r4, (a * a - b * b) / r4, 2.0 * a * b / r4];
            // f_ab = 1/r² − 2b²/r⁴ (or −1/r² + 2a²/r⁴, from the other partial).
            let mixed = 1.0 / r2 + 2.0 * a.abs().max(b.abs()).powi(2) / r4;
            let terms = [hessian[0].abs(), mixed, hessian[2].abs()];
            ((a.atan2(b), [b / r2, -a / r2], hessian), terms)
        }
        Binary::Hypot => {
            let h = a.hypot(b);
            let h3 = h * h * h;
            let hessian = [b * b / h3, -a * b / h3, a * a / h3];
            // f_aa = 1/h − a²/h³ and f_bb = 1/h − b²/h³.
            let terms = [1.0 / h + a * a / h3, hessian[1].abs(), 1.0 / h + b * b / h3];
            ((h, [a / h, b / h], hessian), terms)
        }
        Binary::Powf => {
            let (p, l) = (a.powf(b), a.ln());
            let hessian = [
                b * (b - 1.0) * p / (a * a),
                p / a * (1.0 + b * l),
                p * l * l,
            ];
            // f_ab = a^(b−1) + b·a^(b−1)·ln a.
            let terms = [
                hessian[0].abs(),
                (p / a).abs() * (1.0 + (b * l).abs()),
                hessian[2].abs(),
            ];
            ((p, [b * p / a, p * l], hessian), terms)
        }
    }
}

/// g(x) for hyper-dual x, from [g, g', g''] at x's real part.
fn chain1(x: HyperDual64, [f0, f1, f2]: [f64; 3]) -> HyperDual64 {
    HyperDual64::new(
        f0,
        f1 * x.eps1,
        f1 * x.eps2,
        f1 * x.eps1eps2 + f2 * x.eps1 * x.eps2,
    )
}

/// g(a, b) for hyper-dual a and b, from the value, gradient and Hessian of g.
fn chain2(
    a: HyperDual64,
    b: HyperDual64,
    (f, [fa, fb], [faa, fab, fbb]): Derivatives2,
) -> HyperDual64 {
    HyperDual64::new(
        f,
        fa * a.eps1 + fb * b.eps1,
        fa * a.eps2 + fb * b.eps2,
        fa * a.eps1eps2
            + fb * b.eps1eps2
            + faa * a.eps1 * a.eps2
            + fab * (a.eps1 * b.eps2 + b.eps1 * a.eps2)
            + fbb * b.eps1 * b.eps2,
    )
}

fn abs_all<const N: usize>(xs: [f64; N]) -> [f64; N] {
    xs.map(f64::abs)
}

/// The reference: `v` is the hyper-dual value, computed with num-dual's arithmetic and
/// elementary functions (except where noted). `m` has the same shape and, in each
/// component, the sum of the magnitudes of the terms that make up that component of `v`:
/// the same chain rules with every partial replaced by its absolute value, and values
/// replaced by the magnitudes they were summed from (so a value that is itself the result of
/// cancellation passes its uncertainty on). Where |v| ≪ m, the component is the result of
/// cancellation, and known only to about ε·m.
#[derive(Clone, Copy, Debug)]
struct Reference {
    v: HyperDual64,
    m: HyperDual64,
}

impl Reference {
    fn input(value: f64, eps1: f64, eps2: f64) -> Self {
        Reference {
            v: HyperDual64::new(value, eps1, eps2, 0.0),
            m: HyperDual64::new(value.abs(), eps1.abs(), eps2.abs(), 0.0),
        }
    }

    /// Magnitudes through a function with derivatives `d` at this point: the value's own
    /// size plus the error it inherits from its argument, and the chain rule on magnitudes.
    fn magnitude1(self, d: [f64; 3]) -> HyperDual64 {
        let [f0, f1, f2] = abs_all(d);
        let mut m = chain1(self.m, [f0, f1, f2]);
        m.re = f0 + f1 * self.m.re;
        m
    }
}

impl Add for Reference {
    type Output = Self;
    fn add(self, b: Self) -> Self {
        Reference {
            v: self.v + b.v,
            m: self.m + b.m,
        }
    }
}

impl Sub for Reference {
    type Output = Self;
    fn sub(self, b: Self) -> Self {
        Reference {
            v: self.v - b.v,
            m: self.m + b.m,
        }
    }
}

impl Mul for Reference {
    type Output = Self;
    fn mul(self, b: Self) -> Self {
        Reference {
            v: self.v * b.v,
            m: self.m * b.m,
        }
    }
}

impl Div for Reference {
    type Output = Self;
    fn div(self, b: Self) -> Self {
        let reciprocal = b.magnitude1(unary_derivatives(Unary::Recip, b.v.re));
        Reference {
            v: self.v / b.v,
            m: self.m * reciprocal,
        }
    }
}

impl Neg for Reference {
    type Output = Self;
    fn neg(self) -> Self {
        Reference {
            v: -self.v,
            m: self.m,
        }
    }
}

impl Scalar for Reference {
    fn constant(c: f64) -> Self {
        Reference::input(c, 0.0, 0.0)
    }

    fn value(self) -> f64 {
        self.v.re
    }

    fn unary(self, f: Unary) -> Self {
        let x = self.v;
        let d = unary_derivatives(f, x.re);
        let v = match f {
            Unary::Sin => x.sin(),
            Unary::Cos => x.cos(),
            // num-dual's tan and tanh are quotients sin/cos and sinh/cosh; the derivative of
            // the latter cancels (cosh² − sinh²) and loses accuracy as |x| grows.
            Unary::Tan | Unary::Tanh => chain1(x, d),
            Unary::Asin => x.asin(),
            Unary::Acos => x.acos(),
            Unary::Atan => x.atan(),
            Unary::Sinh => x.sinh(),
            Unary::Cosh => x.cosh(),
            Unary::Exp => x.exp(),
            Unary::Ln => x.ln(),
            Unary::Log10 => x.log10(),
            Unary::Sqrt => x.sqrt(),
            Unary::Cbrt => x.cbrt(),
            Unary::Recip => DualNum::recip(&x),
            // The branch `f64::abs` takes: −0.0 counts as negative, as in `signum`.
            Unary::Abs if x.re.is_sign_negative() => -x,
            Unary::Abs => x,
        };
        Reference {
            v,
            m: self.magnitude1(d),
        }
    }

    /// num-dual has no `hypot`, and its `atan2` goes through `atan(a / b)`: these use
    /// their own value, gradient and Hessian (see `binary_derivatives`).
    fn binary(self, f: Binary, b: Self) -> Self {
        let (d, terms) = binary_derivatives(f, self.v.re, b.v.re);
        let (value, gradient, _) = d;
        let mut m = chain2(self.m, b.m, (value.abs(), abs_all(gradient), terms));
        m.re = value.abs() + gradient[0].abs() * self.m.re + gradient[1].abs() * b.m.re;
        Reference {
            v: chain2(self.v, b.v, d),
            m,
        }
    }

    fn powi(self, n: i32) -> Self {
        let x = self.v.re;
        let n1 = f64::from(n);
        let d = [
            x.powi(n),
            n1 * x.powi(n - 1),
            n1 * (n1 - 1.0) * x.powi(n - 2),
        ];
        let mut v = DualNum::powi(&self.v, n);
        // num-dual forms the value as x^(n−3)·x·x·x; Rust's `powi` is what the code runs.
        v.re = x.powi(n);
        Reference {
            v,
            m: self.magnitude1(d),
        }
    }

    /// num-dual's `mul_add` is `a * b + c`, as the engine computes it.
    fn mul_add(self, a: Self, b: Self) -> Self {
        self * a + b
    }
}

fn arith<T: Scalar>(op: Arith, a: T, b: T) -> T {
    match op {
        Arith::Add => a + b,
        Arith::Sub => a - b,
        Arith::Mul => a * b,
        Arith::Div => a / b,
    }
}

/// What an expression sees: the arguments, the parameter and the locals so far.
struct Env<T> {
    x: [T; 3],
    p: T,
    locals: Vec<T>,
}

fn eval<T: Scalar>(e: &Expr, env: &Env<T>) -> T {
    let ev = |e: &Expr| eval(e, env);
    match e {
        Expr::X(i) => env.x[*i],
        Expr::P => env.p,
        Expr::Local(k) if env.locals.is_empty() => env.x[k % 3],
        Expr::Local(k) => env.locals[k % env.locals.len()],
        Expr::Const(c) => T::constant(*c),
        Expr::Neg(a) => -ev(a),
        Expr::Arith(op, a, b) => arith(*op, ev(a), ev(b)),
        Expr::Unary(f, a) => ev(a).unary(*f),
        Expr::Binary(f, a, b, _) => ev(a).binary(*f, ev(b)),
        Expr::Powi(a, n) => ev(a).powi(*n),
        Expr::MulAdd(a, b, c) => ev(a).mul_add(ev(b), ev(c)),
        // Only the taken branch, as Rust runs it.
        Expr::If(op, a, b, t, o) => {
            if op.holds(ev(a).value(), ev(b).value()) {
                ev(t)
            } else {
                ev(o)
            }
        }
    }
}

/// The function body, run on the given arguments.
fn run<T: Scalar>(body: &Body, x: [T; 3], p: T) -> T {
    let mut env = Env {
        x,
        p,
        locals: Vec::new(),
    };
    for stmt in &body.stmts {
        match stmt {
            Stmt::Let(e) => {
                let value = eval(e, &env);
                env.locals.push(value);
            }
            Stmt::Update(..) if env.locals.is_empty() => {}
            Stmt::Update(k, op, e) => {
                let value = eval(e, &env);
                let t = k % env.locals.len();
                env.locals[t] = arith(*op, env.locals[t], value);
            }
        }
    }
    eval(&body.tail, &env)
}

// ---------------------------------------------------------------------------------------
// Derivatives, from the engine and from the reference.

/// Everything compared, one derivative object per field.
#[derive(Debug)]
struct Derivatives {
    value: f64,
    gradient: [f64; 3],
    tangent: f64,
    /// Row-major 3×3.
    hessian: [f64; 9],
    second: f64,
}

impl Derivatives {
    fn objects(&self) -> [(&'static str, &[f64]); 5] {
        [
            ("value", std::slice::from_ref(&self.value)),
            ("gradient", &self.gradient),
            ("tangent", std::slice::from_ref(&self.tangent)),
            ("hessian", &self.hessian),
            ("bidirectional", std::slice::from_ref(&self.second)),
        ]
    }
}

/// The reference derivatives, and the magnitudes of their terms.
fn reference(body: &Body, at: &Point) -> (Derivatives, Derivatives) {
    // Seeded with eps1 = a and eps2 = b, a hyper-dual evaluation gives the value, the
    // derivatives along a and b, and the second derivative f''[a, b].
    let seeded = |a: [f64; 3], b: [f64; 3]| -> Reference {
        let x = std::array::from_fn(|i| Reference::input(at.x[i], a[i], b[i]));
        run(body, x, Reference::constant(at.p))
    };
    let unit = |i: usize| std::array::from_fn(|k| if k == i { 1.0 } else { 0.0 });
    let hessian: [Reference; 9] = std::array::from_fn(|k| seeded(unit(k / 3), unit(k % 3)));
    let tangent = seeded(at.dir, [0.0; 3]);
    let second = seeded(at.u, at.v);
    let part = |part: fn(&Reference) -> HyperDual64| Derivatives {
        value: part(&hessian[0]).re,
        gradient: std::array::from_fn(|i| part(&hessian[3 * i]).eps1),
        tangent: part(&tangent).eps1,
        hessian: hessian.map(|h| part(&h).eps1eps2),
        second: part(&second).eps1eps2,
    };
    (part(|r| r.v), part(|r| r.m))
}

/// The engine's graph for one function, with the derivative roots built on it.
struct Differentiated {
    graph: Graph,
    x: Vec<NodeId>,
    /// `self.p`, when the body reads it.
    p: Option<NodeId>,
    dir: Vec<NodeId>,
    u: Vec<NodeId>,
    v: Vec<NodeId>,
    /// value, gradient (3), tangent, Hessian (9), bidirectional: the `Derivatives` order.
    roots: Vec<NodeId>,
}

/// Lower `source` (an impl with one function `f`) and differentiate it.
fn differentiate(source: &str) -> Result<Differentiated, String> {
    let imp: syn::ItemImpl = syn::parse_str(source).map_err(|e| format!("does not parse: {e}"))?;
    let ctx = ImplContext::new(&imp.items);
    let f = ctx.function("f").ok_or("no `f`")?;
    let mut graph = Graph::new();
    let mut lowerer = Lowerer::new(&mut graph, &ctx);
    let signature = lowerer.signature(f).ok_or("bad signature")?;
    let (arg, x) = signature.args[0]
        .shape
        .fresh_inputs(lowerer.graph, "x")
        .ok_or("no inputs for `x`")?;
    let result = lowerer.call(f, vec![arg], &f.sig.ident);
    lowerer
        .take_errors()
        .map_err(|e| format!("lowering failed: {e}"))?;
    // `self.p` is an external input of the graph, named by how the body reads it.
    let p = lowerer.externals.node("self.p");
    drop(lowerer);
    let Value::Real(y) = result else {
        return Err(format!("lowered to {result:?}"));
    };

    let g = &mut graph;
    let mut fresh =
        |name: &str| -> Vec<NodeId> { (0..3).map(|i| g.new_input(format!("{name}{i}"))).collect() };
    let (dir, u, v) = (fresh("dir"), fresh("u"), fresh("v"));
    let seeds = |d: &[NodeId]| -> Vec<(NodeId, NodeId)> {
        x.iter().copied().zip(d.iter().copied()).collect()
    };
    let one = g.one();
    let gradient = diff::adjoint(g, &[y], &[one], &x);
    let tangent = diff::tangent(g, &[y], &seeds(&dir))[0];
    let hessian = diff::hessian(g, &[y], &[one], &x, &x);
    let second = diff::bidirectional(g, &[y], &seeds(&u), &seeds(&v))[0];

    let mut roots = vec![y];
    roots.extend(&gradient);
    roots.push(tangent);
    roots.extend(hessian.iter().flatten());
    roots.push(second);
    Ok(Differentiated {
        graph,
        x,
        p,
        dir,
        u,
        v,
        roots,
    })
}

impl Differentiated {
    fn evaluate(&self, at: &Point) -> Derivatives {
        let g = &self.graph;
        let mut inputs = vec![f64::NAN; g.input_count()];
        let mut set = |nodes: &[NodeId], values: &[f64]| {
            for (&n, &value) in nodes.iter().zip(values) {
                let slot = g.input_slot(n).expect("an input node");
                inputs[slot as usize] = value;
            }
        };
        set(&self.x, &at.x);
        set(&self.dir, &at.dir);
        set(&self.u, &at.u);
        set(&self.v, &at.v);
        if let Some(p) = self.p {
            set(&[p], &[at.p]);
        }
        let r = g.evaluate(&self.roots, &inputs);
        Derivatives {
            value: r[0],
            gradient: [r[1], r[2], r[3]],
            tangent: r[4],
            hessian: std::array::from_fn(|k| r[5 + k]),
            second: r[14],
        }
    }
}

// ---------------------------------------------------------------------------------------
// Comparison.

const TOLERANCE: f64 = 1e-12;
/// Beyond this the reference itself is not trusted (overflowing intermediate values).
const LARGEST: f64 = 1e12;
/// A result this much smaller than its terms has lost ~3 digits to cancellation: the
/// rounding of its terms alone then approaches the tolerance.
const ILL_CONDITIONED: f64 = 1e3;

/// Whether the reference is usable: finite and not huge everywhere.
fn tame(d: &Derivatives) -> bool {
    d.objects()
        .iter()
        .all(|(_, xs)| xs.iter().all(|x| x.is_finite() && x.abs() <= LARGEST))
}

fn largest(xs: &[f64]) -> f64 {
    xs.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

enum Verdict {
    Agrees,
    /// Misses the tolerance, but the result is a cancellation of much larger terms and
    /// agrees to TOLERANCE of those terms.
    IllConditioned(String),
    Differs(String),
}

/// Compare one derivative object. Norm-wise relative: every entry within TOLERANCE of the
/// reference, relative to the largest reference entry of the object (so an entry that is
/// small next to its neighbours is not held to its own magnitude).
fn judge(name: &str, ours: &[f64], reference: &[f64], terms: &[f64]) -> Verdict {
    let scale = largest(reference);
    let within = |scale: f64| {
        ours.iter()
            .zip(reference)
            // Written so that NaN is never within.
            .all(|(o, r)| (o - r).abs() <= TOLERANCE * r.abs().max(scale))
    };
    if within(scale) {
        return Verdict::Agrees;
    }
    let term_scale = largest(terms);
    let report = format!(
        "{name}: ours {ours:?}\n  reference {reference:?}\n  magnitude of the terms {terms:?}"
    );
    if term_scale >= ILL_CONDITIONED * scale && within(term_scale) {
        Verdict::IllConditioned(report)
    } else {
        Verdict::Differs(report)
    }
}

/// The outcome of one case. Rejects the case (`prop_assume`) where the reference
/// overflows; fails on a difference; returns the ill-conditioned comparisons, if any.
fn check(body: &Body, at: &Point) -> Result<Vec<String>, TestCaseError> {
    let source = render_model(body);
    let (reference, terms) = reference(body, at);
    prop_assume!(tame(&reference));
    let engine =
        differentiate(&source).map_err(|e| TestCaseError::fail(format!("{e}\n{source}")))?;
    let ours = engine.evaluate(at);
    let plain = run(body, at.x, at.p);
    let mut verdicts: Vec<Verdict> = ours
        .objects()
        .iter()
        .zip(reference.objects())
        .zip(terms.objects())
        .map(|(((name, o), (_, r)), (_, t))| judge(name, o, r, t))
        .collect();
    verdicts.push(judge(
        "value against plain f64",
        &[ours.value],
        &[plain],
        &[terms.value],
    ));
    let mut ill = Vec::new();
    for verdict in verdicts {
        match verdict {
            Verdict::Agrees => {}
            Verdict::IllConditioned(why) => ill.push(format!("{why}\n  at {at:?}\n{source}")),
            Verdict::Differs(why) => {
                return Err(TestCaseError::fail(format!("{why}\n  at {at:?}\n{source}")));
            }
        }
    }
    Ok(ill)
}

/// A runner with a fixed seed (the same cases every run, so a failure reproduces and the
/// suite does not flicker) that writes no regression files.
fn runner(cases: u32, seed: u64) -> TestRunner {
    let cases = super::fuzz_cases(cases);
    TestRunner::new(Config {
        cases,
        max_global_rejects: cases,
        failure_persistence: None,
        rng_seed: RngSeed::Fixed(seed),
        ..Config::default()
    })
}

#[test]
fn derivatives_match_hyper_dual_numbers() {
    let cases = super::fuzz_cases(3000);
    let (skipped, ill) = (Cell::new(0u32), Cell::new(0u32));
    let result =
        runner(3000, 0x0d1f_f00d).run(&(body(), point()), |(body, at)| match check(&body, &at) {
            Ok(found) => {
                if let Some(first) = found.first() {
                    ill.set(ill.get() + 1);
                    eprintln!("ill-conditioned, accepted: {first}\n");
                }
                Ok(())
            }
            Err(TestCaseError::Reject(why)) => {
                skipped.set(skipped.get() + 1);
                Err(TestCaseError::Reject(why))
            }
            Err(failure) => Err(failure),
        });
    if let Err(e) = result {
        panic!("{e}");
    }
    let (skipped, ill) = (skipped.get(), ill.get());
    eprintln!("{cases} cases: {ill} ill-conditioned; {skipped} more skipped as overflowing");
    // Skips and excuses must stay rare, or the test would quietly test little.
    assert!(skipped < cases / 10, "{skipped} cases skipped");
    assert!(ill < cases / 50, "{ill} cases ill-conditioned");
}

/// The hand-written derivatives of the reference against num-dual's own arithmetic, where
/// num-dual is accurate: a mistake in them would make every comparison meaningless.
#[test]
fn reference_formulas_agree_with_num_dual() {
    let seeded = |x: f64| HyperDual64::new(x, 1.0, 1.0, 0.0);
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-13 * (1.0 + b.abs());
    for x in [-0.8, -0.3, 0.2, 0.7] {
        // Positive arguments for the functions that need them.
        let arg = |f: Unary| match f {
            Unary::Ln | Unary::Log10 | Unary::Sqrt | Unary::Cbrt | Unary::Recip => x + 1.0,
            _ => x,
        };
        for f in UNARY {
            let (a, [f0, f1, f2]) = (arg(f), unary_derivatives(f, arg(f)));
            let dual = match f {
                Unary::Tan => seeded(a).sin() / seeded(a).cos(),
                Unary::Tanh => seeded(a).sinh() / seeded(a).cosh(),
                Unary::Abs => seeded(a) * a.signum(),
                // The other functions are num-dual's own (see `Reference::unary`).
                _ => {
                    Reference {
                        v: seeded(a),
                        m: seeded(a),
                    }
                    .unary(f)
                    .v
                }
            };
            let ok = close(dual.re, f0) && close(dual.eps1, f1) && close(dual.eps1eps2, f2);
            assert!(ok, "{f:?} at {a}: {dual:?} vs {:?}", [f0, f1, f2]);
        }
        for y in [-1.3, 0.4, 2.1] {
            let (a, b) = (
                HyperDual64::new(x + 1.0, 1.0, 0.0, 0.0),
                HyperDual64::new(y, 0.0, 1.0, 0.0),
            );
            let by_num_dual = [
                (Binary::Atan2, a.atan2(b)),
                (Binary::Hypot, (a * a + b * b).sqrt()),
                (Binary::Powf, a.powd(b)),
            ];
            for (f, expected) in by_num_dual {
                let ours = chain2(a, b, binary_derivatives(f, a.re, b.re).0);
                let ok = [
                    (ours.re, expected.re),
                    (ours.eps1, expected.eps1),
                    (ours.eps2, expected.eps2),
                    (ours.eps1eps2, expected.eps1eps2),
                ];
                assert!(
                    ok.iter().all(|&(o, e)| close(o, e)),
                    "{f:?} at ({}, {y}): {ours:?} vs {expected:?}",
                    a.re
                );
            }
        }
    }
}

/// The rendered models go through the whole macro too: no error, and output that parses.
#[test]
fn random_models_expand_cleanly() {
    runner(300, 0x5eed)
        .run(&body(), |body| {
            let source = render_model(&body);
            let out = crate::differentiate::expand(
                proc_macro2::TokenStream::new(),
                super::tokens(&source),
            );
            let errors = super::compile_errors(&out);
            prop_assert!(errors.is_empty(), "{errors:?}\n{source}");
            prop_assert!(syn::parse2::<syn::File>(out).is_ok(), "{source}");
            Ok(())
        })
        .unwrap();
}

// ---------------------------------------------------------------------------------------
// Engine bugs found by the property test, as minimal reproductions.

/// The engine's derivatives of `body` (over `x: &[f64; 3]`) at `x`.
fn engine_at(body: &str, x: [f64; 3]) -> Derivatives {
    let source = format!("impl Model {{ fn f(&self, x: &[f64; 3]) -> f64 {{ {body} }} }}");
    let at = Point {
        x,
        p: 0.0,
        dir: [1.0, 0.0, 0.0],
        u: [1.0, 0.0, 0.0],
        v: [1.0, 0.0, 0.0],
    };
    differentiate(&source).unwrap().evaluate(&at)
}

/// tanh' is computed as 1 − tanh², whose relative error grows like ε·cosh²(x): 1e-8 at
/// x = 10, 77% at x = 19, and from x ≈ 19.1 on the derivative is exactly 0 (true:
/// 1/cosh² ≈ 1.7e-17 at x = 20). 1/cosh²(x) (and −2·tanh/cosh² for the second
/// derivative) keep full relative accuracy.
#[test]
fn tanh_derivative_keeps_its_relative_accuracy() {
    for x in [5.0f64, 10.0, 20.0] {
        let d = engine_at("x[0].tanh()", [x, 0.0, 0.0]);
        let (first, second) = (x.cosh().powi(-2), -2.0 * x.tanh() * x.cosh().powi(-2));
        let relative = |ours: f64, exact: f64| ((ours - exact) / exact).abs();
        assert!(
            relative(d.gradient[0], first) < 1e-12,
            "x = {x}: f' = {} not {first}",
            d.gradient[0]
        );
        assert!(
            relative(d.hessian[0], second) < 1e-12,
            "x = {x}: f'' = {} not {second}",
            d.hessian[0]
        );
    }
}

/// A sum that cancels completely is rebuilt as the constant −0.0 (the empty `Sum` of f64
/// is −0.0), where Rust computes +0.0: `atan2` then lands on the other side of its branch
/// cut, −π instead of π.
#[test]
fn cancelled_sums_keep_the_sign_of_zero() {
    let x = [-1.0, 0.5, 0.0];
    let d = engine_at("(-x[1] + x[1]).atan2(x[0])", x);
    assert_eq!(d.value, (-x[1] + x[1]).atan2(x[0]));
}
