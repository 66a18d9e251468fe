//! The Jacobian of a generated right-hand side by dual numbers (num-dual's `Dual64`) run
//! through its generic form `rhs_generic`: forward-mode derivatives, exact to rounding,
//! through everything the generated code does, its unrolled factorizations and their pivot
//! choices included (a comparison of dual numbers compares their values, so the branch the
//! `f64` code takes is the branch the dual code takes).
//!
//! One pass per direction — per state or input component the right-hand side depends on at
//! all; the generated code lists those, so that a cyclic coordinate (a position on the plane,
//! a wheel's angle) costs nothing: its column is exactly zero. The scalar dual number keeps
//! the instantiated code small: num-dual's vector duals (`DualSVec64`) would take fewer
//! passes, but their instantiation through a large right-hand side took minutes to compile.

use crate::error::Singularity;
use crate::scalar::Scalar;
use num_dual::{Dual64, DualNum};

/// The dual number the Jacobian passes compute in.
pub type JacobianDual = Dual64;

macro_rules! forward {
    ($($name:ident),*) => {
        $(
            #[inline(always)]
            fn $name(self) -> Self {
                DualNum::$name(&self)
            }
        )*
    };
}

impl Scalar for Dual64 {
    #[inline(always)]
    fn from_f64(value: f64) -> Self {
        Dual64::from_re(value)
    }

    #[inline(always)]
    fn re(self) -> f64 {
        self.re
    }

    forward!(
        sin, cos, tan, asin, acos, atan, sinh, cosh, tanh, exp, ln, log10, sqrt, cbrt
    );

    /// |x| with the derivative of the branch taken, as the engine differentiates `abs`.
    #[inline(always)]
    fn abs(self) -> Self {
        if self.re < 0.0 { -self } else { self }
    }

    /// A step function: derivative zero.
    #[inline(always)]
    fn signum(self) -> Self {
        Dual64::from_re(self.re.signum())
    }

    #[inline(always)]
    fn powi(self, n: i32) -> Self {
        DualNum::powi(&self, n)
    }

    #[inline(always)]
    fn powf(self, exponent: Self) -> Self {
        DualNum::powd(&self, exponent)
    }

    #[inline(always)]
    fn atan2(self, other: Self) -> Self {
        DualNum::atan2(&self, other)
    }

    /// √(a² + b²) (num-dual has no `hypot`; the scaling that protects `f64::hypot` from
    /// overflow does not matter to a derivative).
    #[inline(always)]
    fn hypot(self, other: Self) -> Self {
        DualNum::sqrt(&(self * self + other * other))
    }
}

/// ∂F/∂x (row-major, S × S) and ∂F/∂u (row-major, S × M) of `rhs` at (t, x, u). `SS` and
/// `SM` are S·S and S·M (the generated code's array lengths); `directions` lists the
/// columns to compute (state components 0…S−1, then inputs S…S+M−1), the others being
/// zero.
pub fn jacobian_by_duals<const S: usize, const M: usize, const SS: usize, const SM: usize>(
    t: f64,
    x: &[f64; S],
    u: &[f64; M],
    directions: &[usize],
    mut rhs: impl FnMut(
        JacobianDual,
        &[JacobianDual; S],
        &[JacobianDual; M],
        &mut [JacobianDual; S],
    ) -> Result<(), Singularity>,
) -> Result<([f64; SS], [f64; SM]), Singularity> {
    let mut state = [0.0; SS];
    let mut input = [0.0; SM];
    let t = JacobianDual::from_re(t);
    for &column in directions {
        let seed = |value: f64, direction: usize| {
            let d = JacobianDual::from_re(value);
            if direction == column {
                d.derivative()
            } else {
                d
            }
        };
        let xd: [JacobianDual; S] = core::array::from_fn(|i| seed(x[i], i));
        let ud: [JacobianDual; M] = core::array::from_fn(|i| seed(u[i], S + i));
        let mut dx = [JacobianDual::from_re(0.0); S];
        rhs(t, &xd, &ud, &mut dx)?;
        for (row, value) in dx.iter().enumerate() {
            let slot = if column < S {
                state.get_mut(row * S + column)
            } else {
                input.get_mut(row * M + column - S)
            };
            if let Some(slot) = slot {
                *slot = value.eps;
            }
        }
    }
    Ok((state, input))
}

/// ∂F/∂t of `rhs` at (t, x, u): one pass of dual numbers with t seeded (the generated code's
/// `time_derivative` calls it only for a right-hand side that depends on t at all).
pub fn time_derivative_by_duals<const S: usize, const M: usize>(
    t: f64,
    x: &[f64; S],
    u: &[f64; M],
    mut rhs: impl FnMut(
        JacobianDual,
        &[JacobianDual; S],
        &[JacobianDual; M],
        &mut [JacobianDual; S],
    ) -> Result<(), Singularity>,
) -> Result<[f64; S], Singularity> {
    let td = JacobianDual::from_re(t).derivative();
    let xd: [JacobianDual; S] = core::array::from_fn(|i| JacobianDual::from_re(x[i]));
    let ud: [JacobianDual; M] = core::array::from_fn(|i| JacobianDual::from_re(u[i]));
    let mut dx = [JacobianDual::from_re(0.0); S];
    rhs(td, &xd, &ud, &mut dx)?;
    Ok(dx.map(|v| v.eps))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ẋ₀ = x₁ sin(2t) + u₀ t², ẋ₁ = −x₀: ∂F/∂t = (2 x₁ cos 2t + 2 u₀ t, 0).
    fn rhs(
        t: JacobianDual,
        x: &[JacobianDual; 2],
        u: &[JacobianDual; 1],
        dx: &mut [JacobianDual; 2],
    ) -> Result<(), Singularity> {
        dx[0] = x[1] * Scalar::sin(t * 2.0) + u[0] * t * t;
        dx[1] = -x[0];
        Ok(())
    }

    #[test]
    fn the_time_derivative_is_the_rates_derivative_in_t() {
        let (t, x, u) = (0.7, [0.3, -1.1], [2.5]);
        let d = time_derivative_by_duals(t, &x, &u, rhs).unwrap();
        let expected = [2.0 * x[1] * (2.0 * t).cos() + 2.0 * u[0] * t, 0.0];
        assert!((d[0] - expected[0]).abs() < 1e-15 && d[1] == 0.0, "{d:?}");
    }
}
