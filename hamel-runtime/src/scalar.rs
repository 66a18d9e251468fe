//! The scalar type generated code can compute in.
//!
//! Generated code is straight-line arithmetic plus the elementary functions of `f64`. Written
//! against this trait it also runs on other number types — dual numbers in particular, which
//! is how the Jacobian of a generated right-hand side can be obtained for linearization
//! without the macro emitting third-order derivative code. For `f64` every method is the
//! inherent one, so the instantiation compiles to exactly the plain `f64` code.

use core::fmt::Debug;
use core::ops::{Add, Div, Mul, Neg, Sub};

pub trait Scalar:
    Copy
    + Debug
    + PartialOrd
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    fn from_f64(value: f64) -> Self;
    /// The value part (for dual numbers, without the derivative parts).
    fn re(self) -> f64;
    fn sin(self) -> Self;
    fn cos(self) -> Self;
    fn tan(self) -> Self;
    fn asin(self) -> Self;
    fn acos(self) -> Self;
    fn atan(self) -> Self;
    fn sinh(self) -> Self;
    fn cosh(self) -> Self;
    fn tanh(self) -> Self;
    fn exp(self) -> Self;
    fn ln(self) -> Self;
    fn log10(self) -> Self;
    fn sqrt(self) -> Self;
    fn cbrt(self) -> Self;
    fn abs(self) -> Self;
    fn signum(self) -> Self;
    fn powi(self, n: i32) -> Self;
    fn powf(self, exponent: Self) -> Self;
    fn atan2(self, other: Self) -> Self;
    fn hypot(self, other: Self) -> Self;
}

macro_rules! forward {
    ($($name:ident),*) => {
        $(
            #[inline(always)]
            fn $name(self) -> Self {
                f64::$name(self)
            }
        )*
    };
}

impl Scalar for f64 {
    #[inline(always)]
    fn from_f64(value: f64) -> Self {
        value
    }

    #[inline(always)]
    fn re(self) -> f64 {
        self
    }

    forward!(
        sin, cos, tan, asin, acos, atan, sinh, cosh, tanh, exp, ln, log10, sqrt, cbrt, abs, signum
    );

    #[inline(always)]
    fn powi(self, n: i32) -> Self {
        f64::powi(self, n)
    }

    #[inline(always)]
    fn powf(self, exponent: Self) -> Self {
        f64::powf(self, exponent)
    }

    #[inline(always)]
    fn atan2(self, other: Self) -> Self {
        f64::atan2(self, other)
    }

    #[inline(always)]
    fn hypot(self, other: Self) -> Self {
        f64::hypot(self, other)
    }
}
