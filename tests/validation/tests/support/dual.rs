//! The reference AD: num-dual's hyper-dual numbers behind `hamel::Scalar`.
//!
//! A hyper-dual number x + ε₁ a + ε₂ b + ε₁ε₂ c (ε₁² = ε₂² = 0) carries one first derivative
//! per direction and the mixed second derivative: seeding ε₁ with u and ε₂ with v, a function
//! evaluated on it yields F, F'·u, F'·v and F''[u, v]. Running the engine's `f_generic::<D>`
//! on it gives derivatives computed by num-dual's rules, independently of the engine's own
//! derivative passes.

use num_dual::{DualNum, HyperDual64};
use std::cmp::Ordering;
use std::ops::{Add, Div, Mul, Neg, Sub};

#[derive(Clone, Copy, Debug)]
pub struct D(pub HyperDual64);

impl D {
    /// Value `re` with first-order parts `eps1` and `eps2` (the two seed directions).
    pub fn seeded(re: f64, eps1: f64, eps2: f64) -> Self {
        D(HyperDual64::new(re, eps1, eps2, 0.0))
    }

    pub fn eps1(self) -> f64 {
        self.0.eps1
    }

    pub fn eps1eps2(self) -> f64 {
        self.0.eps1eps2
    }

    fn constant(value: f64) -> Self {
        D(HyperDual64::from_re(value))
    }

    fn has_derivative_parts(self) -> bool {
        self.0.eps1 != 0.0 || self.0.eps2 != 0.0 || self.0.eps1eps2 != 0.0
    }
}

// Comparisons look at the value only, as `if` in the generated code must.
impl PartialEq for D {
    fn eq(&self, other: &Self) -> bool {
        self.0.re == other.0.re
    }
}

impl PartialOrd for D {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        self.0.re.partial_cmp(&other.0.re)
    }
}

macro_rules! binary_op {
    ($($trait:ident $method:ident),*) => {
        $(
            impl $trait for D {
                type Output = D;
                fn $method(self, other: D) -> D {
                    D($trait::$method(self.0, other.0))
                }
            }
        )*
    };
}

binary_op!(Add add, Sub sub, Mul mul, Div div);

impl Neg for D {
    type Output = D;
    fn neg(self) -> D {
        D(-self.0)
    }
}

macro_rules! forward {
    ($($name:ident),*) => {
        $(
            fn $name(self) -> Self {
                D(DualNum::$name(&self.0))
            }
        )*
    };
}

impl hamel::Scalar for D {
    fn from_f64(value: f64) -> Self {
        D::constant(value)
    }

    fn re(self) -> f64 {
        self.0.re
    }

    forward!(
        sin, cos, tan, asin, acos, atan, sinh, cosh, tanh, exp, ln, log10, sqrt, cbrt
    );

    fn abs(self) -> Self {
        if self.0.re < 0.0 { -self } else { self }
    }

    /// Piecewise constant: its derivative parts are zero.
    fn signum(self) -> Self {
        D::constant(self.0.re.signum())
    }

    fn powi(self, n: i32) -> Self {
        D(DualNum::powi(&self.0, n))
    }

    /// num-dual's `powd` (exp(e·ln x)) when the exponent varies; with a constant exponent its
    /// `powf`, which also covers negative bases.
    fn powf(self, exponent: Self) -> Self {
        if exponent.has_derivative_parts() {
            D(self.0.powd(exponent.0))
        } else {
            D(DualNum::powf(&self.0, exponent.0.re))
        }
    }

    fn atan2(self, other: Self) -> Self {
        D(DualNum::atan2(&self.0, other.0))
    }

    fn hypot(self, other: Self) -> Self {
        (self * self + other * other).sqrt()
    }
}
