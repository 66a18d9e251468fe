//! Nested dual numbers behind `hamel::Scalar`: num-dual's `Dual<T>` over any dual type `T`,
//! so that a model's `rhs_generic` runs on a dual of a dual of … a real, and the vector
//! fields built from it can be differentiated again to any order (`control.rs` computes Lie
//! derivatives and brackets this way, independently of the engine's tangent sweeps).

use num_dual::{Dual, DualNum};
use std::cmp::Ordering;
use std::ops::{Add, Div, Mul, Neg, Sub};

/// The number types of the reference computation: `f64`, `Dual<f64>`, `Dual<Dual<f64>>`, ….
pub trait Number: DualNum<Primitive = f64> + Copy + Send + Sync {}
impl<T: DualNum<Primitive = f64> + Copy + Send + Sync> Number for T {}

/// A number of the reference computation as a `hamel::Scalar`.
#[derive(Clone, Copy, Debug)]
pub struct N<T>(pub T);

impl<T: Number> N<T> {
    fn value(self) -> f64 {
        self.0.re()
    }
}

// Comparisons look at the value only, as `if` in the generated code must.
impl<T: Number> PartialEq for N<T> {
    fn eq(&self, other: &Self) -> bool {
        self.value() == other.value()
    }
}

impl<T: Number> PartialOrd for N<T> {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        self.value().partial_cmp(&other.value())
    }
}

macro_rules! binary_op {
    ($($trait:ident $method:ident),*) => {
        $(
            impl<T: Number> $trait for N<T> {
                type Output = N<T>;
                fn $method(self, other: N<T>) -> N<T> {
                    N($trait::$method(self.0, other.0))
                }
            }
        )*
    };
}

binary_op!(Add add, Sub sub, Mul mul, Div div);

impl<T: Number> Neg for N<T> {
    type Output = N<T>;
    fn neg(self) -> N<T> {
        N(-self.0)
    }
}

macro_rules! forward {
    ($($name:ident),*) => {
        $(
            fn $name(self) -> Self {
                N(DualNum::$name(&self.0))
            }
        )*
    };
}

impl<T: Number> hamel::Scalar for N<T> {
    fn from_f64(value: f64) -> Self {
        N(T::from(value))
    }

    fn re(self) -> f64 {
        self.value()
    }

    forward!(
        sin, cos, tan, asin, acos, atan, sinh, cosh, tanh, exp, ln, log10, sqrt, cbrt
    );

    fn abs(self) -> Self {
        if self.value() < 0.0 { -self } else { self }
    }

    /// Piecewise constant: its derivative parts are zero.
    fn signum(self) -> Self {
        N(T::from(self.value().signum()))
    }

    fn powi(self, n: i32) -> Self {
        N(DualNum::powi(&self.0, n))
    }

    fn powf(self, exponent: Self) -> Self {
        N(self.0.powd(exponent.0))
    }

    fn atan2(self, other: Self) -> Self {
        N(DualNum::atan2(&self.0, other.0))
    }

    fn hypot(self, other: Self) -> Self {
        N(DualNum::sqrt(&(self.0 * self.0 + other.0 * other.0)))
    }
}

/// A map of the state to R values (a vector field when R = S), evaluable on any number type
/// of the reference computation.
pub trait Map<const S: usize, const R: usize> {
    fn eval<T: Number>(&self, x: &[T; S]) -> [T; R];
}

impl<const S: usize, const R: usize, F: Map<S, R>> Map<S, R> for &F {
    fn eval<T: Number>(&self, x: &[T; S]) -> [T; R] {
        (**self).eval(x)
    }
}

/// The derivative of `map` at `x` along `v`: map(x + ε v)'s ε part, one level deeper.
pub fn along<const S: usize, const R: usize, T: Number, F: Map<S, R>>(
    map: &F,
    x: &[T; S],
    v: &[T; S],
) -> [T; R] {
    let seeded: [Dual<T>; S] = core::array::from_fn(|i| Dual::new(x[i], v[i]));
    map.eval(&seeded).map(|d| d.eps)
}

/// [X, Y] = ∂Y/∂x · X − ∂X/∂x · Y (Isidori's sign).
pub struct Bracket<X, Y>(pub X, pub Y);

impl<const S: usize, X: Map<S, S>, Y: Map<S, S>> Map<S, S> for Bracket<X, Y> {
    fn eval<T: Number>(&self, x: &[T; S]) -> [T; S] {
        let (xv, yv) = (self.0.eval(x), self.1.eval(x));
        let dy = along(&self.1, x, &xv);
        let dx = along(&self.0, x, &yv);
        core::array::from_fn(|i| dy[i] - dx[i])
    }
}

/// L_X H = ∂H/∂x · X, for a time-independent H.
pub struct Lie<H, X>(pub H, pub X);

impl<const S: usize, const R: usize, H: Map<S, R>, X: Map<S, S>> Map<S, R> for Lie<H, X> {
    fn eval<T: Number>(&self, x: &[T; S]) -> [T; R] {
        along(&self.0, x, &self.1.eval(x))
    }
}

/// A model's right-hand side F(x, u) at t = 0 on the reference's number types: what
/// `rhs_generic` gives (`generic_rhs!` implements it for a model).
pub trait Rhs<const S: usize, const M: usize> {
    fn rhs<T: Number>(&self, x: &[T; S], u: &[T; M]) -> [T; S];
}

/// Implements [`Rhs`] for a model by its generated `rhs_generic`.
#[macro_export]
macro_rules! generic_rhs {
    ($model:ty, $s:literal, $m:literal) => {
        impl $crate::support::nested::Rhs<$s, $m> for $model {
            fn rhs<T: $crate::support::nested::Number>(&self, x: &[T; $s], u: &[T; $m]) -> [T; $s] {
                use $crate::support::nested::N;
                let mut dx = [N(T::from(0.0)); $s];
                self.rhs_generic(N(T::from(0.0)), &x.map(N), &u.map(N), &mut dx)
                    .expect("a regular state");
                dx.map(|d| d.0)
            }
        }
    };
}

/// The drift f(x) = F(x, 0).
pub struct Drift<'a, P, const M: usize>(pub &'a P);

impl<const S: usize, const M: usize, P: Rhs<S, M>> Map<S, S> for Drift<'_, P, M> {
    fn eval<T: Number>(&self, x: &[T; S]) -> [T; S] {
        self.0.rhs(x, &[T::from(0.0); M])
    }
}

/// The input field g_j(x) = ∂F/∂u_j at u = 0, by a dual number seeded in u_j.
pub struct InputField<'a, P, const M: usize>(pub &'a P, pub usize);

impl<const S: usize, const M: usize, P: Rhs<S, M>> Map<S, S> for InputField<'_, P, M> {
    fn eval<T: Number>(&self, x: &[T; S]) -> [T; S] {
        let lifted: [Dual<T>; S] = x.map(Dual::from_re);
        let u: [Dual<T>; M] = core::array::from_fn(|j| {
            Dual::new(T::from(0.0), T::from(if j == self.1 { 1.0 } else { 0.0 }))
        });
        self.0.rhs(&lifted, &u).map(|d| d.eps)
    }
}
