//! Hyper-dual numbers (num-dual's `HyperDual64`) as a scalar the generated code computes in:
//! one pass with the seeds ε₁ in direction a and ε₂ in direction b gives ∂²F/∂z_a∂z_b in the
//! ε₁ε₂ part, exact to rounding, through every branch the `f64` code takes (comparisons
//! compare the values). A newtype, because neither `hamel::Scalar` nor `HyperDual64` is this
//! crate's.

use core::ops::{Add, Div, Mul, Neg, Sub};
use hamel_runtime::Scalar;
use num_dual::{DualNum, HyperDual64};

/// A hyper-dual number: value, ε₁, ε₂ and ε₁ε₂ parts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hyper(pub HyperDual64);

impl Hyper {
    /// The value with seeds of the given sizes in ε₁ and ε₂.
    pub fn seeded(value: f64, eps1: f64, eps2: f64) -> Hyper {
        Hyper(HyperDual64::new(value, eps1, eps2, 0.0))
    }
}

impl PartialOrd for Hyper {
    fn partial_cmp(&self, other: &Self) -> Option<core::cmp::Ordering> {
        self.0.re.partial_cmp(&other.0.re)
    }
}

macro_rules! binary {
    ($($trait:ident $method:ident),*) => {
        $(
            impl $trait for Hyper {
                type Output = Hyper;
                #[inline(always)]
                fn $method(self, other: Hyper) -> Hyper {
                    Hyper(self.0.$method(other.0))
                }
            }
        )*
    };
}

binary!(Add add, Sub sub, Mul mul, Div div);

impl Neg for Hyper {
    type Output = Hyper;
    #[inline(always)]
    fn neg(self) -> Hyper {
        Hyper(-self.0)
    }
}

macro_rules! forward {
    ($($name:ident),*) => {
        $(
            #[inline(always)]
            fn $name(self) -> Self {
                Hyper(DualNum::$name(&self.0))
            }
        )*
    };
}

impl Scalar for Hyper {
    #[inline(always)]
    fn from_f64(value: f64) -> Self {
        Hyper(HyperDual64::from_re(value))
    }

    #[inline(always)]
    fn re(self) -> f64 {
        self.0.re
    }

    forward!(
        sin, cos, tan, asin, acos, atan, sinh, cosh, tanh, exp, ln, log10, sqrt, cbrt
    );

    /// |x| with the derivatives of the branch taken, as the runtime's dual numbers.
    #[inline(always)]
    fn abs(self) -> Self {
        if self.0.re < 0.0 { -self } else { self }
    }

    /// A step function: derivatives zero.
    #[inline(always)]
    fn signum(self) -> Self {
        Self::from_f64(self.0.re.signum())
    }

    #[inline(always)]
    fn powi(self, n: i32) -> Self {
        Hyper(DualNum::powi(&self.0, n))
    }

    #[inline(always)]
    fn powf(self, exponent: Self) -> Self {
        Hyper(DualNum::powd(&self.0, exponent.0))
    }

    #[inline(always)]
    fn atan2(self, other: Self) -> Self {
        Hyper(DualNum::atan2(&self.0, other.0))
    }

    /// √(a² + b²), as the runtime's dual numbers compute it.
    #[inline(always)]
    fn hypot(self, other: Self) -> Self {
        Hyper(DualNum::sqrt(&(self.0 * self.0 + other.0 * other.0)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ∂²/∂a∂b of sin(a)·b² at (a, b) = (0.3, 1.7) is cos(a)·2b.
    #[test]
    fn mixed_second_derivative() {
        let (a, b) = (0.3f64, 1.7f64);
        let ha = Hyper::seeded(a, 1.0, 0.0);
        let hb = Hyper::seeded(b, 0.0, 1.0);
        let f = ha.sin() * hb * hb;
        assert_eq!(f.re(), a.sin() * b * b);
        assert!((f.0.eps1eps2 - a.cos() * 2.0 * b).abs() < 1e-15);
        assert!((f.0.eps1 - a.cos() * b * b).abs() < 1e-15);
        assert!((f.0.eps2 - a.sin() * 2.0 * b).abs() < 1e-15);
    }
}
